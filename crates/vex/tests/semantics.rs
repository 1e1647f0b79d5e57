//! The semantics issue 34 found wrong, each checked against what SideFX's
//! VEX reference documents (quoted at each test), not against geode.

mod common;
use common::*;

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry};

/// A triangle (points 0-2) and a quad (points 3-6) side by side.
fn tri_and_quad() -> Geometry {
    let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
    Geometry::from_polygons(
        vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(0.0, 1.0),
            p(2.0, 0.0),
            p(3.0, 0.0),
            p(3.0, 1.0),
            p(2.0, 1.0),
        ],
        vec![0, 1, 2, 3, 4, 5, 6],
        &[3, 4],
    )
    .expect("valid polygons")
}

/// A polyline through four points.
fn polyline() -> Geometry {
    let mut g = four_points();
    g.add_polyline(&[0, 1, 2, 3]).expect("points exist");
    g
}

fn ints(g: &Geometry, class: AttribClass, name: &str) -> Vec<i32> {
    g.attrib(class, name).unwrap().as_i32().unwrap().to_vec()
}

/// "@numvtx: the number of vertices in the primitive" (VEX attributes
/// page), in primitive and vertex wrangles.
#[test]
fn numvtx_counts_the_primitives_vertices() {
    let g = tri_and_quad();
    let prims = wrangle("i@n = @numvtx;", AttribClass::Primitive, &g);
    assert_eq!(ints(&prims, AttribClass::Primitive, "n"), vec![3, 4]);
    let verts = wrangle("i@n = @numvtx;", AttribClass::Vertex, &g);
    assert_eq!(
        ints(&verts, AttribClass::Vertex, "n"),
        vec![3, 3, 3, 4, 4, 4, 4]
    );
}

/// "@group_name: ... assigning 1 puts the element in the group, 0 takes it
/// out" (VEX attributes page, "Accessing group membership").
#[test]
fn group_bindings_read_and_write_membership() {
    let out = wrangle(
        "@group_right = @P.x > 1.5;",
        AttribClass::Point,
        &four_points(),
    );
    let grp = out.point_groups().get("right").expect("the group is made");
    assert_eq!(
        (0..4).map(|p| grp.contains(p)).collect::<Vec<_>>(),
        vec![false, false, true, true]
    );
    // Read back, and an element that does not assign keeps its membership.
    let again = wrangle(
        "i@was = @group_right; if (@ptnum == 0) @group_right = 1;",
        AttribClass::Point,
        &out,
    );
    assert_eq!(ints(&again, AttribClass::Point, "was"), vec![0, 0, 1, 1]);
    let grp = again.point_groups().get("right").unwrap();
    assert_eq!(
        (0..4).map(|p| grp.contains(p)).collect::<Vec<_>>(),
        vec![true, false, true, true]
    );
}

/// removepoint: "If and_prims is 1, the function deletes any degenerate
/// primitives that referred to the removed point (for example, closed
/// polygons with fewer than 3 vertices or open polygons with fewer than 2
/// vertices). If this is 0, the function only deletes primitives that
/// become invalid."
#[test]
fn removepoint_keeps_what_is_not_degenerate() {
    let out = wrangle(
        "if (@ptnum == 1) removepoint(0, @ptnum);",
        AttribClass::Point,
        &polyline(),
    );
    assert_eq!(out.num_points(), 3);
    assert_eq!(out.num_prims(), 1, "the polyline keeps its other points");
    assert_eq!(out.prim_points(0), &[0, 1, 2]);
    let xs: Vec<f32> = out.positions().iter().map(|p| p.x).collect();
    assert_eq!(xs, vec![0.0, 2.0, 3.0]);

    // A triangle losing a corner is degenerate: removed by default, kept
    // (with two vertices) when and_prims is 0; the quad loses a corner and
    // stays a triangle either way.
    let g = tri_and_quad();
    let gone = wrangle(
        "if (@ptnum == 0 || @ptnum == 3) removepoint(0, @ptnum);",
        AttribClass::Point,
        &g,
    );
    assert_eq!(gone.num_prims(), 1);
    assert_eq!(gone.prim_points(0).len(), 3);
    let kept = wrangle(
        "if (@ptnum == 0) removepoint(0, @ptnum, 0);",
        AttribClass::Point,
        &g,
    );
    assert_eq!(kept.num_prims(), 2);
    assert_eq!(kept.prim_points(0).len(), 2);
}

