//! Shared fixtures for the io behaviour tests: sample geometries and external validators.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use geode_geo::glam::{Mat4, Quat, Vec2, Vec3};
use geode_geo::{primitives, AttribClass, AttribData, Attribute, Geometry, Group, TypeInfo};

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

pub fn corpus() -> PathBuf {
    let p = repo_root().join("corpus");
    assert!(
        p.is_dir(),
        "the test corpus is part of the repository, at {}",
        p.display()
    );
    p
}

/// A torus with point uv, N and Cd, a primitive attribute and a group.
pub fn attributed_torus() -> Geometry {
    let mut g = primitives::torus(1.0, 0.35, 24, 12);
    let n = geode_geo::ops::point_normals(&g);
    let p = g.positions().to_vec();
    let uv: Vec<Vec2> = p
        .iter()
        .map(|q| Vec2::new(q.x * 0.25 + 0.5, q.z * 0.25 + 0.5))
        .collect();
    let cd: Vec<Vec3> = p
        .iter()
        .map(|q| (*q * 0.3 + Vec3::splat(0.5)).clamp(Vec3::ZERO, Vec3::ONE))
        .collect();
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
    )
    .unwrap();
    g.set_attrib(
        AttribClass::Point,
        "uv",
        Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
    )
    .unwrap();
    g.set_attrib(
        AttribClass::Point,
        "Cd",
        Attribute::from_data(AttribData::Vec3(cd), TypeInfo::Color),
    )
    .unwrap();
    let w: Vec<f32> = (0..g.num_prims()).map(|i| i as f32 * 0.5).collect();
    g.set_attrib(
        AttribClass::Primitive,
        "weight",
        Attribute::from_data(AttribData::Float(w), TypeInfo::None),
    )
    .unwrap();
    let half = Group::from_members(g.num_prims(), 0..g.num_prims() / 2);
    g.set_prim_group("half", half).unwrap();
    g
}

/// A cube with per-corner (vertex) uvs and normals.
pub fn vertex_attributed_cube() -> Geometry {
    let mut g = primitives::cube(2.0);
    let vn = geode_geo::ops::vertex_normals(&g, 30.0);
    let uv: Vec<Vec2> = (0..g.num_vertices())
        .map(|v| Vec2::new((v % 4) as f32 / 4.0, (v / 4) as f32 / 6.0))
        .collect();
    g.set_attrib(
        AttribClass::Vertex,
        "N",
        Attribute::from_data(AttribData::Vec3(vn), TypeInfo::Normal),
    )
    .unwrap();
    g.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
    )
    .unwrap();
    g
}

/// A grid of packed instances of a sphere, plus a loose polyline.
pub fn instanced_scene(n: usize) -> Geometry {
    let src = Arc::new(primitives::uv_sphere(0.2, 12, 6));
    let positions: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new((i % 10) as f32, 0.0, (i / 10) as f32))
        .collect();
    let transforms: Vec<Mat4> = (0..n)
        .map(|i| {
            Mat4::from_scale_rotation_translation(
                Vec3::splat(1.0 + i as f32 * 0.01),
                Quat::from_rotation_y(i as f32 * 0.3),
                Vec3::ZERO,
            )
        })
        .collect();
    let mut g = Geometry::new();
    g.add_packed_many(&src, &positions, &transforms).unwrap();
    let a = g.add_point(Vec3::new(0.0, 2.0, 0.0));
    let b = g.add_point(Vec3::new(5.0, 2.0, 0.0));
    let c = g.add_point(Vec3::new(5.0, 2.0, 5.0));
    g.add_polyline(&[a, b, c]).unwrap();
    g
}

/// Instances of two sources, rotated and scaled (one of them mirrored), and
/// one sheared: what `EXT_mesh_gpu_instancing` holds and what it cannot.
pub fn mixed_instances() -> Geometry {
    let ball = Arc::new(primitives::uv_sphere(0.2, 12, 6));
    let cube = Arc::new(primitives::cube(0.3));
    let mut g = Geometry::new();
    for i in 0..30 {
        let source = if i % 3 == 0 { &cube } else { &ball };
        let scale = if i == 7 {
            Vec3::new(-1.0, 1.0, 2.0)
        } else {
            Vec3::splat(1.0 + i as f32 * 0.05)
        };
        let local = Mat4::from_scale_rotation_translation(
            scale,
            Quat::from_euler(
                geode_geo::glam::EulerRot::XYZ,
                0.1 * i as f32,
                0.7,
                -0.2 * i as f32,
            ),
            Vec3::ZERO,
        );
        let p = g.add_point(Vec3::new(i as f32, (i % 4) as f32, 0.5 * i as f32));
        g.add_packed(p, Arc::clone(source), local).unwrap();
    }
    let mut shear = Mat4::IDENTITY;
    shear.y_axis.x = 0.75;
    let p = g.add_point(Vec3::new(-3.0, 0.0, 0.0));
    g.add_packed(p, Arc::clone(&ball), shear).unwrap();
    g
}

/// True unless the run was told to skip the external validators
/// (GEODE_SKIP_ORACLES=1): a missing validator then fails the test.
pub fn validators_required() -> bool {
    std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1")
}

