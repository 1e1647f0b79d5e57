//! VEX's execution model on geometry: every element reads the input's
//! snapshot, its own writes are visible to itself, writes to other
//! elements and new or removed geometry apply after the run in element
//! order, and the output is the same bytes on any thread count.

mod common;
use common::*;

use geode_geo::glam::Vec2;
use geode_geo::{primitives, AttribClass, Geometry};

fn xs(g: &Geometry) -> Vec<f32> {
    g.positions().iter().map(|p| p.x).collect()
}

#[test]
fn elements_read_the_snapshot_not_each_others_writes() {
    let g = four_points();
    let out = wrangle(
        "@P.x += point(0, \"P\", (@ptnum + 1) % 4).x;",
        AttribClass::Point,
        &g,
    );
    assert_eq!(xs(&out), vec![1.0, 3.0, 5.0, 3.0]);
}

#[test]
fn an_element_sees_its_own_writes() {
    let out = wrangle(
        "@P.x = 10 + @ptnum; f@r = @P.x * 2;",
        AttribClass::Point,
        &four_points(),
    );
    assert_eq!(
        out.attrib(AttribClass::Point, "r")
            .unwrap()
            .as_f32()
            .unwrap(),
        &[20.0, 22.0, 24.0, 26.0]
    );
}

#[test]
fn writes_to_other_elements_apply_in_element_order() {
    let out = wrangle(
        "setpointattrib(0, \"sum\", 0, @ptnum, \"add\"); setpointattrib(0, \"last\", 0, @ptnum); setpointattrib(0, \"big\", 0, @ptnum * 2, \"max\");",
        AttribClass::Point,
        &four_points(),
    );
    assert_eq!(
        out.attrib(AttribClass::Point, "sum")
            .unwrap()
            .as_i32()
            .unwrap()[0],
        6
    );
    assert_eq!(
        out.attrib(AttribClass::Point, "last")
            .unwrap()
            .as_i32()
            .unwrap()[0],
        3
    );
    assert_eq!(
        out.attrib(AttribClass::Point, "big")
            .unwrap()
            .as_i32()
            .unwrap()[0],
        6
    );
    let d = wrangle(
        "setdetailattrib(0, \"total\", @P.x, \"add\");",
        AttribClass::Point,
        &four_points(),
    );
    assert_eq!(df(&d, "total"), 6.0);
}

#[test]
fn new_points_and_primitives_are_numbered_in_element_order() {
    let out = wrangle(
        "int p = addpoint(0, @P + {0, 1, 0}); int pr = addprim(0, \"polyline\", @ptnum, p); setprimattrib(0, \"from\", pr, @ptnum); setpointattrib(0, \"top\", p, 1);",
        AttribClass::Point,
        &four_points(),
    );
    assert_eq!(out.num_points(), 8);
    assert_eq!(out.num_prims(), 4);
    for i in 0..4 {
        assert_eq!(out.positions()[4 + i].to_array(), [i as f32, 1.0, 0.0]);
        assert_eq!(out.prim_points(i), &[i as u32, 4 + i as u32]);
    }
    assert_eq!(
        out.attrib(AttribClass::Primitive, "from")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[0, 1, 2, 3]
    );
    assert_eq!(
        out.attrib(AttribClass::Point, "top")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[0, 0, 0, 0, 1, 1, 1, 1]
    );
}

#[test]
fn addprim_then_addvertex_builds_a_polygon() {
    let out = wrangle(
        "int pr = addprim(0, \"poly\"); for (int i = 0; i < 3; i++) addvertex(0, pr, i);",
        AttribClass::Detail,
        &four_points(),
    );
    assert_eq!(out.num_prims(), 1);
    assert_eq!(out.prim_points(0), &[0, 1, 2]);
    let copy = wrangle(
        "int p = addpoint(0, 3); setpointattrib(0, \"P\", p, {9, 9, 9});",
        AttribClass::Detail,
        &four_points(),
    );
    assert_eq!(copy.num_points(), 5);
    assert_eq!(copy.positions()[4].to_array(), [9.0, 9.0, 9.0]);
}

