//! The binary geometry codec: every geometry comes back with the same content, damaged bytes are errors, never panics.

use std::collections::HashMap;
use std::sync::Arc;

use geode_geo::codec::{decode, encode, DecodeError, EncodeError};
use geode_geo::glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};
use geode_geo::{
    primitives, AttribClass, AttribData, AttribValue, Attribute, Geometry, Group, KnotVector,
    PatchBasis, Payload, StringColumn, TypeInfo,
};
use proptest::prelude::*;

/// Every attribute type on every class, groups, a patch and packed instances of two sources.
fn rich(seed: u64) -> Geometry {
    let mut g = primitives::torus(1.0, 0.3, 6 + (seed % 5) as u32, 4);
    let ball = Arc::new(primitives::uv_sphere(0.2, 6, 4));
    let cube = Arc::new(primitives::cube(0.5));
    for i in 0..3 {
        let p = g.add_point(Vec3::new(i as f32, 2.0, seed as f32 * 0.001));
        let src = if i % 2 == 0 { &ball } else { &cube };
        g.add_packed(p, Arc::clone(src), Mat4::from_rotation_z(i as f32))
            .unwrap();
    }
    let grid: Vec<u32> = (0..4)
        .map(|_| g.add_point(Vec3::splat(seed as f32)))
        .collect();
    let knots = || KnotVector {
        order: 2,
        knots: vec![0.0, 0.0, 1.0, 1.0],
    };
    g.add_patch(
        &grid,
        PatchBasis {
            u: knots(),
            v: knots(),
        },
    )
    .unwrap();
    let f = |i: usize| (i as f32 + seed as f32) * 0.37;
    let columns = |n: usize| -> Vec<(&'static str, AttribData, TypeInfo)> {
        vec![
            (
                "f",
                AttribData::Float((0..n).map(f).collect()),
                TypeInfo::None,
            ),
            (
                "i",
                AttribData::Int((0..n).map(|i| i as i32 - 5).collect()),
                TypeInfo::None,
            ),
            (
                "uv",
                AttribData::Vec2((0..n).map(|i| Vec2::splat(f(i))).collect()),
                TypeInfo::TexCoord,
            ),
            (
                "N",
                AttribData::Vec3((0..n).map(|i| Vec3::splat(f(i))).collect()),
                TypeInfo::Normal,
            ),
            (
                "c4",
                AttribData::Vec4((0..n).map(|i| Vec4::splat(f(i))).collect()),
                TypeInfo::Color,
            ),
            (
                "q",
                AttribData::Quat((0..n).map(|i| Quat::from_rotation_x(f(i))).collect()),
                TypeInfo::Quaternion,
            ),
            (
                "m3",
                AttribData::Mat3((0..n).map(|i| Mat3::from_rotation_y(f(i))).collect()),
                TypeInfo::Transform,
            ),
            (
                "m4",
                AttribData::Mat4((0..n).map(|i| Mat4::from_rotation_y(f(i))).collect()),
                TypeInfo::None,
            ),
            (
                "s",
                AttribData::String(StringColumn {
                    table: vec!["a".into(), "béta".into()],
                    indices: (0..n).map(|i| (i % 2) as u32).collect(),
                }),
                TypeInfo::None,
            ),
            (
                "ia",
                AttribData::IntArray((0..n).map(|i| vec![i as i32; i % 3]).collect()),
                TypeInfo::None,
            ),
            (
                "fa",
                AttribData::FloatArray((0..n).map(|i| vec![f(i); i % 2]).collect()),
                TypeInfo::None,
            ),
            (
                "va",
                AttribData::Vec3Array((0..n).map(|i| vec![Vec3::X * f(i); i % 2]).collect()),
                TypeInfo::None,
            ),
            (
                "sa",
                AttribData::StringArray((0..n).map(|i| vec!["x".into(); i % 3]).collect()),
                TypeInfo::None,
            ),
        ]
    };
    for (class, n) in [
        (AttribClass::Point, g.num_points()),
        (AttribClass::Vertex, g.num_vertices()),
        (AttribClass::Primitive, g.num_prims()),
        (AttribClass::Detail, 1),
    ] {
        for (name, data, info) in columns(n) {
            g.set_attrib(class, name, Attribute::from_data(data, info))
                .unwrap();
        }
    }
    let f0 = g.attrib(AttribClass::Point, "f").unwrap().clone();
    g.set_attrib(
        AttribClass::Point,
        "f",
        f0.with_default(AttribValue::Float(seed as f32)).unwrap(),
    )
    .unwrap();
    g.set_point_group(
        "odd",
        Group::from_members(g.num_points(), (1..g.num_points()).step_by(2)),
    )
    .unwrap();
    g.set_prim_group("first", Group::from_members(g.num_prims(), [0]))
        .unwrap();
    g
}

fn round_trip(g: &Geometry) -> Result<Geometry, DecodeError> {
    let mut sources: HashMap<u128, Arc<Geometry>> = HashMap::new();
    let mut bytes = Vec::new();
    encode(g, &mut bytes, &mut |s| {
        sources.insert(s.content_hash(), Arc::clone(s));
    })
    .unwrap();
    decode(&bytes, &|h| sources.get(&h).cloned())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn every_geometry_comes_back_with_its_content(seed in 0u64..10_000) {
        let g = rich(seed);
        let back = round_trip(&g).unwrap();
        prop_assert_eq!(back.content_hash(), g.content_hash());
        for class in AttribClass::ALL {
            prop_assert_eq!(back.attribs(class), g.attribs(class));
        }
        prop_assert_eq!(back.point_groups(), g.point_groups());
        prop_assert_eq!(back.prim_kinds(), g.prim_kinds());
    }
}

#[test]
fn damaged_bytes_are_errors_never_panics() {
    let g = rich(7);
    let mut sources: HashMap<u128, Arc<Geometry>> = HashMap::new();
    let mut bytes = Vec::new();
    encode(&g, &mut bytes, &mut |s| {
        sources.insert(s.content_hash(), Arc::clone(s));
    })
    .unwrap();
    let find = |h: u128| sources.get(&h).cloned();
    for at in (0..bytes.len()).step_by(bytes.len() / 500 + 1) {
        assert!(
            decode(&bytes[..at], &find).is_err(),
            "a prefix of {at} bytes decoded"
        );
        for damage in [0xffu8, 0x80, 0x01] {
            let mut b = bytes.clone();
            b[at] ^= damage;
            let _ = decode(&b, &find);
        }
    }
    assert_eq!(decode(b"GEOX", &find).unwrap_err(), DecodeError::Magic);
    assert_eq!(
        decode(&bytes, &|_| None).unwrap_err(),
        DecodeError::MissingSource(g.packed_instances()[0].source.content_hash())
    );
}

#[test]
fn a_payload_has_no_byte_form() {
    let mut g = primitives::cube(1.0);
    g.set_payload("hierarchy", Payload::new(5u32, 1, 4));
    let e = encode(&g, &mut Vec::new(), &mut |_| {}).unwrap_err();
    assert_eq!(e, EncodeError::Payload("hierarchy".into()));
}

/// A table without attributes has elements but no bytes (a plain torus's vertex table).
#[test]
fn tables_without_attributes_need_no_bytes() {
    for segs in [12u32, 25, 400] {
        let g = primitives::torus(1.0, 0.2, segs, 8);
        assert_eq!(
            round_trip(&g).unwrap().content_hash(),
            g.content_hash(),
            "{segs}"
        );
    }
}
