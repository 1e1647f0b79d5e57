//! Data-driven: every OpenSubdiv regression shape in the test corpus (`corpus/`) reads,
//! with its tags available as attributes that match the tag lines.

mod common;

use geode_geo::AttribClass;
use geode_io::{obj, read, NoProgress};

#[test]
fn every_opensubdiv_shape_reads_with_its_tags() {
    let dir = common::corpus().join("opensubdiv");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(
        files.len() >= 80,
        "expected the full corpus, found {} files",
        files.len()
    );
    for path in files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
    {
        let text = std::fs::read_to_string(path).unwrap();
        let g = read(path, &NoProgress).unwrap_or_else(|e| panic!("{e}"));
        let name = path.file_name().unwrap().to_string_lossy();
        let count = |prefix: &str| text.lines().filter(|l| l.starts_with(prefix)).count();
        assert_eq!(g.num_points(), count("v "), "{name}: points");
        assert_eq!(g.num_prims(), count("f "), "{name}: faces");
        assert!(geode_geo::ops::validate(&g).is_empty(), "{name}");

        // Every crease tag's edge carries its sharpness on the vertices of that edge.
        let topo = g.topology();
        for line in text.lines().filter(|l| l.starts_with("t crease ")) {
            let t: Vec<&str> = line.split_whitespace().collect();
            let (a, b, s): (u32, u32, f32) = (
                t[3].parse().unwrap(),
                t[4].parse().unwrap(),
                t[5].parse().unwrap(),
            );
            let c = g
                .attrib(AttribClass::Vertex, obj::CREASE)
                .unwrap()
                .as_f32()
                .unwrap();
            let e = topo.find_edge(a, b).unwrap();
            for h in topo.edge_half_edges(e) {
                assert_eq!(c[h.0 as usize], s, "{name}: crease {a}-{b}");
            }
        }
        for line in text.lines().filter(|l| l.starts_with("t corner ")) {
            let t: Vec<&str> = line.split_whitespace().collect();
            let (p, s): (usize, f32) = (t[3].parse().unwrap(), t[4].parse().unwrap());
            assert_eq!(
                g.attrib(AttribClass::Point, obj::CORNER)
                    .unwrap()
                    .as_f32()
                    .unwrap()[p],
                s,
                "{name}: corner {p}"
            );
        }
        for line in text
            .lines()
            .filter(|l| l.starts_with("t interpolateboundary "))
        {
            let v: i32 = line.split_whitespace().nth(3).unwrap().parse().unwrap();
            assert_eq!(
                g.attrib(AttribClass::Detail, obj::BOUNDARY)
                    .unwrap()
                    .as_i32()
                    .unwrap(),
                &[v],
                "{name}"
            );
        }
        for line in text.lines().filter(|l| l.starts_with("t hole ")) {
            let t: Vec<&str> = line.split_whitespace().collect();
            let holes = g
                .attrib(AttribClass::Primitive, obj::HOLE)
                .unwrap()
                .as_i32()
                .unwrap();
            for f in &t[3..] {
                assert_eq!(holes[f.parse::<usize>().unwrap()], 1, "{name}: hole {f}");
            }
        }
        if text.contains("t creasemethod") {
            assert!(
                g.attrib(AttribClass::Detail, obj::CREASE_METHOD).is_some(),
                "{name}"
            );
        }
        if text.contains("edit ") {
            assert!(
                g.attrib(AttribClass::Detail, obj::RAW_TAGS).is_some(),
                "{name}: hierarchical edits kept"
            );
        }
        // Writing and reading back keeps the content exactly.
        let back = geode_io::read_bytes(
            &geode_io::write_bytes(&g, geode_io::Format::Obj, path, &NoProgress).unwrap(),
            geode_io::Format::Obj,
            path,
            &NoProgress,
        )
        .unwrap();
        assert_eq!(back.num_points(), g.num_points(), "{name}");
        assert_eq!(back.positions(), g.positions(), "{name}");
        for class in [
            AttribClass::Point,
            AttribClass::Vertex,
            AttribClass::Primitive,
            AttribClass::Detail,
        ] {
            for (n, a) in g.attribs(class).iter() {
                assert_eq!(
                    back.attrib(class, n).map(|b| b.data()),
                    Some(a.data()),
                    "{name}: {class} {n}"
                );
            }
        }
    }
}
