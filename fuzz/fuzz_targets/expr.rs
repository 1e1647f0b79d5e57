//! Fuzz target: the per-element expression language (group and field expressions) must parse to an expression or an error with a column on any text, never panic or overflow the stack; what parses evaluates and becomes a field.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(e) = geode_nodes::Expr::parse(text, &["x", "y", "z"]) {
        let _ = e.eval(&[0.5, -1.0, 2.0]);
        let xyz = [geode_frep::Field::x(), geode_frep::Field::y(), geode_frep::Field::z()];
        let _ = geode_frep::Tape::compile(&e.to_field(&xyz));
    }
});
