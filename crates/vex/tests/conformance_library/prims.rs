//! Library programs over primitives: a unit quad, two triangles and an open
//! polyline, each with its documented value.

use super::*;

/// Over `unit_quad`: one quad whose parametric (u, v) is its (x, y).
#[rustfmt::skip]
pub(super) const QUAD_CASES: &[(&str, &str, Want)] = &[
    (r#"f@r = point(0, "f", 2);"#, "r", F(2.0)),
    (r#"f@r = prim(0, "pf", 0);"#, "r", F(5.0)),
    (r#"f@r = vertex(0, "vf", 3);"#, "r", F(13.0)),
    (r#"f@r = vertex(0, "vf", 0, 2);"#, "r", F(12.0)),
    (r#"f@r = detail(0, "d");"#, "r", F(4.5)),
    (r#"f@r = detail(0, "d", 0);"#, "r", F(4.5)),
    (r#"i@r = haspointattrib(0, "f");"#, "r", I(1)),
    (r#"i@r = hasprimattrib(0, "pf") * 10 + hasprimattrib(0, "f");"#, "r", I(10)),
    (r#"i@r = hasvertexattrib(0, "vf");"#, "r", I(1)),
    (r#"i@r = hasdetailattrib(0, "d") * 10 + hasdetailattrib(0, "nope");"#, "r", I(10)),
    (r#"i@r = hasattrib(0, "point", "f") * 10 + hasattrib(0, "prim", "f");"#, "r", I(10)),
    (r#"i@r = attribsize(0, "point", "P") * 100 + attribsize(0, "point", "f") * 10 + attribsize(0, "point", "nope");"#, "r", I(310)),
    // attribtype: "-1 Attribute not found ... 0 Integer, 1 Float or vector, 2 String".
    (r#"i@r = attribtype(0, "point", "id") * 100 + attribtype(0, "point", "P") * 10 + attribtype(0, "point", "name");"#, "r", I(12)),
    (r#"i@r = attribtype(0, "point", "nope");"#, "r", I(-1)),
    (r#"i@r = findattribval(0, "point", "id", 10);"#, "r", I(0)),
    (r#"i@r = findattribval(0, "point", "id", 10, 1);"#, "r", I(2)),
    (r#"i@r = findattribval(0, "point", "id", 99);"#, "r", I(-1)),
    (r#"i@r = findattribval(0, "point", "name", "c");"#, "r", I(3)),
    (r#"i@r = findattribvalcount(0, "point", "id", 10);"#, "r", I(2)),
    (r#"i@r = nuniqueval(0, "point", "id") * 10 + nuniqueval(0, "point", "name");"#, "r", I(33)),
    (r#"int s = 0; for (int i = 0; i < nuniqueval(0, "point", "id"); i++) s += uniqueval(0, "point", "id", i); i@r = s;"#, "r", I(60)),
    (r#"i@r = nvertices(0, 0);"#, "r", I(4)),
    (r#"i@r = primvertexcount(0, 0);"#, "r", I(4)),
    (r#"i@r = inpointgroup(0, "odd", 3) * 10 + inpointgroup(0, "odd", 2);"#, "r", I(10)),
    (r#"i@r = inprimgroup(0, "face", 0);"#, "r", I(1)),
    (r#"i@r = npointsgroup(0, "odd");"#, "r", I(2)),
    (r#"i@r = nprimitivesgroup(0, "face");"#, "r", I(1)),
    // Group patterns (SOP group syntax): "n-m" inclusive; "*" every element;
    // "^pattern" removes from the preceding results; "!pattern" every element
    // except; "n-m:step"; an empty string means all; numbers come back in
    // their order in the string ("ordered" mode).
    (r#"int a[] = expandpointgroup(0, "0-2"); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10 + a[2];"#, "r", I(3012)),
    (r#"int a[] = expandpointgroup(0, "*"); i@r = len(a);"#, "r", I(4)),
    (r#"int a[] = expandpointgroup(0, "* ^1"); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10 + a[2];"#, "r", I(3023)),
    (r#"int a[] = expandpointgroup(0, "^1"); i@r = len(a);"#, "r", I(0)),
    (r#"int a[] = expandpointgroup(0, "odd"); i@r = len(a) * 100 + a[0] * 10 + a[1];"#, "r", I(213)),
    (r#"int a[] = expandpointgroup(0, "o*"); i@r = len(a);"#, "r", I(2)),
    (r#"int a[] = expandpointgroup(0, "0-3:2"); i@r = len(a) * 100 + a[0] * 10 + a[1];"#, "r", I(202)),
    (r#"int a[] = expandpointgroup(0, "odd ^3"); i@r = len(a) * 10 + a[0];"#, "r", I(11)),
    (r#"int a[] = expandprimgroup(0, "face"); i@r = len(a) * 10 + a[0];"#, "r", I(10)),
    (r#"vector mn, mx; getbbox(0, mn, mx); v@r = mx - mn;"#, "r", V(&[1.0, 1.0, 0.0])),
    // primintrinsic on the unit square.
    (r#"f@r = primintrinsic(0, "measuredarea", 0);"#, "r", F(1.0)),
    (r#"f@r = primintrinsic(0, "measuredperimeter", 0);"#, "r", F(4.0)),
    (r#"i@r = primintrinsic(0, "closed", 0);"#, "r", I(1)),
    (r#"s@r = primintrinsic(0, "typename", 0);"#, "r", S("Poly")),
    (r#"i@r = primintrinsic(0, "vertexcount", 0);"#, "r", I(4)),
    (r#"i@r = primintrinsic(0, "pointcount", 0);"#, "r", I(4)),
    (r#"i@r = detailintrinsic(0, "primitivecount");"#, "r", I(1)),
    // xyzdist: the closest location on the surface, its primitive and uv in
    // the quad's bilinear space P0(1-u)(1-v) + P1(1-u)v + P2uv + P3u(1-v) = (u, v, 0).
    (r#"f@r = xyzdist(0, {0.25, 0.75, 2});"#, "r", F(2.0)),
    (r#"int pr; vector uv; xyzdist(0, {0.25, 0.75, 2}, pr, uv); i@r = pr;"#, "r", I(0)),
    (r#"int pr; vector uv; xyzdist(0, {0.25, 0.75, 2}, pr, uv); v@r = uv;"#, "r", V(&[0.25, 0.75, 0.0])),
    (r#"int pr; vector uv; f@r = xyzdist(0, {2, 0.5, 0}, pr, uv);"#, "r", F(1.0)),
    (r#"int pr; vector uv; xyzdist(0, {2, 0.5, 0}, pr, uv); v@r = uv;"#, "r", V(&[1.0, 0.5, 0.0])),
    // "&prim ... -1 if no primitive was found" (within maxdist).
    (r#"int pr = 7; vector uv; xyzdist(0, {0.5, 0.5, 5}, pr, uv, 1); i@r = pr;"#, "r", I(-1)),
    // primuv interpolates point, vertex and primitive attributes at (u, v):
    // weights (1-u)(1-v), (1-u)v, uv, u(1-v) = 0.1875, 0.5625, 0.1875, 0.0625.
    (r#"f@r = primuv(0, "f", 0, {0.25, 0.75, 0});"#, "r", F(1.125)),
    (r#"v@r = primuv(0, "P", 0, {0.25, 0.75, 0});"#, "r", V(&[0.25, 0.75, 0.0])),
    (r#"f@r = primuv(0, "vf", 0, {0.25, 0.75, 0});"#, "r", F(11.125)),
    (r#"f@r = primuv(0, "pf", 0, {0.25, 0.75, 0});"#, "r", F(5.0)),
    (r#"int pr; vector uv; xyzdist(0, {0.3, 0.6, 1}, pr, uv); v@r = primuv(0, "P", pr, uv);"#, "r", V(&[0.3, 0.6, 0.0])),
    (r#"vector n = normalize(prim_normal(0, 0, {0.5, 0.5, 0})); v@r = set(n.x, n.y, abs(n.z));"#, "r", V(&[0.0, 0.0, 1.0])),
    // intersect: "uses the length of the vector as the maximum distance".
    (r#"vector p, uvw; i@r = intersect(0, {0.25, 0.75, 1}, {0, 0, -2}, p, uvw);"#, "r", I(0)),
    (r#"vector p, uvw; intersect(0, {0.25, 0.75, 1}, {0, 0, -2}, p, uvw); v@r = p;"#, "r", V(&[0.25, 0.75, 0.0])),
    (r#"vector p, uvw; intersect(0, {0.25, 0.75, 1}, {0, 0, -2}, p, uvw); v@r = uvw;"#, "r", V(&[0.25, 0.75, 0.0])),
    (r#"vector p, uvw; i@r = intersect(0, {0.25, 0.75, 1}, {0, 0, -0.5}, p, uvw);"#, "r", I(-1)),
    (r#"vector p, uvw; i@r = intersect(0, {2, 2, 1}, {0, 0, -2}, p, uvw);"#, "r", I(-1)),
    (r#"setpointgroup(0, "odd", 1, 0); ||| i@r = npointsgroup(0, "odd");"#, "r", I(1)),
    // setpointgroup: "Use "toggle" to toggle the point's membership,
    // regardless of the value."
    (r#"setpointgroup(0, "t", 1, 1); setpointgroup(0, "t", 2, 0, "toggle"); ||| setpointgroup(0, "t", 1, 1, "toggle"); ||| i@r = inpointgroup(0, "t", 1) * 10 + inpointgroup(0, "t", 2);"#, "r", I(1)),
    // "The variadic argument "farthest" can be used to indicate whether to
    // return the last intersection instead of the first": a second quad
    // (primitive 1) one unit below the first.
    (r#"int a = addpoint(0, {0, 0, -1}); int b = addpoint(0, {0, 1, -1}); int c = addpoint(0, {1, 1, -1}); int d = addpoint(0, {1, 0, -1}); addprim(0, "poly", a, b, c, d); ||| vector p; float u, v; i@r = intersect(0, {0.25, 0.75, 1}, {0, 0, -5}, p, u, v);"#, "r", I(0)),
    (r#"int a = addpoint(0, {0, 0, -1}); int b = addpoint(0, {0, 1, -1}); int c = addpoint(0, {1, 1, -1}); int d = addpoint(0, {1, 0, -1}); addprim(0, "poly", a, b, c, d); ||| vector p; float u, v; i@r = intersect(0, {0.25, 0.75, 1}, {0, 0, -5}, p, u, v, "farthest", 1);"#, "r", I(1)),
    (r#"int a = addpoint(0, {0, 0, -1}); int b = addpoint(0, {0, 1, -1}); int c = addpoint(0, {1, 1, -1}); int d = addpoint(0, {1, 0, -1}); addprim(0, "poly", a, b, c, d); ||| vector p; float u, v; intersect(0, {0.25, 0.75, 1}, {0, 0, -5}, p, u, v, "farthest", 1); p@r = set(p.x, p.y, p.z, u);"#, "r", V(&[0.25, 0.75, -1.0, 0.25])),
    (r#"int a = addpoint(0, {0, 0, -1}); int b = addpoint(0, {0, 1, -1}); int c = addpoint(0, {1, 1, -1}); int d = addpoint(0, {1, 0, -1}); addprim(0, "poly", a, b, c, d); ||| vector p; float u, v; i@r = intersect(0, {0.25, 0.75, 1}, {0, 0, -5}, p, u, v, "farthest", 0);"#, "r", I(0)),
    // xyzdist's group form on the quad's group `face`.
    (r#"int pr; vector uv; xyzdist(0, "face", {0.25, 0.75, 2}, pr, uv); v@r = uv;"#, "r", V(&[0.25, 0.75, 0.0])),

    (r#"setvertexattrib(0, "vf", 0, 2, 9.0); ||| f@r = vertex(0, "vf", 2);"#, "r", F(9.0)),
    // addvertex: "Adds a vertex to a primitive in a geometry"; "prim_num:
    // The primitive number to add the vertex to. point_num: The point
    // number to wire the new vertex to." The input's quad takes a fifth
    // vertex, after its own; their vertex values stay, the new one's is
    // the default (0).
    (r#"addvertex(0, 0, 1); ||| i@r = primvertexcount(0, 0) * 10 + primpoint(0, 0, 4);"#, "r", I(51)),
    (r#"addvertex(0, 0, 1); ||| f@r = vertex(0, "vf", 0, 3) * 100 + vertex(0, "vf", 0, 4);"#, "r", F(1300.0)),
    // "You can use this number with setvertexattrib to set attributes on
    // the new vertex": writes apply after the vertex is added.
    (r#"addvertex(0, 0, 1); setvertexattrib(0, "vf", 0, 4, 7.0); ||| f@r = vertex(0, "vf", 0, 4);"#, "r", F(7.0)),
    // Removals come last: point 3 loses both its vertices.
    (r#"addvertex(0, 0, 3); removepoint(0, 3); ||| i@r = primvertexcount(0, 0) * 10 + npoints(0);"#, "r", I(33)),
];

/// Over `two_triangles`: primitive 0 on points (0, 1, 2), primitive 1 on
/// (1, 3, 2); p0 (0,0,0), p1 (2,0,0), p2 (0,2,0), p3 (3,3,0).
#[rustfmt::skip]
pub(super) const TRI_CASES: &[(&str, &str, Want)] = &[
    (r#"i@r = npoints(0) * 10 + nprimitives(0);"#, "r", I(42)),
    (r#"i@r = nvertices(0);"#, "r", I(6)),
    (r#"i@r = nvertices(0, 1);"#, "r", I(3)),
    (r#"i@r = primvertexcount(0, 1);"#, "r", I(3)),
    (r#"int p[] = primpoints(0, 1); i@r = p[0] * 100 + p[1] * 10 + p[2];"#, "r", I(132)),
    (r#"i@r = primpoint(0, 1, 1);"#, "r", I(3)),
    (r#"i@r = primvertex(0, 1, 0);"#, "r", I(3)),
    (r#"int v[] = primvertices(0, 1); i@r = v[0] * 100 + v[1] * 10 + v[2];"#, "r", I(345)),
    (r#"i@r = vertexindex(0, 1, 2);"#, "r", I(5)),
    // vertexindex: "Returns -1 if the function could not find the equivalent linear vertex index."
    (r#"i@r = vertexindex(0, 1, 3);"#, "r", I(-1)),
    (r#"i@r = vertexpoint(0, 4);"#, "r", I(3)),
    (r#"i@r = vertexprim(0, 4);"#, "r", I(1)),
    (r#"i@r = vertexprimindex(0, 4) * 10 + vertexprimindex(0, 2);"#, "r", I(12)),
    (r#"i@r = pointvertex(0, 2) * 10 + pointvertex(0, 3);"#, "r", I(24)),
    (r#"int v[] = pointvertices(0, 1); i@r = len(v) * 100 + v[0] * 10 + v[1];"#, "r", I(213)),
    // vertexnext / vertexprev: the next (previous) vertex sharing the point, or -1.
    (r#"i@r = vertexnext(0, 2);"#, "r", I(5)),
    (r#"i@r = vertexnext(0, 5);"#, "r", I(-1)),
    (r#"i@r = vertexprev(0, 5);"#, "r", I(2)),
    (r#"i@r = vertexprev(0, 0);"#, "r", I(-1)),
    (r#"int p[] = sort(pointprims(0, 2)); i@r = len(p) * 100 + p[0] * 10 + p[1];"#, "r", I(201)),
    (r#"int n[] = sort(neighbours(0, 1)); i@r = len(n) * 1000 + n[0] * 100 + n[1] * 10 + n[2];"#, "r", I(3023)),
    (r#"i@r = neighbourcount(0, 1) * 10 + neighbourcount(0, 0);"#, "r", I(32)),
    (r#"i@r = neighbour(0, 0, 0) + neighbour(0, 0, 1);"#, "r", I(3)),
    (r#"i@r = neighbour(0, 0, 2);"#, "r", I(-1)),
    (r#"i@r = inprimgroup(0, "second", 1) * 10 + inprimgroup(0, "second", 0);"#, "r", I(10)),
    (r#"i@r = nprimitivesgroup(0, "second");"#, "r", I(1)),
    (r#"i@r = inpointgroup(0, "corner", 0);"#, "r", I(1)),
    (r#"int a[] = expandprimgroup(0, "second"); i@r = len(a) * 10 + a[0];"#, "r", I(11)),
    (r#"int a[] = expandprimgroup(0, "*"); i@r = len(a);"#, "r", I(2)),
    // Half-edges.
    (r#"int h = primhedge(0, 1); i@r = hedge_prim(0, h);"#, "r", I(1)),
    (r#"i@r = hedge_isvalid(0, primhedge(0, 0)) * 10 + hedge_isvalid(0, -1);"#, "r", I(10)),
    (r#"int h = primhedge(0, 0); i@r = hedge_next(0, hedge_next(0, hedge_next(0, h))) == h;"#, "r", I(1)),
    (r#"int h = primhedge(0, 0); i@r = hedge_dstpoint(0, h) == hedge_srcpoint(0, hedge_next(0, h));"#, "r", I(1)),
    (r#"int h = primhedge(0, 1); int s = 0; for (int i = 0; i < 3; i++) { s += hedge_srcpoint(0, h); h = hedge_next(0, h); } i@r = s;"#, "r", I(6)),
    (r#"int h = pointhedge(0, 3); i@r = hedge_srcpoint(0, h);"#, "r", I(3)),
    (r#"int h = primhedge(0, 1); i@r = vertexpoint(0, hedge_srcvertex(0, h)) == hedge_srcpoint(0, h) && vertexpoint(0, hedge_dstvertex(0, h)) == hedge_dstpoint(0, h);"#, "r", I(1)),
    (r#"int h = primhedge(0, 1); i@r = vertexprim(0, hedge_srcvertex(0, h));"#, "r", I(1)),
    // Bounds: of every point, or of a primitive group's points.
    (r#"vector mn, mx; getbbox(0, mn, mx); v@r = mx;"#, "r", V(&[3.0, 3.0, 0.0])),
    (r#"v@r = getbbox_min(0);"#, "r", V(&[0.0, 0.0, 0.0])),
    (r#"v@r = getbbox_max(0);"#, "r", V(&[3.0, 3.0, 0.0])),
    (r#"v@r = getbbox_size(0);"#, "r", V(&[3.0, 3.0, 0.0])),
    (r#"v@r = getbbox_center(0);"#, "r", V(&[1.5, 1.5, 0.0])),
    (r#"v@r = getbbox_max(0, "0");"#, "r", V(&[2.0, 2.0, 0.0])),
    (r#"v@r = getbbox_size(0, "0");"#, "r", V(&[2.0, 2.0, 0.0])),
    (r#"v@r = getbbox_center(0, "0");"#, "r", V(&[1.0, 1.0, 0.0])),
    (r#"v@r = getbbox_min(0, "second");"#, "r", V(&[0.0, 0.0, 0.0])),
    (r#"vector mn, mx; getbbox(0, "0", mn, mx); v@r = mx;"#, "r", V(&[2.0, 2.0, 0.0])),
    (r#"vector r = relbbox(0, {1.5, 0.75, 0}); u@r = set(r.x, r.y);"#, "r", V(&[0.5, 0.25])),
    (r#"vector r = relpointbbox(0, {3, 0, 0}); f@r = r.x;"#, "r", F(1.0)),
    (r#"f@r = primintrinsic(0, "measuredarea", 0);"#, "r", F(2.0)),
    (r#"f@r = primintrinsic(0, "measuredperimeter", 0);"#, "r", F(6.828_427)),
    (r#"i@r = detailintrinsic(0, "pointcount") * 100 + detailintrinsic(0, "primitivecount") * 10 + detailintrinsic(0, "vertexcount");"#, "r", I(426)),
    // xyzdist in a triangle's space P0(1-u-v) + P1u + P2v.
    (r#"int pr; vector uv; f@r = xyzdist(0, {0.5, 0.5, -1}, pr, uv);"#, "r", F(1.0)),
    (r#"int pr; vector uv; xyzdist(0, {0.5, 0.5, -1}, pr, uv); v@r = uv;"#, "r", V(&[0.25, 0.25, 0.0])),
    (r#"int pr; vector uv; xyzdist(0, {0.5, 0.5, -1}, pr, uv); i@r = pr;"#, "r", I(0)),
    // (2, 1.5) on primitive 1: p1(1-u-v) + p3u + p2v = (2 + u - 2v, 3u + 2v).
    (r#"int pr; vector uv; xyzdist(0, {2, 1.5, 1}, pr, uv); i@r = pr;"#, "r", I(1)),
    (r#"int pr; vector uv; xyzdist(0, {2, 1.5, 1}, pr, uv); v@r = uv;"#, "r", V(&[0.375, 0.1875, 0.0])),
    (r#"v@r = primuv(0, "P", 1, {0.375, 0.1875, 0});"#, "r", V(&[2.0, 1.5, 0.0])),
    (r#"v@r = primuv(0, "P", 0, {0.25, 0.5, 0});"#, "r", V(&[0.5, 1.0, 0.0])),
    (r#"vector p, uvw; i@r = intersect(0, {2, 1.5, 1}, {0, 0, -5}, p, uvw);"#, "r", I(1)),
    (r#"vector p, uvw; intersect(0, {2, 1.5, 1}, {0, 0, -5}, p, uvw); v@r = uvw;"#, "r", V(&[0.375, 0.1875, 0.0])),
    // xyzdist's group forms: "Finds the distance from origin to the closest
    // location in the given primitive group on the given geometry"; the
    // group is "the name of a primitive group or a pattern to generate a
    // primitive group. Uses the same semantics as a SOP group, so empty
    // strings will match all primitives" (uvintersect's primgroup, worded
    // alike on xyzdist's page). Primitive 1 lies on x + y >= 2: from
    // (0.5, 0.5, -1) its closest point is (1, 1, 0) on edge p1-p2, at
    // sqrt(0.5 + 1); there (2 + u - 2v, 3u + 2v) = (1, 1): u 0, v 0.5.
    (r#"int pr; vector uv; f@r = xyzdist(0, "second", {0.5, 0.5, -1}, pr, uv);"#, "r", F(1.224_744_9)),
    (r#"int pr; vector uv; xyzdist(0, "second", {0.5, 0.5, -1}, pr, uv); i@r = pr;"#, "r", I(1)),
    (r#"int pr; vector uv; xyzdist(0, "second", {0.5, 0.5, -1}, pr, uv); v@r = uv;"#, "r", V(&[0.0, 0.5, 0.0])),
    (r#"f@r = xyzdist(0, "1", {0.5, 0.5, -1});"#, "r", F(1.224_744_9)),
    (r#"int pr; vector uv; xyzdist(0, "!0", {0.5, 0.5, -1}, pr, uv); i@r = pr;"#, "r", I(1)),
    (r#"int pr; vector uv; xyzdist(0, "", {0.5, 0.5, -1}, pr, uv); i@r = pr;"#, "r", I(0)),
    // "&prim ... -1 if no primitive was found": none in the group, or none
    // within maxdist of it.
    (r#"int pr = 7; vector uv; xyzdist(0, "nosuchgroup", {0.5, 0.5, -1}, pr, uv); i@r = pr;"#, "r", I(-1)),
    (r#"int pr = 7; vector uv; xyzdist(0, "second", {0.5, 0.5, -1}, pr, uv, 1); i@r = pr;"#, "r", I(-1)),
    // Each group its own surface within one run.
    (r#"int a, b; vector uv; xyzdist(0, "0", {2, 1.5, 1}, a, uv); xyzdist(0, "second", {0.5, 0.5, -1}, b, uv); i@r = a * 10 + b;"#, "r", I(1)),
    // intersect: "Computes the intersection of the specified ray with
    // primitives in the given group"; "group: If given, only intersect
    // primitives in this group." (0.5, 0.5) is inside primitive 0 only.
    (r#"vector p, uvw; i@r = intersect(0, "second", {0.5, 0.5, 1}, {0, 0, -5}, p, uvw);"#, "r", I(-1)),
    (r#"vector p, uvw; i@r = intersect(0, "0", {0.5, 0.5, 1}, {0, 0, -5}, p, uvw);"#, "r", I(0)),
    (r#"vector p, uvw; i@r = intersect(0, "second", {2, 1.5, 1}, {0, 0, -5}, p, uvw);"#, "r", I(1)),
    (r#"vector p, uvw; intersect(0, "second", {2, 1.5, 1}, {0, 0, -5}, p, uvw); v@r = uvw;"#, "r", V(&[0.375, 0.1875, 0.0])),
    (r#"vector p, uvw; intersect(0, "second", {2, 1.5, 1}, {0, 0, -5}, p, uvw); v@r = p;"#, "r", V(&[2.0, 1.5, 0.0])),
    (r#"vector p, uvw; i@r = intersect(0, "0", {2, 1.5, 1}, {0, 0, -5}, p, uvw);"#, "r", I(-1)),
    // "int intersect(<geometry>geometry, vector orig, vector dir, vector &p,
    // float &u, float &v)": the parametric location as two floats.
    (r#"vector p; float u, v; i@r = intersect(0, {2, 1.5, 1}, {0, 0, -5}, p, u, v);"#, "r", I(1)),
    (r#"vector p; float u, v; intersect(0, {2, 1.5, 1}, {0, 0, -5}, p, u, v); u@r = set(u, v);"#, "r", V(&[0.375, 0.1875])),
    (r#"vector p; float u, v; intersect(0, {2, 1.5, 1}, {0, 0, -5}, p, u, v); v@r = p;"#, "r", V(&[2.0, 1.5, 0.0])),
    (r#"vector p; float u = 3, v = 3; i@r = intersect(0, {5, 5, 1}, {0, 0, -5}, p, u, v);"#, "r", I(-1)),
    // Writes.
    (r#"setprimattrib(0, "w", 1, 2.5); ||| f@r = prim(0, "w", 1);"#, "r", F(2.5)),
    (r#"setvertexattrib(0, "c", 1, 2, 9.0); ||| f@r = vertex(0, "c", 5);"#, "r", F(9.0)),
    (r#"setprimgroup(0, "pg", 1, 1); ||| i@r = inprimgroup(0, "pg", 1) * 10 + inprimgroup(0, "pg", 0);"#, "r", I(10)),
    // addvertex on the input's primitive 0: primitive 1's vertices move
    // along (its first is now linear vertex 4).
    (r#"addvertex(0, 0, 3); ||| int p[] = primpoints(0, 0); i@r = len(p) * 10000 + p[0] * 1000 + p[1] * 100 + p[2] * 10 + p[3];"#, "r", I(40123)),
    (r#"addvertex(0, 0, 3); ||| i@r = primvertex(0, 1, 0) * 10 + vertexpoint(0, 4);"#, "r", I(41)),
    // With a new point and a new primitive in the same run: the new
    // primitive (0, 1, 4) comes after the input's (4 + 3 vertices).
    (r#"int p = addpoint(0, {5, 5, 0}); addprim(0, "poly", 0, 1, p); addvertex(0, 0, p); ||| i@r = primpoint(0, 0, 3) * 100 + primvertex(0, 2, 0) * 10 + primpoint(0, 2, 2);"#, "r", I(474)),
    // removeprim(..., 1): points no other primitive uses go too (p0 here).
    (r#"removeprim(0, 0, 1); ||| i@r = nprimitives(0) * 10 + npoints(0);"#, "r", I(13)),
    (r#"removeprim(0, 0, 0); ||| i@r = nprimitives(0) * 10 + npoints(0);"#, "r", I(14)),
    // removepoint(..., 1): "deletes any degenerate primitives that referred to the removed point".
    (r#"removepoint(0, 0, 1); ||| i@r = nprimitives(0) * 10 + npoints(0);"#, "r", I(13)),
];

/// Over `polyline`: four points at x = 0..3 joined by one open polyline.
#[rustfmt::skip]
pub(super) const LINE_CASES: &[(&str, &str, Want)] = &[
    (r#"i@r = primintrinsic(0, "closed", 0);"#, "r", I(0)),
    (r#"f@r = primintrinsic(0, "measuredperimeter", 0);"#, "r", F(3.0)),
    (r#"int pr; vector uv; f@r = xyzdist(0, {1.5, 2, 0}, pr, uv);"#, "r", F(2.0)),
    (r#"i@r = neighbourcount(0, 0) * 10 + neighbourcount(0, 1);"#, "r", I(12)),
];
