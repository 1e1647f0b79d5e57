//! Houdini's `.geo` and `.bgeo`: files Houdini wrote read as the geometry they hold, and every geode geometry written and read back unchanged.

mod common;

use std::path::{Path, PathBuf};

use geode_geo::glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};
use geode_geo::{
    AttribClass, AttribData, AttribValue, Attribute, Geometry, Group, PrimKind, StringColumn,
    TypeInfo,
};
use geode_io::{read, read_bytes, write, write_bytes, Format, NoProgress};
use proptest::prelude::*;

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/houdini")
        .join(name)
}

fn read_sample(name: &str) -> Geometry {
    read(&sample(name), &NoProgress).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Twice the signed volume enclosed by the polygons (fanned), positive
/// when faces wind counter-clockwise seen from outside.
fn signed_volume(g: &Geometry) -> f32 {
    let p = g.positions();
    let mut v = 0.0;
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        for k in 1..pts.len() - 1 {
            let (a, b, c) = (
                p[pts[0] as usize],
                p[pts[k] as usize],
                p[pts[k + 1] as usize],
            );
            v += a.dot(b.cross(c)) / 6.0;
        }
    }
    v
}

#[test]
fn houdini_text_and_binary_files_read_as_the_same_geometry() {
    for stem in [
        "cube_multi_groups_16_5",
        "cube_multi_groups_14",
        "cube_primgroup",
        "cubes_connectivity",
        "grid_tetra_16_5",
        "points_noprim_16_5",
        "simple_partanim_16_5",
        "packed_points_simple_16_5",
    ] {
        let text = read_sample(&format!("{stem}.geo"));
        let binary = read_sample(&format!("{stem}.bgeo"));
        assert_same(&text, &binary, stem);
    }
}

#[test]
fn houdini_cubes_keep_groups_and_face_outward() {
    let g = read_sample("cube_multi_groups_16_5.bgeo");
    assert_eq!(
        (g.num_points(), g.num_vertices(), g.num_prims()),
        (32, 96, 24)
    );
    assert_eq!(g.prim_groups()["all"].count(), 24);
    // boolRLE [2,false,3,true,3,false,...]: three faces of each cube.
    let faces: Vec<usize> = g.prim_groups()["faces"].members().collect();
    assert_eq!(faces, vec![2, 3, 4, 8, 9, 10, 14, 15, 16, 20, 21, 22]);
    // Four unit cubes, wound counter-clockwise from outside once read.
    assert!(
        (signed_volume(&g) - 4.0).abs() < 1e-5,
        "{}",
        signed_volume(&g)
    );
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
}

/// Houdini's packed geometry: each packed primitive's embedded detail is
/// placed by its point, transform and pivot (the pivot lands on the point).
#[test]
fn houdini_packed_geometry_reads_as_instances() {
    let g = read_sample("packed_points_simple_16_5.bgeo");
    assert_eq!(g.packed_instances().len(), 2);
    // Houdini packed each piece about its bounding box's centre: the pivot.
    for i in 0..2 {
        let inst = g.packed_instance(i).unwrap();
        let b = geode_geo::ops::bounds(&inst.source).unwrap();
        let centre = g
            .packed_world_transform(i)
            .unwrap()
            .transform_point3((b.min + b.max) * 0.5);
        let p = g.positions()[g.prim_points(i)[0] as usize];
        assert!(
            (centre - p).length() < 1e-5,
            "instance {i}: centre {centre} away from its point {p}"
        );
    }
    let e = read(&sample("pack1_16_5.bgeo"), &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("primitive type `Sphere` is not supported"),
        "{e}"
    );
}

