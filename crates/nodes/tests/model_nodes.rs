//! The modelling nodes through the graph: the boolean-built part of
//! `examples/boolean_part.json`, the bevelled extruded panel of
//! `examples/extruded_panel.json` (volumes worked out by hand), the
//! reduced and remeshed scan of `examples/scan_cleanup.json`, and the
//! errors a user meets (an open input, an unknown operation, a missing
//! group or attribute).

use std::sync::Arc;

use geode_geo::Geometry;

fn cook(text: &str, node: &str) -> Result<Arc<Geometry>, geode_op::CookError> {
    let net = geode_graph::load_str(text, &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::new(1 << 29);
    let engine = geode_graph::Engine::new(net, &cache);
    engine
        .cook(node, &geode_graph::CookOptions::at_frame(1.0))
        .map(|r| r.value.as_geometry().unwrap().clone())
        .map_err(|mut errors| errors.remove(0))
}

fn volume(g: &Geometry) -> f64 {
    let p = g.positions();
    let mut v = 0.0;
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 1..q.len() - 1 {
            let (a, b, c) = (
                p[q[0] as usize].as_dvec3(),
                p[q[j] as usize].as_dvec3(),
                p[q[j + 1] as usize].as_dvec3(),
            );
            v += a.dot(b.cross(c)) / 6.0;
        }
    }
    v
}

fn closed(g: &Geometry) -> bool {
    let mut edges = std::collections::HashMap::new();
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 0..q.len() {
            let (a, b) = (q[j], q[(j + 1) % q.len()]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    edges.values().all(|&n| n == 2)
}

#[test]
fn the_boolean_part_is_drilled_and_bossed() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/boolean_part.json"
    ))
    .unwrap();
    let drilled = cook(&text, "/drilled").unwrap();
    // The plate less two 32-sided prisms through its 0.4 thickness.
    let bore = 0.5 * 32.0 * 0.2f64.powi(2) * (2.0 * std::f64::consts::PI / 32.0).sin();
    let want = 2.0 * 0.4 * 1.2 - 2.0 * 0.4 * bore;
    assert!(
        (volume(&drilled) - want).abs() < 1e-5,
        "{} vs {want}",
        volume(&drilled)
    );
    assert!(closed(&drilled));
    for g in ["a_outside_b", "b_inside_a"] {
        assert!(drilled.prim_groups()[g].count() > 0, "{g}");
    }
    let part = cook(&text, "/out").unwrap();
    assert!(closed(&part));
    // The boss adds its half above the plate's top (y = 0.2): less than
    // a hemisphere of radius 0.35, more than nothing.
    let added = volume(&part) - volume(&drilled);
    let hemisphere = 2.0 / 3.0 * std::f64::consts::PI * 0.35f64.powi(3);
    assert!(added > 0.8 * hemisphere && added < hemisphere, "{added}");
    assert!(part.attrib(geode_geo::AttribClass::Vertex, "N").is_some());
    // Cut faces are laid out afresh as manifold lays out its own (the
    // plate's cut top is one face, not its two triangles and the first
    // boolean's): manifold3d on the same solids, never written out between
    // the booleans, gives 1430 triangles, 6 under 0.1 degrees and 30
    // under 1 (per-triangle faces gave 1930, 34 and 217).
    let angles: Vec<f64> = (0..part.num_prims())
        .map(|k| min_angle_of(&part, k))
        .collect();
    assert!(part.num_prims() < 1500, "{} triangles", part.num_prims());
    assert!(angles.iter().filter(|&&a| a < 0.1).count() <= 10);
    assert!(angles.iter().filter(|&&a| a < 1.0).count() <= 40);
}

/// The smallest corner angle of triangle `k`, in degrees.
fn min_angle_of(g: &Geometry, k: usize) -> f64 {
    let p: Vec<_> = g
        .prim_points(k)
        .iter()
        .map(|&i| g.positions()[i as usize].as_dvec3())
        .collect();
    (0..3)
        .map(|i| {
            let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
            (b - a).angle_between(c - a).to_degrees()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn an_open_input_is_an_input_error_naming_the_node() {
    let text = r#"{"geode": "network", "version": 1, "output": "cut", "nodes": {
        "a": {"type": "box"}, "b": {"type": "grid"},
        "cut": {"type": "boolean", "inputs": ["a", "b"], "params": {"operation": "subtract"}}}}"#;
    let err = cook(text, "/cut").unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("cut") && msg.contains("input B is not a closed manifold mesh"),
        "{msg}"
    );
    assert_eq!(err.kind, geode_op::ErrorKind::Input);
}

#[test]
fn an_unknown_operation_is_refused_at_load() {
    let text = r#"{"geode": "network", "version": 1, "output": "cut", "nodes": {
        "a": {"type": "box"}, "b": {"type": "sphere"},
        "cut": {"type": "boolean", "inputs": ["a", "b"], "params": {"operation": "xor"}}}}"#;
    let err = geode_graph::load_str(text, &geode_nodes::registry())
        .map(|_| ())
        .unwrap_err();
    let msg = format!("{err:?}");
    assert!(msg.contains("operation") && msg.contains("xor"), "{msg}");
}

