//! Sweeps are closed, outward-facing manifolds with the analytic volume;
//! copy to points places copies by the instance attributes, packed or not,
//! carries template attributes and picks pieces by variant.

use geode_curve::frames::{frames, FrameMethod};
use geode_curve::shapes::{helix, line, torus_knot};
use geode_curve::sweep::Tube;
use geode_curve::{copy_to_points, sweep, CopyOptions, SweepOptions};
use geode_geo::glam::{DVec3, Quat, Vec3};
use geode_geo::{ops, primitives, AttribClass, AttribData, Attribute, Geometry, TypeInfo};

fn mesh(t: Tube) -> Geometry {
    Geometry::from_polygons(t.positions, t.faces, &t.counts).unwrap()
}

fn closed(g: &Geometry) {
    let r = g.topology().manifold_report(g);
    assert!(r.is_closed_manifold(), "{r:?}");
}

#[test]
fn capped_sweeps_are_closed_outward_and_have_the_right_volume() {
    let sides = 64;
    let ngon = 0.5 * sides as f64 * (std::f64::consts::TAU / sides as f64).sin();
    // A straight tube: exactly the n-gon's area times the length.
    let s = line(DVec3::ZERO, DVec3::new(0.0, 0.0, 3.0), 10);
    let f = frames(
        &s.points,
        &s.tangents,
        false,
        FrameMethod::DoubleReflection,
        None,
    );
    let g = mesh(
        sweep(
            &s.points,
            &f,
            &[0.5; 10],
            false,
            &SweepOptions::circle(sides, true),
            &|| false,
        )
        .unwrap(),
    );
    closed(&g);
    let v = ops::signed_volume(&g) as f64;
    assert!((v - ngon * 0.25 * 3.0).abs() < 1e-4, "{v}");
    // Along a helix, by Pappus the same area times the length of the axis.
    let h = helix(1.0, 0.5, 2.0, 400);
    let f = frames(
        &h.points,
        &h.tangents,
        false,
        FrameMethod::DoubleReflection,
        None,
    );
    let g = mesh(
        sweep(
            &h.points,
            &f,
            &[0.1; 400],
            false,
            &SweepOptions::circle(sides, true),
            &|| false,
        )
        .unwrap(),
    );
    closed(&g);
    let length = 2.0 * ((std::f64::consts::TAU).powi(2) + 0.25).sqrt();
    let v = ops::signed_volume(&g) as f64;
    let want = ngon * 0.01 * length;
    assert!((v - want).abs() / want < 0.01, "{v} vs {want}");
    // A closed knot needs no caps and still closes (its frame closes).
    let k = torus_knot(2, 3, 1.0, 0.4, 300);
    let f = frames(
        &k.points,
        &k.tangents,
        true,
        FrameMethod::DoubleReflection,
        None,
    );
    let t = sweep(
        &k.points,
        &f,
        &[0.08; 300],
        true,
        &SweepOptions::circle(12, false),
        &|| false,
    )
    .unwrap();
    assert_eq!(t.uvs.len(), t.faces.len(), "a uv per vertex");
    let g = mesh(t);
    closed(&g);
    assert!(ops::signed_volume(&g) > 0.0);
}

fn template() -> Geometry {
    let mut t = Geometry::new();
    t.add_points(&[
        Vec3::ZERO,
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(0.0, 5.0, 0.0),
    ]);
    let set = |t: &mut Geometry, name: &str, data: AttribData, info: TypeInfo| {
        t.set_attrib(AttribClass::Point, name, Attribute::from_data(data, info))
            .unwrap();
    };
    set(
        &mut t,
        "pscale",
        AttribData::Float(vec![1.0, 2.0, 1.0]),
        TypeInfo::None,
    );
    set(
        &mut t,
        "orient",
        AttribData::Quat(vec![
            Quat::IDENTITY,
            Quat::IDENTITY,
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
        ]),
        TypeInfo::Quaternion,
    );
    set(
        &mut t,
        "Cd",
        AttribData::Vec3(vec![Vec3::X, Vec3::Y, Vec3::Z]),
        TypeInfo::Color,
    );
    set(
        &mut t,
        "variant",
        AttribData::Int(vec![0, 1, 3]),
        TypeInfo::None,
    );
    t
}