#[test]
fn houdini_run_layout_keeps_vertex_and_string_attributes() {
    let g = read_sample("cubes_connectivity.geo");
    assert_eq!((g.num_points(), g.num_prims()), (24, 18));
    let uv = g
        .attrib(AttribClass::Vertex, "uv")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert_eq!(uv.len(), 72);
    let names = g
        .attrib(AttribClass::Primitive, "name")
        .unwrap()
        .as_strings()
        .unwrap();
    let per_prim: Vec<&str> = (0..18).map(|i| names.get(i)).collect();
    assert_eq!(per_prim[..6], ["piece0"; 6]);
    assert_eq!(per_prim[12..], ["piece2"; 6]);
    // Houdini's first uv of the first face is [1,0,0]; its first vertex stays first.
    assert_eq!(uv[0], Vec3::new(1.0, 0.0, 0.0));
    assert!((signed_volume(&g) - 3.0).abs() < 1e-5);
    let varmap = g
        .attrib(AttribClass::Detail, "varmap")
        .unwrap()
        .as_strings()
        .unwrap();
    assert_eq!(varmap.get(0), "name -> NAME");
}

#[test]
fn houdini_unsupported_primitives_and_malformed_files_are_named() {
    let e = read(&sample("pack1_16_5.bgeo"), &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pack1_16_5.bgeo: embedded detail `embed:0x")
            && e.ends_with("`: primitives[0]: primitive type `Sphere` is not supported: geode reads polygons, polylines and embedded packed geometry (in Houdini, unpack or convert to polygons before saving)"),
        "{e}"
    );
    let e = read(&sample("badgrid.geo"), &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(
        e.ends_with("badgrid.geo: pointattributes `P`: a tuple of 3 values, expected 4"),
        "{e}"
    );
    let path = Path::new("x.bgeo");
    let e = read_bytes(b"\x7fNSJb[", Format::Bgeo, path, &NoProgress).unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.bgeo: byte 6: unexpected end of file inside an array or map"
    );
    let e = read_bytes(b"\x7fNSJb[\x11", Format::Bgeo, path, &NoProgress).unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.bgeo: byte 7: unexpected end of file: 1 more bytes expected, 0 left"
    );
    let e = read_bytes(
        b"[\"pointcount\", 5,",
        Format::Geo,
        Path::new("x.geo"),
        &NoProgress,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("x.geo: line 1: column 17: malformed JSON"),
        "{e}"
    );
    let e = read_bytes(
        b"[\"pointcount\", 99999999]",
        Format::Geo,
        Path::new("x.geo"),
        &NoProgress,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.geo: pointcount: 99999999 is not a count this 24-byte file can hold (at most 25600)"
    );
}

/// Equal counts, topology, every attribute (values, type info, default) and every group.
fn assert_same(a: &Geometry, b: &Geometry, what: &str) {
    assert_eq!(a.vertex_points(), b.vertex_points(), "{what}: vertices");
    assert_eq!(a.prim_offsets(), b.prim_offsets(), "{what}: primitives");
    assert_eq!(a.prim_kinds(), b.prim_kinds(), "{what}: kinds");
    for class in AttribClass::ALL {
        let names_a: Vec<&str> = a.attribs(class).names().collect();
        let names_b: Vec<&str> = b.attribs(class).names().collect();
        assert_eq!(names_a, names_b, "{what}: {class} attributes");
        for name in names_a {
            assert_eq!(
                a.attrib(class, name),
                b.attrib(class, name),
                "{what}: {class} `{name}`"
            );
        }
    }
    assert_eq!(a.point_groups(), b.point_groups(), "{what}: point groups");
    assert_eq!(a.prim_groups(), b.prim_groups(), "{what}: primitive groups");
}

/// A small deterministic generator (the property test draws its seed).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn f(&mut self) -> f32 {
        (self.below(2_000_001) as f32 - 1_000_000.0) / 7919.0
    }
    fn fs(&mut self, n: usize) -> Vec<f32> {
        (0..n).map(|_| self.f()).collect()
    }
}

