//! Round trips through every format: counts, exact positions, attributes.

mod common;

use std::path::Path;

use common::*;
use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, Geometry, PrimKind};
use geode_io::{read, write, NoProgress};

fn round_trip(g: &Geometry, ext: &str) -> Geometry {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("g.{ext}"));
    write(g, &path, &NoProgress).unwrap();
    read(&path, &NoProgress).unwrap()
}

fn attr3<'a>(g: &'a Geometry, class: AttribClass, name: &str) -> &'a [Vec3] {
    g.attrib(class, name)
        .unwrap_or_else(|| panic!("{name} missing"))
        .as_vec3()
        .unwrap()
}

#[test]
fn obj_keeps_everything() {
    let g = attributed_torus();
    let back = round_trip(&g, "obj");
    assert_eq!(back.num_points(), g.num_points());
    assert_eq!(back.num_prims(), g.num_prims());
    assert_eq!(
        back.positions(),
        g.positions(),
        "shortest float text round trips exactly"
    );
    assert_eq!(back.vertex_points(), g.vertex_points());
    assert_eq!(
        attr3(&back, AttribClass::Point, "Cd"),
        attr3(&g, AttribClass::Point, "Cd")
    );
    // Point uv/N come back per vertex (OBJ indexes them per corner).
    let uv = back
        .attrib(AttribClass::Vertex, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    let puv = g
        .attrib(AttribClass::Point, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    for (v, &p) in g.vertex_points().iter().enumerate() {
        assert_eq!(uv[v], puv[p as usize]);
    }
    assert_eq!(back.prim_groups()["half"], g.prim_groups()["half"]);

    let c = vertex_attributed_cube();
    let back = round_trip(&c, "obj");
    assert_eq!(
        attr3(&back, AttribClass::Vertex, "N"),
        attr3(&c, AttribClass::Vertex, "N")
    );
    assert_eq!(
        back.attrib(AttribClass::Vertex, "uv").unwrap().as_vec2(),
        c.attrib(AttribClass::Vertex, "uv").unwrap().as_vec2()
    );
}

#[test]
fn stl_positions_exact_and_triangulated() {
    let g = attributed_torus();
    let back = round_trip(&g, "stl");
    assert_eq!(
        back.num_points(),
        g.num_points(),
        "identical corners weld back into shared points"
    );
    assert_eq!(back.num_prims(), 2 * g.num_prims());
    let sorted = |g: &Geometry| {
        let mut v: Vec<[u32; 3]> = g
            .positions()
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        v.sort_unstable();
        v
    };
    assert_eq!(sorted(&back), sorted(&g), "the same positions, bit for bit");
    assert!(back.topology().manifold_report(&back).is_closed_manifold());
    assert!((ops::signed_volume(&back) - ops::signed_volume(&g)).abs() < 1e-5);
}

#[test]
fn ply_keeps_attributes() {
    let g = attributed_torus();
    let back = round_trip(&g, "ply");
    assert_eq!(
        (back.num_points(), back.num_prims()),
        (g.num_points(), g.num_prims())
    );
    assert_eq!(back.positions(), g.positions());
    assert_eq!(back.vertex_points(), g.vertex_points());
    for name in ["N", "Cd"] {
        assert_eq!(
            attr3(&back, AttribClass::Point, name),
            attr3(&g, AttribClass::Point, name)
        );
    }
    assert_eq!(
        back.attrib(AttribClass::Point, "uv").unwrap().as_vec2(),
        g.attrib(AttribClass::Point, "uv").unwrap().as_vec2()
    );
    assert_eq!(
        back.attrib(AttribClass::Primitive, "weight")
            .unwrap()
            .as_f32(),
        g.attrib(AttribClass::Primitive, "weight").unwrap().as_f32()
    );
    // Polylines stay polylines.
    let mut lines = Geometry::new();
    lines.add_points(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
    lines.add_polyline(&[0, 1, 2]).unwrap();
    let back = round_trip(&lines, "ply");
    assert_eq!(back.num_prims(), 1);
    assert_eq!(back.prim_points(0), &[0, 1, 2]);
    assert_eq!(back.prim_kind(0), PrimKind::Polyline);
}

/// Every attribute PLY can carry comes back with its type and type info
/// (polylines, a vertex colour, quaternions, int arrays); what it cannot
/// (strings, groups) is named in one warning.
#[test]
fn ply_keeps_every_numeric_attribute_and_names_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    for (name, g, expect_dropped) in [
        ("curves", framed_curves(), "detail `name` (string)"),
        ("cube", vertex_attributed_cube(), ""),
        ("torus", attributed_torus(), "primitive group `half`"),
    ] {
        let path = dir.path().join(format!("{name}.ply"));
        let warnings = Warnings::default();
        write(&g, &path, &warnings).unwrap();
        let back = read(&path, &NoProgress).unwrap();
        assert_eq!(back.prim_kinds(), g.prim_kinds(), "{name}");
        assert_eq!(back.vertex_points(), g.vertex_points(), "{name}");
        for class in [
            AttribClass::Point,
            AttribClass::Vertex,
            AttribClass::Primitive,
        ] {
            for (attr, a) in g.attribs(class).iter() {
                if a.attrib_type() == geode_geo::AttribType::String {
                    continue;
                }
                let b = back
                    .attrib(class, attr)
                    .unwrap_or_else(|| panic!("{name}: {class} `{attr}` lost"));
                assert_eq!(b.data(), a.data(), "{name}: {class} `{attr}`");
                assert_eq!(b.type_info, a.type_info, "{name}: {class} `{attr}`");
            }
        }
        let warned = warnings.0.lock().unwrap().clone();
        if expect_dropped.is_empty() {
            assert!(warned.is_empty(), "{warned:?}");
        } else {
            assert_eq!(
                warned,
                vec![format!(
                    "{}: PLY cannot hold {expect_dropped}; not written",
                    path.display()
                )]
            );
        }
    }
}

#[test]
fn glb_instances_share_nodes_and_keep_every_transform() {
    let g = mixed_instances();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mixed.glb");
    write(&g, &path, &NoProgress).unwrap();
    // One instancing node per source, the shear on a node of its own.
    let bytes = std::fs::read(&path).unwrap();
    let glb = gltf::Glb::from_slice(&bytes).unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&glb.json).unwrap();
    let nodes = doc["nodes"].as_array().unwrap();
    let instancing: Vec<u64> = nodes
        .iter()
        .filter_map(|n| {
            n["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"].as_u64()
        })
        .map(|a| doc["accessors"][a as usize]["count"].as_u64().unwrap())
        .collect();
    assert_eq!(
        instancing,
        vec![10, 20],
        "cube first (instance 0), then the ball"
    );
    assert_eq!(nodes.len(), 3);
    assert_eq!(
        doc["extensionsRequired"],
        serde_json::json!(["EXT_mesh_gpu_instancing"])
    );
    // Read back: the same world transforms, instance by instance.
    let back = read(&path, &NoProgress).unwrap();
    let worlds = |g: &Geometry| -> Vec<(usize, [f32; 16])> {
        let mut w: Vec<(usize, [f32; 16])> = (0..g.num_prims())
            .filter(|&p| matches!(g.prim_kind(p), PrimKind::Packed(_)))
            .map(|p| {
                let src = g.packed_instance(p).unwrap().source.num_points();
                (src, g.packed_world_transform(p).unwrap().to_cols_array())
            })
            .collect();
        w.sort_by(|a, b| a.partial_cmp(b).unwrap());
        w
    };
    let (a, b) = (worlds(&g), worlds(&back));
    assert_eq!(a.len(), 31);
    assert_eq!(a.len(), b.len());
    for ((sa, ma), (sb, mb)) in a.iter().zip(&b) {
        assert_eq!(sa, sb);
        for (x, y) in ma.iter().zip(mb) {
            assert!((x - y).abs() < 1e-5, "{ma:?} vs {mb:?}");
        }
    }
}

#[test]
fn glb_keeps_attributes_and_instances() {
    let g = attributed_torus();
    let back = round_trip(&g, "glb");
    assert_eq!(back.num_points(), g.num_points());
    assert_eq!(back.num_prims(), 2 * g.num_prims());
    assert_eq!(back.positions(), g.positions(), "binary floats are exact");
    for name in ["N", "Cd"] {
        let a = attr3(&back, AttribClass::Point, name);
        let b = attr3(&g, AttribClass::Point, name);
        for (x, y) in a.iter().zip(b) {
            assert!((*x - *y).length() < 1e-6, "{name}: {x} vs {y}");
        }
    }
    let uv = back
        .attrib(AttribClass::Point, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    let uv0 = g
        .attrib(AttribClass::Point, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    for (a, b) in uv.iter().zip(uv0) {
        assert!((*a - *b).length() < 1e-6, "v flip undone on read");
    }

    let scene = instanced_scene(40);
    let back = round_trip(&scene, "glb");
    let packed = back
        .prim_kinds()
        .iter()
        .filter(|k| matches!(k, PrimKind::Packed(_)))
        .count();
    assert_eq!(packed, 40, "instances stay instances");
    let b0 = ops::bounds(&scene).unwrap();
    let b1 = ops::bounds(&back).unwrap();
    assert!((b0.min - b1.min).length() < 1e-4 && (b0.max - b1.max).length() < 1e-4);
    let flat0 = ops::unpack(&scene).unwrap();
    let flat1 = ops::unpack(&back).unwrap();
    assert_eq!(flat0.num_points(), flat1.num_points());
    assert!((ops::surface_area(&flat0) - ops::surface_area(&flat1)).abs() < 1e-3);
}

#[test]
fn formats_without_instancing_unpack() {
    let scene = instanced_scene(5);
    let flat = ops::unpack(&scene).unwrap();
    assert_eq!(round_trip(&scene, "obj").num_prims(), flat.num_prims());
    assert_eq!(round_trip(&scene, "ply").num_prims(), flat.num_prims());
}

#[test]
fn unknown_extension_is_a_clear_error() {
    let e = write(&Geometry::new(), Path::new("out.xyz"), &NoProgress).unwrap_err();
    assert_eq!(
        e.to_string(),
        "out.xyz: unknown file format (expected one of: .obj, .stl, .ply, .glb, .usda, .geo, .bgeo)"
    );
}

/// `.gltf` JSON files: buffers as base64 data URIs and as external `.bin` files.
#[test]
fn gltf_json_with_data_uri_and_external_buffers() {
    use base64::Engine as _;
    let g = attributed_torus();
    let glb =
        geode_io::write_bytes(&g, geode_io::Format::Glb, Path::new("t.glb"), &NoProgress).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let mut doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin = &glb[20 + json_len + 8..];
    let dir = tempfile::tempdir().unwrap();

    doc["buffers"][0]["uri"] = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bin)
    )
    .into();
    let embedded = dir.path().join("embedded.gltf");
    std::fs::write(&embedded, serde_json::to_vec(&doc).unwrap()).unwrap();
    let a = read(&embedded, &NoProgress).unwrap();

    doc["buffers"][0]["uri"] = "mesh.bin".into();
    std::fs::write(dir.path().join("mesh.bin"), bin).unwrap();
    let external = dir.path().join("external.gltf");
    std::fs::write(&external, serde_json::to_vec(&doc).unwrap()).unwrap();
    let b = read(&external, &NoProgress).unwrap();

    for back in [&a, &b] {
        assert_eq!(back.positions(), g.positions());
        assert_eq!(back.num_prims(), 2 * g.num_prims());
    }
    std::fs::remove_file(dir.path().join("mesh.bin")).unwrap();
    let e = read(&external, &NoProgress).unwrap_err().to_string();
    assert!(
        e.contains("external.gltf: buffer 0: cannot read") && e.contains("mesh.bin"),
        "{e}"
    );
}

/// Point attributes beyond N, uv and Cd travel as glTF `_NAME` attributes
/// and come back with their geode type and type info; what glTF cannot
/// carry is named in one warning.
#[test]
fn glb_keeps_custom_point_attributes() {
    let g = instancing_torus();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.glb");
    let warnings = Warnings::default();
    write(&g, &path, &warnings).unwrap();
    let back = read(&path, &NoProgress).unwrap();
    for name in ["orient", "pscale", "id", "xform", "T"] {
        let (a, b) = (
            g.attrib(AttribClass::Point, name).unwrap(),
            back.attrib(AttribClass::Point, name)
                .unwrap_or_else(|| panic!("`{name}` lost")),
        );
        assert_eq!(b.data(), a.data(), "{name}");
        assert_eq!(b.type_info, a.type_info, "{name}");
    }
    assert_eq!(
        warnings.0.lock().unwrap().clone(),
        vec![format!(
            "{}: GLB cannot hold primitive `weight` (float), primitive group `half`; not written",
            path.display()
        )]
    );
}

/// OBJ keeps colours, uvs, normals, materials, primitive groups and the
/// subdivision tags; the rest is named in one warning.
#[test]
fn obj_names_what_it_drops() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.obj");
    let warnings = Warnings::default();
    write(&framed_curves(), &path, &warnings).unwrap();
    assert_eq!(
        warnings.0.lock().unwrap().clone(),
        vec![format!(
            "{}: OBJ cannot hold point `B` (vector3), point `T` (vector3), point `orient` (quaternion), point `pscale` (float), point `tags` (int array), vertex `Cd` (vector3), primitive `id` (int), detail `name` (string); not written",
            path.display()
        )]
    );
    let quiet = Warnings::default();
    write(
        &vertex_attributed_cube(),
        &dir.path().join("cube.obj"),
        &quiet,
    )
    .unwrap();
    assert!(
        quiet.0.lock().unwrap().is_empty(),
        "{:?}",
        quiet.0.lock().unwrap()
    );
}

