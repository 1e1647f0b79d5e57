//! docs/wrangle.md's function reference is the library table's: this test
//! fails when they differ and rewrites it with GEODE_WRITE_DOCS=1.

use std::path::PathBuf;

const BEGIN: &str = "<!-- functions:begin -->\n";
const END: &str = "<!-- functions:end -->";

#[test]
fn the_function_reference_is_the_tables() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/wrangle.md");
    let text = std::fs::read_to_string(&path).expect("docs/wrangle.md");
    let start = text.find(BEGIN).expect("the begin marker") + BEGIN.len();
    let end = text.find(END).expect("the end marker");
    let want = geode_vex::docs_markdown();
    if text[start..end] == want {
        return;
    }
    if std::env::var_os("GEODE_WRITE_DOCS").is_some() {
        let new = format!("{}{want}{}", &text[..start], &text[end..]);
        std::fs::write(&path, new).expect("write docs/wrangle.md");
        return;
    }
    panic!("docs/wrangle.md's function reference is stale: run GEODE_WRITE_DOCS=1 cargo test -p geode-vex --test docs");
}
