//! Transfer against a brute-force nearest search, and blur against what
//! averaging must do: a constant stays, a linear field stays linear inside
//! a regular grid, pinned values stay, Taubin's passes keep the mean.

use geode_attrib::blur::{blur, point_neighbours, proximity_neighbours, Mode};
use geode_attrib::kdtree::KdTree;
use geode_attrib::transfer::{apply, from_points, from_surface, Reach};
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::ops::TriangleBvh;
use geode_geo::primitives::{grid, uv_sphere};
use geode_geo::{AttribData, Attribute, Group, TypeInfo};

fn cloud(n: usize, seed: u32, scale: f32) -> Vec<Vec3> {
    let mut s = seed.wrapping_mul(2654435761).max(1);
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s as f32 / u32::MAX as f32) * scale
    };
    (0..n).map(|_| Vec3::new(next(), next(), next())).collect()
}

fn floats(a: &Attribute) -> Vec<f32> {
    a.data().as_floats().unwrap().0.to_vec()
}

const NONE: &(dyn Fn() -> bool + Sync) = &|| false;

#[test]
fn nearest_point_transfer_matches_brute_force() {
    let src = cloud(4000, 1, 10.0);
    let dst = cloud(2000, 2, 10.0);
    let values: Vec<Vec3> = src
        .iter()
        .map(|p| Vec3::new(p.x.sin(), p.y * 2.0, 1.0))
        .collect();
    let attr = Attribute::from_data(AttribData::Vec3(values.clone()), TypeInfo::Color);
    let reach = Reach {
        threshold: f32::INFINITY,
        blend_width: 0.0,
        samples: 1,
    };
    let stencil = from_points(&KdTree::new(&src), &dst, &reach, NONE).unwrap();
    let out = apply(&stencil, &attr, None);
    let AttribData::Vec3(got) = out.data() else {
        panic!()
    };
    for (i, q) in dst.iter().enumerate() {
        let (mut best, mut bd) = (0, f32::INFINITY);
        for (j, p) in src.iter().enumerate() {
            let d = p.distance_squared(*q);
            if d < bd {
                (best, bd) = (j, d);
            }
        }
        assert_eq!(got[i], values[best], "destination {i}");
    }
}

#[test]
fn threshold_and_blend_width_fade_to_the_own_value() {
    // One source at the origin with value 1; destinations along x with 0.
    let src = [Vec3::ZERO];
    let dst: Vec<Vec3> = (0..=40).map(|i| Vec3::X * (i as f32 * 0.1)).collect();
    let attr = Attribute::from_data(AttribData::Float(vec![1.0]), TypeInfo::None);
    let own = Attribute::from_data(AttribData::Float(vec![0.0; dst.len()]), TypeInfo::None);
    let reach = Reach {
        threshold: 1.0,
        blend_width: 2.0,
        samples: 1,
    };
    let s = from_points(&KdTree::new(&src), &dst, &reach, NONE).unwrap();
    let v = floats(&apply(&s, &attr, Some(&own)));
    for (i, x) in v.iter().enumerate() {
        let d = i as f32 * 0.1;
        let want = if d <= 1.0 {
            1.0
        } else if d >= 3.0 {
            0.0
        } else {
            let t = 1.0 - (d - 1.0) / 2.0;
            t * t * (3.0 - 2.0 * t)
        };
        assert!((x - want).abs() < 1e-5, "at {d}: {x} against {want}");
    }
    // Halfway through the blend width, exactly a half.
    assert!((v[20] - 0.5).abs() < 1e-6);
}

#[test]
fn several_samples_average_by_inverse_squared_distance() {
    let src = [Vec3::ZERO, Vec3::X * 2.0];
    let attr = Attribute::from_data(AttribData::Float(vec![0.0, 10.0]), TypeInfo::None);
    let reach = Reach {
        threshold: f32::INFINITY,
        blend_width: 0.0,
        samples: 2,
    };
    let q = Vec3::X * 0.5; // distances 0.5 and 1.5: weights 4 and 4/9
    let s = from_points(&KdTree::new(&src), &[q], &reach, NONE).unwrap();
    let want = 10.0 * (4.0 / 9.0) / (4.0 + 4.0 / 9.0);
    assert!((floats(&apply(&s, &attr, None))[0] - want).abs() < 1e-5);
}

