//! Helpers shared by the wrangle tests: run a snippet over a geometry and
//! read back attributes.

#![allow(dead_code)]

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use geode_geo::{AttribClass, AttribData, AttribValue, Attribute, Geometry, Group, TypeInfo};
use geode_vex::{compile, run, BindSpec, Channel, CompileError, RunError, RunOptions, RunReport};

pub fn spec<'a>(
    class: AttribClass,
    inputs: Vec<Option<&'a Geometry>>,
    ch: &'a dyn Fn(&str) -> Option<Channel>,
    names: &'a dyn Fn() -> Vec<String>,
) -> BindSpec<'a> {
    BindSpec {
        run_over: class,
        inputs,
        channels: ch,
        channel_names: names,
        frame: 1.0,
        time: 0.0,
    }
}

fn no_channels(_: &str) -> Option<Channel> {
    None
}

fn no_names() -> Vec<String> {
    Vec::new()
}

/// Compiles and runs `src` over `class` elements of `g` (with `extra` as
/// inputs 1..), returning the result or the first error as text.
pub fn wrangle_with(
    src: &str,
    class: AttribClass,
    g: &Geometry,
    extra: &[&Geometry],
) -> Result<(Geometry, RunReport), String> {
    let cancel = || false;
    run_with(src, class, g, extra, &cancel, 1 << 32).map_err(|e| e.to_string())
}

/// `wrangle_with` told when to stop and how much memory it may hold.
pub fn run_with(
    src: &str,
    class: AttribClass,
    g: &Geometry,
    extra: &[&Geometry],
    cancel: &(dyn Fn() -> bool + Sync),
    memory_budget: u64,
) -> Result<(Geometry, RunReport), RunError> {
    let mut inputs = vec![Some(g)];
    inputs.extend(extra.iter().map(|x| Some(*x)));
    let s = spec(class, inputs.clone(), &no_channels, &no_names);
    let p = compile(src, &s).unwrap_or_else(|e| panic!("{src}\n{e}"));
    let mut out = g.clone();
    let report = run(
        &p,
        &mut out,
        &inputs,
        &RunOptions {
            group: None,
            cancel,
            memory_budget,
        },
    )?;
    Ok((out, report))
}

pub fn wrangle(src: &str, class: AttribClass, g: &Geometry) -> Geometry {
    wrangle_with(src, class, g, &[])
        .unwrap_or_else(|e| panic!("{src}\n{e}"))
        .0
}

/// A detail wrangle on a geometry of four points in a row.
pub fn detail(src: &str) -> Geometry {
    wrangle(src, AttribClass::Detail, &four_points())
}

pub fn four_points() -> Geometry {
    let mut g = Geometry::new();
    g.add_points(&[
        [0.0, 0.0, 0.0].into(),
        [1.0, 0.0, 0.0].into(),
        [2.0, 0.0, 0.0].into(),
        [3.0, 0.0, 0.0].into(),
    ]);
    g
}

pub fn compile_error(src: &str) -> CompileError {
    let g = four_points();
    let s = spec(AttribClass::Point, vec![Some(&g)], &no_channels, &no_names);
    match compile(src, &s) {
        Ok(_) => panic!("{src} compiled"),
        Err(e) => e,
    }
}

pub fn df(g: &Geometry, name: &str) -> f32 {
    let a = g
        .attrib(AttribClass::Detail, name)
        .unwrap_or_else(|| panic!("no detail attribute {name}"));
    a.as_f32()
        .map(|v| v[0])
        .or_else(|| a.as_i32().map(|v| v[0] as f32))
        .expect("a number")
}

pub fn di(g: &Geometry, name: &str) -> i32 {
    g.attrib(AttribClass::Detail, name)
        .and_then(|a| a.as_i32())
        .unwrap_or_else(|| panic!("no int detail attribute {name}"))[0]
}

pub fn dv(g: &Geometry, name: &str) -> Vec<f32> {
    let a = g
        .attrib(AttribClass::Detail, name)
        .unwrap_or_else(|| panic!("no detail attribute {name}"));
    a.data()
        .as_floats()
        .map(|(f, _)| f.to_vec())
        .expect("floats")
}

pub fn ds(g: &Geometry, name: &str) -> String {
    g.attrib(AttribClass::Detail, name)
        .and_then(|a| a.as_strings())
        .map(|s| s.get(0).to_string())
        .unwrap_or_else(|| panic!("no string detail attribute {name}"))
}

/// A compile spec with no parameters.
pub fn spec_default(class: AttribClass, g: &Geometry) -> BindSpec<'_> {
    spec(class, vec![Some(g)], &no_channels, &no_names)
}

/// A channel for every name: `s` a string, any other three numbers.
pub fn any_channel(name: &str) -> Option<Channel> {
    match name {
        "s" => Some(Channel::Str("text".into())),
        _ => Some(Channel::Num(vec![1.0, 2.0, 3.0])),
    }
}