#[test]
fn the_extruded_panel_is_a_slab_with_raised_tiles_and_rounded_edges() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/extruded_panel.json"
    ))
    .unwrap();
    let slab = cook(&text, "/slab").unwrap();
    assert!(closed(&slab));
    assert!(
        (volume(&slab) - 2.0 * 1.5 * 0.2).abs() < 1e-5,
        "{}",
        volume(&slab)
    );
    let tiles = cook(&text, "/tiles").unwrap();
    assert!(closed(&tiles));
    // Twelve 0.5 x 0.5 tiles, each a frustum to a 0.4 x 0.4 top 0.1 up.
    let tile = 0.1 / 3.0 * (0.25 + 0.16 + 0.2);
    let want = 0.6 + 12.0 * tile;
    assert!(
        (volume(&tiles) - want).abs() < 1e-5,
        "{} vs {want}",
        volume(&tiles)
    );
    assert_eq!(tiles.prim_groups()["extrudeFront"].count(), 12);
    assert_eq!(tiles.prim_groups()["extrudeSide"].count(), 48);
    // Every sharp edge rounded at 0.02: still closed, a little lighter. A
    // convex edge rounded at offset d loses at most d^2 (1 - pi/4) of
    // section (at 90 degrees; less where its faces are wider apart), a
    // concave one gains some: the slab's 14.8 and the tiles' 48.6 units of
    // edge bound the loss.
    let out = cook(&text, "/out").unwrap();
    assert!(closed(&out));
    let removed = want - volume(&out);
    let bound = (14.8 + 48.6) * 0.02 * 0.02 * (1.0 - std::f64::consts::FRAC_PI_4);
    assert!(removed > 0.0 && removed < bound, "{removed} vs {bound}");
    assert!(out.prim_groups()["bevelEdges"].count() > 0);
    assert!(out.prim_groups()["bevelCorners"].count() > 0);
}

/// The smallest corner angle of any triangle, in degrees.
fn min_angle(g: &Geometry) -> f64 {
    let p = g.positions();
    (0..g.num_prims())
        .flat_map(|k| {
            let q = g.prim_points(k);
            let at = |i: usize| p[q[i % 3] as usize].as_dvec3();
            (0..3).map(move |i| {
                (at(i + 1) - at(i))
                    .angle_between(at(i + 2) - at(i))
                    .to_degrees()
            })
        })
        .fold(f64::MAX, f64::min)
}

/// Mean length of the triangles' edges (each counted once per side).
fn mean_edge(g: &Geometry) -> f64 {
    let p = g.positions();
    let mut sum = 0.0;
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 0..3 {
            sum += p[q[j] as usize].distance(p[q[(j + 1) % 3] as usize]) as f64;
        }
    }
    sum / (3 * g.num_prims()) as f64
}

#[test]
fn the_scan_is_reduced_to_a_tenth_and_remeshed_evenly() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scan_cleanup.json"
    ))
    .unwrap();
    // The "scan": a blended solid polygonised densely, with seeded noise
    // the size of a scanner's along the normals.
    let scan = cook(&text, "/noisy").unwrap();
    assert!(
        closed(&scan) && scan.num_prims() > 50_000,
        "{}",
        scan.num_prims()
    );
    let reduced = cook(&text, "/reduced").unwrap();
    assert!(closed(&reduced));
    let tenth = scan.num_prims() as f64 / 10.0;
    assert!(
        (reduced.num_prims() as f64 - tenth).abs() <= 2.0,
        "{}",
        reduced.num_prims()
    );
    let remeshed = cook(&text, "/remeshed").unwrap();
    assert!(closed(&remeshed));
    // Volume kept to a fraction of a percent through both.
    for g in [&reduced, &remeshed] {
        let change = (volume(g) / volume(&scan) - 1.0).abs();
        assert!(change < 0.005, "{change}");
    }
    // Even triangles at the asked length: 0.02 of the box diagonal.
    let b = geode_geo::ops::bounds(&scan).unwrap();
    let target = 0.02 * b.size().length() as f64;
    let mean = mean_edge(&remeshed);
    assert!((mean / target - 1.0).abs() < 0.1, "{mean} vs {target}");
    assert!(min_angle(&remeshed) > 15.0, "{}", min_angle(&remeshed));
    assert!(min_angle(&reduced) < min_angle(&remeshed));
    // At the default crease angle the noise makes small triangles whose
    // three edges are all creases: their corners must not be relaxed onto
    // the opposite edge (a triangle of no area, 0.00003 degrees, before).
    let creased = text.replace(r#""crease_angle": 60"#, r#""crease_angle": 30"#);
    assert_ne!(creased, text);
    let at_30 = cook(&creased, "/remeshed").unwrap();
    assert!(closed(&at_30));
    assert!(min_angle(&at_30) > 1.0, "{}", min_angle(&at_30));
}

#[test]
fn a_missing_group_or_attribute_names_the_parameter() {
    let net = |params: &str| {
        format!(
            r#"{{"geode": "network", "version": 1, "output": "x", "nodes": {{
            "a": {{"type": "box"}},
            "x": {{"type": "polyextrude", "inputs": ["a"], "params": {params}}}}}}}"#
        )
    };
    let err = cook(&net(r#"{"group": "topp"}"#), "/x").unwrap_err();
    assert_eq!(err.param.as_deref(), Some("group"), "{err}");
    let err = cook(&net(r#"{"distance_attrib": "thick"}"#), "/x").unwrap_err();
    assert_eq!(err.param.as_deref(), Some("distance_attrib"), "{err}");
    assert!(err.to_string().contains("thick"), "{err}");
    // A pattern selects by number.
    let one = cook(&net(r#"{"group": "0", "distance": 1}"#), "/x").unwrap();
    assert!((volume(&one) - 2.0).abs() < 1e-5, "{}", volume(&one));
}