/// One random column of `len` elements, with a type info that suits it.
fn random_attribute(r: &mut Rng, len: usize) -> Attribute {
    let words = ["", "a", "pieza", "ünï", "x y"];
    let (data, info, default) = match r.below(13) {
        0 => (
            AttribData::Float(r.fs(len)),
            TypeInfo::None,
            AttribValue::Float(r.f()),
        ),
        1 => (
            AttribData::Int((0..len).map(|_| r.next() as i32).collect()),
            TypeInfo::None,
            AttribValue::Int(-7),
        ),
        2 => (
            AttribData::Vec2((0..len).map(|_| Vec2::new(r.f(), r.f())).collect()),
            TypeInfo::TexCoord,
            AttribValue::Vec2(Vec2::new(0.5, 1.0)),
        ),
        3 => {
            let info = [
                TypeInfo::Vector,
                TypeInfo::Normal,
                TypeInfo::Color,
                TypeInfo::None,
            ][r.below(4) as usize];
            let v = (0..len).map(|_| Vec3::new(r.f(), r.f(), r.f())).collect();
            (
                AttribData::Vec3(v),
                info,
                AttribValue::Vec3(Vec3::new(1.0, 2.0, 3.0)),
            )
        }
        4 => (
            AttribData::Vec4((0..len).map(|_| Vec4::from_slice(&r.fs(4))).collect()),
            TypeInfo::Color,
            AttribValue::Vec4(Vec4::ONE),
        ),
        5 => (
            AttribData::Quat((0..len).map(|_| Quat::from_slice(&r.fs(4))).collect()),
            TypeInfo::Quaternion,
            AttribValue::Quat(Quat::IDENTITY),
        ),
        6 => (
            AttribData::Mat3((0..len).map(|_| Mat3::from_cols_slice(&r.fs(9))).collect()),
            TypeInfo::Transform,
            AttribValue::Mat3(Mat3::from_cols_slice(&r.fs(9))),
        ),
        7 => (
            AttribData::Mat4((0..len).map(|_| Mat4::from_cols_slice(&r.fs(16))).collect()),
            TypeInfo::None,
            AttribValue::Mat4(Mat4::IDENTITY),
        ),
        8 => {
            let table: Vec<String> = words
                .iter()
                .take(1 + r.below(5) as usize)
                .map(|s| s.to_string())
                .collect();
            let indices = (0..len)
                .map(|_| r.below(table.len() as u64) as u32)
                .collect();
            (
                AttribData::String(StringColumn { table, indices }),
                TypeInfo::None,
                AttribValue::String(String::new()),
            )
        }
        9 => (
            AttribData::IntArray(
                (0..len)
                    .map(|_| (0..r.below(4)).map(|_| r.next() as i32).collect())
                    .collect(),
            ),
            TypeInfo::None,
            AttribValue::IntArray(Vec::new()),
        ),
        10 => (
            AttribData::FloatArray(
                (0..len)
                    .map(|_| {
                        let k = r.below(4) as usize;
                        r.fs(k)
                    })
                    .collect(),
            ),
            TypeInfo::None,
            AttribValue::FloatArray(Vec::new()),
        ),
        11 => (
            AttribData::Vec3Array(
                (0..len)
                    .map(|_| {
                        (0..r.below(3))
                            .map(|_| Vec3::new(r.f(), r.f(), r.f()))
                            .collect()
                    })
                    .collect(),
            ),
            TypeInfo::None,
            AttribValue::Vec3Array(Vec::new()),
        ),
        _ => (
            AttribData::StringArray(
                (0..len)
                    .map(|_| {
                        (0..r.below(3))
                            .map(|_| words[r.below(5) as usize].to_string())
                            .collect()
                    })
                    .collect(),
            ),
            TypeInfo::None,
            AttribValue::StringArray(Vec::new()),
        ),
    };
    Attribute::from_data(data, info)
        .with_default(default)
        .unwrap()
}

