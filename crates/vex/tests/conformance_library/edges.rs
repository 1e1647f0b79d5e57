//! Programs geode once got wrong (with the documented value), and programs
//! at the edges of the library that must neither panic nor hang.

use super::*;

/// Which geometry a known disagreement runs over.
#[derive(Debug, Clone, Copy)]
pub(super) enum Geo {
    Points,
    Quad,
    Tris,
}

impl Geo {
    pub(super) fn make(self) -> fn() -> geode_geo::Geometry {
        match self {
            Geo::Points => four_points,
            Geo::Quad => unit_quad,
            Geo::Tris => two_triangles,
        }
    }
}

/// Programs where geode gave something other than SideFX's documentation
/// says, each with the documented value (the comment says what geode gave
/// before the fix).
#[rustfmt::skip]
pub(super) const ONCE_DISAGREED: &[(Geo, &str, &str, Want)] = &[
    // invlerp: "If min and max are equal, the mixing value is 0.5." (geode: 0)
    (Geo::Points, r#"f@r = invlerp(3, 2, 2);"#, "r", F(0.5)),
    // find: "the first substring that starts at or after a start position,
    // and at or before an end position" ("bc" starts at 4; geode: -1, as if
    // the whole needle had to end before `end`).
    (Geo::Points, r#"i@r = find("abcabc", "bc", 3, 4);"#, "r", I(4)),
    // find: "int find(<type>array[], <type>target, int start) ... limit the
    // result to the first occurrence at or after a start position" (geode:
    // compile error, no start argument on arrays).
    (Geo::Points, r#"int a[] = {5, 6, 5}; i@r = find(a, 5, 1);"#, "r", I(2)),
    // re_split: "This does not match Python ... a,b, will only split into two
    // strings." (geode: 3)
    (Geo::Points, r#"string a[] = re_split(",", "a,b,"); i@r = len(a);"#, "r", I(2)),
    // sum: "float sum(<vector>v) Returns the sum of the vector's components."
    // (geode: compile error)
    (Geo::Points, r#"f@r = sum({1, 2, 3});"#, "r", F(6.0)),
    // upush: "Pushes a uniform value onto an array for all SIMD processors
    // (regardless of the processor enabled state)": it always appends
    // (geode: skips a value already present, len 2).
    (Geo::Points, r#"int a[] = {1, 2}; upush(a, 2); i@r = len(a);"#, "r", I(3)),
    // reorder: "string reorder(string value, int indices[]) Returns a
    // reordered version of the characters" (geode: compile error).
    (Geo::Points, r#"int o[] = {2, 0, 1}; s@r = reorder("abc", o);"#, "r", S("cab")),
    // nearpoint / nearpoints: "ptgroup: A point group pattern to limit the
    // search to. Can be a SOP-style group pattern such as 0-10" (geode: -1
    // and an empty array; only group names are looked up).
    (Geo::Points, r#"i@r = nearpoint(0, "2-3", {0, 0, 0});"#, "r", I(2)),
    (Geo::Points, r#"int n[] = sort(nearpoints(0, "0 3", {1, 0, 0}, 10)); i@r = len(n) * 100 + n[0] * 10 + n[1];"#, "r", I(203)),
    // attribtype: "3 Array of integers ... 4 Array of floats ... 5 Array of
    // strings" (geode: 4, 5, 6 as docs/wrangle.md says).
    (Geo::Quad, r#"i@r = attribtype(0, "point", "ia") * 100 + attribtype(0, "point", "fa") * 10 + attribtype(0, "point", "sa");"#, "r", I(345)),
    // Group syntax: "!pattern Every point/primitive except the ones matching
    // the pattern" (geode: empty).
    (Geo::Quad, r#"int a[] = expandpointgroup(0, "!1"); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10 + a[2];"#, "r", I(3023)),
    (Geo::Tris, r#"int a[] = expandprimgroup(0, "!0"); i@r = len(a) * 10 + a[0];"#, "r", I(11)),
    // expandpointgroup: "This uses the SOP group naming convention, in
    // particular that an empty string means all." (geode: empty)
    (Geo::Quad, r#"int a[] = expandpointgroup(0, ""); i@r = len(a);"#, "r", I(4)),
    // expandpointgroup: "ordered is the default mode and will return numbers
    // in the order of appearance in the string" (geode: sorted, {1, 3}).
    (Geo::Quad, r#"int a[] = expandpointgroup(0, "3 1"); i@r = len(a) * 100 + a[0] * 10 + a[1];"#, "r", I(231)),
    // setvertexattrib: "To use a linear vertex index, set the prim_num to the
    // linear vertex number and set vertex_num to -1. You can also instead set
    // the prim_num to -1 and the vertex_num to the linear vertex number."
    // (geode: nothing is written in either form)
    (Geo::Tris, r#"setvertexattrib(0, "c", -1, 4, 3.0); ||| f@r = vertex(0, "c", 4);"#, "r", F(3.0)),
    (Geo::Tris, r#"setvertexattrib(0, "c", 4, -1, 3.0); ||| f@r = vertex(0, "c", 4);"#, "r", F(3.0)),
    // slice, which the page calls "equivalent to using the
    // value[start:end:step] slice syntax": "If step is zero, the function
    // returns an empty string/array." (geode: the whole array or string)
    (Geo::Points, r#"int a[] = {1, 2, 3}; int b[] = a[::0]; i@r = len(b);"#, "r", I(0)),
    (Geo::Points, r#"string s = "abc"; s@r = s[::0];"#, "r", S("")),
];

/// Programs at the edges of the library (empty needles, bad handles,
/// out-of-range numbers, overflow): whatever they give, a compile error
/// included, they must neither panic nor hang.
#[rustfmt::skip]
pub(super) const EDGE_PROGRAMS: &[(Geo, &str)] = &[
    (Geo::Points, r#"int a[]; i@r = pop(a);"#),
    (Geo::Points, r#"int a[] = {1}; i@r = removeindex(a, 5);"#),
    (Geo::Points, r#"int a[]; i@r = a[-1];"#),
    (Geo::Points, r#"int a[]; insert(a, -5, 1); i@r = len(a);"#),
    (Geo::Points, r#"int a[] = {1}; resize(a, -3); i@r = len(a);"#),
    (Geo::Points, r#"i@r = atoi("12", 1);"#),
    (Geo::Points, r#"i@r = atoi("-99999999999");"#),
    (Geo::Points, r#"s@r = sprintf("%d %d", 1);"#),
    (Geo::Points, r#"s@r = sprintf("%*d|%q", 5, 3);"#),
    (Geo::Points, r#"s@r = sprintf("%.300f", 1.0);"#),
    (Geo::Points, r#"s@r = re_find("(", "abc");"#),
    (Geo::Points, r#"s@r = re_replace("[", "x", "abc");"#),
    (Geo::Points, r#"s@r = re_replace("", "-", "abc");"#),
    (Geo::Points, r#"string a[] = re_split("", "abc"); i@r = len(a);"#),
    (Geo::Points, r#"string a[] = re_findall("", "abc"); i@r = len(a);"#),
    (Geo::Points, r#"s@r = replace("abc", "", "x");"#),
    (Geo::Points, r#"i@r = find("abc", "");"#),
    (Geo::Points, r#"int w[] = find("aaa", ""); i@r = len(w);"#),
    (Geo::Points, r#"string p[] = split("abc", ""); i@r = len(p);"#),
    (Geo::Points, r#"s@r = strip("abc", "");"#),
    (Geo::Points, r#"s@r = chr(-1);"#),
    (Geo::Points, r#"s@r = chr(1114112);"#),
    (Geo::Points, r#"i@r = ord("");"#),
    (Geo::Points, r#"string s = "h\xc3\xa9llo"; s@r = s[1] + s[-1:];"#),
    (Geo::Points, r#"s@r = toupper("stra\xc3\x9fe");"#),
    (Geo::Points, r#"i@r = abs(-2147483647 - 1);"#),
    (Geo::Points, r#"int m = -2147483647 - 1; i@r = m / -1;"#),
    (Geo::Points, r#"int m = -2147483647 - 1; i@r = m % -1;"#),
    (Geo::Points, r#"i@r = 1 << 40;"#),
    (Geo::Points, r#"s@r = itoa(-2147483647 - 1);"#),
    (Geo::Points, r#"int a[] = {3, 1}; i@r = sum(a) + 2147483647;"#),
    (Geo::Points, r#"int a[] = expandpointgroup(0, "5-2"); i@r = len(a);"#),
    (Geo::Points, r#"int a[] = expandpointgroup(0, "0-10000000"); i@r = len(a);"#),
    (Geo::Points, r#"int a[] = expandpointgroup(0, "0-3:0"); i@r = len(a);"#),
    (Geo::Points, r#"int a[] = expandpointgroup(0, "-3--1 ^ ! *"); i@r = len(a);"#),
    (Geo::Points, r#"i@r = primpoint(0, 99, 0) + vertexpoint(0, -5) + pointvertex(0, 99);"#),
    (Geo::Points, r#"f@r = xyzdist(0, {0, 0, 0});"#),
    (Geo::Points, r#"vector p, uvw; i@r = intersect(0, {0, 0, 0}, {1, 0, 0}, p, uvw);"#),
    (Geo::Points, r#"f@r = primuv(0, "P", 0, {0.5, 0.5, 0}).x;"#),
    (Geo::Tris, r#"vector p; float u, v; i@r = intersect(0, {1, 1, 1}, {0, 0, -2}, p, u, v, 3, 1);"#),
    (Geo::Tris, r#"vector p; float u, v; i@r = intersect(0, {1, 1, 1}, {0, 0, -2}, p, u, v, "farthest", 1, "farthest");"#),
    (Geo::Tris, r#"vector p; float u, v; i@r = intersect(0, {1, 1, 1}, {0, 0, 0}, p, u, v, "farthest", 1);"#),
    (Geo::Tris, r#"vector p, uvw; i@r = intersect(0, "^*", {1, 1, 1}, {0, 0, -2}, p, uvw);"#),
    (Geo::Tris, r#"int pr; vector uv; f@r = xyzdist(0, "0-99999 ^1", {1, 1, 1}, pr, uv, -1) + xyzdist(0, "!*", {1, 1, 1});"#),
    (Geo::Points, r#"int h = pcopen(0, "P", {0, 0, 0}, -1, -1); i@r = pcnumfound(h);"#),
    (Geo::Points, r#"int h = pcopen(0, "P", {0, 0, 0}, 10, 0); vector v = pcfilter(h, "P"); f@r = v.x;"#),
    (Geo::Points, r#"vector v = pcfilter(5, "P"); i@r = pciterate(99) + pcnumfound(-1);"#),
    (Geo::Points, r#"int h = pcopen(0, "nope", {0, 0, 0}, 10, 4); float x; while (pciterate(h)) pcimport(h, "nope", x); f@r = x;"#),
    (Geo::Points, r#"int n[] = nearpoints(0, {0, 0, 0}, 1e30, -1); i@r = len(n);"#),
    (Geo::Points, r#"i@r = nearpoint(0, {0, 0, 0}, -1);"#),
    (Geo::Points, r#"matrix3 m = 0; m = invert(m); f@r = m.xx;"#),
    (Geo::Points, r#"f@r = smooth(1, 1, 1) + fit(1, 2, 2, 0, 1) + efit(1, 2, 2, 0, 1);"#),
    (Geo::Points, r#"f@r = qdistance({0, 0, 0, 0}, {0, 0, 0, 0});"#),
    (Geo::Points, r#"p@r = slerp({0, 0, 0, 0}, {0, 0, 0, 0}, 0.5);"#),
    (Geo::Points, r#"v@r = quaterniontoeuler({0, 0, 0, 0}, 99);"#),
    (Geo::Points, r#"matrix m = maketransform(99, -4, {1, 2, 3}, {4, 5, 6}, {0, 0, 0}); f@r = determinant(m);"#),
    (Geo::Points, r#"matrix3 m = lookat({1, 1, 1}, {1, 1, 1}, {0, 0, 0}); f@r = m.xx;"#),
    (Geo::Points, r#"v@r = cracktransform(0, 0, 9, {0, 0, 0}, ident());"#),
    (Geo::Points, r#"matrix m = 0; v@r = cracktransform(XFORM_TRS, XFORM_ZYX, 1, {1, 2, 3}, {4, 5, 6}, m);"#),
    (Geo::Points, r#"matrix m = maketransform(0, 0, {1, 2, 3}, {4, 5, 6}, {0, 1, 0}); vector t, r, s, sh; cracktransform(99, -7, {0, 0, 0}, {0, 0, 0}, m, t, r, s, sh); v@r = t + r + s + sh;"#),
    (Geo::Points, r#"matrix m = {1e30, 0, 0, 0, 0, 1e-30, 0, 0, 0, 0, -1e30, 0, 1, 1, 1, 1}; v@r = cracktransform(XFORM_TSR, XFORM_YXZ, 0, {0, 0, 0}, m);"#),
    (Geo::Points, r#"vector4 q = dihedral({1, 0, 0}, {-1, 0, 0}); p@r = q;"#),
    (Geo::Points, r#"vector4 q = dihedral({0, 0, 0}, {1, 0, 0}); p@r = q;"#),
    (Geo::Points, r#"int a[] = argsort(array()); i@r = len(a);"#),
    (Geo::Points, r#"int a[] = {1, 2}; int o[] = {5, -9}; int b[] = reorder(a, o); i@r = len(b);"#),
    (Geo::Points, r#"int a[] = {1, 2, 3}; int b[] = a[-100:100:-7]; i@r = len(b);"#),
    (Geo::Points, r#"int a[] = {1, 2, 3}; int b[] = a[2147483647:-2147483647:-2147483647]; i@r = len(b);"#),
    (Geo::Points, r#"string s = "abc"; s@r = s[-2147483647 - 1:];"#),
    (Geo::Points, r#"setpointattrib(0, "a", 99, 1); setpointattrib(0, "a", -1, 1); i@r = 1;"#),
    (Geo::Points, r#"removepoint(0, 99); removeprim(0, 5, 1); i@r = 1;"#),
    (Geo::Points, r#"int p = addprim(0, "poly", 0, 99); addvertex(0, 42, 1); addvertex(0, p, -3); i@r = p;"#),
    (Geo::Points, r#"int p = addprim(0, "nonsense", 0, 1); i@r = p;"#),
    (Geo::Points, r#"setpointgroup(0, "", 1, 1); setprimgroup(0, "g", 0, 1); i@r = 1;"#),
    (Geo::Tris, r#"i@r = hedge_next(0, 12345) + hedge_srcpoint(0, -7) + hedge_prim(0, 99999);"#),
    (Geo::Tris, r#"i@r = neighbour(0, 99, 0) + neighbourcount(0, -1) + len(neighbours(0, 42));"#),
    (Geo::Tris, r#"vector p, uvw; i@r = intersect(0, {1, 1, 1}, {0, 0, 0}, p, uvw);"#),
    (Geo::Tris, r#"int pr; vector uv; f@r = xyzdist(0, {1, 1, 1}, pr, uv, -1);"#),
    (Geo::Tris, r#"f@r = primuv(0, "P", 7, {0.5, 0.5, 0}).x + primuv(0, "P", 0, {9, -9, 0}).x;"#),
    (Geo::Tris, r#"f@r = primintrinsic(0, "nonsense", 0) + primintrinsic(0, "measuredarea", 99);"#),
    (Geo::Tris, r#"v@r = getbbox_min(0, "nonsense") + relbbox(0, {1, 1, 1});"#),
    (Geo::Tris, r#"i@r = vertexindex(0, -1, -1) + vertexprimindex(0, 99) + vertexnext(0, -2);"#),
    (Geo::Quad, r#"i@r = findattribval(0, "point", "name", 3) + findattribval(0, "vertex", "f", 1);"#),
    (Geo::Quad, r#"i@r = uniqueval(0, "point", "id", 99) + nuniqueval(0, "point", "f");"#),
    (Geo::Quad, r#"f@r = primuv(0, "name", 0, {0.5, 0.5, 0});"#),
    (Geo::Quad, r#"f@r = point(0, "f", -1) + vertex(0, "vf", 0, 99) + prim(0, "pf", 99);"#),
];
