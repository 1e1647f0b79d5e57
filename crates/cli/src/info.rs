//! The `geode info` report: counts, bounds, attributes, groups, topology and content hash.

use std::fmt::Write as _;
use std::path::Path;

use geode_geo::{ops, AttribClass, Geometry, PrimKind};

pub struct Report {
    file: String,
    points: usize,
    vertices: usize,
    polygons: usize,
    polylines: usize,
    packed: usize,
    patches: usize,
    bounds: Option<ops::Aabb>,
    attributes: Vec<(AttribClass, String, String, String)>,
    groups: Vec<(&'static str, String, usize)>,
    manifold: geode_geo::ManifoldReport,
    hash: u128,
}

impl Report {
    pub fn new(path: &Path, g: &Geometry) -> Report {
        let count = |f: fn(&PrimKind) -> bool| g.prim_kinds().iter().filter(|k| f(k)).count();
        let mut attributes = Vec::new();
        for class in [
            AttribClass::Point,
            AttribClass::Vertex,
            AttribClass::Primitive,
            AttribClass::Detail,
        ] {
            for (name, a) in g.attribs(class).iter() {
                attributes.push((
                    class,
                    name.to_owned(),
                    a.attrib_type().to_string(),
                    a.type_info.to_string(),
                ));
            }
        }
        let mut groups = Vec::new();
        for (n, grp) in g.point_groups() {
            groups.push(("point", n.clone(), grp.count()));
        }
        for (n, grp) in g.prim_groups() {
            groups.push(("primitive", n.clone(), grp.count()));
        }
        Report {
            file: path.display().to_string(),
            points: g.num_points(),
            vertices: g.num_vertices(),
            polygons: count(|k| *k == PrimKind::Polygon),
            polylines: count(|k| *k == PrimKind::Polyline),
            packed: count(|k| matches!(k, PrimKind::Packed(_))),
            patches: count(|k| matches!(k, PrimKind::Patch(_))),
            bounds: ops::bounds(g),
            attributes,
            groups,
            manifold: g.topology().manifold_report(g),
            hash: g.content_hash(),
        }
    }

    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "file:        {}", self.file);
        let _ = writeln!(s, "points:      {}", self.points);
        let _ = writeln!(s, "vertices:    {}", self.vertices);
        let _ = writeln!(
            s,
            "primitives:  {} ({} polygons, {} polylines, {} packed, {} patches)",
            self.polygons + self.polylines + self.packed + self.patches,
            self.polygons,
            self.polylines,
            self.packed,
            self.patches
        );
        match &self.bounds {
            Some(b) => {
                let _ = writeln!(
                    s,
                    "bounds:      min {} max {} size {}",
                    b.min,
                    b.max,
                    b.size()
                );
            }
            None => s.push_str("bounds:      empty\n"),
        }
        s.push_str("attributes:\n");
        for (class, name, ty, info) in &self.attributes {
            let _ = writeln!(
                s,
                "  {:<10} {:<20} {:<10} {}",
                class.to_string(),
                name,
                ty,
                info
            );
        }
        if !self.groups.is_empty() {
            s.push_str("groups:\n");
            for (kind, name, n) in &self.groups {
                let _ = writeln!(s, "  {kind:<10} {name:<20} {n} members");
            }
        }
        let m = &self.manifold;
        let _ = writeln!(
            s,
            "topology:    {}",
            if self.polygons == 0 {
                "no polygons".to_owned()
            } else if m.is_closed_manifold() {
                "closed manifold".to_owned()
            } else {
                format!(
                    "{} boundary edges, {} non-manifold edges, {} inconsistently wound edges, {} non-manifold points, {} degenerate polygons",
                    m.boundary_edges, m.non_manifold_edges, m.inconsistent_edges, m.non_manifold_points, m.degenerate_polygons
                )
            }
        );
        let _ = writeln!(s, "content hash: {:032x}", self.hash);
        s
    }

    pub fn to_json(&self) -> String {
        let m = &self.manifold;
        serde_json::json!({
            "file": self.file,
            "points": self.points,
            "vertices": self.vertices,
            "polygons": self.polygons,
            "polylines": self.polylines,
            "packed": self.packed,
            "patches": self.patches,
            "bounds": self.bounds.map(|b| serde_json::json!({"min": b.min.to_array(), "max": b.max.to_array()})),
            "attributes": self.attributes.iter().map(|(c, n, t, i)| serde_json::json!({"class": c.to_string(), "name": n, "type": t, "typeinfo": i})).collect::<Vec<_>>(),
            "groups": self.groups.iter().map(|(k, n, c)| serde_json::json!({"kind": k, "name": n, "members": c})).collect::<Vec<_>>(),
            "boundary_edges": m.boundary_edges,
            "non_manifold_edges": m.non_manifold_edges,
            "inconsistent_edges": m.inconsistent_edges,
            "non_manifold_points": m.non_manifold_points,
            "degenerate_polygons": m.degenerate_polygons,
            "content_hash": format!("{:032x}", self.hash),
        })
        .to_string()
    }
}

/// `geode info` of a `.vdb` file: each float grid's name, class, voxel
/// transform, background, active voxels and their bounds, leaves and tiles.
pub fn volumes_text(path: &Path, volumes: &[geode_geo::volume::SparseVolume]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "file:        {}", path.display());
    let _ = writeln!(s, "grids:       {} float", volumes.len());
    for v in volumes {
        let j = volume_json(v);
        let _ = writeln!(s, "grid {:?}:", v.name);
        let _ = writeln!(
            s,
            "  class:       {}",
            j["class"].as_str().unwrap_or_default()
        );
        let _ = writeln!(s, "  voxel size:  {:?}", v.transform.scale);
        let _ = writeln!(s, "  translation: {:?}", v.transform.translation);
        let _ = writeln!(s, "  background:  {}", v.background);
        let _ = writeln!(s, "  active:      {} voxels", v.active_voxel_count());
        match v.active_bounds() {
            Some((lo, hi)) => {
                let _ = writeln!(
                    s,
                    "  bounds:      index {lo:?} to {hi:?}, world {:?} to {:?}",
                    v.transform.to_world(lo),
                    v.transform.to_world(hi)
                );
            }
            None => s.push_str("  bounds:      empty\n"),
        }
        let _ = writeln!(
            s,
            "  tree:        {} leaves, {} tiles",
            v.leaves().len(),
            v.tiles().len()
        );
    }
    s
}

/// The same as JSON.
pub fn volumes_json(path: &Path, volumes: &[geode_geo::volume::SparseVolume]) -> String {
    serde_json::json!({
        "file": path.display().to_string(),
        "grids": volumes.iter().map(volume_json).collect::<Vec<_>>(),
    })
    .to_string()
}

fn volume_json(v: &geode_geo::volume::SparseVolume) -> serde_json::Value {
    use geode_geo::volume::VolumeClass;
    let class = match v.class {
        VolumeClass::LevelSet => "level set",
        VolumeClass::FogVolume => "fog volume",
        VolumeClass::Unknown => "unknown",
    };
    let bounds = v.active_bounds().map(|(lo, hi)| {
        serde_json::json!({"index_min": lo, "index_max": hi,
            "min": v.transform.to_world(lo), "max": v.transform.to_world(hi)})
    });
    serde_json::json!({
        "name": v.name,
        "class": class,
        "voxel_size": v.transform.scale,
        "translation": v.transform.translation,
        "background": v.background,
        "active_voxels": v.active_voxel_count(),
        "bounds": bounds,
        "leaves": v.leaves().len(),
        "tiles": v.tiles().len(),
    })
}
