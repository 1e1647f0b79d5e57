//! Node-level benchmarks: workloads cooked through the engine as users cook
//! them, timed by the spans of the nodes that do the work (the engine's cook
//! events; upstream nodes and file reading excluded), median of a few runs,
//! printed as one table with each row's peer and goal. OpenSubdiv's time
//! (Far, one thread, refine and interpolate) stands beside the subdivision
//! rows when `GEODE_OSD_REF` names tools/osd_ref/osd_ref (tools/test.sh
//! builds it). Rows at 1/10 size show how a workload scales.
//! Run: GEODE_OSD_REF=tools/osd_ref/osd_ref cargo bench -p geode-nodes --bench nodes [-- FILTER]

use std::time::Duration;

use geode_graph::{load_str, Cache, CookOptions, Engine};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

/// One workload: a network (JSON), the node pulled, the frame, and the
/// nodes whose spans make the row's figure.
struct Row {
    name: String,
    network: String,
    pull: &'static str,
    frame: f64,
    timed: &'static [&'static str],
    peer: Peer,
    /// The goal; none where the row only shows scaling.
    goal_ms: Option<f64>,
    /// Also report the peak resident memory the timed nodes added (their
    /// inputs cooked first, into a cache).
    memory: bool,
}

enum Peer {
    None,
    /// A figure measured elsewhere (another tool on this machine).
    Quoted(&'static str),
    /// OpenSubdiv refining the row's OBJ to `levels`, timed now.
    OpenSubdiv {
        obj: String,
        levels: u32,
    },
}

fn example(file: &str) -> String {
    let path = format!("{}/../../examples/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn corpus(path: &str) -> String {
    format!("{}/../../corpus/{path}", env!("CARGO_MANIFEST_DIR"))
}

/// An example network with more nodes (a JSON object of node entries).
fn extended(file: &str, extra: &str) -> String {
    let mut doc: serde_json::Value = serde_json::from_str(&example(file)).unwrap();
    let extra: serde_json::Map<String, serde_json::Value> = serde_json::from_str(extra).unwrap();
    doc["nodes"].as_object_mut().unwrap().extend(extra);
    doc.to_string()
}

/// A network of the given node entries.
fn network(output: &str, nodes: &str) -> String {
    format!(r#"{{"geode": "network", "version": 1, "output": "{output}", "nodes": {{{nodes}}}}}"#)
}

/// The 32k-quad sphere the scatter rows cover or fill.
const SPHERE_32K: &str = r#""ball": {"type": "sphere", "params": {"rows": 128, "columns": 256}}"#;

fn scatter(mode: &str, count: u64, relax: bool) -> String {
    network(
        "scatter",
        &format!(
            r#"{SPHERE_32K}, "scatter": {{"type": "scatter", "inputs": ["ball"], "params": {{"mode": "{mode}", "count": {count}, "seed": 1, "relax": {relax}}}}}"#
        ),
    )
}

/// A million packed copies of a 10k-quad sphere on a 1000 x 1000 grid.
fn million_copies(extra: &str) -> String {
    network(
        "copies",
        &format!(
            r#""ball": {{"type": "sphere", "params": {{"radius": 0.03, "rows": 100, "columns": 100}}}},
            "field": {{"type": "grid", "params": {{"size": [100, 100], "rows": 1000, "columns": 1000}}}},
            "heights": {{"type": "attribute_randomize", "inputs": ["field"], "params": {{"name": "pscale", "type": "float", "min": [0.5, 0, 0], "max": [2, 0, 0], "seed": 3}}}},
            "copies": {{"type": "copy_to_points", "inputs": ["ball", "heights"], "params": {{"pack": true}}}}{extra}"#
        ),
    )
}

fn colonize(attractors: u64) -> String {
    network(
        "grow",
        &format!(
            r#""ball": {{"type": "sphere", "params": {{"rows": 64, "columns": 128}}}},
            "food": {{"type": "scatter", "inputs": ["ball"], "params": {{"mode": "inside", "count": {attractors}, "seed": 5}}}},
            "seed": {{"type": "curve_line", "params": {{"start": [0, -1, 0], "end": [0, -0.98, 0], "points": 2}}}},
            "grow": {{"type": "space_colonize", "inputs": ["food", "seed"], "params": {{"influence": 0.1, "kill": 0.02, "step": 0.01, "iterations": 10000}}}}"#
        ),
    )
}

fn rows() -> Vec<Row> {
    let row = |name: &str, network: String, pull, timed, peer, goal_ms| Row {
        name: name.to_string(),
        network,
        pull,
        frame: 1.0,
        timed,
        peer,
        goal_ms,
        memory: false,
    };
    let car = corpus("opensubdiv/catmark_car.obj");
    let mut rows = Vec::new();
    for levels in [3, 4, 5] {
        let net = network(
            "subd",
            &format!(
                r#""car": {{"type": "file", "params": {{"file": "{car}"}}}},
                "subd": {{"type": "subdivide", "inputs": ["car"], "params": {{"levels": {levels}}}}}"#
            ),
        );
        let peer = Peer::OpenSubdiv {
            obj: car.clone(),
            levels,
        };
        rows.push(row(
            &format!("subdivide catmark_car, level {levels}"),
            net,
            "/subd",
            &["/subd"],
            peer,
            None,
        ));
    }
    let blender_surface =
        Peer::Quoted("Blender 3.4 Distribute Points on Faces, 7.9M on a 64k-face sphere: 630 ms");
    rows.extend([
        row(
            "scatter 7.9M points on a 32k-quad sphere's surface",
            scatter("surface", 7_900_000, false),
            "/scatter",
            &["/scatter"],
            blender_surface,
            Some(300.0),
        ),
        row(
            "scatter 7.9M points inside that sphere",
            scatter("inside", 7_900_000, false),
            "/scatter",
            &["/scatter"],
            Peer::None,
            Some(600.0),
        ),
        row(
            "scatter 1M points on that surface with relax (blue noise)",
            scatter("surface", 1_000_000, true),
            "/scatter",
            &["/scatter"],
            Peer::None,
            Some(2000.0),
        ),
        row(
            "scatter 100k points on that surface with relax (1/10 size)",
            scatter("surface", 100_000, true),
            "/scatter",
            &["/scatter"],
            Peer::None,
            None,
        ),
        row(
            "scatter_field 3,000 points with relax (the coral's)",
            example("coral.json"),
            "/food",
            &["/food"],
            Peer::None,
            Some(10.0),
        ),
        row(
            "copy_to_points 1M packed copies of a 10k-quad sphere",
            million_copies(""),
            "/copies",
            &["/copies"],
            Peer::Quoted("Blender 3.4 Instance on Points (not realised): 110 ms"),
            Some(50.0),
        ),
    ]);
    let glb = std::env::temp_dir().join("geode-bench-copies.glb");
    let write = format!(
        r#", "out": {{"type": "write", "inputs": ["copies"], "params": {{"file": "{}"}}}}"#,
        glb.display()
    );
    let mut glb_row = row(
        "GLB write of those 1M packed copies",
        million_copies(&write),
        "/out",
        &["/out"],
        Peer::None,
        Some(500.0),
    );
    glb_row.memory = true;
    rows.push(glb_row);
    let transform = network(
        "move",
        &format!(
            r#"{SPHERE_32K}, "scatter": {{"type": "scatter", "inputs": ["ball"], "params": {{"mode": "surface", "count": 7900000, "seed": 1}}}},
            "move": {{"type": "transform", "inputs": ["scatter"], "params": {{"translate": [1, 2, 3], "rotate": [10, 20, 30], "uniform_scale": 2}}}}"#
        ),
    );
    rows.extend([
        row(
            "transform of 7.9M points",
            transform,
            "/move",
            &["/move"],
            Peer::Quoted("memory bandwidth: ~190 MB in and out"),
            Some(40.0),
        ),
        row(
            "space_colonize 1M attractors in the unit ball",
            colonize(1_000_000),
            "/grow",
            &["/grow"],
            Peer::Quoted("a plain kd-tree version: 9.45 s"),
            Some(2000.0),
        ),
        row(
            "space_colonize 100k attractors (1/10 size)",
            colonize(100_000),
            "/grow",
            &["/grow"],
            Peer::None,
            None,
        ),
        row(
            "coral smooth join (frep_sweep + polygonise), frame 61, depth 7",
            example("coral.json"),
            "/smooth",
            &["/skeleton", "/smooth"],
            Peer::None,
            Some(300.0),
        ),
        row(
            "gyroid part (distance offset, polygonise), depth 7",
            example("frep_gyroid_part.json"),
            "/mesh",
            &["/inner", "/mesh"],
            Peer::None,
            None,
        ),
        row(
            "printing an STL part end to end (frep_from_mesh, shell, gyroid, drains, polygonise depth 7, wall_thickness)",
            example("frep_print_part.json").replace(
                "$HIP",
                &format!("{}/../../examples", env!("CARGO_MANIFEST_DIR")),
            ),
            "/check",
            &[
                "/part", "/welded", "/solid", "/skin", "/cavity", "/gyroid", "/infill",
                "/hollowed", "/drain", "/drain_up", "/drain_copy", "/drains", "/printable",
                "/mesh", "/check",
            ],
            Peer::None,
            None,
        ),
        row(
            "wall_thickness of the gyroid part (310k triangles)",
            extended(
                "frep_gyroid_part.json",
                r#"{"measured": {"type": "wall_thickness", "inputs": ["mesh"]}}"#,
            ),
            "/measured",
            &["/measured"],
            Peer::None,
            None,
        ),
    ]);
    rows.iter_mut()
        .filter(|r| r.name.starts_with("coral"))
        .for_each(|r| r.frame = 61.0);
    rows
}

/// Peak resident memory of this process so far (kB), and a reset of it.
fn peak_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn reset_peak() {
    // Writing 5 to clear_refs resets the peak resident size (Linux 4.0+).
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The summed spans of `row.timed` in one cold cook, and the peak resident
/// memory the timed nodes added (kB; their inputs are cooked into a cache
/// first when the row reports memory, else the cache is off).
fn run_once(row: &Row) -> (Duration, u64) {
    let net = load_str(&row.network, &geode_nodes::registry())
        .unwrap_or_else(|e| panic!("{}: {e:?}", row.name));
    let cache = if row.memory {
        Cache::new(16 << 30)
    } else {
        Cache::disabled()
    };
    let engine = Engine::new(net, &cache);
    let opts = CookOptions::at_frame(row.frame);
    if row.memory {
        let inputs: Vec<String> = engine
            .network()
            .paths()
            .filter(|p| !row.timed.contains(p) && *p != row.pull)
            .map(str::to_owned)
            .collect();
        for path in inputs {
            engine
                .cook(&path, &opts)
                .unwrap_or_else(|e| panic!("{}: {e:?}", row.name));
        }
    }
    reset_peak();
    let before = peak_kb().unwrap_or(0);
    let result = engine
        .cook(row.pull, &opts)
        .unwrap_or_else(|e| panic!("{}: {e:?}", row.name));
    let added = peak_kb().unwrap_or(0).saturating_sub(before);
    let seconds: f64 = row
        .timed
        .iter()
        .map(|path| {
            result
                .events
                .iter()
                .find(|e| e.path == *path)
                .unwrap_or_else(|| panic!("{}: {path} did not cook", row.name))
                .seconds
        })
        .sum();
    (Duration::from_secs_f64(seconds), added)
}

/// The reference program's input for an OBJ: positions, faces, `t crease`
/// tags and the uv channel (smooth inside, island boundaries kept: geode's
/// default), with edge-only boundaries, as geode's `subdivide` reads it.
fn osd_input(obj: &str, levels: u32) -> String {
    let (mut verts, mut uvs, mut faces, mut creases) = (vec![], vec![], vec![], vec![]);
    let mut uv_of_corner = Vec::new();
    let index = |w: &str, k: usize| -> i64 {
        w.split('/')
            .nth(k)
            .and_then(|i| i.parse::<i64>().ok())
            .unwrap_or(1)
            - 1
    };
    for line in obj.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first().copied() {
            Some("v") => verts.push(words[1..4].join(" ")),
            Some("vt") => uvs.push(words[1..3].join(" ")),
            Some("f") => {
                let corners = &words[1..];
                let idx: Vec<String> = corners.iter().map(|w| index(w, 0).to_string()).collect();
                uv_of_corner.extend(corners.iter().map(|w| index(w, 1).to_string()));
                faces.push(format!("{} {}", idx.len(), idx.join(" ")));
            }
            Some("t") if words.get(1) == Some(&"crease") => {
                creases.push(format!("{} {} {}", words[3], words[4], words[5]));
            }
            _ => {}
        }
    }
    let fvar = if uvs.is_empty() {
        String::new()
    } else {
        format!(
            "fvar 4 {}\n{}\n{}\n",
            uvs.len(),
            uvs.join("\n"),
            uv_of_corner.join(" ")
        )
    };
    format!(
        "boundary 1 crease 0 levels {levels}\nverts {}\n{}\nfaces {}\n{}\ncreases {}\n{}\ncorners 0\nholes 0\n{fvar}",
        verts.len(),
        verts.join("\n"),
        faces.len(),
        faces.join("\n"),
        creases.len(),
        creases.join("\n"),
    )
}

/// OpenSubdiv's median time refining `obj` to `levels` (the reference
/// program's timing mode), or why there is none.
fn opensubdiv_ms(obj: &str, levels: u32) -> Result<f64, String> {
    use std::io::Write;
    let bin = std::env::var("GEODE_OSD_REF").map_err(|_| "GEODE_OSD_REF unset".to_string())?;
    let text = std::fs::read_to_string(obj).map_err(|e| format!("{obj}: {e}"))?;
    let input = osd_input(&text, levels);
    let mut child = std::process::Command::new(&bin)
        .env("OSD_REF_TIME", "5")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("{bin}: {e}"))?;
    child
        .stdin
        .take()
        .ok_or("no stdin")?
        .write_all(input.as_bytes())
        .map_err(|e| e.to_string())?;
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    String::from_utf8_lossy(&out.stdout)
        .trim()
        .parse()
        .map_err(|_| format!("{bin} printed no time"))
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let runs = 3;
    println!("| workload | geode (median of {runs}) | peer, same machine | goal |");
    println!("|---|---|---|---|");
    for row in rows() {
        if filter.as_deref().is_some_and(|f| !row.name.contains(f)) {
            continue;
        }
        let mut times: Vec<(Duration, u64)> = (0..runs).map(|_| run_once(&row)).collect();
        times.sort();
        let (median, added_kb) = times[runs / 2];
        let median = median.as_secs_f64() * 1e3;
        let memory = if row.memory {
            format!(", +{:.0} MB peak", added_kb as f64 / 1024.0)
        } else {
            String::new()
        };
        let (peer, goal) = match &row.peer {
            Peer::None => ("—".to_string(), row.goal_ms),
            Peer::Quoted(text) => (text.to_string(), row.goal_ms),
            Peer::OpenSubdiv { obj, levels } => match opensubdiv_ms(obj, *levels) {
                Ok(ms) => (format!("OpenSubdiv Far: {ms:.1} ms"), Some(0.5 * ms)),
                Err(why) => (format!("OpenSubdiv not run ({why})"), None),
            },
        };
        let goal_text = match goal {
            Some(g) if median > g => format!("≤ {g:.0} ms (over)"),
            Some(g) => format!("≤ {g:.0} ms"),
            None => "—".to_string(),
        };
        println!(
            "| {} | {median:.1} ms{memory} | {peer} | {goal_text} |",
            row.name
        );
    }
}
