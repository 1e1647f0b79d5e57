//! Rebuilding curves from locations on other curves (resample, carve,
//! interpolation): every point attribute is blended between the two points
//! a new point lies between, primitive attributes and groups follow their
//! curve, detail attributes stay.

use geode_geo::{AttribClass, Attribute, GeoError, Geometry, Group, PrimKind};

/// One output curve: the source primitive it came from and, per new point,
/// the two source points it lies between and how far (`(a, b, t)`).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveOut {
    pub prim: usize,
    pub closed: bool,
    pub points: Vec<(u32, u32, f32)>,
}

/// A geometry of the `curves` built from `g`'s attributes. Curves too short
/// for their kind (2 points open, 3 closed) are left out.
pub fn rebuild(g: &Geometry, curves: &[CurveOut]) -> Result<Geometry, GeoError> {
    let kept: Vec<&CurveOut> = curves
        .iter()
        .filter(|c| c.points.len() >= if c.closed { 3 } else { 2 })
        .collect();
    let pairs: Vec<(u32, u32, f32)> = kept.iter().flat_map(|c| c.points.iter().copied()).collect();
    let (mut counts, mut kinds) = (Vec::new(), Vec::new());
    for c in &kept {
        counts.push(c.points.len() as u32);
        kinds.push(if c.closed {
            PrimKind::Polygon
        } else {
            PrimKind::Polyline
        });
    }
    let positions = match g
        .attrib(AttribClass::Point, "P")
        .map(|a| a.data().blend(&pairs))
    {
        Some(geode_geo::AttribData::Vec3(v)) => v,
        _ => Vec::new(),
    };
    let mut out =
        Geometry::from_prims(positions, (0..pairs.len() as u32).collect(), &counts, kinds)?;
    for (name, a) in g.attribs(AttribClass::Point).iter() {
        if name == "P" {
            continue;
        }
        let blended = Attribute::from_data(a.data().blend(&pairs), a.type_info)
            .with_default(a.default_value().clone())
            .map_err(|found| GeoError::AttribType {
                class: AttribClass::Point,
                name: name.into(),
                expected: a.attrib_type(),
                found,
            })?;
        out.set_attrib(AttribClass::Point, name, blended)?;
    }
    let prims: Vec<u32> = kept.iter().map(|c| c.prim as u32).collect();
    for (name, a) in g.attribs(AttribClass::Primitive).iter() {
        let column = Attribute::from_data(a.data().gather(&prims), a.type_info)
            .with_default(a.default_value().clone())
            .map_err(|found| GeoError::AttribType {
                class: AttribClass::Primitive,
                name: name.into(),
                expected: a.attrib_type(),
                found,
            })?;
        out.set_attrib(AttribClass::Primitive, name, column)?;
    }
    for (name, grp) in g.prim_groups() {
        out.set_prim_group(
            name,
            Group::from_flags(prims.iter().map(|&p| grp.contains(p as usize))),
        )?;
    }
    for (name, a) in g.attribs(AttribClass::Detail).iter() {
        out.set_attrib(AttribClass::Detail, name, a.clone())?;
    }
    Ok(out)
}
