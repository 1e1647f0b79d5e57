//! Malformed input gives an error naming the file and the position, never a panic.

use std::path::Path;

use geode_io::{read, Format, NoProgress, Position};

fn read_err(name: &str, bytes: &[u8]) -> geode_io::IoError {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let e = read(&path, &NoProgress).expect_err("must be rejected");
    assert!(
        e.to_string().starts_with(&path.display().to_string()),
        "names the file: {e}"
    );
    e
}

#[test]
fn truncated_binary_stl() {
    let mut bytes = geode_io::write_bytes(
        &geode_geo::primitives::cube(1.0),
        Format::Stl,
        Path::new("c.stl"),
        &NoProgress,
    )
    .unwrap();
    bytes.truncate(bytes.len() - 7);
    let e = read_err("cube.stl", &bytes);
    assert_eq!(e.position(), Some(Position::Byte(84 + 50 * 11)));
    assert!(
        e.to_string()
            .contains("declares 12 triangles (684 bytes) but the file has 677 bytes: truncated"),
        "{e}"
    );
}

#[test]
fn obj_index_out_of_range() {
    let e = read_err("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
    assert_eq!(e.position(), Some(Position::Line(5)));
    assert!(
        e.to_string()
            .ends_with("line 5: vertex index 4 out of range (3 vertexs defined so far)"),
        "{e}"
    );
}

#[test]
fn ply_with_wrong_counts() {
    let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n";
    let e = read_err("short.ply", text.as_bytes());
    assert_eq!(e.position(), Some(Position::Line(13)));
    // The face line is taken for the fourth vertex and has one number too many.
    assert!(
        e.to_string()
            .ends_with("line 13: unexpected `2` after the element's declared properties"),
        "{e}"
    );
    let long = text.replace("element vertex 4", "element vertex 2");
    let e = read_err("long.ply", long.as_bytes());
    assert!(
        e.to_string()
            .ends_with("line 12: unexpected `0` after the element's declared properties"),
        "{e}"
    );

    let bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0\0\0\0\0\0\0\0\0\0\0";
    let e = read_err("short_bin.ply", bin);
    let body = bin.len() - 14;
    assert_eq!(e.position(), Some(Position::Byte(body as u64 + 12)));
    assert!(
        e.to_string()
            .contains("file ends while reading property `x` of vertex 1 of 2"),
        "{e}"
    );
}

#[test]
fn empty_files() {
    for ext in ["obj", "stl", "ply", "glb", "gltf"] {
        let e = read_err(&format!("empty.{ext}"), b"");
        assert_eq!(e.position(), Some(Position::Byte(0)));
        assert!(e.to_string().contains("empty file"), "{e}");
    }
}

/// A fixed-seed xorshift so the "random" bytes are the same on every run.
fn noise(seed: u64, len: usize) -> Vec<u8> {
    let mut x = seed;
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect()
}

#[test]
fn random_bytes_never_panic() {
    for seed in 1..200u64 {
        let bytes = noise(seed, (seed as usize * 37) % 3000 + 1);
        for f in [Format::Obj, Format::Stl, Format::Ply, Format::Glb] {
            let name = Path::new("noise").with_extension(f.extension());
            // Errors are fine; a panic (caught or not) is not.
            if let Err(e) = geode_io::parse_unguarded(&bytes, f, None, &NoProgress) {
                assert!(!e.message.is_empty());
            }
            let _ = geode_io::read_bytes(&bytes, f, &name, &NoProgress);
        }
    }
    // Prefixes of valid files exercise deeper paths than pure noise.
    let g = geode_geo::primitives::torus(1.0, 0.3, 8, 6);
    for f in [Format::Obj, Format::Stl, Format::Ply, Format::Glb] {
        let valid = geode_io::write_bytes(&g, f, Path::new("t"), &NoProgress).unwrap();
        for cut in (1..valid.len()).step_by(valid.len() / 97 + 1) {
            let _ = geode_io::parse_unguarded(&valid[..cut], f, None, &NoProgress);
        }
        let mut flipped = valid.clone();
        for i in (0..flipped.len()).step_by(53) {
            flipped[i] ^= 0x5a;
            let _ = geode_io::parse_unguarded(&flipped, f, None, &NoProgress);
        }
    }
}

#[test]
fn random_bytes_error_names_file_and_position() {
    let e = read_err("noise.obj", &noise(7, 500));
    assert!(e.position().is_some(), "{e}");
    let e = read_err("noise.ply", &noise(7, 500));
    assert_eq!(e.position(), Some(Position::Line(1)), "{e}");
    let e = read_err("noise.stl", &noise(7, 500));
    assert!(matches!(e.position(), Some(Position::Byte(_))), "{e}");
}

/// Inputs that once crashed a reader under cargo-fuzz stay rejected cleanly.
#[test]
fn fuzz_regressions() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            continue; // the VDB reader's, replayed by tests/vdb.rs
        }
        let f = Format::from_path(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let _ = geode_io::parse_unguarded(&bytes, f, None, &NoProgress);
        n += 1;
    }
    assert!(n >= 3);
}

/// Declared counts are untrusted: a huge count costs neither time nor memory.
#[test]
fn huge_declared_counts_are_cheap() {
    let empty_elements =
        b"ply\nformat binary_little_endian 1.0\nelement junk 4000000000\nend_header\n";
    let g = geode_io::parse_unguarded(empty_elements, Format::Ply, None, &NoProgress).unwrap();
    assert_eq!(g.num_points(), 0);
    let huge = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n\0\0\0\0";
    let e = geode_io::parse_unguarded(huge, Format::Ply, None, &NoProgress).unwrap_err();
    assert!(
        e.message
            .contains("file ends while reading property `x` of vertex 1 of 4000000000"),
        "{}",
        e.message
    );
}

/// glTF nodes listing the same child twice at each of 60 levels would walk
/// 2^60 nodes: refused at the visit limit instead of hanging.
#[test]
fn gltf_node_hierarchies_sharing_children_are_refused() {
    let levels = 60;
    let nodes: Vec<String> = (0..levels)
        .map(|i| format!(r#"{{"children": [{0}, {0}]}}"#, i + 1))
        .chain(std::iter::once("{}".to_string()))
        .collect();
    let doc = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{}]}}"#,
        nodes.join(", ")
    );
    let e = geode_io::parse_unguarded(doc.as_bytes(), Format::Gltf, None, &NoProgress).unwrap_err();
    assert_eq!(
        e.message,
        "node hierarchy reaches more than 1000000 nodes (children shared between parents?)"
    );
}

/// A GLB header declaring fewer bytes than itself is refused by its byte
/// (gltf's reader subtracted and overflowed; found by the read_gltf fuzz target).
#[test]
fn glb_headers_shorter_than_themselves_are_refused() {
    let mut glb = b"glTF\x02\0\0\0\x04\0\0\0".to_vec();
    glb.extend_from_slice(&[0; 20]);
    let e = geode_io::parse_unguarded(&glb, Format::Glb, None, &NoProgress).unwrap_err();
    assert_eq!(e.pos, Some(Position::Byte(8)));
    assert_eq!(
        e.message,
        "invalid GLB: the header declares 4 bytes, fewer than the header's 12"
    );
}
