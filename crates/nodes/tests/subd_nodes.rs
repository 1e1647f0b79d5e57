//! The subdivide node on OpenSubdiv-tagged OBJ files, through the engine.

mod common;

use common::{err, geo};
use geode_geo::AttribClass;

#[test]
fn subdividing_a_creased_box_keeps_its_creases_and_closes() {
    let path = format!(
        "{}/../../examples/assets/creased_box.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let nodes = format!(
        r#""box": {{"type": "file", "params": {{"file": "{path}"}}}},
            "smooth": {{"type": "subdivide", "inputs": ["box"], "params": {{"levels": 3, "limit": true}}}}"#
    );
    let g = geo(&nodes, "smooth");
    let base = geo(&nodes, "box");
    assert_eq!(g.num_prims(), 64 * base.num_prims());
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    assert!(g.attrib(AttribClass::Point, "N").is_some());
    // Chaikin differs from uniform decay where semi-sharp creases meet.
    let shape = format!(
        "{}/../../../shared/corpus/opensubdiv/catmark_chaikin1.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let chaikin = |method: &str| {
        geo(
            &format!(
                r#""m": {{"type": "file", "params": {{"file": "{shape}"}}}}, "s": {{"type": "subdivide", "inputs": ["m"], "params": {{"levels": 2, "crease_method": "{method}"}}}}"#
            ),
            "s",
        )
    };
    assert!(
        chaikin("chaikin").positions() != chaikin("uniform").positions(),
        "the crease method is applied"
    );
    assert!(
        chaikin("from_geometry").positions() == chaikin("chaikin").positions(),
        "the shape's own tag says chaikin"
    );
    let e = err(
        r#""l": {"type": "curve_line"}, "s": {"type": "subdivide", "inputs": ["l"]}"#,
        "s",
    );
    assert!(e.contains("/s") && e.contains("not a polygon"), "{e}");
}
