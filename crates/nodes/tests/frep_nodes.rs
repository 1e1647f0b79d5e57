//! FRep nodes through the engine: primitives, CSG, blends, offsets, morphs,
//! transforms, deformations, expressions, polygonise and sample, and the
//! seed's limitations fixed (wrong wire types, bypass, animated alpha).

mod common;

use common::{cook_at as cook, geo as mesh, net};
use geode_geo::{ops, AttribClass, Geometry};
use geode_graph::load_str;

fn poly(input: &str, depth: u32, half: f64) -> String {
    format!(
        r#""mesh": {{"type": "polygonise", "inputs": ["{input}"], "params": {{"min": [-{half}, -{half}, -{half}], "max": [{half}, {half}, {half}], "depth": {depth}}}}}"#
    )
}

fn volume(g: &Geometry) -> f64 {
    assert!(g.topology().manifold_report(g).is_closed_manifold());
    ops::signed_volume(g) as f64
}

#[test]
fn primitives_mesh_to_their_volumes() {
    let pi = std::f64::consts::PI;
    for (node, v) in [
        (
            r#""s": {"type": "frep_sphere", "params": {"radius": 0.9}}"#,
            4.0 / 3.0 * pi * 0.729,
        ),
        (
            r#""s": {"type": "frep_box", "params": {"size": [1.2, 0.8, 1.0]}}"#,
            0.96,
        ),
        (
            r#""s": {"type": "frep_torus", "params": {"major_radius": 0.8, "minor_radius": 0.2}}"#,
            2.0 * pi * pi * 0.8 * 0.04,
        ),
        (
            r#""s": {"type": "frep_cylinder", "params": {"radius": 0.5, "height": 1.2}}"#,
            pi * 0.25 * 1.2,
        ),
        (
            r#""s": {"type": "frep_cone", "params": {"apex": [0, 0.6, 0], "radius": 0.6, "height": 1.2}}"#,
            pi * 0.36 * 1.2 / 3.0,
        ),
    ] {
        let g = mesh(&format!("{node}, {}", poly("s", 6, 1.0)), "mesh");
        let got = volume(&g);
        assert!((got - v).abs() / v < 0.01, "{node}: {got} vs {v}");
    }
}

