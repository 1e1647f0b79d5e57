//! Any text given to the snippet compiler or the expression parser gives a
//! program, a value or an error, never a panic or a stack overflow: random
//! token soups built from VEX's own pieces, and nesting far past the limit.

mod common;

use common::{any_channel, compile_over_points};
use geode_vex::{parse_expression, Globals};
use proptest::prelude::*;

const PIECES: &[&str] = &[
    "(", ")", "{", "}", "[", "]", ",", ";", "+", "-", "*", "/", "%", "?", ":", "=", "==", "&&",
    "!", ".", "x", "y", "1", "2.5", "0x1f", "\"s\"", "'t'", "@P", "f@a", "v[]@b", "$F", "$T",
    "$HIP", "$X", "sin", "fit", "rand", "ch", "chv", "chs", "int", "vector", "float", "if", "else",
    "for", "foreach", "while", "return", "break", "function", "\n", " ", "//", "/*", "*/", "#",
];

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(PIECES), 0..60).prop_map(|v| v.join(""))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn expressions_never_panic(text in soup()) {
        if let Ok(e) = parse_expression(&text) {
            let g = Globals { frame: 3.0, fps: 24.0, hip: "/h", node: "n" };
            let _ = e.eval(&g, &any_channel);
        }
    }

    #[test]
    fn snippets_never_panic(text in soup()) {
        let _ = compile_over_points(&text);
    }
}

#[test]
fn nesting_past_the_limit_is_an_error_in_every_form() {
    let deep = [
        format!("f@a = {}1{};", "(".repeat(100_000), ")".repeat(100_000)),
        format!("f@a = {}1;", "-".repeat(100_000)),
        format!("f@a = {};", vec!["1"; 100_000].join("+")),
        format!("{}{}", "{".repeat(100_000), "}".repeat(100_000)),
        format!("{}f@a = 1;", "if (1) ".repeat(100_000)),
        format!("f@a = x{};", "[0]".repeat(100_000)),
    ];
    for src in &deep {
        let e = compile_over_points(src).expect_err("too deep");
        assert!(e.msg.contains("nested too deeply"), "{}", e.msg);
    }
    let e =
        parse_expression(&format!("{}1{}", "(".repeat(100_000), ")".repeat(100_000))).unwrap_err();
    assert!(e.msg.contains("nested too deeply"), "{}", e.msg);
}

/// `2@` (Houdini's matrix2) is folded as a prefix but has no type here: an
/// error naming it, not a panic (found by the vex_text fuzz target).
#[test]
fn unsupported_type_prefixes_are_errors() {
    let e = compile_over_points("f@a = 2@P;").expect_err("2@ is not a type");
    assert_eq!(e.msg, "2@P: the type prefix 2@ is not supported");
}