/// Compiles `text` over the points of an empty geometry, every channel
/// answered by `any_channel`: how the robustness tests and the fuzz target
/// feed the compiler arbitrary text.
pub fn compile_over_points(text: &str) -> Result<geode_vex::Program, CompileError> {
    let geo = Geometry::new();
    let s = spec(
        AttribClass::Point,
        vec![Some(&geo)],
        &any_channel,
        &no_names,
    );
    compile(text, &s)
}

// ----- conformance checks -----

/// What a conformance case expects of the detail attribute it writes.
#[derive(Debug)]
pub enum Want {
    F(f32),
    I(i32),
    V(&'static [f32]),
    S(&'static str),
}

/// The node parameters conformance snippets read with ch(), chf()...:
/// `f` 2.5, `i` 7, `v` {1, 2, 3}, `u` {4, 5}, `p` {1, 2, 3, 4}, `s` "text".
pub fn conformance_channel(name: &str) -> Option<Channel> {
    Some(match name {
        "f" => Channel::Num(vec![2.5]),
        "i" => Channel::Num(vec![7.0]),
        "v" => Channel::Num(vec![1.0, 2.0, 3.0]),
        "u" => Channel::Num(vec![4.0, 5.0]),
        "p" => Channel::Num(vec![1.0, 2.0, 3.0, 4.0]),
        "s" => Channel::Str("text".into()),
        _ => return None,
    })
}

fn conformance_channel_names() -> Vec<String> {
    ["f", "i", "v", "u", "p", "s"].map(String::from).to_vec()
}

/// How long one conformance program may run before it counts as a hang.
const CASE_LIMIT: Duration = Duration::from_secs(20);

/// One detail wrangle over `g` with the conformance parameters; compile
/// and run errors (and a run past `CASE_LIMIT`) come back as text.
fn detail_stage(src: &str, g: &Geometry) -> Result<Geometry, String> {
    let inputs = vec![Some(g)];
    let s = spec(
        AttribClass::Detail,
        inputs.clone(),
        &conformance_channel,
        &conformance_channel_names,
    );
    let p = compile(src, &s).map_err(|e| format!("compile error: {e}"))?;
    let start = Instant::now();
    let cancel = move || start.elapsed() > CASE_LIMIT;
    let mut out = g.clone();
    run(
        &p,
        &mut out,
        &inputs,
        &RunOptions {
            group: None,
            cancel: &cancel,
            memory_budget: 1 << 32,
        },
    )
    .map_err(|e| {
        if start.elapsed() > CASE_LIMIT {
            format!("HANG: still running after {CASE_LIMIT:?} ({e})")
        } else {
            format!("run error: {e}")
        }
    })?;
    Ok(out)
}

/// The detail attribute `name` of `g` as the kind `want` names, or why not.
fn read_detail(g: &Geometry, name: &str, want: &Want) -> Result<String, String> {
    let a = g
        .attrib(AttribClass::Detail, name)
        .ok_or_else(|| format!("no detail attribute {name}"))?;
    let kind = || {
        format!(
            "a {:?} attribute, which {want:?} does not read",
            a.attrib_type()
        )
    };
    match want {
        Want::F(_) => a
            .as_f32()
            .map(|v| v[0])
            .or_else(|| a.as_i32().map(|v| v[0] as f32))
            .map(|x| x.to_string())
            .ok_or_else(kind),
        Want::I(_) => a.as_i32().map(|v| v[0].to_string()).ok_or_else(kind),
        Want::V(_) => a
            .data()
            .as_floats()
            .map(|(f, n)| format!("{:?}", &f[..n.min(f.len())]))
            .ok_or_else(kind),
        Want::S(_) => a
            .as_strings()
            .map(|s| s.get(0).to_string())
            .ok_or_else(kind),
    }
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-5 * (1.0 + b.abs())
}

fn matches(g: &Geometry, name: &str, want: &Want) -> Result<bool, String> {
    let a = g
        .attrib(AttribClass::Detail, name)
        .ok_or_else(|| format!("no detail attribute {name}"))?;
    Ok(match want {
        Want::F(x) => a
            .as_f32()
            .map(|v| v[0])
            .or_else(|| a.as_i32().map(|v| v[0] as f32))
            .is_some_and(|got| close(got, *x)),
        Want::I(x) => a.as_i32().is_some_and(|v| v[0] == *x),
        Want::V(xs) => a.data().as_floats().is_some_and(|(f, n)| {
            n == xs.len()
                && f.len() >= n
                && f[..n].iter().zip(xs.iter()).all(|(a, b)| close(*a, *b))
        }),
        Want::S(s) => a.as_strings().is_some_and(|c| c.get(0) == *s),
    })
}

/// Runs a conformance program as a detail wrangle over `g` and checks the
/// detail attribute `name` against `want`. A program `A ||| B` runs `A`,
/// then `B` over `A`'s output (to read back what `A` wrote to points,
/// primitives or groups, which applies after its run). A panic inside the
/// run is reported as `PANIC: ...`.
pub fn check_detail(src: &str, name: &str, want: &Want, g: &Geometry) -> Result<(), String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let mut geo = g.clone();
        for stage in src.split("|||") {
            geo = detail_stage(stage, &geo)?;
        }
        if matches(&geo, name, want)? {
            Ok(())
        } else {
            let got = read_detail(&geo, name, want)?;
            Err(format!("got {got}, want {want:?}"))
        }
    }));
    match outcome {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(format!("PANIC: {msg}"))
        }
    }
}