/// `addpoint`/`addprim` with literal arguments run as calls of numbers;
/// a string variable or an array of points takes the general path. Both
/// make the same geometry, over the detail and over points.
#[test]
fn calls_of_edits_and_of_values_make_the_same_geometry() {
    let direct = "int a = addpoint(0, set(@P.x, 2, 0)); int b = addpoint(0, 1); addprim(0, \"polyline\", a, b); addprim(0, \"poly\", a, b, 0);";
    let values = "string t = \"polyline\"; string u = \"poly\"; int a = addpoint(0, set(@P.x, 2, 0)); int b = addpoint(0, 1); addprim(0, t, array(a, b)); addprim(0, u, a, b, 0);";
    for class in [AttribClass::Detail, AttribClass::Point] {
        let one = wrangle(direct, class, &four_points());
        let two = wrangle(values, class, &four_points());
        let n = if class == AttribClass::Detail { 1 } else { 4 };
        assert_eq!(one.num_points(), 4 + 2 * n);
        assert_eq!(one.num_prims(), 2 * n);
        assert_eq!(one.positions(), two.positions());
        for k in 0..one.num_prims() {
            assert_eq!(one.prim_points(k), two.prim_points(k), "{class:?} prim {k}");
            assert_eq!(one.prim_kinds()[k], two.prim_kinds()[k]);
        }
        // The copy of point 1 sits where point 1 is.
        assert_eq!(one.positions()[5], one.positions()[1]);
    }
    for bad in [
        "addprim(0, \"curve\", 0, 1);",
        "string t = \"curve\"; addprim(0, t, 0, 1);",
    ] {
        let msg = wrangle_with(bad, AttribClass::Detail, &four_points(), &[])
            .expect_err("an unknown type is refused");
        assert!(msg.contains("unknown type \"curve\""), "{msg}");
    }
}

/// addvertex on the input's primitives from every element: each gets its
/// vertices in element order, then call order, on any thread count.
#[test]
fn addvertex_on_input_primitives_applies_in_element_order() {
    let grid = primitives::grid(Vec2::splat(4.0), 30, 30);
    let src =
        "int pr = @ptnum % 7; addvertex(0, pr, @ptnum); if (@ptnum % 2 == 0) addvertex(0, pr, 0);";
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| wrangle(src, AttribClass::Point, &grid))
    };
    let out = run_on(1);
    for prim in 0..7 {
        let mut want: Vec<u32> = grid.prim_points(prim).to_vec();
        for p in (prim as u32..grid.num_points() as u32).step_by(7) {
            want.push(p);
            if p % 2 == 0 {
                want.push(0);
            }
        }
        assert_eq!(out.prim_points(prim), &want[..], "primitive {prim}");
    }
    assert_eq!(out.prim_points(7), grid.prim_points(7));
    for threads in [2, 8] {
        assert_eq!(run_on(threads), out, "{threads} threads");
    }
}

/// A packed primitive takes no vertex: the element that asks is named.
#[test]
fn addvertex_on_a_packed_primitive_is_refused() {
    let mut g = four_points();
    g.add_packed(
        0,
        std::sync::Arc::new(four_points()),
        geode_geo::glam::Mat4::IDENTITY,
    )
    .unwrap();
    let e = wrangle_with(
        "if (@ptnum == 2) addvertex(0, 0, 1);",
        AttribClass::Point,
        &g,
        &[],
    )
    .unwrap_err();
    assert_eq!(
        e,
        "element 2 (line 1, column 18): addvertex: primitive 0 is a packed primitive: only polygons and polylines take vertices"
    );
}

#[test]
fn removals_apply_after_the_run() {
    let out = wrangle(
        "if (@ptnum % 2) removepoint(0, @ptnum); f@seen = npoints(0);",
        AttribClass::Point,
        &four_points(),
    );
    assert_eq!(xs(&out), vec![0.0, 2.0]);
    assert_eq!(
        out.attrib(AttribClass::Point, "seen")
            .unwrap()
            .as_f32()
            .unwrap(),
        &[4.0, 4.0]
    );
    let grid = primitives::grid(Vec2::splat(1.0), 3, 3);
    let n = grid.num_prims();
    let out = wrangle(
        "if (@primnum == 0) removeprim(0, @primnum, 1);",
        AttribClass::Primitive,
        &grid,
    );
    assert_eq!(out.num_prims(), n - 1);
}