#[test]
fn copies_are_placed_alike_packed_or_not_and_carry_template_attributes() {
    let source = primitives::cube(1.0);
    let mut opts = CopyOptions {
        packed: false,
        piece_attrib: String::new(),
        variant_attrib: String::new(),
    };
    let real = copy_to_points(&source, &template(), &opts, &|| false).unwrap();
    assert_eq!(real.num_points(), 3 * source.num_points());
    // Copy 1 is doubled and moved to (5, 0, 0); copy 2 is turned 90 degrees
    // about Z: the source corner (0.5, 0.5, 0.5) goes to (-0.5, 0.5, 0.5).
    let n = source.num_points();
    let corner = source
        .positions()
        .iter()
        .position(|p| *p == Vec3::splat(0.5))
        .unwrap();
    assert_eq!(real.positions()[n + corner], Vec3::new(6.0, 1.0, 1.0));
    assert!((real.positions()[2 * n + corner] - Vec3::new(-0.5, 5.5, 0.5)).length() < 1e-6);
    let cd = real
        .attrib(AttribClass::Point, "Cd")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert_eq!((cd[0], cd[n], cd[2 * n]), (Vec3::X, Vec3::Y, Vec3::Z));
    for gone in ["pscale", "orient"] {
        assert!(
            real.attrib(AttribClass::Point, gone).is_none(),
            "{gone} places copies, it is not carried"
        );
    }
    // Packed: one point and one shared source per copy, same world geometry.
    opts.packed = true;
    let packed = copy_to_points(&source, &template(), &opts, &|| false).unwrap();
    assert_eq!((packed.num_points(), packed.num_prims()), (3, 3));
    let unpacked = ops::unpack(&packed).unwrap();
    for (a, b) in unpacked.positions().iter().zip(real.positions()) {
        assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
    }
    let cd = packed
        .attrib(AttribClass::Point, "Cd")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert_eq!(cd, &[Vec3::X, Vec3::Y, Vec3::Z]);
}

#[test]
fn the_variant_attribute_picks_a_piece_per_point() {
    let mut a = primitives::cube(1.0);
    let b = primitives::uv_sphere(0.5, 6, 4);
    let name = |g: &mut Geometry, v: i32| {
        let n = g.num_prims();
        g.set_attrib(
            AttribClass::Primitive,
            "piece",
            Attribute::from_data(AttribData::Int(vec![v; n]), TypeInfo::None),
        )
        .unwrap();
    };
    name(&mut a, 7);
    let mut b = b;
    name(&mut b, 3);
    let source = ops::merge(&[&a, &b]).unwrap();
    let opts = CopyOptions {
        packed: true,
        piece_attrib: "piece".into(),
        variant_attrib: "variant".into(),
    };
    let g = copy_to_points(&source, &template(), &opts, &|| false).unwrap();
    // variant 0 -> cube, 1 -> sphere, 3 -> 3 mod 2 = 1 -> sphere.
    let prims: Vec<usize> = (0..3)
        .map(|i| g.packed_instance(i).unwrap().source.num_prims())
        .collect();
    assert_eq!(prims.iter().filter(|&&p| p == a.num_prims()).count(), 1);
    assert_eq!(prims.iter().filter(|&&p| p == b.num_prims()).count(), 2);
    let bad = CopyOptions {
        piece_attrib: "nope".into(),
        ..opts
    };
    assert!(copy_to_points(&source, &template(), &bad, &|| false)
        .unwrap_err()
        .to_string()
        .contains("`nope`"));
}
