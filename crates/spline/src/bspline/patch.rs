//! NURBS surfaces as geode patch primitives and back: a patch's vertices
//! are its control grid and its points carry the weights (`Pw`), so the
//! surface survives any point operation (a transform is exact) and any
//! merge; `convert_patches` tessellates them into polygons for formats
//! and nodes that need a mesh.

use geode_geo::{
    ops, AttribClass, AttribData, Attribute, GeoError, Geometry, Group, KnotVector, PatchBasis,
    PrimKind, TypeInfo, WEIGHT,
};

use super::basis::{KnotError, Knots};
use super::curve::lift;
use super::surface::NurbsSurface;

fn knot_vector(k: &Knots) -> KnotVector {
    KnotVector {
        order: k.degree as u32 + 1,
        knots: k.knots.clone(),
    }
}

/// Adds `s` as a patch primitive over new points (weights in `Pw` when any
/// differs from 1); returns the primitive.
pub fn add_patch(g: &mut Geometry, s: &NurbsSurface) -> Result<u32, GeoError> {
    let cartesian: Vec<_> = s
        .points
        .iter()
        .map(|h| (h.truncate() / h.w).as_vec3())
        .collect();
    let before = g.num_points();
    let first = g.add_points(&cartesian);
    let rational = s.points.iter().any(|h| h.w != 1.0);
    if rational || g.attrib(AttribClass::Point, WEIGHT).is_some() {
        let mut column = match g.attrib(AttribClass::Point, WEIGHT) {
            None => vec![1.0; before],
            Some(a) => a.as_f32().map(|w| w[..before].to_vec()).ok_or_else(|| {
                GeoError::Invalid(format!("point attribute `{WEIGHT}` is not a float"))
            })?,
        };
        column.extend(s.points.iter().map(|h| h.w as f32));
        g.set_attrib(
            AttribClass::Point,
            WEIGHT,
            Attribute::from_data(AttribData::Float(column), TypeInfo::None),
        )?;
    }
    let grid: Vec<u32> = (first..first + s.points.len() as u32).collect();
    g.add_patch(
        &grid,
        PatchBasis {
            u: knot_vector(&s.u),
            v: knot_vector(&s.v),
        },
    )
}

/// The NURBS surface of patch primitive `prim` (None: not a patch).
pub fn surface(g: &Geometry, prim: usize) -> Option<Result<NurbsSurface, KnotError>> {
    let basis = g.patch_basis(prim)?;
    let p = g.positions();
    let w = g
        .attrib(AttribClass::Point, WEIGHT)
        .and_then(|a| a.as_f32());
    let points = g
        .prim_points(prim)
        .iter()
        .map(|&k| {
            let weight = w.map_or(1.0, |w| w[k as usize] as f64);
            lift(p[k as usize].as_dvec3(), weight)
        })
        .collect();
    let knots = |k: &KnotVector| Knots::new(k.order as usize - 1, k.knots.clone(), k.count());
    Some((|| {
        NurbsSurface::new(knots(&basis.u)?, knots(&basis.v)?, points)
    })())
}