#[test]
fn groups_are_set_and_read() {
    let out = wrangle(
        "setpointgroup(0, \"odd\", @ptnum, @ptnum % 2);",
        AttribClass::Point,
        &four_points(),
    );
    let g = out.point_groups().get("odd").expect("the group");
    assert_eq!(
        (0..4).map(|i| g.contains(i)).collect::<Vec<_>>(),
        vec![false, true, false, true]
    );
    let read = wrangle(
        "i@in = inpointgroup(0, \"odd\", @ptnum);",
        AttribClass::Point,
        &out,
    );
    assert_eq!(
        read.attrib(AttribClass::Point, "in")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[0, 1, 0, 1]
    );
}

#[test]
fn primitives_and_vertices_bind_their_numbers() {
    let grid = primitives::grid(Vec2::splat(1.0), 3, 3);
    let out = wrangle(
        "i@n = len(primpoints(0, @primnum)) * 100 + @primnum;",
        AttribClass::Primitive,
        &grid,
    );
    let n: Vec<i32> = (0..grid.num_prims() as i32).map(|p| 400 + p).collect();
    assert_eq!(
        out.attrib(AttribClass::Primitive, "n")
            .unwrap()
            .as_i32()
            .unwrap(),
        n.as_slice()
    );
    let out = wrangle(
        "i@pr = @primnum; i@pt = @ptnum; i@v = @vtxnum;",
        AttribClass::Vertex,
        &grid,
    );
    let pr = out
        .attrib(AttribClass::Vertex, "pr")
        .unwrap()
        .as_i32()
        .unwrap();
    let pt = out
        .attrib(AttribClass::Vertex, "pt")
        .unwrap()
        .as_i32()
        .unwrap();
    let v = out
        .attrib(AttribClass::Vertex, "v")
        .unwrap()
        .as_i32()
        .unwrap();
    for i in 0..grid.num_vertices() {
        assert_eq!(v[i], i as i32);
        assert_eq!(pt[i], grid.vertex_points()[i] as i32);
        assert!(grid.prim_vertex_range(pr[i] as usize).contains(&i));
    }
}

#[test]
fn other_inputs_are_read_by_number_and_by_opinput_bindings() {
    let mut other = four_points();
    for p in other.positions_mut() {
        p.y = 5.0;
    }
    let (out, _) = wrangle_with(
        "@P.y = @opinput1_P.y + point(1, \"P\", 0).y; i@n = npoints(1);",
        AttribClass::Point,
        &four_points(),
        &[&other],
    )
    .unwrap();
    assert!(out.positions().iter().all(|p| p.y == 10.0));
    assert_eq!(
        out.attrib(AttribClass::Point, "n")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[4; 4]
    );
}

#[test]
fn neighbours_follow_the_topology() {
    let grid = primitives::grid(Vec2::splat(1.0), 3, 3);
    let out = wrangle(
        "i@nc = neighbourcount(0, @ptnum); i@np = len(pointprims(0, @ptnum));",
        AttribClass::Point,
        &grid,
    );
    let nc = out
        .attrib(AttribClass::Point, "nc")
        .unwrap()
        .as_i32()
        .unwrap();
    let np = out
        .attrib(AttribClass::Point, "np")
        .unwrap()
        .as_i32()
        .unwrap();
    // A 3x3-quad grid has 4x4 points: point 5 is inside (4 quads, 4
    // neighbours), point 4 on an edge, point 0 a corner.
    assert_eq!((nc[5], np[5]), (4, 4));
    assert_eq!((nc[4], np[4]), (3, 2));
    assert_eq!((nc[0], np[0]), (2, 1));
}

#[test]
fn printf_prints_in_element_order() {
    let (_, report) = wrangle_with(
        "printf(\"%d;\", @ptnum);",
        AttribClass::Point,
        &four_points(),
        &[],
    )
    .unwrap();
    assert_eq!(report.printed.concat(), "0;1;2;3;");
}

#[test]
fn a_group_limits_the_elements() {
    let g = four_points();
    let s = spec_default(AttribClass::Point, &g);
    let p = geode_vex::compile("@P.y = 1;", &s).unwrap();
    let mut out = g.clone();
    let cancel = || false;
    geode_vex::run(
        &p,
        &mut out,
        &[Some(&g)],
        &geode_vex::RunOptions {
            group: Some(&[1, 3]),
            cancel: &cancel,
            memory_budget: u64::MAX,
        },
    )
    .unwrap();
    assert_eq!(
        out.positions().iter().map(|p| p.y).collect::<Vec<_>>(),
        vec![0.0, 1.0, 0.0, 1.0]
    );
}

