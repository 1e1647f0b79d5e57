//! Helpers shared by the wrangle tests: run a snippet over a geometry and
//! read back attributes.

#![allow(dead_code)]

use geode_geo::{AttribClass, Geometry};
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
