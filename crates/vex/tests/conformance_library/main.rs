//! Conformance of the function library (docs/wrangle.md's "Function
//! reference"): each program's expected value is taken from SideFX's VEX
//! reference pages (or from C's printf rules, which sprintf follows, and
//! plain analytic math), never from running geode. Each runs as a detail
//! wrangle over a small geometry and checks a detail attribute it writes;
//! `A ||| B` runs `B` over `A`'s output to read back geometry writes.
//!
//! Fixtures (tests/common): four points at x = 0..3; a unit quad whose
//! parametric (u, v) is its (x, y); two triangles; an open polyline.

mod edges;
mod points;
mod prims;

#[path = "../common/mod.rs"]
mod common;
use common::*;
use edges::{Geo, EDGE_PROGRAMS, ONCE_DISAGREED};
use points::CASES;
use prims::{LINE_CASES, QUAD_CASES, TRI_CASES};
use std::f32::consts::{
    E, FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, FRAC_PI_6, LN_2, PI, SQRT_2,
};
use Want::*;

/// How long an edge program may take before it counts as a hang; it runs
/// on its own thread, so one that ignores the cancel flag is left behind.
const EDGE_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

fn edge_outcome(geo: Geo, src: &'static str) -> Option<String> {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(check_detail(src, "r", &Want::I(i32::MIN), &geo.make()()));
    });
    match rx.recv_timeout(EDGE_LIMIT) {
        Ok(Err(e)) if e.starts_with("PANIC") || e.starts_with("HANG") => Some(e),
        Ok(_) => None,
        Err(_) => Some(format!("HANG: no result after {EDGE_LIMIT:?}")),
    }
}

#[test]
fn edge_programs_neither_panic_nor_hang() {
    let failures: Vec<String> = EDGE_PROGRAMS
        .iter()
        .filter_map(|&(geo, src)| {
            edge_outcome(geo, src).map(|e| format!("[{geo:?}] {src}\n    {e}"))
        })
        .collect();
    report("edge programs", EDGE_PROGRAMS.len(), failures);
}

fn report(label: &str, cases: usize, failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{label}: {} of {} failed:\n{}",
        failures.len(),
        cases,
        failures.join("\n")
    );
}

#[test]
fn library_programs_on_points_give_their_documented_results() {
    report("points", CASES.len(), failures(four_points, CASES));
}

#[test]
fn library_programs_on_a_quad_give_their_documented_results() {
    report("quad", QUAD_CASES.len(), failures(unit_quad, QUAD_CASES));
}

#[test]
fn library_programs_on_triangles_give_their_documented_results() {
    report(
        "triangles",
        TRI_CASES.len(),
        failures(two_triangles, TRI_CASES),
    );
}

#[test]
fn library_programs_on_a_polyline_give_their_documented_results() {
    report("polyline", LINE_CASES.len(), failures(polyline, LINE_CASES));
}

#[test]
fn printf_formats_as_c_does() {
    let (_, report) = wrangle_with(
        r#"printf("%d-%s|%5.1f\n", 3, "a", 2.26);"#,
        geode_geo::AttribClass::Detail,
        &four_points(),
        &[],
    )
    .unwrap();
    assert_eq!(report.printed.concat(), "3-a|  2.3\n");
}

/// Where geode once disagreed with SideFX's documentation (found by this
/// suite, fixed since): kept apart so a regression names the finding.
#[test]
fn documented_semantics_geode_once_missed() {
    let failures: Vec<String> = ONCE_DISAGREED
        .iter()
        .filter_map(|(geo, src, name, want)| {
            check_detail(src, name, want, &geo.make()())
                .err()
                .map(|e| format!("[{geo:?}] {src}\n    {e}"))
        })
        .collect();
    report("once disagreed", ONCE_DISAGREED.len(), failures);
}

