//! Hostile Houdini files: 100,000 levels of nesting in `.geo` and `.bgeo`
//! are refused with their position and the limit (never a stack overflow),
//! and counts as large as an i64 holds (`boolRLE` runs, `nvertices_rle`
//! repeats, `startvertex`) are refused by name instead of overflowing.

use std::path::Path;

use geode_io::{parse_unguarded, read_bytes, Format, NoProgress};

const LEVELS: usize = 100_000;

fn error(bytes: &[u8], format: Format) -> String {
    let name = if format == Format::Geo {
        "x.geo"
    } else {
        "x.bgeo"
    };
    // Unguarded first: a panic here fails the test instead of being caught.
    parse_unguarded(bytes, format, None, &NoProgress).unwrap_err();
    read_bytes(bytes, format, Path::new(name), &NoProgress)
        .unwrap_err()
        .to_string()
}

#[test]
fn deeply_nested_text_json_is_refused_with_its_line_and_column() {
    let deep = format!("{}{}", "[".repeat(LEVELS), "]".repeat(LEVELS));
    assert_eq!(
        error(deep.as_bytes(), Format::Geo),
        "x.geo: line 1: column 128: malformed JSON: recursion limit exceeded at line 1 column 128"
    );
    let maps = "{\"a\":".repeat(LEVELS);
    assert_eq!(
        error(maps.as_bytes(), Format::Geo),
        "x.geo: line 1: column 636: malformed JSON: recursion limit exceeded at line 1 column 636"
    );
}

#[test]
fn deeply_nested_binary_json_is_refused_with_its_byte_offset() {
    let mut arrays = b"\x7fNSJb".to_vec();
    arrays.extend(std::iter::repeat_n(b'[', LEVELS));
    assert_eq!(
        error(&arrays, Format::Bgeo),
        "x.bgeo: byte 261: nesting deeper than 256 levels"
    );
    // Maps nest through their values (key: a string token, then a map).
    let mut maps = b"\x7fNSJb".to_vec();
    for _ in 0..LEVELS {
        maps.extend_from_slice(b"{\x27\x01k");
    }
    assert_eq!(
        error(&maps, Format::Bgeo),
        "x.bgeo: byte 1029: nesting deeper than 256 levels"
    );
}

/// A triangle whose primitive run and point group are given by `run` and `rle`.
fn triangle(run: &str, rle: &str) -> String {
    format!(
        r#"["pointcount",3,"vertexcount",3,"primitivecount",1,
        "topology",["pointref",["indices",[0,1,2]]],
        "attributes",["pointattributes",[[["scope","public","type","numeric","name","P"],
            ["size",3,"storage","fpreal32","values",["size",3,"storage","fpreal32","tuples",[[0,0,0],[1,0,0],[0,1,0]]]]]]],
        "primitives",[[["type","Polygon_run"],{run}]],
        "pointgroups",[[["name","g"],["selection",["unordered",["boolRLE",{rle}]]]]]]"#
    )
}

#[test]
fn counts_as_large_as_an_i64_are_refused_by_name() {
    let run = r#"["startvertex",0,"nprimitives",1,"nvertices_rle",[3,1]]"#;
    let ok = triangle(run, "[1,true,2,false]");
    let g = read_bytes(ok.as_bytes(), Format::Geo, Path::new("x.geo"), &NoProgress).unwrap();
    assert_eq!(g.num_prims(), 1);
    let max = i64::MAX;
    assert_eq!(
        error(
            triangle(run, &format!("[1,true,{max},false]")).as_bytes(),
            Format::Geo
        ),
        format!(
            "x.geo: pointgroups `g`: `boolRLE` run 1 counts {max} elements where 2 of 3 are left"
        )
    );
    assert_eq!(
        error(triangle(run, "[-1,true]").as_bytes(), Format::Geo),
        "x.geo: pointgroups `g`: `boolRLE` run 0 counts -1 elements where 3 of 3 are left"
    );
    let repeat = format!(r#"["startvertex",0,"nprimitives",1,"nvertices_rle",[3,1,3,{max}]]"#);
    assert_eq!(
        error(triangle(&repeat, "[3,true]").as_bytes(), Format::Geo),
        format!("x.geo: primitives[0] (Polygon_run): `nvertices_rle` repeats a size {max} times where 0 of `nprimitives` 1 are left")
    );
    let start = format!(r#"["startvertex",{max},"nprimitives",1,"nvertices_rle",[3,1]]"#);
    assert_eq!(
        error(triangle(&start, "[3,true]").as_bytes(), Format::Geo),
        format!("x.geo: primitives[0] (Polygon_run): a primitive of 3 vertices from vertex {max} runs past vertexcount 3")
    );
    let negative = r#"["startvertex",-3,"nprimitives",1,"nvertices_rle",[3,1]]"#;
    assert_eq!(
        error(triangle(negative, "[3,true]").as_bytes(), Format::Geo),
        "x.geo: primitives[0] (Polygon_run): a primitive of 3 vertices from vertex -3 runs past vertexcount 3"
    );
}

/// Packed geometry nested in packed geometry, as deep as the nesting limit
/// lets a file hold: the reader's recursion into embedded details fits a
/// test thread's stack, and one level past the limit is refused.
#[test]
fn the_deepest_embedded_packed_geometry_reads() {
    use geode_geo::{glam::Mat4, glam::Vec3, Geometry};
    use geode_io::write_bytes;
    let nest = |levels: usize| {
        let mut g = Geometry::new();
        g.add_point(Vec3::ZERO);
        for _ in 0..levels {
            let mut outer = Geometry::new();
            let p = outer.add_point(Vec3::X);
            outer
                .add_packed(p, std::sync::Arc::new(g), Mat4::IDENTITY)
                .unwrap();
            g = outer;
        }
        write_bytes(&g, Format::Bgeo, Path::new("x.bgeo"), &NoProgress).unwrap()
    };
    let (mut fits, mut refused) = (0, 0);
    for levels in (60..90).step_by(3) {
        let bytes = nest(levels);
        match read_bytes(&bytes, Format::Bgeo, Path::new("x.bgeo"), &NoProgress) {
            Ok(g) => {
                assert_eq!(g.packed_instances().len(), 1);
                fits = levels;
            }
            Err(e) => {
                assert!(
                    e.to_string().contains("nesting deeper than 256 levels"),
                    "{e}"
                );
                refused += 1;
            }
        }
    }
    assert!(
        fits >= 60 && refused > 0,
        "deepest read {fits}, refused {refused}"
    );
}
