//! The binary field codec: every field comes back with its identity and its values; damaged bytes are errors, never panics.

use geode_frep::codec::{decode, encode, FieldDecodeError};
use geode_frep::eval::PointEval;
use geode_frep::shapes;
use geode_frep::tape::Tape;
use geode_frep::Field;

/// The unit tetrahedron's mesh as a field.
fn tetrahedron() -> Field {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    Field::mesh(geode_frep::MeshDistance::new(p, t, &|| false).unwrap())
}

/// A small sphere sampled into a narrow-band volume, as a field.
fn volume() -> Field {
    let options = geode_frep::SampleOptions {
        min: [-0.3; 3],
        max: [0.3; 3],
        voxel_size: 0.05,
        half_width: 2.0,
        memory_budget: 1 << 30,
    };
    let s = shapes::sphere([0.02, 0.0, -0.01], 0.2);
    let plan = geode_frep::SamplePlan::new(&s, options, &|| false).unwrap();
    let v = plan.sample(&s, "surface", &|| false).unwrap();
    Field::volume(geode_frep::VolumeField::new(v))
}

fn fields() -> Vec<Field> {
    let s = shapes::sphere([0.1, 0.2, 0.3], 1.0);
    let b = shapes::block([0.0; 3], [0.5, 0.7, 0.9]);
    let t = shapes::torus([0.0, 0.5, 0.0], 1.0, 0.25);
    let points: Vec<[f64; 3]> = (0..40)
        .map(|i| [i as f64 * 0.05, (i as f64 * 0.3).sin(), 0.0])
        .collect();
    let radii: Vec<f64> = (0..40).map(|i| 0.05 + i as f64 * 0.002).collect();
    let sweep = shapes::sphere_sweep(&points, &radii).unwrap();
    // A chain as deep as a long sweep of unions: no recursion may follow it.
    let mut deep = Field::x();
    for i in 0..100_000 {
        deep = deep.binary(geode_frep::Binary::Add, Field::constant(i as f64 * 1e-6));
    }
    vec![
        s.clone(),
        shapes::blend_union(&s, &b, [0.2, 1.0, 1.0]),
        shapes::subtraction(&t, &b, 0.0),
        shapes::morph(&s, &t, 0.3).sin().abs(),
        shapes::union(&sweep, &shapes::offset(&s, 0.1), 1.0),
        tetrahedron().max(shapes::sphere([0.5; 3], 0.2)),
        volume().min(shapes::block([0.0; 3], [0.1, 0.3, 0.3])),
        deep,
    ]
}

#[test]
fn every_field_comes_back_with_its_identity_and_values() {
    for (k, f) in fields().into_iter().enumerate() {
        let mut bytes = Vec::new();
        encode(&f, &mut bytes);
        let back = decode(&bytes).unwrap();
        assert_eq!(back.identity(), f.identity(), "field {k}");
        if k == 7 {
            continue; // the deep chain: identity is enough, a tape of it is large
        }
        let (ta, tb) = (Tape::compile(&f), Tape::compile(&back));
        let (mut ea, mut eb) = (PointEval::new(&ta), PointEval::new(&tb));
        for i in 0..200 {
            let p = [
                (i as f64 * 0.37).sin() * 1.5,
                (i as f64 * 0.11).cos(),
                i as f64 * 0.01 - 1.0,
            ];
            assert_eq!(
                ea.eval(p).to_bits(),
                eb.eval(p).to_bits(),
                "field {k} at {p:?}"
            );
        }
    }
}

#[test]
fn damaged_fields_are_errors_never_panics() {
    for f in fields().into_iter().take(7) {
        let mut bytes = Vec::new();
        encode(&f, &mut bytes);
        for at in (0..bytes.len()).step_by(bytes.len() / 300 + 1) {
            assert!(decode(&bytes[..at]).is_err());
            for damage in [0xffu8, 0x01, 0x80] {
                let mut b = bytes.clone();
                b[at] ^= damage;
                let _ = decode(&b);
            }
        }
    }
    assert_eq!(decode(b"GEOX").unwrap_err(), FieldDecodeError::Magic);
}

/// A mesh's field survives the codec: same identity, same values, and a
/// corrupted triangle index is refused, not evaluated.
#[test]
fn mesh_fields_round_trip() {
    let f = tetrahedron().max(shapes::sphere([0.5; 3], 0.2));
    let mut bytes = Vec::new();
    geode_frep::codec::encode(&f, &mut bytes);
    let back = geode_frep::codec::decode(&bytes).unwrap();
    assert_eq!(back.identity(), f.identity());
    for q in [[0.1, 0.1, 0.1], [0.5, 0.5, 0.5], [2.0, -1.0, 0.3]] {
        assert_eq!(back.eval_tree(q), f.eval_tree(q));
    }
    // The last triangle's last index, made to point past the points.
    let mut bad = bytes.clone();
    let needle: Vec<u8> = [1u32, 2, 3].iter().flat_map(|v| v.to_le_bytes()).collect();
    let pos = bad
        .windows(12)
        .rposition(|w| w == needle.as_slice())
        .unwrap();
    bad[pos + 8..pos + 12].copy_from_slice(&99u32.to_le_bytes());
    assert!(geode_frep::codec::decode(&bad).is_err());
}

/// The fuzzer's seeds (fuzz/seeds/field_codec) are encodings of these
/// fields, current with the codec's version: `GEODE_WRITE_SEEDS=1 cargo
/// test -p geode-frep --test codec seeds` writes them again.
#[test]
fn the_fuzz_seeds_decode() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/field_codec");
    let small: Vec<Field> = fields().into_iter().take(7).collect();
    if std::env::var_os("GEODE_WRITE_SEEDS").is_some() {
        std::fs::create_dir_all(&dir).unwrap();
        for (k, f) in small.iter().enumerate() {
            let mut bytes = Vec::new();
            encode(f, &mut bytes);
            std::fs::write(dir.join(format!("field{k}.bin")), bytes).unwrap();
        }
    }
    for (k, f) in small.iter().enumerate() {
        let bytes = std::fs::read(dir.join(format!("field{k}.bin"))).unwrap();
        assert_eq!(decode(&bytes).unwrap().identity(), f.identity(), "seed {k}");
    }
}
