//! Prints the instructions a snippet compiles to (run over the detail, or
//! over points with `--points`): `cargo run -p geode-vex --example listing
//! -- 'f@s = 1;'`.

use geode_geo::{AttribClass, Geometry};
use geode_vex::{compile, BindSpec, Channel};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let points = args.iter().any(|a| a == "--points");
    let Some(src) = args.iter().find(|a| !a.starts_with("--")) else {
        eprintln!("usage: listing [--points] SNIPPET");
        std::process::exit(2);
    };
    let mut g = Geometry::new();
    g.add_point(geode_geo::glam::Vec3::ZERO);
    let no_channels = |_: &str| -> Option<Channel> { None };
    let no_names = Vec::new;
    let spec = BindSpec {
        run_over: if points {
            AttribClass::Point
        } else {
            AttribClass::Detail
        },
        inputs: vec![Some(&g)],
        channels: &no_channels,
        channel_names: &no_names,
        frame: 1.0,
        time: 0.0,
    };
    match compile(src, &spec) {
        Ok(p) => print!("{}", p.listing()),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
