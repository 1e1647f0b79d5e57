//! Hierarchy properties: refinement reproduces the parent exactly, finer
//! detail follows coarse edits in the local frame, unrefine never changes
//! the surface, refine then unrefine restores an unedited hierarchy, and
//! the torus at level 0 is the Catmull-Clark limit of its control mesh.

use super::*;
use geode_geo::random::unit_f64;

fn lumpy(topology: Topology, seed: u64) -> Hspline {
    let mut h = Hspline::new(topology, 7, 9, [3.0, 1.0]).unwrap();
    for (k, p) in h.base.points.iter_mut().enumerate() {
        *p += DVec3::new(
            unit_f64(seed, k as u64, 0),
            unit_f64(seed, k as u64, 1),
            unit_f64(seed, k as u64, 2),
        ) * 0.2;
    }
    h
}

fn max_deviation(a: &Grid, b: &Grid, wrap: (bool, bool)) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..=40 {
        for j in 0..=40 {
            let (s, t) = (i as f64 / 40.0, j as f64 / 40.0);
            worst = worst.max((evaluate(a, wrap, s, t).0 - evaluate(b, wrap, s, t).0).length());
        }
    }
    worst
}

#[test]
fn refinement_reproduces_the_parent_exactly() {
    for topology in [Topology::Plane, Topology::Cylinder, Topology::Torus] {
        for seed in 0..5 {
            let mut h = lumpy(topology, seed);
            h.refine(None).unwrap();
            h.refine(Some(((3, 9), (4, 12)))).unwrap();
            let w = topology.wraps();
            for level in 1..h.levels() {
                let d = max_deviation(&h.grid(level - 1).unwrap(), &h.grid(level).unwrap(), w);
                assert!(d < 1e-9, "{topology:?} seed {seed} level {level}: {d}");
            }
        }
    }
}

#[test]
fn finer_detail_follows_a_coarse_edit_in_the_local_frame() {
    let mut h = lumpy(Topology::Torus, 1);
    h.refine(None).unwrap();
    h.refine(None).unwrap();
    let (i, j) = (20, 25);
    h.move_cv(2, i, j, DVec3::new(0.0, 0.3, 0.1)).unwrap();
    let displacement = |h: &Hspline| {
        let fine = h.grid(2).unwrap();
        let reference = refine_grid(&h.grid(1).unwrap(), h.topology.wraps());
        fine.at(i, j) - reference.at(i, j)
    };
    let before = displacement(&h);
    assert!(
        (before - DVec3::new(0.0, 0.3, 0.1)).length() < 1e-12,
        "the edit moved the vertex by the vector asked"
    );
    // Turn the whole coarse surface: the detail turns with it.
    let r =
        geode_geo::glam::DQuat::from_rotation_y(0.7) * geode_geo::glam::DQuat::from_rotation_x(0.3);
    for p in h.base.points.iter_mut() {
        *p = r * *p + DVec3::new(1.0, -2.0, 0.5);
    }
    let after = displacement(&h);
    assert!(
        (after - r * before).length() < 1e-9,
        "{after} vs {}",
        r * before
    );
    // The stored offset itself is untouched by the coarse edit.
    assert_eq!(h.nonzero_offsets(2), vec![(i, j)]);
}

#[test]
fn unrefine_never_changes_the_surface_and_undoes_an_unedited_refinement() {
    for seed in 0..5 {
        let original = lumpy(Topology::Plane, seed);
        let mut h = original.clone();
        h.refine(None).unwrap();
        h.refine(None).unwrap();
        h.unrefine();
        assert_eq!(
            h, original,
            "refine then unrefine with no edit restores the hierarchy"
        );
        h.refine(None).unwrap();
        h.refine(Some(((2, 8), (3, 10)))).unwrap();
        let n = h.grid(2).unwrap();
        let k = (unit_f64(seed, 9, 0) * 4.0) as usize;
        let (i, j) = (n.nu / 2 + k % 2, n.nv / 2 - k % 3);
        h.move_cv(2, i, j, DVec3::new(0.1, 0.2, -0.1)).unwrap();
        let before = h.grid(2).unwrap();
        h.unrefine();
        assert_eq!(h.levels(), 3, "an edited level stays");
        let after = h.grid(2).unwrap();
        assert!(max_deviation(&before, &after, h.topology.wraps()) < 1e-12);
        assert!(
            h.overlays[1].offsets.len() <= 5 * 5,
            "trimmed to the support of the one offset"
        );
        h.zero_offsets(2);
        h.unrefine();
        assert_eq!(h.levels(), 1);
        assert!(
            max_deviation(
                &h.grid(0).unwrap(),
                &original.grid(0).unwrap(),
                (false, false)
            ) < 1e-12
        );
    }
}