/// `g` with every patch replaced by its tessellation (`samples` along u and
/// v: quads with point `N` and `uv`), each carrying its patch's primitive
/// attributes; other primitives stay as they are, in front.
pub fn convert_patches(g: &Geometry, samples: [usize; 2]) -> Result<Geometry, GeoError> {
    if !g.has_patches() {
        return Ok(g.clone());
    }
    let patches = g.prims_where(|k| matches!(k, PrimKind::Patch(_)));
    let mut rest = g.clone();
    ops::delete_prims(
        &mut rest,
        &Group::from_members(g.num_prims(), patches.iter().copied()),
        true,
    );
    let mut parts = vec![rest];
    for &prim in &patches {
        let s = surface(g, prim)
            .expect("a patch")
            .map_err(|e| GeoError::Invalid(format!("patch primitive {prim}: {e}")))?;
        let mut mesh = s.tessellate(samples[0], samples[1]).into_geometry()?;
        let ids = vec![prim as u32; mesh.num_prims()];
        for (name, a) in g.attribs(AttribClass::Primitive).iter() {
            mesh.set_attrib(
                AttribClass::Primitive,
                name,
                Attribute::from_data(a.data().gather(&ids), a.type_info),
            )?;
        }
        parts.push(mesh);
    }
    let refs: Vec<&Geometry> = parts.iter().collect();
    let mut out = ops::merge(&refs)?;
    out.remove_attrib(AttribClass::Point, WEIGHT)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use geode_geo::glam::{DVec3, Mat4, Quat, Vec3};

    use super::*;

    /// The largest distance between `s` and patch `prim` of `g` at a grid of
    /// parameters (for tests of exactness after point operations).
    fn deviation(g: &Geometry, prim: usize, s: &NurbsSurface, map: impl Fn(DVec3) -> DVec3) -> f64 {
        let Some(Ok(t)) = surface(g, prim) else {
            return f64::INFINITY;
        };
        let ((u0, u1), (v0, v1)) = (s.u.domain(), s.v.domain());
        let mut worst = 0.0f64;
        for i in 0..=16 {
            for j in 0..=16 {
                let (u, v) = (
                    u0 + (u1 - u0) * i as f64 / 16.0,
                    v0 + (v1 - v0) * j as f64 / 16.0,
                );
                worst = worst.max((map(s.point(u, v)) - t.point(u, v)).length());
            }
        }
        worst
    }

    #[test]
    fn a_rational_patch_survives_transforms_and_merges_exactly() {
        let torus = NurbsSurface::torus(1.5, 0.5);
        let mut g = Geometry::new();
        add_patch(&mut g, &torus).unwrap();
        assert!(
            g.attrib(AttribClass::Point, WEIGHT).is_some(),
            "rational weights kept"
        );
        assert!(deviation(&g, 0, &torus, |p| p) < 1e-6);
        // A rigid turn and move: the patch is the moved torus (f32 points).
        let m = Mat4::from_rotation_translation(
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7),
            Vec3::new(3.0, -1.0, 2.0),
        );
        let mut moved = g.clone();
        ops::transform(&mut moved, m);
        let dm = m.as_dmat4();
        let d = deviation(&moved, 0, &torus, |p| dm.transform_point3(p));
        assert!(d < 1e-5, "{d}");
        // A non-uniform scale too: B-splines are affine invariant.
        let mut squashed = g.clone();
        ops::transform(&mut squashed, Mat4::from_scale(Vec3::new(2.0, 0.5, 1.0)));
        let d = deviation(&squashed, 0, &torus, |p| p * DVec3::new(2.0, 0.5, 1.0));
        assert!(d < 1e-5, "{d}");
        // Merged behind a polygonal mesh, with a second patch.
        let mut sphere = Geometry::new();
        add_patch(&mut sphere, &NurbsSurface::sphere(1.0)).unwrap();
        let box_mesh = geode_geo::primitives::box_mesh(Vec3::ONE, [1, 1, 1]);
        let merged = ops::merge(&[&box_mesh, &moved, &sphere]).unwrap();
        assert!(ops::validate(&merged).is_empty());
        let first = box_mesh.num_prims();
        assert!(deviation(&merged, first, &torus, |p| dm.transform_point3(p)) < 1e-5);
        assert!(deviation(&merged, first + 1, &NurbsSurface::sphere(1.0), |p| p) < 1e-6);
        // Converted: the polygons stay in front, each patch becomes quads
        // on the surface.
        let mesh = convert_patches(&merged, [20, 40]).unwrap();
        assert!(!mesh.has_patches());
        assert_eq!(mesh.num_prims(), first + 2 * 19 * 39);
        for p in &mesh.positions()[box_mesh.num_points() + 800..] {
            assert!((p.length() - 1.0).abs() < 1e-5, "{p}");
        }
    }
}
