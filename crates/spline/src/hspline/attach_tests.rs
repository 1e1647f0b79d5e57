//! Attachments: exact hsplines away from the joint, the joint's valences,
//! smoothness, offsets across the joint, both surfaces moving it, errors.

use std::collections::HashMap;

use geode_geo::glam::DVec3;

use super::*;

fn torus() -> Hspline {
    Hspline::new(Topology::Torus, 12, 16, [4.0, 1.5]).unwrap()
}

fn limb(rows: usize) -> Hspline {
    Hspline::new(Topology::Cylinder, rows, 8, [0.5, 1.5]).unwrap()
}

/// Deterministic offsets on every movable vertex of `level`.
fn scatter_offsets(h: &mut Hspline, level: usize, seed: u64, size: f64) {
    let (nu, nv) = h.grid_size(level).unwrap();
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * size
    };
    for i in 0..nu {
        for j in 0..nv {
            if h.movable(level, i, j) {
                let d = DVec3::new(next(), next(), next());
                h.move_cv(level, i, j, d).unwrap();
            }
        }
    }
}

fn parameter(k: usize, n: usize, closed: bool) -> f64 {
    super::super::parameter(k, n, closed)
}

#[test]
fn far_from_the_joint_the_attached_surface_is_each_hspline_exactly() {
    let mut parent = torus();
    parent.refine(None).unwrap();
    parent.refine(None).unwrap();
    scatter_offsets(&mut parent, 1, 1, 0.05);
    scatter_offsets(&mut parent, 2, 2, 0.02);
    let mut arm = limb(7);
    arm.refine(None).unwrap();
    arm.refine(Some(((2, 9), (0, 16)))).unwrap();
    scatter_offsets(&mut arm, 1, 3, 0.03);
    scatter_offsets(&mut arm, 2, 4, 0.01);
    let region = ((3, 5), (4, 6));
    let limbs = [Limb {
        surface: arm.clone(),
        region,
    }];
    let a = attach(&parent, &limbs, false, 0).unwrap();
    let (pnu, pnv) = parent.grid_size(2).unwrap();
    let (lnu, lnv) = arm.grid_size(2).unwrap();
    let cyclic = |x: f64, lo: f64, hi: f64, n: f64| {
        // Distance from x to the interval [lo, hi] on a circle of length n.
        (0..3)
            .map(|k| {
                let y = x + (k as f64 - 1.0) * n;
                (lo - y).max(y - hi).max(0.0)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (mut parent_checked, mut limb_checked, mut worst) = (0, 0, 0.0f64);
    for (k, &(s, i, j)) in a.origin.iter().enumerate() {
        let (i, j) = (i as usize, j as usize);
        let expected = if s == 0 {
            // Level-0 place of the vertex: index / 4 on a wrapped side.
            let (x, y) = (i as f64 / 4.0, j as f64 / 4.0);
            let d = cyclic(x, 3.0, 5.0, 12.0).max(cyclic(y, 4.0, 6.0, 16.0));
            if d < 3.0 {
                continue;
            }
            parent_checked += 1;
            parent.point(parameter(i, pnu, true), parameter(j, pnv, true))
        } else {
            // Level-0 row of a limb vertex: (index + 3) / 4; the rim is row 1.
            if ((i + 3) as f64 / 4.0) < 4.0 {
                continue;
            }
            limb_checked += 1;
            arm.point(parameter(i, lnu, false), parameter(j, lnv, true))
        };
        let (dp, dn) = (
            (a.positions[k] - expected.0).length(),
            (a.normals[k] - expected.1).length(),
        );
        if dp.max(dn) > 1e-9 && std::env::var("DEBUG_ATTACH").is_ok() {
            eprintln!("surface {s} ({i}, {j}): position {dp:e} normal {dn:e}");
        }
        worst = worst.max(dp).max(dn);
    }
    assert!(
        parent_checked > 300 && limb_checked > 100,
        "{parent_checked} {limb_checked}"
    );
    assert!(worst < 1e-9, "deviation {worst:e}");
}

fn valences(quads: &[[u32; 4]]) -> HashMap<u32, usize> {
    let mut edges = std::collections::HashSet::new();
    for q in quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    let mut out = HashMap::new();
    for (a, b) in edges {
        *out.entry(a).or_insert(0) += 1;
        *out.entry(b).or_insert(0) += 1;
    }
    out
}

/// Every directed edge at most once (oriented manifold); returns the
/// number of boundary edges.
fn oriented_manifold(quads: &[[u32; 4]]) -> usize {
    let mut directed = std::collections::HashSet::new();
    for q in quads {
        for k in 0..4 {
            assert!(
                directed.insert((q[k], q[(k + 1) % 4])),
                "edge used twice the same way"
            );
        }
    }
    directed
        .iter()
        .filter(|&&(a, b)| !directed.contains(&(b, a)))
        .count()
}

#[test]
fn rim_corners_get_five_edges_and_limbs_side_by_side_six() {
    let parent = Hspline::new(Topology::Plane, 10, 12, [6.0, 6.0]).unwrap();
    let one = attach(
        &parent,
        &[Limb {
            surface: limb(6),
            region: ((3, 5), (2, 4)),
        }],
        true,
        0,
    )
    .unwrap();
    let count = |v: &HashMap<u32, usize>, n: usize| v.values().filter(|&&x| x == n).count();
    let single = valences(&one.cage_quads);
    assert_eq!(count(&single, 5), 4);
    assert_eq!(count(&single, 6), 0);
    oriented_manifold(&one.cage_quads);
    let two = attach(
        &parent,
        &[
            Limb {
                surface: limb(6),
                region: ((3, 5), (2, 4)),
            },
            Limb {
                surface: limb(6),
                region: ((3, 5), (4, 6)),
            },
        ],
        true,
        0,
    )
    .unwrap();
    let pair = valences(&two.cage_quads);
    assert_eq!(count(&pair, 5), 4, "outer corners");
    assert_eq!(count(&pair, 6), 2, "shared corners");
    oriented_manifold(&two.cage_quads);
    // The refined surface stays an oriented manifold.
    let fine = attach(&parent, &[], true, 2).unwrap();
    oriented_manifold(&fine.quads);
}

#[test]
fn the_joint_is_smooth_and_the_surface_closed_but_for_the_limb_end() {
    let parent = torus();
    let limbs = [Limb {
        surface: limb(7),
        region: ((3, 5), (4, 6)),
    }];
    let a = attach(&parent, &limbs, true, 4).unwrap();
    // A torus with one open tube: the only boundary is the tube's end.
    assert_eq!(oriented_manifold(&a.quads), 8 << 4);
    let mut worst = 0.0f64;
    for q in &a.quads {
        for k in 0..4 {
            let (n0, n1) = (a.normals[q[k] as usize], a.normals[q[(k + 1) % 4] as usize]);
            worst = worst.max(n0.angle_between(n1).to_degrees());
        }
    }
    assert!(worst < 10.0, "normals turn {worst} degrees across one edge");
    // Outward: the placed limb points away from the torus's core.
    for (k, p) in a.positions.iter().enumerate() {
        if a.origin[k].0 == 1 {
            let radial = DVec3::new(p.x, 0.0, p.z).normalize();
            let core = radial * 2.0;
            assert!((*p - core).length() > 0.6, "limb point inside the torus");
        }
    }
}

#[test]
fn an_offset_on_an_extraordinary_vertex_moves_its_limit_by_the_mask_weight() {
    let mut parent = torus();
    parent.refine(None).unwrap();
    let limbs = |p: &Hspline| {
        let l = [Limb {
            surface: limb(7),
            region: ((3, 5), (4, 6)),
        }];
        attach(p, &l, true, 0).unwrap()
    };
    let before = limbs(&parent);
    // The rim corner (3, 4) is vertex (6, 8) of level 1; five edges meet there.
    let k = before.origin.iter().position(|&o| o == (0, 6, 8)).unwrap();
    let normal = before.normals[k];
    // An offset along the local normal (0.1, 0, 0).
    parent.overlays[0].offsets[6 * 32 + 8] = DVec3::new(0.1, 0.0, 0.0);
    let after = limbs(&parent);
    let moved = after.positions[k] - before.positions[k];
    // The smooth limit mask weighs the vertex itself n / (n + 5).
    assert!(
        (moved - normal * (0.1 * 5.0 / 10.0)).length() < 1e-9,
        "{moved}"
    );
    // Only points near the corner moved.
    let far = before
        .positions
        .iter()
        .zip(&after.positions)
        .filter(|(a, b)| (**a - **b).length() > 1e-12)
        .count();
    assert!(far > 0 && far < 40, "{far} points moved");
}

#[test]
fn the_joint_moves_with_both_surfaces() {
    let parent = torus();
    let arm = limb(7);
    let region = ((3, 5), (4, 6));
    let base = attach(
        &parent,
        &[Limb {
            surface: arm.clone(),
            region,
        }],
        true,
        2,
    )
    .unwrap();
    let joint = |a: &Attached| -> Vec<DVec3> {
        // Points of the limb's first spans (its rows up to 2 at level 2).
        (0..a.positions.len())
            .filter(|&k| a.origin[k].0 == 1 && a.origin[k].1 <= 6)
            .map(|k| a.positions[k])
            .collect()
    };
    let moved_by = |a: &Attached| {
        joint(&base)
            .iter()
            .zip(joint(a))
            .map(|(x, y)| (*x - y).length())
            .fold(0.0, f64::max)
    };
    // A parent vertex next to the rim.
    let mut p2 = parent.clone();
    p2.move_cv(0, 2, 4, DVec3::new(0.0, 0.3, 0.0)).unwrap();
    let a = attach(
        &p2,
        &[Limb {
            surface: arm.clone(),
            region,
        }],
        true,
        2,
    )
    .unwrap();
    assert!(moved_by(&a) > 0.01);
    // A limb vertex on its second row.
    let mut l2 = arm.clone();
    l2.move_cv(0, 2, 3, DVec3::new(0.2, 0.0, 0.0)).unwrap();
    let b = attach(
        &parent,
        &[Limb {
            surface: l2,
            region,
        }],
        true,
        2,
    )
    .unwrap();
    assert!(moved_by(&b) > 0.01);
    // Moving the whole parent carries the placed limb along rigidly.
    let mut p3 = parent.clone();
    let shift = DVec3::new(1.0, -2.0, 0.5);
    p3.base.points.iter_mut().for_each(|p| *p += shift);
    let c = attach(
        &p3,
        &[Limb {
            surface: arm,
            region,
        }],
        true,
        2,
    )
    .unwrap();
    let worst = base
        .positions
        .iter()
        .zip(&c.positions)
        .map(|(x, y)| (*x + shift - *y).length())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst}");
}

#[test]
fn bad_attachments_are_errors() {
    let parent = Hspline::new(Topology::Plane, 8, 8, [4.0, 4.0]).unwrap();
    let at = |surface: Hspline, region| Limb { surface, region };
    assert!(matches!(
        attach(&parent, &[at(limb(6), ((2, 4), (2, 5)))], true, 0),
        Err(AttachError::RingMismatch {
            ring: 10,
            around: 8,
            ..
        })
    ));
    assert!(matches!(
        attach(&parent, &[at(limb(6), ((0, 2), (2, 4)))], true, 0),
        Err(AttachError::BadRegion { .. })
    ));
    assert!(matches!(
        attach(&parent, &[at(limb(6), ((5, 7), (2, 4)))], true, 0),
        Err(AttachError::BadRegion { .. })
    ));
    let plane = Hspline::new(Topology::Plane, 6, 8, [1.0, 1.0]).unwrap();
    assert_eq!(
        attach(&parent, &[at(plane, ((2, 4), (2, 4)))], true, 0).unwrap_err(),
        AttachError::NotCylinder(0)
    );
    assert_eq!(
        attach(
            &parent,
            &[at(limb(6), ((2, 4), (2, 4))), at(limb(6), ((3, 5), (3, 5)))],
            true,
            0
        )
        .unwrap_err(),
        AttachError::Overlap(0, 1)
    );
    assert!(matches!(
        attach(&parent, &[at(limb(6), ((2, 4), (2, 4)))], true, 11),
        Err(AttachError::TooLarge(11))
    ));
}