fn random_geometry(seed: u64) -> Geometry {
    let mut r = Rng(seed | 1);
    let n = 1 + r.below(40) as usize;
    let positions: Vec<Vec3> = (0..n).map(|_| Vec3::new(r.f(), r.f(), r.f())).collect();
    let prims = r.below(12) as usize;
    let (mut verts, mut counts, mut kinds) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..prims {
        let polygon = r.below(3) > 0;
        let size = if polygon {
            3 + r.below(4)
        } else {
            2 + r.below(4)
        };
        verts.extend((0..size).map(|_| r.below(n as u64) as u32));
        counts.push(size as u32);
        kinds.push(if polygon {
            PrimKind::Polygon
        } else {
            PrimKind::Polyline
        });
    }
    let mut g = Geometry::from_prims(positions, verts, &counts, kinds).unwrap();
    // Packed copies of a cube and of a geometry that packs the cube in turn.
    let cube = std::sync::Arc::new(geode_geo::primitives::cube(0.5));
    let mut nest = Geometry::new();
    let p = nest.add_point(Vec3::Y);
    nest.add_packed(p, cube.clone(), Mat4::from_scale(Vec3::splat(2.0)))
        .unwrap();
    let nest = std::sync::Arc::new(nest);
    for k in 0..r.below(4) {
        let axis = Vec3::new(r.f(), r.f(), r.f() + 0.1).normalize_or(Vec3::Z);
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(0.5 + r.below(4) as f32, 1.0, 2.0),
            Quat::from_axis_angle(axis, r.f()),
            if k == 0 {
                Vec3::ZERO
            } else {
                Vec3::new(r.f(), r.f(), r.f())
            },
        );
        let src = if r.below(2) == 0 { &cube } else { &nest };
        let point = r.below(n as u64) as u32;
        g.add_packed(point, src.clone(), m).unwrap();
    }
    for (class, len) in [
        (AttribClass::Point, g.num_points()),
        (AttribClass::Vertex, g.num_vertices()),
        (AttribClass::Primitive, g.num_prims()),
        (AttribClass::Detail, 1),
    ] {
        for k in 0..r.below(4) {
            let a = random_attribute(&mut r, len);
            g.set_attrib(class, &format!("{class}_{k}"), a).unwrap();
        }
    }
    let pg = Group::from_flags((0..g.num_points()).map(|_| r.below(2) == 1));
    g.set_point_group("some_points", pg).unwrap();
    let qg = Group::from_flags((0..g.num_prims()).map(|_| r.below(3) == 0));
    g.set_prim_group("some_prims", qg).unwrap();
    g
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn houdini_round_trip_keeps_every_attribute_group_and_primitive(seed in any::<u64>()) {
        let g = random_geometry(seed);
        for format in [Format::Geo, Format::Bgeo] {
            let path = PathBuf::from(format!("g.{format}"));
            let bytes = write_bytes(&g, format, &path, &NoProgress).unwrap();
            let back = read_bytes(&bytes, format, &path, &NoProgress).unwrap();
            assert_same(&g, &back, &format!("seed {seed} {format}"));
            prop_assert_eq!(g.content_hash(), back.content_hash());
        }
    }
}

#[test]
fn houdini_files_are_written_atomically_and_read_back() {
    let g = common::attributed_torus();
    let dir = tempfile::tempdir().unwrap();
    for ext in ["geo", "bgeo"] {
        let path = dir.path().join(format!("torus.{ext}"));
        write(&g, &path, &NoProgress).unwrap();
        assert_same(&g, &read(&path, &NoProgress).unwrap(), ext);
    }
}

/// Damaged Houdini files (truncated anywhere, bytes flipped, lengths made
/// huge) give an error or a geometry, never a panic: the parser runs here
/// without the panic guard of `read`.
#[test]
fn houdini_damaged_files_never_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/houdini");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let format = match path.extension().and_then(|e| e.to_str()) {
            Some("geo") => Format::Geo,
            Some("bgeo") => Format::Bgeo,
            _ => continue,
        };
        let bytes = std::fs::read(&path).unwrap();
        let step = (bytes.len() / 400).max(1);
        for at in (0..bytes.len()).step_by(step) {
            let _ = geode_io::parse_unguarded(&bytes[..at], format, None, &NoProgress);
            for damage in [0xffu8, 0xf8, 0x40, 0x5b, 0x26] {
                let mut b = bytes.clone();
                b[at] = if damage == 0xff { b[at] ^ 0xff } else { damage };
                let _ = geode_io::parse_unguarded(&b, format, None, &NoProgress);
            }
        }
    }
}