#[test]
fn an_endless_loop_stops_on_cancel() {
    // Over points (masks) and over the detail (one lane, plain jumps),
    // with and without a call in the loop (the one-lane path hands calls
    // to the batch path and must still count its turns).
    let g = four_points();
    for class in [AttribClass::Point, AttribClass::Detail] {
        for src in [
            "int i = 0; while (1) { i++; }",
            "float s = 0; for (;;) { s += sin(s); }",
            "int a[]; while (1) { push(a, 1); pop(a); }",
        ] {
            let s = spec_default(class, &g);
            let p = geode_vex::compile(src, &s).unwrap();
            let mut out = g.clone();
            let t0 = std::time::Instant::now();
            let cancel = move || t0.elapsed().as_millis() > 50;
            let r = geode_vex::run(
                &p,
                &mut out,
                &[Some(&g)],
                &geode_vex::RunOptions {
                    group: None,
                    cancel: &cancel,
                    memory_budget: u64::MAX,
                },
            );
            assert_eq!(
                r.unwrap_err(),
                geode_vex::RunError::Cancelled,
                "{class:?}: {src}"
            );
        }
    }
}

/// A wrangle that reads, writes, creates and removes over many batches.
const BUSY: &str = r#"
vector n = normalize(@P + {0.1, 0.2, 0.3});
@P += n * noise(@P * 3) * 0.1;
f@r = rand(@ptnum);
setpointattrib(0, "acc", @ptnum % 7, 1, "add");
if (@ptnum % 5 == 0) {
    int p = addpoint(0, @P * 2);
    addprim(0, "polyline", @ptnum, p);
}
if (@ptnum % 11 == 3) removepoint(0, @ptnum);
"#;

#[test]
fn one_and_many_threads_give_the_same_bytes() {
    let grid = primitives::grid(Vec2::splat(4.0), 120, 120);
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| wrangle(BUSY, AttribClass::Point, &grid))
    };
    let one = run_on(1);
    assert!(one.num_points() > grid.num_points());
    for threads in [2, 3, 8] {
        assert_eq!(
            run_on(threads).content_hash(),
            one.content_hash(),
            "{threads} threads"
        );
    }
}

#[test]
fn array_attributes_are_bound_and_appended_to() {
    let out = wrangle(
        "i[]@assoc = array(); setpointattrib(0, \"assoc\", 0, array(@ptnum), \"append\"); f[]@w = array(@P.x, 1);",
        AttribClass::Point,
        &four_points(),
    );
    match out.attrib(AttribClass::Point, "assoc").unwrap().data() {
        geode_geo::AttribData::IntArray(v) => {
            assert_eq!(v, &vec![vec![0, 1, 2, 3], vec![], vec![], vec![]])
        }
        other => panic!("{:?}", other.attrib_type()),
    }
    match out.attrib(AttribClass::Point, "w").unwrap().data() {
        geode_geo::AttribData::FloatArray(v) => assert_eq!(v[2], vec![2.0, 1.0]),
        other => panic!("{:?}", other.attrib_type()),
    }
    let read = wrangle(
        "int a[] = i[]@assoc; i@n = len(a);",
        AttribClass::Point,
        &out,
    );
    assert_eq!(
        read.attrib(AttribClass::Point, "n")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[4, 0, 0, 0]
    );
    let near = wrangle("setpointgroup(0, \"far\", @ptnum, @ptnum >= 2); i@n = nearpoint(0, \"far\", {0, 0, 0}, 10);", AttribClass::Point, &four_points());
    assert_eq!(
        near.attrib(AttribClass::Point, "n")
            .unwrap()
            .as_i32()
            .unwrap(),
        &[-1; 4]
    );
}