/// STL holds triangle positions only: every attribute but P, every group
/// and every polyline is named in one warning, and plain positions warn
/// of nothing.
#[test]
fn stl_names_everything_it_drops() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.stl");
    let warnings = Warnings::default();
    write(&vertex_attributed_cube(), &path, &warnings).unwrap();
    let warned = warnings.0.lock().unwrap().clone();
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].starts_with(&format!("{}: STL cannot hold ", path.display())),
        "{warned:?}"
    );
    assert!(
        warned[0].contains("vertex `N` (vector3)") || warned[0].contains("`uv`"),
        "{warned:?}"
    );
    let plain = geode_geo::Geometry::from_triangles(
        vec![
            geode_geo::glam::Vec3::ZERO,
            geode_geo::glam::Vec3::X,
            geode_geo::glam::Vec3::Y,
        ],
        &[[0, 1, 2]],
    )
    .unwrap();
    let quiet = Warnings::default();
    write(&plain, &dir.path().join("t.stl"), &quiet).unwrap();
    assert!(quiet.0.lock().unwrap().is_empty());
}

/// Houdini's uv is three floats (z = 0): OBJ and glTF write its first two
/// as their texture coordinates (glTF's v flipped), read back as pairs.
#[test]
fn a_three_float_uv_is_written_as_texture_coordinates() {
    use geode_geo::{AttribData, Attribute, TypeInfo};
    let mut g = geode_geo::primitives::grid(geode_geo::glam::Vec2::ONE, 2, 2);
    let uv: Vec<Vec3> = (0..g.num_vertices())
        .map(|v| Vec3::new(v as f32 * 0.01, 0.5 - v as f32 * 0.02, 0.0))
        .collect();
    g.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec3(uv.clone()), TypeInfo::TexCoord),
    )
    .unwrap();
    for ext in ["obj", "glb"] {
        let back = round_trip(&g, ext);
        let got: Vec<geode_geo::glam::Vec2> =
            match back.attrib(AttribClass::Vertex, "uv").map(|a| a.data()) {
                Some(AttribData::Vec2(v)) => v.clone(),
                Some(AttribData::Vec3(v)) => v.iter().map(|t| t.truncate()).collect(),
                other => panic!("{ext}: no uv read back: {other:?}"),
            };
        // Corners may come back in another order and count (glTF
        // triangulates); compare as sets.
        let mut a: Vec<(i32, i32)> = got
            .iter()
            .map(|t| ((t.x * 1e4).round() as i32, (t.y * 1e4).round() as i32))
            .collect();
        let mut b: Vec<(i32, i32)> = uv
            .iter()
            .map(|t| ((t.x * 1e4).round() as i32, (t.y * 1e4).round() as i32))
            .collect();
        a.sort();
        a.dedup();
        b.sort();
        b.dedup();
        assert_eq!(a, b, "{ext}");
    }
}