/// Runs a validator command; None when its tool is not installed (and not required).
pub fn run_validator(mut cmd: Command, what: &str) -> Option<String> {
    match cmd.output() {
        Ok(out) => {
            let text = String::from_utf8_lossy(&out.stdout).into_owned()
                + &String::from_utf8_lossy(&out.stderr);
            if !out.status.success()
                && (text.contains("Cannot find") || text.contains("ModuleNotFoundError"))
            {
                assert!(!validators_required(), "{what} is not installed:\n{text}");
                eprintln!("skipping: {what} not installed");
                return None;
            }
            assert!(out.status.success(), "{what} rejected the files:\n{text}");
            Some(text)
        }
        Err(e) => {
            assert!(!validators_required(), "{what} could not run: {e}");
            eprintln!("skipping: {what} could not run: {e}");
            None
        }
    }
}

/// Two polylines with what `polyframe` and a user add: point `orient`, `T`,
/// `B`, `N`, `pscale`, a vertex `Cd`, a primitive `id`, a detail `name` and a
/// point int array `tags` (which no format but Houdini's carries).
pub fn framed_curves() -> Geometry {
    let mut g = Geometry::new();
    let pts: Vec<Vec3> = (0..7)
        .map(|i| Vec3::new(i as f32, (i as f32 * 0.7).sin(), 0.0))
        .collect();
    g.add_points(&pts);
    g.add_polyline(&[0, 1, 2, 3]).unwrap();
    g.add_polyline(&[3, 4, 5, 6]).unwrap();
    let n = g.num_points();
    let set = |g: &mut Geometry, class, name: &str, data, info| {
        g.set_attrib(class, name, Attribute::from_data(data, info))
            .unwrap();
    };
    let orient = (0..n)
        .map(|i| Quat::from_rotation_z(i as f32 * 0.1))
        .collect();
    set(
        &mut g,
        AttribClass::Point,
        "orient",
        AttribData::Quat(orient),
        TypeInfo::Quaternion,
    );
    let t = (0..n)
        .map(|i| Vec3::new(1.0, i as f32 * 0.01, 0.0))
        .collect();
    set(
        &mut g,
        AttribClass::Point,
        "T",
        AttribData::Vec3(t),
        TypeInfo::Vector,
    );
    set(
        &mut g,
        AttribClass::Point,
        "B",
        AttribData::Vec3(vec![Vec3::Z; n]),
        TypeInfo::Vector,
    );
    set(
        &mut g,
        AttribClass::Point,
        "N",
        AttribData::Vec3(vec![Vec3::Y; n]),
        TypeInfo::Normal,
    );
    let pscale = (0..n).map(|i| 0.5 + i as f32 * 0.25).collect();
    set(
        &mut g,
        AttribClass::Point,
        "pscale",
        AttribData::Float(pscale),
        TypeInfo::None,
    );
    let cd = (0..g.num_vertices())
        .map(|v| Vec3::new(v as f32 / 8.0, 0.5, 1.0))
        .collect();
    set(
        &mut g,
        AttribClass::Vertex,
        "Cd",
        AttribData::Vec3(cd),
        TypeInfo::Color,
    );
    set(
        &mut g,
        AttribClass::Primitive,
        "id",
        AttribData::Int(vec![7, 9]),
        TypeInfo::None,
    );
    let name = geode_geo::StringColumn {
        table: vec!["chain".into()],
        indices: vec![0],
    };
    set(
        &mut g,
        AttribClass::Detail,
        "name",
        AttribData::String(name),
        TypeInfo::None,
    );
    let tags = (0..n).map(|i| vec![i as i32; i % 3]).collect();
    set(
        &mut g,
        AttribClass::Point,
        "tags",
        AttribData::IntArray(tags),
        TypeInfo::None,
    );
    g
}

/// A progress sink that keeps the warnings a writer gives.
#[derive(Default)]
pub struct Warnings(pub std::sync::Mutex<Vec<String>>);

impl geode_io::Progress for Warnings {
    fn warn(&self, message: &str) {
        self.0.lock().unwrap().push(message.to_owned());
    }
}

/// The attributed torus with more point attributes: a quaternion `orient`,
/// a float `pscale`, an int `id`, a 3x3 `xform`, a vector `T`.
pub fn instancing_torus() -> Geometry {
    let mut g = attributed_torus();
    let n = g.num_points();
    let set = |g: &mut Geometry, name: &str, data, info| {
        g.set_attrib(AttribClass::Point, name, Attribute::from_data(data, info))
            .unwrap();
    };
    let orient = (0..n)
        .map(|i| Quat::from_rotation_y(i as f32 * 0.05))
        .collect();
    set(
        &mut g,
        "orient",
        AttribData::Quat(orient),
        TypeInfo::Quaternion,
    );
    set(
        &mut g,
        "pscale",
        AttribData::Float((0..n).map(|i| 1.0 + i as f32 * 0.01).collect()),
        TypeInfo::None,
    );
    set(
        &mut g,
        "id",
        AttribData::Int((0..n as i32).map(|i| i * 3 - 100).collect()),
        TypeInfo::None,
    );
    let xform = (0..n)
        .map(|i| geode_geo::glam::Mat3::from_rotation_x(i as f32 * 0.1))
        .collect();
    set(
        &mut g,
        "xform",
        AttribData::Mat3(xform),
        TypeInfo::Transform,
    );
    let t = (0..n)
        .map(|i| Vec3::new(0.0, 1.0, i as f32 * 0.1))
        .collect();
    set(&mut g, "T", AttribData::Vec3(t), TypeInfo::Vector);
    g
}
