//! One test per class of compile error, with its exact message, line and
//! column; and runtime errors naming the element.

mod common;
use common::*;

fn msg(src: &str) -> String {
    compile_error(src).to_string()
}

#[test]
fn undeclared_variable_names_the_closest_declared_one() {
    assert_eq!(
        msg("float speed = 1;\n@P.y += sped;"),
        "line 2, column 9: undeclared variable 'sped' (did you mean 'speed'?)"
    );
    assert_eq!(
        msg("@P.y += zzz;"),
        "line 1, column 9: undeclared variable 'zzz'"
    );
}

#[test]
fn unknown_function_names_the_closest_known_one() {
    assert_eq!(
        msg("float l = lenght(@P);"),
        "line 1, column 11: unknown function 'lenght' (did you mean 'length'?)"
    );
    assert_eq!(
        msg("float wave(float x) { return x; }\nf@a = wav(1);"),
        "line 2, column 7: unknown function 'wav' (did you mean 'wave'?)"
    );
}

#[test]
fn wrong_argument_types_list_what_was_given() {
    assert_eq!(
        msg("vector c = cross(1.0, @P);"),
        "line 1, column 12: no form of 'cross' takes (float, vector)"
    );
    assert_eq!(
        msg("int n = npoints(\"a\");"),
        "line 1, column 17: 'npoints' expects an int here, not a string"
    );
    assert_eq!(
        msg("float x = fit(1, 2);"),
        "line 1, column 11: 'fit' takes 5 arguments, not 2"
    );
    assert_eq!(
        msg("string s = \"a\"; float x = s * 2;"),
        "line 1, column 29: operator '*' has no form for string and int"
    );
}

#[test]
fn redeclaration_is_refused_in_one_scope_but_not_in_an_inner_one() {
    assert_eq!(
        msg("int x = 1;\nfloat x = 2;"),
        "line 2, column 7: redeclaration of 'x'"
    );
    let g = detail("int x = 1; { float x = 2; } i@r = x;");
    assert_eq!(di(&g, "r"), 1);
}

#[test]
fn syntax_errors_say_what_was_expected() {
    assert_eq!(
        msg("@P.y += 1\n@P.x = 2;"),
        "line 2, column 1: expected ';' but found '@P'"
    );
    assert_eq!(
        msg("if (1 { }"),
        "line 1, column 7: expected ')' but found '{'"
    );
    assert_eq!(
        msg("float x = ;"),
        "line 1, column 11: expected an expression but found ';'"
    );
    assert_eq!(
        msg("s@n = \"open;"),
        "line 1, column 7: unterminated string"
    );
}

#[test]
fn type_errors_of_bindings_and_assignments() {
    assert_eq!(
        msg("i@a = 1; f@a = 2;"),
        "line 1, column 10: @a is bound as i@a (int) and f@a (float)"
    );
    assert_eq!(msg("@ptnum = 3;"), "line 1, column 1: @ptnum is read-only");
    assert_eq!(
        msg("vector v = \"x\";"),
        "line 1, column 12: cannot convert string to vector"
    );
    assert_eq!(msg("break;"), "line 1, column 1: 'break' outside a loop");
    assert_eq!(
        msg("float f(float x) { return f(x); } f@a = f(1);"),
        "line 1, column 27: 'f' calls itself: VEX functions cannot recurse"
    );
}

#[test]
fn runtime_errors_name_the_element() {
    let g = four_points();
    let e = wrangle_with(
        "if (@ptnum == 2) addprim(0, \"nurbs\", 0, 1);",
        geode_geo::AttribClass::Point,
        &g,
        &[],
    )
    .unwrap_err();
    assert_eq!(e, "element 2 (line 1, column 18): addprim: unknown type \"nurbs\": expected \"poly\" or \"polyline\"");
}

/// A geometry change checked when it applies, after every element ran,
/// still names the statement that queued it (it used to say line 0).
#[test]
fn an_effect_refused_when_it_applies_names_its_call() {
    let g = four_points();
    for class in [
        geode_geo::AttribClass::Point,
        geode_geo::AttribClass::Detail,
    ] {
        let src = "int n = 0;\nif (@ptnum == 0 || n == 0)\n    addprim(0, \"polyline\", 0, 1000);";
        let e = wrangle_with(src, class, &g, &[]).unwrap_err();
        assert!(
            e.contains("(line 3, column 5): point 1000 does not exist"),
            "{class:?}: {e}"
        );
    }
}

/// A swapped pair of letters is one edit: the suggestion finds the name.
#[test]
fn transposed_letters_still_suggest_the_function() {
    assert_eq!(
        msg("f@n = nosie(@P);"),
        "line 1, column 7: unknown function 'nosie' (did you mean 'noise'?)"
    );
    assert!(msg("f@f = fti(1, 0, 1, 2, 3);").contains("did you mean 'fit'?"));
}

/// Where every form of a call writes an argument, it needs a variable
/// there; where only some forms do, the others are tried and the message
/// lists every form.
#[test]
fn outputs_need_a_variable_where_the_forms_write_them() {
    assert_eq!(
        msg("vector p; int n = intersect(0, @P, {0, 0, -1}, p, {1, 1, 1});"),
        "line 1, column 51: 'intersect' writes argument 5: it needs a variable, attribute, component or array element there"
    );
    let e = msg("vector uv; float d = xyzdist(0, @P, 3, uv);");
    assert!(
        e.starts_with("line 1, column 22: 'xyzdist' takes no (int, vector, int, vector); its forms: float xyzdist(int geo, vector pos"),
        "{e}"
    );
}

#[test]
fn unknown_options_are_named() {
    let run = |src: &str| {
        wrangle_with(src, geode_geo::AttribClass::Detail, &four_points(), &[]).unwrap_err()
    };
    assert_eq!(
        run(r#"vector p; float u, v; i@n = intersect(0, {0, 0, 1}, {0, 0, -2}, p, u, v, "nearest", 1);"#),
        "element 0 (line 1, column 29): intersect: unknown option \"nearest\": expected \"farthest\""
    );
    assert_eq!(
        run(
            r#"vector p; float u, v; i@n = intersect(0, {0, 0, 1}, {0, 0, -2}, p, u, v, "farthest");"#
        ),
        "element 0 (line 1, column 29): intersect: option \"farthest\" has no value after it"
    );
}
