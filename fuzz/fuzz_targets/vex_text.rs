//! Fuzz target: the VEX snippet compiler and the parameter expression parser must return Ok or Err on any text, never panic or overflow the stack.
#![no_main]

use geode_geo::{AttribClass, Geometry};
use geode_vex::{compile, parse_expression, BindSpec, Channel, Globals};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let channel = |_: &str| Some(Channel::Num(vec![1.0, 2.0, 3.0]));
    if let Ok(e) = parse_expression(text) {
        let g = Globals { frame: 3.0, fps: 24.0, hip: "/h", node: "n" };
        let _ = e.eval(&g, &channel);
    }
    let geo = Geometry::new();
    let names = Vec::new;
    let spec = BindSpec {
        run_over: AttribClass::Point,
        inputs: vec![Some(&geo)],
        channels: &channel,
        channel_names: &names,
        frame: 1.0,
        time: 0.0,
    };
    let _ = compile(text, &spec);
});