/// removeprim: "If andpoints is 1, the function will also delete any
/// points associated with the primitive that are not associated with any
/// other primitives." Points no primitive used before stay.
#[test]
fn removeprim_deletes_only_its_own_unshared_points() {
    let mut g = tri_and_quad();
    g.add_point(Vec3::new(9.0, 9.0, 9.0));
    let out = wrangle(
        "if (@primnum == 1) removeprim(0, @primnum, 1);",
        AttribClass::Primitive,
        &g,
    );
    assert_eq!(out.num_prims(), 1);
    assert_eq!(out.num_points(), 4, "the triangle's 3 and the lone point");
}

/// setvertexattrib: "If prim_num is -1, vertex_num is a linear vertex
/// index."
#[test]
fn setvertexattrib_takes_a_linear_vertex_with_prim_minus_one() {
    let out = wrangle(
        "setvertexattrib(0, \"va\", -1, 4, 7);",
        AttribClass::Detail,
        &tri_and_quad(),
    );
    assert_eq!(
        ints(&out, AttribClass::Vertex, "va"),
        vec![0, 0, 0, 0, 7, 0, 0]
    );
}

/// maketransform(trs, xyz, t, r, s): "trs: the transform order
/// (XFORM_SRT, XFORM_TRS ...)"; with row vectors each step applies in the
/// order named: TRS translates, rotates, then scales.
#[test]
fn maketransform_follows_its_order_code() {
    let trs = detail(
        "matrix m = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 2, 2}); v@r = {1, 0, 0} * m;",
    );
    let r = dv(&trs, "r");
    for (a, b) in r.iter().zip([-4.0, 4.0, 6.0]) {
        assert!((a - b).abs() < 1e-5, "{r:?}");
    }
    let srt = detail(
        "matrix m = maketransform(5 - 5, 0, {1, 2, 3}, {0, 0, 90}, {2, 2, 2}); v@r = {1, 0, 0} * m;",
    );
    let r = dv(&srt, "r");
    for (a, b) in r.iter().zip([1.0, 4.0, 3.0]) {
        assert!((a - b).abs() < 1e-5, "{r:?}");
    }
}

/// "Arguments to user functions are always passed by reference, so
/// modifications in a function affect the variable the function was
/// called with" (VEX language reference, Functions): an attribute passed
/// to a function that writes it is written.
#[test]
fn a_binding_passed_by_reference_is_written() {
    let g = four_points();
    let src =
        "void up(vector p) { p.y = 1; } void tag(float x) { x = 7; } up(@P); tag(f@w); up(@N);";
    let out = wrangle(src, AttribClass::Point, &g);
    assert!(
        out.positions().iter().all(|p| p.y == 1.0),
        "@P written through the parameter"
    );
    let w = out
        .attrib(AttribClass::Point, "w")
        .unwrap()
        .as_f32()
        .unwrap();
    assert_eq!(w, [7.0; 4]);
    let n = out
        .attrib(AttribClass::Point, "N")
        .expect("@N made by the write");
    assert_eq!(n.as_vec3().unwrap()[0], Vec3::new(0.0, 1.0, 0.0));
    // A function that only reads its parameter writes nothing back.
    let out = wrangle(
        "float len(vector v) { return length(v); } f@l = len(@N);",
        AttribClass::Point,
        &g,
    );
    assert!(out.attrib(AttribClass::Point, "N").is_none());
    // A read-only attribute cannot be written through a parameter.
    let e = compile_error("void bump(int x) { x++; } bump(@ptnum);");
    assert!(e.to_string().contains("@ptnum is read-only"), "{e}");
}

/// xyzdist's group form reads its third argument (the position); the
/// plain form writes it ("&prim: ... overwrites this variable with the
/// primitive number of the closest primitive"): a binding there is
/// written, or created, only by the form that writes it.
#[test]
fn a_binding_is_written_only_by_the_form_that_writes_it() {
    let g = two_triangles();
    // v@q does not exist: it reads as zero, whose closest point on
    // primitive 1 (x + y >= 2) is (1, 1, 0).
    let read = wrangle(
        r#"f@d = xyzdist(0, "second", v@q);"#,
        AttribClass::Point,
        &g,
    );
    assert!(read.attrib(AttribClass::Point, "q").is_none());
    let d = read
        .attrib(AttribClass::Point, "d")
        .unwrap()
        .as_f32()
        .unwrap();
    assert!(
        d.iter()
            .all(|x| (x - std::f32::consts::SQRT_2).abs() < 1e-6),
        "{d:?}"
    );
    let written = wrangle(
        "vector uv; f@d = xyzdist(0, {2, 1.5, 1}, i@pr, uv);",
        AttribClass::Point,
        &g,
    );
    assert_eq!(ints(&written, AttribClass::Point, "pr"), vec![1; 4]);
}