#[test]
fn matrix3_vector_and_string_array_attributes_round_trip() {
    let out = wrangle(
        "3@xf = ident() * (@ptnum + 1); v[]@trail = array(@P, @P * 2); s[]@tags = array(\"a\", itoa(@ptnum));",
        AttribClass::Point,
        &four_points(),
    );
    let xf = out.attrib(AttribClass::Point, "xf").unwrap();
    assert_eq!(
        xf.as_mat3().unwrap()[2],
        geode_geo::glam::Mat3::from_diagonal(geode_geo::glam::Vec3::splat(3.0))
    );
    match out.attrib(AttribClass::Point, "trail").unwrap().data() {
        geode_geo::AttribData::Vec3Array(v) => assert_eq!(
            v[1],
            vec![geode_geo::glam::Vec3::X, geode_geo::glam::Vec3::X * 2.0]
        ),
        other => panic!("{:?}", other.attrib_type()),
    }
    match out.attrib(AttribClass::Point, "tags").unwrap().data() {
        geode_geo::AttribData::StringArray(v) => {
            assert_eq!(v[3], vec!["a".to_string(), "3".to_string()])
        }
        other => panic!("{:?}", other.attrib_type()),
    }
    let read = wrangle("matrix3 m = 3@xf; vector t[] = v[]@trail; string s[] = s[]@tags; f@r = m.zz + t[1].x + len(s);", AttribClass::Point, &out);
    assert_eq!(
        read.attrib(AttribClass::Point, "r")
            .unwrap()
            .as_f32()
            .unwrap(),
        &[3.0, 6.0, 9.0, 12.0]
    );
}

/// Appends from many batches, interleaved over two attributes, with a
/// `set` and an `add` among them.
const APPENDS: &str = r#"
setdetailattrib(0, "ids", array(@ptnum * 10), "append");
setdetailattrib(0, "names", array(itoa(@ptnum)), "append");
if (@ptnum == 300) setdetailattrib(0, "ids", array(-1));
setdetailattrib(0, "ids", @ptnum * 10 + 1, "add");
setdetailattrib(0, "s", sprintf("%d,", @ptnum), "append");
setpointattrib(0, "trail", @ptnum % 3, array(@P), "append");
"#;

/// What `APPENDS` makes over `n` points at x = 0, 1, 2...: each element's
/// writes in call order, elements in order.
fn appends_by_hand(n: i32) -> (Vec<i32>, Vec<String>, String, Vec<Vec<f32>>) {
    let (mut ids, mut names, mut s, mut trail) =
        (Vec::new(), Vec::new(), String::new(), vec![Vec::new(); 3]);
    for p in 0..n {
        ids.push(p * 10);
        names.push(p.to_string());
        if p == 300 {
            ids = vec![-1];
        }
        ids.push(p * 10 + 1);
        s.push_str(&format!("{p},"));
        trail[(p % 3) as usize].push(p as f32);
    }
    (ids, names, s, trail)
}

fn points_in_a_row(n: usize) -> Geometry {
    let mut g = Geometry::new();
    let p: Vec<geode_geo::glam::Vec3> = (0..n)
        .map(|i| geode_geo::glam::Vec3::new(i as f32, 0.0, 0.0))
        .collect();
    g.add_points(&p);
    g
}

#[test]
fn appends_to_one_element_keep_element_then_call_order() {
    let n = 700; // three batches
    let out = wrangle(APPENDS, AttribClass::Point, &points_in_a_row(n));
    let (ids, names, s, trail) = appends_by_hand(n as i32);
    let detail = |name: &str| {
        out.attrib(AttribClass::Detail, name)
            .unwrap()
            .data()
            .clone()
    };
    assert_eq!(detail("ids"), geode_geo::AttribData::IntArray(vec![ids]));
    assert_eq!(
        detail("names"),
        geode_geo::AttribData::StringArray(vec![names])
    );
    assert_eq!(ds(&out, "s"), s);
    match out.attrib(AttribClass::Point, "trail").unwrap().data() {
        geode_geo::AttribData::Vec3Array(v) => {
            for (k, want) in trail.iter().enumerate() {
                let xs: Vec<f32> = v[k].iter().map(|p| p.x).collect();
                assert_eq!(&xs, want, "point {k}");
            }
            assert!(v[3..].iter().all(Vec::is_empty));
        }
        other => panic!("{:?}", other.attrib_type()),
    }
}

#[test]
fn appends_give_the_same_bytes_on_any_thread_count() {
    let g = points_in_a_row(2000);
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| wrangle(APPENDS, AttribClass::Point, &g))
    };
    let one = run_on(1);
    for threads in [2, 3, 8] {
        assert_eq!(run_on(threads), one, "{threads} threads");
        assert_eq!(run_on(threads).content_hash(), one.content_hash());
    }
}

