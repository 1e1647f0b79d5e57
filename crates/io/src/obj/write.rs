//! OBJ writer: points (with colours), texture coordinates and normals, faces and lines, groups, materials, tags.

use std::io::Write;
use std::path::Path;

use geode_geo::{AttribClass, Geometry, Group, PrimKind};

use crate::atomic::os_err;
use crate::error::IoError;
use crate::progress::{describe_attrib, report_dropped, Progress, Throttle};

pub fn write_obj(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    let e = os_err(path);
    let mut throttle = Throttle::new(progress, "writing OBJ", g.num_prims() as u64);
    writeln!(w, "# written by geode {}", env!("CARGO_PKG_VERSION")).map_err(&e)?;
    let cd = g.attrib(AttribClass::Point, "Cd").and_then(|a| a.as_vec3());
    let mut buf = String::with_capacity(1 << 16);
    use std::fmt::Write as _;
    for (i, p) in g.positions().iter().enumerate() {
        match cd {
            Some(c) => {
                let c = c[i];
                let _ = writeln!(buf, "v {} {} {} {} {} {}", p.x, p.y, p.z, c.x, c.y, c.z);
            }
            None => {
                let _ = writeln!(buf, "v {} {} {}", p.x, p.y, p.z);
            }
        }
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    // Per-vertex indices into the vt/vn lists (point attributes are written per point).
    let uv_of = |class: AttribClass| crate::texcoords(g, class);
    let (uv, uv_by_point) = match (uv_of(AttribClass::Vertex), uv_of(AttribClass::Point)) {
        (Some(v), _) => (Some(v), false),
        (None, Some(p)) => (Some(p), true),
        _ => (None, false),
    };
    let n_of = |class: AttribClass| g.attrib(class, "N").and_then(|a| a.as_vec3());
    let (nrm, n_by_point) = match (n_of(AttribClass::Vertex), n_of(AttribClass::Point)) {
        (Some(v), _) => (Some(v), false),
        (None, Some(p)) => (Some(p), true),
        _ => (None, false),
    };
    for t in uv.iter().flat_map(|v| v.iter()) {
        let _ = writeln!(buf, "vt {} {}", t.x, t.y);
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    for n in nrm.iter().flat_map(|v| v.iter()) {
        let _ = writeln!(buf, "vn {} {} {}", n.x, n.y, n.z);
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    let material = g
        .attrib(AttribClass::Primitive, "material")
        .and_then(|a| a.as_strings());
    let groups: Vec<(&String, &Group)> = g.prim_groups().iter().collect();
    let mut last_groups: Option<Vec<&str>> = None;
    let mut last_material: Option<&str> = None;
    let vp = g.vertex_points();
    for prim in 0..g.num_prims() {
        throttle.tick(prim as u64);
        let kw = match g.prim_kind(prim) {
            PrimKind::Polygon => "f",
            PrimKind::Polyline => "l",
            PrimKind::Packed(_) | PrimKind::Patch(_) => {
                return Err(IoError::Unsupported {
                    path: path.to_owned(),
                    message: "OBJ here holds polygons and polylines; unpack packed primitives and convert patches first".into(),
                })
            }
        };
        if !groups.is_empty() {
            let mine: Vec<&str> = groups
                .iter()
                .filter(|(_, grp)| grp.contains(prim))
                .map(|(n, _)| n.as_str())
                .collect();
            if last_groups.as_ref() != Some(&mine) {
                let _ = writeln!(buf, "g {}", mine.join(" ")).map(|_| ());
                last_groups = Some(mine);
            }
        }
        if let Some(m) = material {
            let name = m.get(prim);
            if last_material != Some(name) {
                let _ = writeln!(buf, "usemtl {name}");
                last_material = Some(name);
            }
        }
        buf.push_str(kw);
        for v in g.prim_vertex_range(prim) {
            let p = vp[v] + 1;
            let t = uv
                .as_ref()
                .map(|_| if uv_by_point { p } else { v as u32 + 1 });
            let n = nrm.map(|_| if n_by_point { p } else { v as u32 + 1 });
            let _ = match (t, n) {
                (None, None) => write!(buf, " {p}"),
                (Some(t), None) => write!(buf, " {p}/{t}"),
                (None, Some(n)) => write!(buf, " {p}//{n}"),
                (Some(t), Some(n)) => write!(buf, " {p}/{t}/{n}"),
            };
        }
        buf.push('\n');
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    super::tags::write_tags(g, &mut buf);
    w.write_all(buf.as_bytes()).map_err(&e)?;
    report_dropped(progress, path, "OBJ", &dropped(g));
    throttle.finish();
    Ok(())
}

/// What OBJ cannot hold: every attribute but those written above (`Cd`,
/// `uv`, `N`, `material`, the subdivision tags) and point groups.
fn dropped(g: &Geometry) -> Vec<String> {
    use super::tags::{
        BOUNDARY, CORNER, CREASE, CREASE_METHOD, FVAR_BOUNDARY, HOLE, RAW_TAGS, TRIANGLE_RULE,
    };
    use geode_geo::AttribType as T;
    let written = |class: AttribClass, name: &str, ty: T| match (class, name, ty) {
        (AttribClass::Point, geode_geo::P, _) | (AttribClass::Point, "Cd", T::Vec3) => true,
        // A vertex uv or N is written in preference to a point one.
        (AttribClass::Vertex, "uv", T::Vec2 | T::Vec3) | (AttribClass::Vertex, "N", T::Vec3) => {
            true
        }
        (AttribClass::Point, "uv", T::Vec2 | T::Vec3) => {
            crate::texcoords(g, AttribClass::Vertex).is_none()
        }
        (AttribClass::Point, "N", T::Vec3) => g.attrib(AttribClass::Vertex, "N").is_none(),
        (AttribClass::Primitive, "material", T::String) => true,
        (AttribClass::Vertex, CREASE, _)
        | (AttribClass::Point, CORNER, _)
        | (AttribClass::Primitive, HOLE, _) => true,
        (AttribClass::Detail, n, _) => [
            BOUNDARY,
            FVAR_BOUNDARY,
            CREASE_METHOD,
            TRIANGLE_RULE,
            RAW_TAGS,
        ]
        .contains(&n),
        _ => false,
    };
    let mut out = Vec::new();
    for class in AttribClass::ALL {
        for (name, a) in g.attribs(class).iter() {
            if !written(class, name, a.attrib_type()) {
                out.push(describe_attrib(class, name, a.attrib_type()));
            }
        }
    }
    out.extend(
        g.point_groups()
            .keys()
            .map(|n| format!("point group `{n}`")),
    );
    out
}
