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
        // Found by tools/vex_mutate.py: right-nested forms.
        format!("f@r = {}1{};", "1 ? ".repeat(30_000), " : 0".repeat(30_000)),
        format!("float x; f@r = {}1;", "x = ".repeat(30_000)),
        format!("{}f@a = 1;", "if (0) f@a = 2; else ".repeat(50_000)),
        format!(
            "{}f@a = 1;{}",
            "while (0) { ".repeat(50_000),
            "}".repeat(50_000)
        ),
        format!("f@a = {}1{};", "sin(".repeat(50_000), ")".repeat(50_000)),
        format!("f@a = {}1{};", "{".repeat(50_000), "}".repeat(50_000)),
        format!(
            "int a[]; f@a = a[{}0{}];",
            "a[".repeat(50_000),
            "]".repeat(50_000)
        ),
    ];
    for src in &deep {
        let e = compile_over_points(src).expect_err("too deep");
        assert!(e.msg.contains("nested too deeply"), "{}", e.msg);
    }
    let e =
        parse_expression(&format!("{}1{}", "(".repeat(100_000), ")".repeat(100_000))).unwrap_err();
    assert!(e.msg.contains("nested too deeply"), "{}", e.msg);
}

/// Functions each calling the one before are inlined one inside another:
/// the chain is refused past a depth, not a stack overflow.
#[test]
fn long_chains_of_function_calls_are_refused() {
    let mut src = String::from("float f0(float x) { return x; }\n");
    for i in 1..7_000 {
        src.push_str(&format!(
            "float f{i}(float x) {{ return f{}(x) + 1; }}\n",
            i - 1
        ));
    }
    src.push_str("f@r = f6999(1);");
    let e = compile_over_points(&src).expect_err("too deep");
    assert!(
        e.msg.contains("call each other more than 64 deep"),
        "{}",
        e.msg
    );
    let ok = "float f0(float x) { return x; } float f1(float x) { return f0(x) + 1; } f@r = f1(1);";
    compile_over_points(ok).expect("two levels compile");
}

/// `2@` (Houdini's matrix2) is folded as a prefix but has no type here: an
/// error naming it, not a panic (found by the vex_text fuzz target).
#[test]
fn unsupported_type_prefixes_are_errors() {
    let e = compile_over_points("f@a = 2@P;").expect_err("2@ is not a type");
    assert_eq!(e.msg, "2@P: the type prefix 2@ is not supported");
}