#[test]
fn houdini_primitive_runs_cannot_claim_more_than_the_header() {
    let doc = br#"["pointcount",3,"vertexcount",3,"primitivecount",1,
        "topology",["pointref",["indices",[0,1,2]]],
        "attributes",["pointattributes",[[["scope","public","type","numeric","name","P"],
            ["size",3,"storage","fpreal32","values",["size",3,"storage","fpreal32","tuples",[[0,0,0],[1,0,0],[0,1,0]]]]]]],
        "primitives",[[["type","Polygon_run"],["startvertex",0,"nprimitives",1000000000000,"nvertices_rle",[3,1000000000000]]]]]"#;
    let e = read_bytes(doc, Format::Geo, Path::new("x.geo"), &NoProgress).unwrap_err();
    assert_eq!(
        e.to_string(),
        "x.geo: primitives[0] (Polygon_run): 1000000000000 primitives where the primitivecount of 1 leaves room for 1"
    );
    let ok = String::from_utf8_lossy(doc).replace("1000000000000", "1");
    let g = read_bytes(ok.as_bytes(), Format::Geo, Path::new("x.geo"), &NoProgress).unwrap();
    assert_eq!((g.num_prims(), g.prim_points(0)), (1, &[0u32, 2, 1][..]));
}

/// A reader told the memory budget, as the file node and the CLI tell it.
struct Within(u64);

impl geode_io::Progress for Within {
    fn memory_budget(&self) -> u64 {
        self.0
    }
}

/// Counts whose geometry, or an attribute's values, would need more than
/// the memory budget are refused before anything is allocated for them
/// (constant pages let a small file claim a billion points).
#[test]
fn counts_beyond_the_memory_budget_are_refused_before_allocating() {
    let mut g = Geometry::new();
    g.add_points(&vec![Vec3::ZERO; 2048]);
    g.set_attrib(
        AttribClass::Point,
        "xform",
        Attribute::from_data(AttribData::Mat4(vec![Mat4::IDENTITY; 2048]), TypeInfo::None),
    )
    .unwrap();
    for format in [Format::Geo, Format::Bgeo] {
        let path = Path::new("x.geo");
        let bytes = write_bytes(&g, format, path, &NoProgress).unwrap();
        let e = read_bytes(&bytes, format, path, &Within(10_000)).unwrap_err();
        // Of the budget's kind (a cook over it is a resource error), not a malformed file.
        assert!(matches!(e, geode_io::IoError::TooLarge { .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "x.geo: pointcount: 2048 points, 0 vertices and 0 primitives would need 24.6 KB, more than the memory budget of 10.0 KB (GEODE_MEMORY_MB)"
        );
        let e = read_bytes(&bytes, format, path, &Within(100_000)).unwrap_err();
        assert!(matches!(e, geode_io::IoError::TooLarge { .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "x.geo: pointattributes `xform`: 2048 elements of 16 values would need 262 KB, more than the memory budget of 100 KB (GEODE_MEMORY_MB)"
        );
        let back = read_bytes(&bytes, format, path, &Within(1_000_000)).unwrap();
        assert_eq!(back.num_points(), 2048);
    }
}

/// A writer asked to stop.
struct Stopped;

impl geode_io::Progress for Stopped {
    fn cancelled(&self) -> bool {
        true
    }
}

/// Encoding many packed instances stops when asked, writing nothing (it
/// once ran to the end, seconds for a million).
#[test]
fn encoding_packed_instances_stops_when_cancelled() {
    let cube = std::sync::Arc::new(geode_geo::primitives::cube(0.5));
    let mut g = Geometry::new();
    for i in 0..10_000 {
        let p = g.add_point(Vec3::new(i as f32, 0.0, 0.0));
        g.add_packed(p, cube.clone(), Mat4::IDENTITY).unwrap();
    }
    for format in [Format::Geo, Format::Bgeo] {
        let e = write_bytes(&g, format, Path::new("x.bgeo"), &Stopped).unwrap_err();
        assert_eq!(e.to_string(), "x.bgeo: cancelled, nothing was written");
    }
}
