//! Hostile nesting in the program readers: 100,000 levels of parentheses,
//! `if`s, operator chains and unary minus in HyperFun are refused with the
//! position and the limit (never a stack overflow, which no test could
//! catch), deep `.vm` chains load and compile, and the inputs that once
//! crashed a reader under the fuzzer (tests/fuzz_regressions) stay handled.

use geode_frep::{parse_hf, parse_vm, Field, PointEval, Tape};

const LEVELS: usize = 100_000;

/// The error for an object `m` whose body is `body`.
fn hf_error(body: &str) -> String {
    parse_hf(&format!("m(x[3], a[1])\n{{\n{body}\n}}\n"), None, &[])
        .unwrap_err()
        .to_string()
}

#[test]
fn hyperfun_nested_parentheses_are_refused() {
    let body = format!("  m = {}1{};", "(".repeat(LEVELS), ")".repeat(LEVELS));
    assert_eq!(
        hf_error(&body),
        "line 3, column 206: nested too deeply (more than 200 levels)"
    );
}

#[test]
fn hyperfun_nested_ifs_are_refused() {
    let body = format!(
        "{}  m = 1;\n{}",
        "if 1 then\n".repeat(LEVELS),
        "endif;\n".repeat(LEVELS)
    );
    assert_eq!(
        hf_error(&body),
        "line 202, column 4: nested too deeply (more than 200 levels)"
    );
}

#[test]
fn hyperfun_operator_chains_are_refused() {
    let sum = format!("  m = {};", vec!["1"; LEVELS].join("+"));
    assert_eq!(
        hf_error(&sum),
        "line 3, column 403: nested too deeply (more than 200 levels)"
    );
    let product = format!("  m = {};", vec!["x[1]"; LEVELS].join("*"));
    assert_eq!(
        hf_error(&product),
        "line 3, column 994: nested too deeply (more than 200 levels)"
    );
    let union = format!("  m = {};", vec!["x[1]"; LEVELS].join(" | "));
    assert_eq!(
        hf_error(&union),
        "line 3, column 1388: nested too deeply (more than 200 levels)"
    );
    let power = format!("  m = {};", vec!["2"; LEVELS].join("^"));
    assert_eq!(
        hf_error(&power),
        "line 3, column 405: nested too deeply (more than 200 levels)"
    );
    let relations = format!("  m = {};", vec!["x[1]"; LEVELS].join(" < "));
    assert_eq!(
        hf_error(&relations),
        "line 3, column 1388: nested too deeply (more than 200 levels)"
    );
}

#[test]
fn hyperfun_unary_chains_are_refused() {
    // `--` starts a comment, so the minus signs are spaced.
    let minus = format!("  m = {}1;", "- ".repeat(LEVELS));
    assert_eq!(
        hf_error(&minus),
        "line 3, column 405: nested too deeply (more than 200 levels)"
    );
    let not = format!("  m = {}1;", "not ".repeat(LEVELS));
    assert_eq!(
        hf_error(&not),
        "line 3, column 807: nested too deeply (more than 200 levels)"
    );
}

/// Just under the limit in every object of a chain of objects calling each
/// other as deep as the compiler allows: the compiler's recursion (objects
/// times expression depth) still fits a test thread's stack.
#[test]
fn hyperfun_deepest_accepted_program_compiles() {
    let mut program = String::from("o0(x[3])\n{\n  o0 = x[1];\n}\n");
    for k in 1..64 {
        let depth = 190;
        program += &format!(
            "o{k}(x[3])\n{{\n  o{k} = {}o{}(x){};\n}}\n",
            "(".repeat(depth),
            k - 1,
            ")".repeat(depth)
        );
    }
    let f = parse_hf(&program, None, &[]).unwrap();
    assert_eq!(
        PointEval::new(&Tape::compile(&f)).eval([0.25, 0.0, 0.0]),
        0.25
    );
}

/// Loops inside loops, each under the per-loop limit, are stopped by the
/// compiler's budget of statements instead of running for hours.
#[test]
fn hyperfun_nested_loops_are_stopped() {
    let body = "  i = 0;\n  while i < 100000 loop\n    j = 0;\n    while j < 100000 loop j = j + 1; endloop;\n    i = i + 1;\n  endloop;\n  m = 0;";
    assert_eq!(
        hf_error(body),
        "line 6, column 27: the program runs more than 1000000 statements while compiling (loops inside loops?)"
    );
}

/// `.vm` is SSA: a chain is a list of lines, read without recursion, and the
/// field's passes (compiling, evaluating, dropping) are iterative.
#[test]
fn vm_chains_of_100000_lines_load_and_evaluate() {
    let mut negations = String::from("_0 var-x\n");
    for i in 1..=LEVELS {
        negations += &format!("_{i} neg _{}\n", i - 1);
    }
    let f = parse_vm(&negations).unwrap();
    // An even number of negations, then the sign flip into geode's convention.
    assert_eq!(
        PointEval::new(&Tape::compile(&f)).eval([0.5, 0.0, 0.0]),
        -0.5
    );
    let mut sums = String::from("_0 var-x\n_1 const 1\n_2 add _0 _1\n");
    for i in 3..=LEVELS {
        sums += &format!("_{i} add _{} _1\n", i - 1);
    }
    let f = parse_vm(&sums).unwrap();
    let mut encoded = Vec::new();
    geode_frep::codec::encode(&f, &mut encoded);
    let again = geode_frep::codec::decode(&encoded).unwrap();
    assert_eq!(again.identity(), f.identity());
    let v = PointEval::new(&Tape::compile(&again)).eval([2.0, 0.0, 0.0]);
    assert_eq!(v, -(2.0 + (LEVELS - 1) as f64));
}

/// Inputs that once crashed the HyperFun or `.vm` reader or the field
/// codec under the fuzzer (kept by tools/fuzz.sh) give a field or an
/// error, as the fuzz targets check: what loads compiles to a tape and
/// evaluates.
#[test]
fn fuzz_regressions() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    type Reader = fn(&[u8]) -> Option<Field>;
    let readers: [(&str, Reader); 3] = [
        ("hyperfun", |b| {
            std::str::from_utf8(b)
                .ok()
                .and_then(|t| parse_hf(t, None, &[1.0, 2.0]).ok())
        }),
        ("vm", |b| {
            std::str::from_utf8(b).ok().and_then(|t| parse_vm(t).ok())
        }),
        ("field_codec", |b| geode_frep::codec::decode(b).ok()),
    ];
    for (reader, parse) in readers {
        let Ok(entries) = std::fs::read_dir(dir.join(reader)) else {
            continue;
        };
        for entry in entries {
            let bytes = std::fs::read(entry.unwrap().path()).unwrap();
            if let Some(field) = parse(&bytes) {
                let _ = PointEval::new(&Tape::compile(&field)).eval([0.1, 0.2, 0.3]);
            }
        }
    }
}