#[test]
fn csg_blend_offset_and_morph() {
    let two = r#""a": {"type": "frep_sphere", "params": {"radius": 0.5, "center": [-0.3, 0, 0]}},
                 "b": {"type": "frep_sphere", "params": {"radius": 0.5, "center": [0.3, 0, 0]}},"#;
    let v = |op: &str, extra: &str| {
        volume(&mesh(
            &format!(
                r#"{two} "c": {{"type": "{op}", "inputs": ["a", "b"], "params": {{{extra}}}}}, {}"#,
                poly("c", 6, 1.0)
            ),
            "mesh",
        ))
    };
    let union = v("frep_csg", r#""operation": "union""#);
    let inter = v("frep_csg", r#""operation": "intersection""#);
    let sub = v("frep_csg", r#""operation": "subtraction""#);
    let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    assert!(
        (union + inter - 2.0 * ball).abs() < 0.01,
        "inclusion-exclusion"
    );
    assert!((sub - (ball - inter)).abs() < 0.01);
    let blended = v(
        "frep_blend",
        r#""operation": "union", "a0": 0.5, "a1": 0.5, "a2": 0.5"#,
    );
    assert!(
        blended > union + 0.01,
        "the blend adds material: {blended} vs {union}"
    );
    // Offset: exact for distance fields.
    for d in [-0.2, 0.0, 0.2] {
        let g = mesh(
            &format!(
                r#""s": {{"type": "frep_sphere", "params": {{"radius": 0.5}}}}, "o": {{"type": "frep_offset", "inputs": ["s"], "params": {{"distance": {d}}}}}, {}"#,
                poly("o", 6, 1.0)
            ),
            "mesh",
        );
        let want = 4.0 / 3.0 * std::f64::consts::PI * (0.5f64 + d).powi(3);
        assert!((volume(&g) - want).abs() / want < 0.01, "offset {d}");
    }
    // Morph with animated alpha: the volume moves from the box's to the sphere's.
    let morph = format!(
        r#""a": {{"type": "frep_box", "params": {{"size": [1, 1, 1]}}}}, "b": {{"type": "frep_sphere", "params": {{"radius": 0.3}}}},
           "m": {{"type": "frep_morph", "inputs": ["a", "b"], "params": {{"alpha": {{"keys": [{{"frame": 1, "value": 0}}, {{"frame": 11, "value": 1}}]}}}}}}, {}"#,
        poly("m", 5, 1.0)
    );
    let at = |f: f64| volume(cook(&morph, "mesh", f).unwrap().as_geometry().unwrap());
    let (v1, v6, v11) = (at(1.0), at(6.0), at(11.0));
    assert!(
        (v1 - 1.0).abs() < 0.01 && v1 > v6 && v6 > v11 && (v11 - 0.113).abs() < 0.01,
        "{v1} {v6} {v11}"
    );
}

#[test]
fn transforms_and_deformations() {
    let g = mesh(
        &format!(
            r#""s": {{"type": "frep_sphere", "params": {{"radius": 0.3}}}}, "t": {{"type": "frep_transform", "inputs": ["s"], "params": {{"translate": [0.4, 0, 0], "scale": [1, 2, 1]}}}}, {}"#,
            poly("t", 6, 1.0)
        ),
        "mesh",
    );
    let b = ops::bounds(&g).unwrap();
    assert!(
        (b.center().x - 0.4).abs() < 0.01
            && (b.size().y - 1.2).abs() < 0.03
            && (b.size().x - 0.6).abs() < 0.03,
        "{b:?}"
    );
    for mode in ["taper", "twist", "bend"] {
        let g = mesh(
            &format!(
                r#""s": {{"type": "frep_box", "params": {{"size": [0.6, 1.2, 0.3]}}}}, "d": {{"type": "frep_deform", "inputs": ["s"], "params": {{"mode": "{mode}"}}}}, {}"#,
                poly("d", 6, 1.0)
            ),
            "mesh",
        );
        assert!(volume(&g) > 0.05, "{mode}");
    }
}

#[test]
fn expression_and_sample() {
    let g = mesh(
        &format!(
            r#""e": {{"type": "frep_expression", "params": {{"expression": "a - (x^2 + y^2 + z^2)", "a": 0.25}}}}, {}"#,
            poly("e", 6, 1.0)
        ),
        "mesh",
    );
    let want = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    assert!((volume(&g) - want).abs() / want < 0.01);
    let sampled = mesh(
        r#""p": {"type": "grid", "params": {"size": [2, 2], "rows": 4, "columns": 4}}, "s": {"type": "frep_sphere", "params": {"radius": 0.5}}, "d": {"type": "frep_sample", "inputs": ["p", "s"]}"#,
        "d",
    );
    let d = sampled
        .attrib(AttribClass::Point, "density")
        .unwrap()
        .as_f32()
        .unwrap();
    let centre = sampled
        .positions()
        .iter()
        .position(|p| p.length() < 1e-6)
        .unwrap();
    assert!((d[centre] - 0.5).abs() < 1e-6);
    assert_eq!(
        d.iter().filter(|v| **v > 1e-6).count(),
        1,
        "only the centre is strictly inside"
    );
    assert_eq!(
        d.iter().filter(|v| v.abs() < 1e-6).count(),
        4,
        "four grid points lie on the sphere"
    );
    let bad = cook(
        r#""e": {"type": "frep_expression", "params": {"expression": "x +"}}"#,
        "e",
        1.0,
    )
    .unwrap_err();
    assert_eq!(
        bad,
        "/e (parameter `expression`): column 4: expected a value, found the end"
    );
}

#[test]
fn the_seeds_limitations_are_fixed() {
    // A mesh where a field is expected is a load error naming both nodes.
    let e = load_str(
        &net(
            r#""b": {"type": "box"}, "m": {"type": "polygonise", "inputs": ["b"]}"#,
            "m",
        ),
        &geode_nodes::registry(),
    )
    .err()
    .unwrap();
    assert_eq!(
        e[0].to_string(),
        "/m: input 1 (field) expects field but /b gives geometry"
    );
    // Node identity is the type, never the name: any name works.
    let g = mesh(
        &format!(
            r#""anything_at_all": {{"type": "frep_sphere", "params": {{"radius": 0.5}}}}, {}"#,
            poly("anything_at_all", 4, 1.0)
        ),
        "mesh",
    );
    assert!(g.num_prims() > 0);
    // A bypassed FRep node passes its input field through.
    let nodes = r#""s": {"type": "frep_sphere"}, "o": {"type": "frep_offset", "inputs": ["s"], "params": {"distance": 3}, "bypass": true}"#;
    let (s, o) = (
        cook(nodes, "s", 1.0).unwrap(),
        cook(nodes, "o", 1.0).unwrap(),
    );
    assert_eq!(s.identity(), o.identity());
    // A field cannot be written to a file directly.
    let v = cook(r#""s": {"type": "frep_sphere"}"#, "s", 1.0).unwrap();
    assert!(v.as_field().is_some());
}

#[test]
fn bounded_blend_sweep_instance_and_point_deform() {
    let pi = std::f64::consts::PI;
    // Bounded blend of three spheres: the blend lives only inside the bound.
    let three = r#""a": {"type": "frep_sphere", "params": {"radius": 0.4, "center": [-0.45, 0, 0]}},
                   "b": {"type": "frep_sphere", "params": {"radius": 0.4, "center": [0.45, 0, 0]}},
                   "bound": {"type": "frep_sphere", "params": {"radius": 0.3, "center": [0, 0.3, 0]}},"#;
    let v = |node: &str| {
        volume(&mesh(
            &format!("{three} {node}, {}", poly("c", 6, 1.0)),
            "mesh",
        ))
    };
    let plain = v(r#""c": {"type": "frep_csg", "inputs": ["a", "b"], "params": {"alpha": 0}}"#);
    let global = v(
        r#""c": {"type": "frep_blend", "inputs": ["a", "b"], "params": {"a0": 0.3, "a1": 0.3, "a2": 0.3}}"#,
    );
    let bounded = v(
        r#""c": {"type": "frep_bounded_blend", "inputs": ["a", "b", "bound"], "params": {"a0": 0.3, "a1": 0.3, "a2": 0.3, "a3": 0.3}}"#,
    );
    assert!(
        plain < bounded && bounded < global,
        "{plain} < {bounded} < {global}"
    );

    // A sphere swept along a straight line is a capsule.
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("line.obj");
    std::fs::write(&obj, "v -0.5 0 0\nv 0 0 0\nv 0.5 0 0\nl 1 2 3\n").unwrap();
    let g = mesh(
        &format!(
            r#""l": {{"type": "file", "params": {{"file": "{}"}}}}, "s": {{"type": "frep_sweep", "inputs": ["l"], "params": {{"radius": 0.2}}}}, {}"#,
            obj.display(),
            poly("s", 6, 1.0)
        ),
        "mesh",
    );
    let capsule = pi * 0.04 * 1.0 + 4.0 / 3.0 * pi * 0.008;
    assert!(
        (volume(&g) - capsule).abs() / capsule < 0.01,
        "{} vs {capsule}",
        volume(&g)
    );

    // Instancing a ball on the four corners of a grid: four balls.
    let g = mesh(
        &format!(
            r#""pts": {{"type": "grid", "params": {{"size": [1, 1], "rows": 1, "columns": 1}}}}, "ball": {{"type": "frep_sphere", "params": {{"radius": 0.2}}}}, "i": {{"type": "frep_instance", "inputs": ["ball", "pts"]}}, {}"#,
            poly("i", 6, 1.0)
        ),
        "mesh",
    );
    let four = 4.0 * 4.0 / 3.0 * pi * 0.008;
    assert!((volume(&g) - four).abs() / four < 0.01);

    // Deform point pushes a bump out of a ball: more volume, still closed.
    let ball = r#""s": {"type": "frep_sphere", "params": {"radius": 0.5}},"#;
    let bumped = volume(&mesh(
        &format!(
            r#"{ball} "d": {{"type": "frep_deform", "inputs": ["s"], "params": {{"mode": "point", "point": [0, 0.5, 0], "offset": [0, 0.3, 0], "falloff": 0.4}}}}, {}"#,
            poly("d", 6, 1.0)
        ),
        "mesh",
    ));
    assert!(bumped > 4.0 / 3.0 * pi * 0.125 + 0.005);
}

#[test]
fn mesh_primitives_feed_frep_networks_as_exact_solids() {
    let pi = std::f64::consts::PI;
    // A sphere moved off-centre, a box rotated 45 degrees about a pivot and
    // a tube: merged meshes become the union of their exact solids.
    let nodes = format!(
        r#""ball": {{"type": "sphere", "params": {{"radius": 0.4, "rows": 4, "columns": 5, "analytic": true}}}},
        "moved": {{"type": "transform", "inputs": ["ball"], "params": {{"translate": [0.5, 0.2, 0]}}}},
        "brick": {{"type": "box", "params": {{"size": [0.5, 0.3, 0.4], "analytic": true}}}},
        "turned": {{"type": "transform", "inputs": ["brick"], "params": {{"rotate": [0, 0, 45], "pivot": [0.1, 0, 0], "translate": [-0.5, 0, 0]}}}},
        "pipe": {{"type": "tube", "params": {{"radius": 0.15, "height": 0.6, "center": [0, -0.8, 0.5], "analytic": true}}}},
        "all": {{"type": "merge", "inputs": ["moved", "turned", "pipe"]}},
        "solid": {{"type": "frep_from_primitives", "inputs": ["all"]}},
        {}"#,
        poly("solid", 7, 1.2)
    );
    let g = mesh(&nodes, "mesh");
    let v = 4.0 / 3.0 * pi * 0.064 + 0.5 * 0.3 * 0.4 + pi * 0.0225 * 0.6;
    let got = volume(&g);
    assert!((got - v).abs() / v < 0.01, "{got} vs {v}");
    // The sphere's exact centre (not its five-sided mesh's) is where it was moved.
    let b = ops::bounds(&g).unwrap();
    assert!((b.max.x - 0.9).abs() < 0.01, "{b:?}");
    assert!(
        (b.min.y - -0.8).abs() < 0.01,
        "tube starts at its centre: {b:?}"
    );
    // A polygon with no exact solid is named.
    let e = common::err(
        r#""g": {"type": "grid"}, "s": {"type": "frep_from_primitives", "inputs": ["g"]}"#,
        "s",
    );
    assert!(
        e.contains("/s") && e.contains("primitive 0 has no analytic shape"),
        "{e}"
    );
}

#[test]
fn a_tolerance_gives_adaptive_output_of_the_same_solid() {
    let nodes = r#""a": {"type": "frep_box", "params": {"size": [1.2, 0.8, 1.0]}},
        "b": {"type": "frep_sphere", "params": {"radius": 0.5, "center": [0.6, 0.4, 0.5]}},
        "s": {"type": "frep_csg", "inputs": ["a", "b"]},"#;
    let uniform = mesh(&format!("{nodes} {}", poly("s", 7, 1.0)), "mesh");
    let adaptive_node =
        poly("s", 7, 1.0).replace(r#""depth": 7"#, r#""depth": 7, "tolerance": 0.002"#);
    let adaptive = mesh(&format!("{nodes} {adaptive_node}"), "mesh");
    let (u, a) = (volume(&uniform), volume(&adaptive));
    assert!((u - a).abs() / u < 0.002, "uniform {u}, adaptive {a}");
    assert!(
        adaptive.num_prims() * 10 < uniform.num_prims(),
        "{} of {}",
        adaptive.num_prims(),
        uniform.num_prims()
    );
    // Normals stay the gradient's: one per kept point.
    let n = adaptive.attrib(AttribClass::Point, "N").expect("N");
    assert_eq!(n.len(), adaptive.num_points());
}