/// Checks every `(program, attribute, want)` over the geometry `geo` makes,
/// one line per failure.
pub fn failures(geo: fn() -> Geometry, cases: &[(&str, &str, Want)]) -> Vec<String> {
    let g = geo();
    cases
        .iter()
        .filter_map(|(src, name, want)| {
            check_detail(src, name, want, &g)
                .err()
                .map(|e| format!("{src}\n    {e}"))
        })
        .collect()
}

// ----- small meshes with known parametric spaces -----

fn point_attrib(g: &mut Geometry, name: &str, data: AttribData) {
    g.set_attrib(
        AttribClass::Point,
        name,
        Attribute::from_data(data, TypeInfo::None),
    )
    .unwrap();
}

/// One unit-square quad, vertices on the points in order, placed so that
/// Houdini's quad parametric space P0(1-u)(1-v) + P1(1-u)v + P2uv + P3u(1-v)
/// maps (u, v) to (u, v, 0): P0 (0,0,0), P1 (0,1,0), P2 (1,1,0), P3 (1,0,0).
/// Point attributes `f` 0,1,2,3 (float), `id` 10,20,10,30 (int), `name`
/// a,b,a,c, and the arrays `ia` (int[]), `fa` (float[]), `sa` (string[]);
/// vertex `vf` 10..13, primitive `pf` 5, detail `d` 4.5; point group `odd`
/// {1, 3}, primitive group `face` {0}.
pub fn unit_quad() -> Geometry {
    let mut g = Geometry::from_polygons(
        vec![
            [0.0, 0.0, 0.0].into(),
            [0.0, 1.0, 0.0].into(),
            [1.0, 1.0, 0.0].into(),
            [1.0, 0.0, 0.0].into(),
        ],
        vec![0, 1, 2, 3],
        &[4],
    )
    .unwrap();
    point_attrib(&mut g, "f", AttribData::Float(vec![0.0, 1.0, 2.0, 3.0]));
    point_attrib(&mut g, "id", AttribData::Int(vec![10, 20, 10, 30]));
    let mut names = AttribData::filled(&AttribValue::String(String::new()), 4);
    for (i, n) in ["a", "b", "a", "c"].into_iter().enumerate() {
        names.set(i, &AttribValue::String(n.into())).unwrap();
    }
    point_attrib(&mut g, "name", names);
    point_attrib(&mut g, "ia", AttribData::IntArray(vec![vec![1, 2]; 4]));
    point_attrib(&mut g, "fa", AttribData::FloatArray(vec![vec![0.5]; 4]));
    point_attrib(
        &mut g,
        "sa",
        AttribData::StringArray(vec![vec!["x".into()]; 4]),
    );
    g.set_attrib(
        AttribClass::Vertex,
        "vf",
        Attribute::from_data(
            AttribData::Float(vec![10.0, 11.0, 12.0, 13.0]),
            TypeInfo::None,
        ),
    )
    .unwrap();
    g.set_attrib(
        AttribClass::Primitive,
        "pf",
        Attribute::from_data(AttribData::Float(vec![5.0]), TypeInfo::None),
    )
    .unwrap();
    g.set_attrib(
        AttribClass::Detail,
        "d",
        Attribute::from_data(AttribData::Float(vec![4.5]), TypeInfo::None),
    )
    .unwrap();
    g.set_point_group("odd", Group::from_members(4, [1, 3]))
        .unwrap();
    g.set_prim_group("face", Group::from_members(1, [0]))
        .unwrap();
    g
}

/// Two triangles: p0 (0,0,0), p1 (2,0,0), p2 (0,2,0), p3 (3,3,0);
/// primitive 0 on (p0, p1, p2) and primitive 1 on (p1, p3, p2), so linear
/// vertices 0..5 sit on points 0, 1, 2, 1, 3, 2. Point group `corner` {0},
/// primitive group `second` {1}.
pub fn two_triangles() -> Geometry {
    let mut g = Geometry::from_triangles(
        vec![
            [0.0, 0.0, 0.0].into(),
            [2.0, 0.0, 0.0].into(),
            [0.0, 2.0, 0.0].into(),
            [3.0, 3.0, 0.0].into(),
        ],
        &[[0, 1, 2], [1, 3, 2]],
    )
    .unwrap();
    g.set_point_group("corner", Group::from_members(4, [0]))
        .unwrap();
    g.set_prim_group("second", Group::from_members(2, [1]))
        .unwrap();
    g
}

/// The four points of `four_points` joined by one open polyline 0-1-2-3.
pub fn polyline() -> Geometry {
    let mut g = four_points();
    g.add_polyline(&[0, 1, 2, 3]).unwrap();
    g
}