/// A vector appended to a float array gives its floats, an int one float;
/// a vector array keeps whole vectors.
#[test]
fn appends_convert_to_the_columns_type() {
    let out = wrangle(
        r#"f[]@fa = array(); v[]@va = array();
setdetailattrib(0, "fa", {1, 2, 3}, "append");
setdetailattrib(0, "fa", 4, "append");
setdetailattrib(0, "va", {6, 7, 8}, "append");
setdetailattrib(0, "va", set(9, 10), "append");"#,
        AttribClass::Detail,
        &four_points(),
    );
    let detail = |name: &str| {
        out.attrib(AttribClass::Detail, name)
            .unwrap()
            .data()
            .clone()
    };
    assert_eq!(
        detail("fa"),
        geode_geo::AttribData::FloatArray(vec![vec![1.0, 2.0, 3.0, 4.0]])
    );
    assert_eq!(
        detail("va"),
        geode_geo::AttribData::Vec3Array(vec![vec![geode_geo::glam::Vec3::new(6.0, 7.0, 8.0)]])
    );
}

/// n elements appending to one detail array cost O(n): 16 times the
/// elements take about 16 times as long, not 256 (generous bounds: the
/// machine may be shared).
#[test]
fn appending_to_one_array_is_linear_in_the_appends() {
    let src = r#"setdetailattrib(0, "ids", array(@ptnum), "append");"#;
    let time = |n: usize| {
        let g = points_in_a_row(n);
        let t = std::time::Instant::now();
        let out = wrangle(src, AttribClass::Point, &g);
        let took = t.elapsed();
        match out.attrib(AttribClass::Detail, "ids").unwrap().data() {
            geode_geo::AttribData::IntArray(v) => assert_eq!(v[0].len(), n),
            other => panic!("{:?}", other.attrib_type()),
        }
        took
    };
    let small = (0..3).map(|_| time(25_000)).min().unwrap();
    let large = time(400_000);
    assert!(
        large < small * 64,
        "400k appends took {large:?}, 25k {small:?}"
    );
}

/// SideFX: over primitives `@P` is the average of the primitive's points;
/// over vertices, attributes the vertices lack are read from their points
/// (then primitives). Both read-only there, and saying why.
#[test]
fn primitives_read_their_centroid_and_vertices_their_points() {
    let g = primitives::grid(Vec2::new(2.0, 2.0), 2, 2);
    let out = wrangle("f@cx = @P.x; f@cz = @P.z;", AttribClass::Primitive, &g);
    let cx = out
        .attrib(AttribClass::Primitive, "cx")
        .unwrap()
        .as_f32()
        .unwrap()
        .to_vec();
    let cz = out
        .attrib(AttribClass::Primitive, "cz")
        .unwrap()
        .as_f32()
        .unwrap()
        .to_vec();
    for prim in 0..g.num_prims() {
        let points = g.prim_points(prim);
        let mean = points
            .iter()
            .map(|&p| g.positions()[p as usize])
            .sum::<geode_geo::glam::Vec3>()
            / points.len() as f32;
        assert!((cx[prim] - mean.x).abs() < 1e-6 && (cz[prim] - mean.z).abs() < 1e-6);
    }
    // Over vertices: the point's position and uv, the primitive's number
    // attribute, and a vertex attribute of its own before any of them.
    let mut g = g;
    let ids: Vec<i32> = (0..g.num_prims() as i32).map(|i| 10 + i).collect();
    g.set_attrib(
        AttribClass::Primitive,
        "id",
        geode_geo::Attribute::from_data(geode_geo::AttribData::Int(ids), geode_geo::TypeInfo::None),
    )
    .unwrap();
    let out = wrangle(
        "f@vx = @P.x; v@t = @uv; i@owner = i@id;",
        AttribClass::Vertex,
        &g,
    );
    let vx = out
        .attrib(AttribClass::Vertex, "vx")
        .unwrap()
        .as_f32()
        .unwrap();
    let owner = out
        .attrib(AttribClass::Vertex, "owner")
        .unwrap()
        .as_i32()
        .unwrap();
    for (v, &p) in g.vertex_points().iter().enumerate() {
        assert_eq!(vx[v], g.positions()[p as usize].x);
        assert_eq!(owner[v], 10 + g.topology().prim_of_vertex(v) as i32);
    }
    let e = geode_vex::compile("@P.y = 1;", &spec_default(AttribClass::Primitive, &g)).unwrap_err();
    assert!(
        e.to_string().contains("average of each primitive's points"),
        "{e}"
    );
    let e = geode_vex::compile("@uv.x = 1;", &spec_default(AttribClass::Vertex, &g)).unwrap_err();
    assert!(e.to_string().contains("from their points"), "{e}");
}