#[test]
fn only_movable_vertices_take_offsets() {
    let mut h = lumpy(Topology::Plane, 3);
    h.refine(Some(((2, 5), (2, 6)))).unwrap();
    let o = h.overlays[0].clone();
    assert!(h.movable(1, o.u.0 + 2, o.v.0 + 2));
    assert!(!h.movable(1, o.u.0, o.v.0 + 2), "on the overlay's edge");
    assert_eq!(
        h.move_cv(1, o.u.0 + 1, o.v.0 + 2, DVec3::X),
        Err(HsplineError::NotMovable {
            level: 1,
            i: o.u.0 + 1,
            j: o.v.0 + 2
        })
    );
    assert_eq!(h.grid(5).unwrap_err(), HsplineError::NoLevel(5, 2));
}

#[test]
fn the_torus_at_level_0_is_the_catmull_clark_limit_of_its_control_mesh() {
    let h = lumpy(Topology::Torus, 7);
    let g = &h.base;
    let mut faces = Vec::new();
    for i in 0..g.nu {
        for j in 0..g.nv {
            let id = |a: usize, b: usize| ((a % g.nu) * g.nv + b % g.nv) as u32;
            faces.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = geode_geo::Geometry::from_polygons(
        g.points.iter().map(|p| p.as_vec3()).collect(),
        faces,
        &vec![4; g.nu * g.nv],
    )
    .unwrap();
    let opts = crate::subd::SubdOptions {
        levels: 1,
        boundary: None,
        crease: None,
        fvar: None,
        limit: true,
    };
    let limit = crate::subd::subdivide(&mesh, &opts, &|| false).unwrap();
    let mut worst = 0.0f64;
    for i in 0..g.nu {
        for j in 0..g.nv {
            let (p, _, _) = evaluate(
                g,
                (true, true),
                i as f64 / g.nu as f64,
                j as f64 / g.nv as f64,
            );
            worst = worst.max((p - limit.positions()[i * g.nv + j].as_dvec3()).length());
        }
    }
    assert!(worst < 2e-6, "to float precision: {worst}");
}

#[test]
fn a_refined_and_edited_torus_tessellates_closed() {
    let mut h = lumpy(Topology::Torus, 2);
    h.refine(None).unwrap();
    h.refine(Some(((4, 10), (6, 14)))).unwrap();
    let o = h.overlays[1].clone();
    h.move_cv(2, o.u.0 + 3, o.v.0 + 3, DVec3::new(0.4, 0.0, 0.0))
        .unwrap();
    let t = h.tessellate(48, 64);
    let flat: Vec<u32> = t.quads.iter().flatten().copied().collect();
    let g = geode_geo::Geometry::from_polygons(t.positions.clone(), flat, &vec![4; t.quads.len()])
        .unwrap();
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    assert!(t.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
}

#[test]
fn enveloping_a_coarse_level_carries_finer_detail_in_the_deformed_frames() {
    use crate::skin::{skin, Joint, Skeleton, SkinMethod};
    use geode_geo::glam::DQuat;
    // An arm: a cylinder along Y from -1 to 1 with a bump near the elbow.
    let mut h = Hspline::new(Topology::Cylinder, 8, 12, [0.4, 2.0]).unwrap();
    h.refine(None).unwrap();
    h.refine(None).unwrap();
    let g2 = h.grid(2).unwrap();
    let (i, j) = (g2.nu / 2 + 1, 3);
    h.move_cv(2, i, j, DVec3::ZERO).unwrap();
    let o = h.overlays[1].index(i, j).unwrap();
    h.overlays[1].offsets[o] = DVec3::new(0.08, 0.0, 0.0); // outward along the normal
    let joint = |name: &str, parent, y: f64, rotation| Joint {
        name: name.into(),
        parent,
        rest: DVec3::new(0.0, y, 0.0),
        rotation,
    };
    let skeleton = Skeleton::new(vec![
        joint("shoulder", None, -1.0, DQuat::IDENTITY),
        joint("elbow", Some(0), 0.0, DQuat::from_rotation_z(1.2)),
        joint("wrist", Some(1), 1.0, DQuat::IDENTITY),
    ])
    .unwrap();
    let motions = skeleton.motions();
    // Hierarchical: envelope level 1, then let level 2's offsets follow.
    let g1 = h.grid(1).unwrap();
    let w1 = skeleton.auto_weights(&g1.points);
    let bent1 = Grid {
        points: skin(&g1.points, &w1, &motions, SkinMethod::Linear),
        ..g1.clone()
    };
    let hierarchical = h.grid_from(1, bent1.clone(), 2).unwrap();
    // The bump stands exactly its offset off the bent coarser surface.
    let reference = refine_grid(&bent1, h.topology.wraps());
    let (_, pu, pv) = evaluate(
        &bent1,
        h.topology.wraps(),
        parameter(i, hierarchical.nu, false),
        parameter(j, hierarchical.nv, true),
    );
    let n = frame(pu, pv)[0];
    let height = (hierarchical.at(i, j) - reference.at(i, j)).dot(n);
    assert!((height - 0.08).abs() < 1e-12, "{height}");
    // Enveloping the finest level instead blends the bump with the bend.
    let w2 = skeleton.auto_weights(&g2.points);
    let flat = skin(
        &h.grid(2).unwrap().points,
        &w2,
        &motions,
        SkinMethod::Linear,
    );
    assert!(flat[i * hierarchical.nv + j].distance(hierarchical.at(i, j)) > 1e-4);
}

#[test]
fn a_surface_point_moves_exactly_through_its_edit_point() {
    let mut h = lumpy(Topology::Plane, 4);
    h.refine(None).unwrap();
    let (s, t) = (0.43, 0.58);
    let before = evaluate(&h.grid(1).unwrap(), (false, false), s, t).0;
    let delta = DVec3::new(0.1, 0.25, -0.05);
    h.move_surface_point(1, s, t, delta).unwrap();
    let after = evaluate(&h.grid(1).unwrap(), (false, false), s, t).0;
    // The offset is stored in the local frame, so the move is exact only up
    // to that frame's round trip.
    assert!(
        (after - before - delta).length() < 1e-12,
        "{}",
        after - before
    );
}

#[test]
fn tag_helpers_answer_neighbours_rows_columns_and_refinement() {
    let mut h = lumpy(Topology::Cylinder, 5);
    assert_eq!(
        h.neighbours(0, 0, 0),
        vec![(1, 0), (0, 8), (0, 1)],
        "wraps in v only"
    );
    assert_eq!(h.along_v(0, 2).len(), 9);
    assert_eq!(h.along_u(0, 3).len(), 7);
    h.refine(Some(((1, 4), (2, 6)))).unwrap();
    assert!(h.refined(0, 2, 3));
    assert!(!h.refined(0, 6, 8));
}

#[test]
fn refining_past_the_size_limit_is_an_error_not_a_panic() {
    let mut h = Hspline::new(Topology::Torus, 4, 1 << 20, [3.0, 1.0]).unwrap();
    h.overlays = (0..4)
        .map(|_| Overlay {
            u: (0, 1),
            v: (0, 1),
            offsets: vec![DVec3::ZERO],
        })
        .collect();
    assert_eq!(h.refine(None), Err(HsplineError::TooLarge(5)));
}

#[test]
fn an_hspline_level_as_a_patch_primitive_is_the_same_surface() {
    use crate::bspline::patch::surface;
    for topology in [Topology::Plane, Topology::Cylinder, Topology::Torus] {
        let h = lumpy(topology, 11);
        let grid = h.grid(h.levels() - 1).unwrap();
        // The patch holds f32 points: compare with the rounded grid.
        let grid = Grid {
            points: grid.points.iter().map(|p| p.as_vec3().as_dvec3()).collect(),
            ..grid
        };
        let (indices, basis) = h.patch_layout(&grid);
        let mut g = geode_geo::Geometry::new();
        g.add_points(&grid.points.iter().map(|p| p.as_vec3()).collect::<Vec<_>>());
        g.add_patch(&indices, basis).unwrap();
        let s = surface(&g, 0).unwrap().unwrap();
        let wrap = h.topology.wraps();
        let spans = |n: usize, closed: bool| if closed { n as f64 } else { n as f64 - 3.0 };
        let mut worst = 0.0f64;
        for a in 0..=20 {
            for b in 0..=20 {
                let (u, v) = (a as f64 / 20.0, b as f64 / 20.0);
                let want = evaluate(&grid, wrap, u, v).0;
                let got = s.point(
                    3.0 + u * spans(grid.nu, wrap.0),
                    3.0 + v * spans(grid.nv, wrap.1),
                );
                worst = worst.max((want - got).length());
            }
        }
        assert!(worst < 1e-12, "{topology:?}: {worst}");
    }
}
