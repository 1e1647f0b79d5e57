//! Property tests of the geometry operations against brute-force or analytic answers.

use geode_geo::glam::{Mat4, Quat, Vec3};
use geode_geo::{ops, Geometry, Group};
use proptest::prelude::*;

fn points(n: std::ops::Range<usize>) -> impl Strategy<Value = Vec<Vec3>> {
    prop::collection::vec(
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        n,
    )
}

/// Connected components of the "closer than d" graph, by brute force.
fn brute_force_clusters(p: &[Vec3], d: f32) -> usize {
    let mut parent: Vec<usize> = (0..p.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            i = p[i];
        }
        i
    }
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            if (p[i] - p[j]).length_squared() <= d * d {
                let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                parent[a] = b;
            }
        }
    }
    (0..p.len()).filter(|&i| find(&mut parent, i) == i).count()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn fuse_matches_brute_force_clusters(p in points(1..300), d in 0.01f32..0.3) {
        let mut g = Geometry::new();
        g.add_points(&p);
        // A polyline through all points keeps every point referenced.
        if p.len() >= 2 {
            g.add_polyline(&(0..p.len() as u32).collect::<Vec<_>>()).unwrap();
        }
        let expected = brute_force_clusters(&p, d);
        ops::fuse_points(&mut g, d);
        prop_assert_eq!(g.num_points(), if p.len() >= 2 && expected == 1 { 0 } else { expected });
        prop_assert!(ops::validate(&g).is_empty());
    }

    #[test]
    fn star_polygons_triangulate_to_their_area(radii in prop::collection::vec(0.2f32..2.0, 3..40)) {
        let n = radii.len();
        let p: Vec<Vec3> = radii.iter().enumerate().map(|(i, r)| {
            let a = std::f32::consts::TAU * i as f32 / n as f32;
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        }).collect();
        let area: f32 = (0..n).map(|i| 0.5 * p[i].truncate().perp_dot(p[(i + 1) % n].truncate())).sum();
        let g = Geometry::from_polygons(p, (0..n as u32).collect(), &[n as u32]).unwrap();
        let t = ops::triangulate(&g, None);
        prop_assert_eq!(t.num_prims(), n - 2);
        let mut sum = 0.0;
        for prim in 0..t.num_prims() {
            let [a, b, c] = [0, 1, 2].map(|k| t.positions()[t.prim_points(prim)[k] as usize]);
            let z = (b - a).cross(c - a).z * 0.5;
            prop_assert!(z > -1e-6, "triangle {prim} flipped");
            sum += z;
        }
        prop_assert!((sum - area).abs() < 1e-4 * area.max(1.0), "{sum} vs {area}");
    }

    #[test]
    fn transform_then_inverse_is_identity(t in (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0), angle in -3.0f32..3.0, s in 0.2f32..4.0) {
        let mut g = geode_geo::primitives::torus(1.0, 0.3, 12, 8);
        // Face normals of planar faces: the inverse transpose maps them exactly.
        let n: Vec<Vec3> = ops::prim_normals(&g);
        g.set_attrib(geode_geo::AttribClass::Primitive, "N", geode_geo::Attribute::from_data(geode_geo::AttribData::Vec3(n), geode_geo::TypeInfo::Normal)).unwrap();
        let orig = g.positions().to_vec();
        let m = Mat4::from_scale_rotation_translation(Vec3::new(s, 1.0, 2.0 * s), Quat::from_rotation_z(angle), Vec3::new(t.0, t.1, t.2));
        ops::transform(&mut g, m);
        // Normals stay normals: recomputing them on the moved mesh agrees.
        let moved_n = g.attrib(geode_geo::AttribClass::Primitive, "N").unwrap().as_vec3().unwrap().to_vec();
        for (a, b) in moved_n.iter().zip(ops::prim_normals(&g)) {
            prop_assert!(a.normalize().angle_between(b) < 2e-3, "{a} vs {b}");
        }
        ops::transform(&mut g, m.inverse());
        for (a, b) in g.positions().iter().zip(&orig) {
            prop_assert!((*a - *b).length() < 1e-4);
        }
    }

    #[test]
    fn merge_then_delete_restores_the_original(a_pts in points(3..50), b_pts in points(3..50)) {
        let tri = |p: &[Vec3]| {
            let n = p.len() as u32;
            let faces: Vec<u32> = (0..n - 2).flat_map(|i| [0, i + 1, i + 2]).collect();
            Geometry::from_polygons(p.to_vec(), faces, &vec![3; (n - 2) as usize]).unwrap()
        };
        let (a, b) = (tri(&a_pts), tri(&b_pts));
        let mut m = ops::merge(&[&a, &b]).unwrap();
        let second = Group::from_members(m.num_prims(), a.num_prims()..m.num_prims());
        ops::delete_prims(&mut m, &second, true);
        prop_assert_eq!(m.content_hash(), a.content_hash());
    }
}
