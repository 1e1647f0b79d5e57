//! Registry-wide checks: every registered node type cooks with its defaults
//! (and small inputs where it needs them), and every cook is a pure function
//! of its key: the same key gives the same output hash on any thread count
//! and in any process state, except declared outputs (which still return the
//! same value, but write a file each time).

use std::collections::BTreeMap;

use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookEnv, PortType};

/// Inputs (as `"name": {node}` entries) and parameters for node types that
/// cannot cook on defaults and the generic inputs alone.
fn setup(node: &str, dir: &str) -> (Vec<String>, String) {
    let helix = r#""in0": {"type": "curve_helix", "params": {"points": 40}}"#.to_string();
    let grid_pts = |name: &str| {
        format!(r#""{name}": {{"type": "grid", "params": {{"rows": 3, "columns": 3}}}}"#)
    };
    let cyl = |name: &str| {
        format!(
            r#""{name}": {{"type": "hspline", "params": {{"topology": "cylinder", "rows": 6, "columns": 6, "samples": [6, 6]}}}}"#
        )
    };
    match node {
        "carve" | "curve_smooth" | "join" | "polyframe" | "resample" | "sweep" | "frep_sweep" => {
            (vec![helix], "{}".into())
        }
        "space_colonize" => (
            vec![
                r#""in0": {"type": "sphere", "params": {"radius": 0.5}}"#.into(),
                r#""in1": {"type": "curve_line", "params": {"points": 2, "end": [0, 0.1, 0]}}"#.into(),
            ],
            r#"{"iterations": 20}"#.into(),
        ),
        "copy_to_points" => (
            vec![r#""in0": {"type": "box"}"#.into(), grid_pts("in1")],
            "{}".into(),
        ),
        "frep_instance" => (
            vec![r#""in0": {"type": "frep_sphere", "params": {"radius": 0.2}}"#.into(), grid_pts("in1")],
            "{}".into(),
        ),
        "frep_from_primitives" => (
            vec![r#""in0": {"type": "sphere", "params": {"analytic": true}}"#.into()],
            "{}".into(),
        ),
        "attach" => (
            vec![
                r#""in0": {"type": "hspline", "params": {"topology": "torus", "rows": 8, "columns": 12, "samples": [6, 6]}}"#.into(),
                cyl("in1"),
            ],
            r#"{"regions": "2 3 2 4"}"#.into(),
        ),
        "skin" => (
            vec![r#""in0": {"type": "box"}"#.into()],
            r#"{"skeleton": "root - 0 -1 0; tip root 0 1 0", "bend_joint": "root", "bend": [0, 0, 30]}"#.into(),
        ),
        "delete" => (
            vec![r#""in0": {"type": "group_bbox", "params": {"group": "low", "max": [1, 0, 1]}, "inputs": ["b"]}, "b": {"type": "box"}"#.into()],
            r#"{"group": "low", "class": "point"}"#.into(),
        ),
        "switch" | "merge" => (vec![r#""in0": {"type": "box"}"#.into()], "{}".into()),
        "attribute_remap" => (
            vec![r#""in0": {"type": "attribute_randomize", "inputs": ["b"]}, "b": {"type": "box"}"#.into()],
            "{}".into(),
        ),
        "file" => (vec![], format!(r#"{{"file": "{dir}/in.obj"}}"#)),
        "python_input" => (
            vec![],
            format!(
                r#"{{"geometry": "{}"}}"#,
                geode_nodes::held::format_hash(held_triangle().content_hash())
            ),
        ),
        "frep_file" => (vec![], format!(r#"{{"file": "{dir}/ball.vm"}}"#)),
        "write" => (
            vec![r#""in0": {"type": "box"}"#.into()],
            format!(r#"{{"file": "{dir}/out.$F4.obj"}}"#),
        ),
        "frep_write" => (vec![], format!(r#"{{"file": "{dir}/out.$F4.vdb", "voxel_size": 0.1}}"#)),
        "bundle_extract" => (
            vec![r#""in0": {"type": "bundle_pack", "params": {"names": "a"}, "inputs": ["b0"]}, "b0": {"type": "box"}"#.into()],
            r#"{"name": "a"}"#.into(),
        ),
        _ => (vec![], "{}".into()),
    }
}

/// The geometry a host (Python) holds for `python_input`: one triangle.
fn held_triangle() -> std::sync::Arc<geode_geo::Geometry> {
    use geode_geo::glam::Vec3;
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    std::sync::Arc::new(geode_geo::Geometry::from_triangles(p.to_vec(), &[[0, 1, 2]]).unwrap())
}

/// A network of one node of `ty` (named `n`) with its inputs.
fn network(ty: &str, dir: &str) -> String {
    let registry = geode_nodes::registry();
    let spec = registry.get(ty).unwrap().spec();
    let (mut entries, params) = setup(ty, dir);
    let mut wires = Vec::new();
    for (i, inp) in spec.inputs.iter().enumerate() {
        let name = format!("in{i}");
        if !entries
            .iter()
            .any(|e| e.starts_with(&format!("\"{name}\"")))
        {
            if !inp.required {
                continue;
            }
            entries.push(match inp.ty {
                PortType::Geometry => format!(r#""{name}": {{"type": "box"}}"#),
                PortType::Field => format!(r#""{name}": {{"type": "frep_sphere"}}"#),
                PortType::Bundle => {
                    format!(r#""{name}": {{"type": "bundle_pack", "inputs": ["{name}b"]}}, "{name}b": {{"type": "box"}}"#)
                }
            });
        }
        wires.push(format!("\"{name}\""));
    }
    entries.push(format!(
        r#""n": {{"type": "{ty}", "params": {params}, "inputs": [{}]}}"#,
        wires.join(", ")
    ));
    format!(
        r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{{}}}}}"#,
        entries.join(", ")
    )
}

/// Cooks node `n` on a pool of `threads`, cache off: (key, output identity).
fn cook(text: &str, threads: usize, env: CookEnv) -> Result<(u128, u128), String> {
    let net = load_str(text, &geode_nodes::registry()).map_err(|e| format!("{e:?}"))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let cache = Cache::disabled();
        let engine = Engine::new(net, &cache);
        let mut opts = CookOptions::at_frame(1.0);
        opts.env = env;
        let r = engine.cook("/n", &opts).map_err(|e| {
            e.iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        })?;
        let key = r.events.iter().find(|e| e.path == "/n").unwrap().key;
        Ok((key, r.value.identity()))
    })
}

#[test]
fn every_node_cooks_on_defaults_and_is_a_pure_function_of_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap().to_owned();
    std::fs::write(
        dir.path().join("in.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    // A ball of radius 0.5 in fidget's sign (negative inside).
    std::fs::write(
        dir.path().join("ball.vm"),
        "_0 var-x\n_1 var-y\n_2 var-z\n_3 square _0\n_4 square _1\n_5 square _2\n_6 add _3 _4\n_7 add _6 _5\n_8 sqrt _7\n_9 const 0.5\n_a sub _8 _9\n",
    )
    .unwrap();
    let registry = geode_nodes::registry();
    let mut failures = BTreeMap::new();
    let mut checked = 0;
    for op in registry.iter() {
        let ty = op.spec().name;
        let text = network(ty, &d);
        let held = geode_op::HeldGeometry::new([held_triangle()]);
        let one = cook(
            &text,
            1,
            CookEnv {
                held: held.clone(),
                ..CookEnv::default().with_hip(&d)
            },
        );
        // Another thread count and another $HIP that the node does not read:
        // the key and the output must not move.
        let many = cook(
            &text,
            3,
            CookEnv {
                held,
                ..CookEnv::default().with_hip("/elsewhere")
            },
        );
        match (one, many) {
            (Ok(a), Ok(b)) => {
                if a != b {
                    failures.insert(ty, format!("not pure: {a:x?} vs {b:x?}"));
                }
                checked += 1;
            }
            (Err(e), _) | (_, Err(e)) => {
                failures.insert(ty, e);
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    assert_eq!(checked, registry.iter().count());
    assert!(checked >= 58, "{checked} node types");
    // The write node wrote its frame's file.
    assert!(dir.path().join("out.0001.obj").exists());
    assert!(dir.path().join("out.0001.vdb").exists());
}

#[test]
fn cooks_read_parameters_through_their_declarations_not_string_literals() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let patterns = [
        "p.float(\"",
        "p.int(\"",
        "p.toggle(\"",
        "p.string(\"",
        "p.list(\"",
        "p.ramp(\"",
        "p.get(\"",
        "(p, \"",
    ];
    let mut found = Vec::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let path = e.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        for (k, line) in text.lines().enumerate() {
            let vector = line.contains("p.vector::<") && line.contains(">(\"");
            if vector || patterns.iter().any(|pat| line.contains(pat)) {
                found.push(format!("{}:{}: {}", path.display(), k + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "read these through their ParamSpec consts:\n{}",
        found.join("\n")
    );
}

/// No node type is declared twice: the library's names and the engine's own
/// containers' (subnet, loop...) are distinct (a duplicate in the library
/// itself fails `Registry::add`).
#[test]
fn every_node_type_is_declared_once() {
    let registry = geode_nodes::registry();
    let names: Vec<&str> = geode_graph::node_specs(&registry)
        .iter()
        .map(|s| s.name)
        .collect();
    let mut unique = names.clone();
    unique.dedup();
    assert_eq!(names, unique, "a name shared by two declarations");
    assert!(names.len() > 60, "{}", names.len());
}