/// Every function of docs/wrangle.md's reference is called by some case.
#[test]
fn every_documented_function_has_a_case() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/wrangle.md");
    let text = std::fs::read_to_string(path).expect("docs/wrangle.md");
    let start = text.find("<!-- functions:begin -->").expect("begin marker");
    let end = text.find("<!-- functions:end -->").expect("end marker");
    let programs: Vec<&str> = [CASES, QUAD_CASES, TRI_CASES, LINE_CASES]
        .iter()
        .flat_map(|cases| cases.iter().map(|c| c.0))
        .chain(ONCE_DISAGREED.iter().map(|c| c.1))
        .chain(["printf("])
        .collect();
    let calls = |name: &str| {
        let call = format!("{name}(");
        programs.iter().any(|p| {
            p.match_indices(&call).any(|(i, _)| {
                !p[..i]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            })
        })
    };
    // Functions that need what this harness has not: tested where it is.
    const TESTED_ELSEWHERE: &[(&str, &str)] = &[
        (
            "chramp",
            "crates/nodes/tests/ramps.rs: needs a ramp parameter",
        ),
        (
            "error",
            "crates/nodes/tests/blocks.rs: stops the cook, so it gives no value to compare",
        ),
    ];
    let mut missing = Vec::new();
    for line in text[start..end].lines().filter(|l| l.starts_with("- `")) {
        // The signatures are the backticked spans before the description.
        let signatures = line.split(':').next().unwrap_or("");
        for sig in signatures.split('`').skip(1).step_by(2) {
            let Some(open) = sig.find('(') else { continue };
            let name = sig[..open].rsplit(' ').next().unwrap_or("");
            let elsewhere = TESTED_ELSEWHERE.iter().any(|(n, _)| *n == name);
            if !name.is_empty()
                && !elsewhere
                && !calls(name)
                && !missing.contains(&name.to_string())
            {
                missing.push(name.to_string());
            }
        }
    }
    let total =
        CASES.len() + QUAD_CASES.len() + TRI_CASES.len() + LINE_CASES.len() + ONCE_DISAGREED.len();
    assert!(total >= 200, "{total} cases");
    assert!(missing.is_empty(), "no case calls: {missing:?}");
}

/// cracktransform undoes maketransform in every transform and rotation
/// order ("The function uses the given transform and rotation orders (trs
/// and xyz), the given pivot point (pivot) and optional pivot rotation
/// (pr)"): the parts come back as given, about a pivot, and inside a pivot
/// frame rotated by pivot_rotate (the pivot frame made as a transform of
/// its own: rotate by pivot_rotate, then move to the pivot).
#[test]
fn cracktransform_undoes_maketransform_in_every_order() {
    let mut failures = Vec::new();
    for trs in ["SRT", "STR", "RST", "RTS", "TSR", "TRS"] {
        for xyz in ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"] {
            // The angle about the order's middle axis within (-90, 90):
            // the other two may then take any value in (-180, 180].
            let r = match &xyz[1..2] {
                "X" => "{-35, 160, -150}",
                "Y" => "{120, -35, -150}",
                _ => "{120, 160, -35}",
            };
            let make = format!(
                "matrix X = maketransform(XFORM_{trs}, XFORM_{xyz}, {{1, -2, 3.5}}, {r}, {{2, 0.5, 3}}, {{0.5, 4, -1}}); \
                 matrix P = maketransform(XFORM_SRT, XFORM_{xyz}, {{0.5, 4, -1}}, {{10, -20, 30}}); \
                 matrix Y = invert(P) * maketransform(XFORM_{trs}, XFORM_{xyz}, {{1, -2, 3.5}}, {r}, {{2, 0.5, 3}}) * P;"
            );
            let checks = [
                ("vector t, a, s; cracktransform(XFORM_{trs}, XFORM_{xyz}, {0.5, 4, -1}, X, t, a, s); v@r = t;", "{1, -2, 3.5}"),
                ("vector t, a, s; cracktransform(XFORM_{trs}, XFORM_{xyz}, {0.5, 4, -1}, X, t, a, s); v@r = a;", r),
                ("vector t, a, s; cracktransform(XFORM_{trs}, XFORM_{xyz}, {0.5, 4, -1}, X, t, a, s); v@r = s;", "{2, 0.5, 3}"),
                ("v@r = cracktransform(XFORM_{trs}, XFORM_{xyz}, 1, {0.5, 4, -1}, X);", r),
                ("v@r = cracktransform(XFORM_{trs}, XFORM_{xyz}, 3, {0.5, 4, -1}, X);", "{0, 0, 0}"),
                ("v@r = cracktransform(XFORM_{trs}, XFORM_{xyz}, 0, {0.5, 4, -1}, {10, -20, 30}, Y);", "{1, -2, 3.5}"),
                ("v@r = cracktransform(XFORM_{trs}, XFORM_{xyz}, 1, {0.5, 4, -1}, {10, -20, 30}, Y);", r),
                ("v@r = cracktransform(XFORM_{trs}, XFORM_{xyz}, 2, {0.5, 4, -1}, {10, -20, 30}, Y);", "{2, 0.5, 3}"),
            ];
            for (check, want) in checks {
                let check = check.replace("{trs}", trs).replace("{xyz}", xyz);
                // Compared in the snippet: the want is a literal there too.
                let src =
                    format!("{make} {check} vector w = {want}; i@ok = length(v@r - w) < 1e-3;");
                if let Err(e) = check_detail(&src, "ok", &Want::I(1), &four_points()) {
                    failures.push(format!("{src}\n    {e}"));
                }
            }
        }
    }
    report("cracktransform", 36 * 8, failures);
}