#[test]
fn surface_transfer_takes_the_nearest_primitive() {
    let sphere = uv_sphere(1.0, 24, 12);
    let (tri_points, tri_prims) = geode_attrib::relation::surface_triangles(&sphere);
    let bvh = TriangleBvh::new(sphere.positions(), &tri_points);
    let dst = cloud(500, 5, 4.0)
        .into_iter()
        .map(|p| p - Vec3::splat(2.0))
        .collect::<Vec<_>>();
    let reach = Reach {
        threshold: f32::INFINITY,
        blend_width: 0.0,
        samples: 1,
    };
    let s = from_surface(&bvh, &tri_prims, &dst, &reach, NONE).unwrap();
    // Brute force over every triangle.
    for (i, q) in dst.iter().enumerate() {
        let (mut best, mut bd) = (u32::MAX, f32::INFINITY);
        for (t, c) in tri_points.iter().enumerate() {
            let corners = c.map(|k| sphere.positions()[k as usize]);
            let (p, _, _) = geode_geo::ops::closest_on_triangle(&corners, *q);
            let d = p.distance_squared(*q);
            if d < bd || (d == bd && tri_prims[t] < best) {
                (best, bd) = (tri_prims[t], d);
            }
        }
        let got = s.sources[s.offsets[i] as usize];
        // Equal distances to two primitives (a shared edge) may go either way.
        if got != best {
            let corners_of = |prim: u32| {
                tri_points
                    .iter()
                    .zip(&tri_prims)
                    .filter(|(_, &p)| p == prim)
                    .map(|(c, _)| {
                        let cs = c.map(|k| sphere.positions()[k as usize]);
                        geode_geo::ops::closest_on_triangle(&cs, *q)
                            .0
                            .distance_squared(*q)
                    })
                    .fold(f32::INFINITY, f32::min)
            };
            assert!(
                (corners_of(got) - bd).abs() < 1e-6,
                "destination {i}: {got} against {best}"
            );
        }
    }
}

#[test]
fn blur_keeps_constants_linear_fields_and_pins() {
    let g = grid(Vec2::new(10.0, 10.0), 10, 10);
    let n = point_neighbours(&g);
    let p = g.positions();
    let constant = Attribute::from_data(AttribData::Float(vec![3.5; p.len()]), TypeInfo::None);
    let out = blur(&constant, &n, 10, 0.5, Mode::Laplacian, None, NONE).unwrap();
    assert!(floats(&out).iter().all(|&x| (x - 3.5).abs() < 1e-6));
    // x is linear: interior points (all four neighbours) keep it, after one
    // pass, exactly.
    let linear = Attribute::from_data(
        AttribData::Float(p.iter().map(|q| q.x).collect()),
        TypeInfo::None,
    );
    let once = floats(&blur(&linear, &n, 1, 0.5, Mode::Laplacian, None, NONE).unwrap());
    for (i, q) in p.iter().enumerate() {
        if q.x.abs() < 4.9 && q.z.abs() < 4.9 {
            assert!((once[i] - q.x).abs() < 1e-5, "point {i}");
        }
    }
    // A spike spreads; a pinned spike stays.
    let mut spike = vec![0.0f32; p.len()];
    spike[60] = 1.0;
    let a = Attribute::from_data(AttribData::Float(spike), TypeInfo::None);
    let free = floats(&blur(&a, &n, 5, 0.5, Mode::Laplacian, None, NONE).unwrap());
    assert!(free[60] < 0.5 && free[61] > 0.0);
    let pin = Group::from_members(p.len(), [60]);
    let held = floats(&blur(&a, &n, 5, 0.5, Mode::Laplacian, Some(&pin), NONE).unwrap());
    assert_eq!(held[60], 1.0);
    // Taubin keeps the spike's mass nearer than plain Laplacian.
    let mass = |v: &[f32]| v.iter().sum::<f32>();
    let taubin = floats(&blur(&a, &n, 10, 0.5, Mode::VolumePreserving, None, NONE).unwrap());
    let lap = floats(&blur(&a, &n, 10, 0.5, Mode::Laplacian, None, NONE).unwrap());
    assert!(taubin.iter().cloned().fold(0.0, f32::max) > lap.iter().cloned().fold(0.0, f32::max));
    assert!(mass(&taubin) > 0.0);
}

#[test]
fn proximity_neighbours_match_brute_force() {
    let pts = cloud(800, 9, 5.0);
    let rows = proximity_neighbours(&pts, 0.8, 6, NONE).unwrap();
    for (i, q) in pts.iter().enumerate() {
        let mut near: Vec<(f32, u32)> = pts
            .iter()
            .enumerate()
            .filter(|(j, p)| *j != i && p.distance(*q) <= 0.8)
            .map(|(j, p)| (p.distance_squared(*q), j as u32))
            .collect();
        near.sort_by(|a, b| a.partial_cmp(b).unwrap());
        near.truncate(6);
        assert_eq!(
            rows.row(i),
            near.iter().map(|x| x.1).collect::<Vec<_>>().as_slice(),
            "point {i}"
        );
    }
}

#[test]
fn cancelled_and_wrong_types_are_errors() {
    let g = grid(Vec2::ONE, 4, 4);
    let n = point_neighbours(&g);
    let ints = Attribute::from_data(AttribData::Int(vec![1; g.num_points()]), TypeInfo::None);
    assert!(blur(&ints, &n, 1, 0.5, Mode::Laplacian, None, NONE).is_err());
    let f = Attribute::from_data(AttribData::Float(vec![1.0; g.num_points()]), TypeInfo::None);
    assert!(blur(&f, &n, 1, 0.5, Mode::Laplacian, None, &|| true).is_err());
    let reach = Reach {
        threshold: -1.0,
        blend_width: 0.0,
        samples: 1,
    };
    assert!(from_points(&KdTree::new(&[Vec3::ZERO]), &[Vec3::ONE], &reach, NONE).is_err());
}
