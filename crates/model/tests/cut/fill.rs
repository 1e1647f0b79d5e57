//! `polyfill`: holes closed in every mode, ring-shaped caps, no fold-backs,
//! exact areas.

use super::*;

fn holed_sphere() -> Geometry {
    let mut g = primitives::uv_sphere(1.0, 32, 16);
    // Two holes: a patch of quads, and the north pole's fan.
    let np = g.num_prims();
    let hole = Group::from_flags(
        (0..np).map(|p| (p < 32) || (100..104).contains(&p) || (132..136).contains(&p)),
    );
    ops::delete_prims(&mut g, &hole, true);
    g
}

#[test]
fn filled_holes_close_the_sphere_in_every_mode() {
    let g = holed_sphere();
    assert_eq!(g.topology().boundary_edges().len(), 32 + 12);
    for mode in [FillMode::Triangles, FillMode::Polygon, FillMode::Fan] {
        for how in [Triangulation::MinWeight, Triangulation::EarClip] {
            let o = FillOptions {
                mode,
                triangulation: how,
                ..FillOptions::default()
            };
            let r = polyfill(&g, &o, &never).unwrap();
            assert_eq!((r.holes_filled, r.holes_skipped), (2, 0));
            let out = &r.geometry;
            assert!(
                out.topology().manifold_report(out).is_closed_manifold(),
                "{mode:?}"
            );
            assert!(volume(out) > 4.0, "{mode:?}: {}", volume(out));
            let filled = &out.prim_groups()["polyfill"];
            assert_eq!(out.num_prims() - filled.count(), g.num_prims());
            if let Some(t) = trimesh(out) {
                closed_and_wound(&t, &format!("{mode:?} {how:?}"));
            }
        }
    }
    let limited = FillOptions {
        max_points: 20,
        ..FillOptions::default()
    };
    let r = polyfill(&g, &limited, &never).unwrap();
    assert_eq!((r.holes_filled, r.holes_skipped), (1, 1));
}

#[test]
fn a_cut_torus_fills_with_ring_shaped_faces_as_clips_cap() {
    // Cut through its middle plane (the torus lies in the XZ plane): the
    // cut leaves an outer and an inner circle in one plane, and their fill
    // is a ring.
    let torus = primitives::torus(1.0, 0.4, 48, 24);
    let half = |cap| {
        let o = ClipOptions {
            normal: Vec3::Y,
            keep: Keep::Above,
            cap,
            ..ClipOptions::default()
        };
        clip(&torus, &o, &never).unwrap().geometry
    };
    let open = half(Cap::None);
    let capped = half(Cap::Triangles);
    for mode in [FillMode::Triangles, FillMode::Polygon] {
        let o = FillOptions {
            mode,
            ..FillOptions::default()
        };
        let r = polyfill(&open, &o, &never).unwrap();
        assert_eq!((r.holes_filled, r.holes_skipped), (2, 0));
        let out = &r.geometry;
        // The same solid as clip's own cap closes.
        assert!(
            (volume(out) - volume(&capped)).abs() < 1e-5,
            "{mode:?}: {} against {}",
            volume(out),
            volume(&capped)
        );
        let filled = &out.prim_groups()["polyfill"];
        let area: f32 = filled.members().map(|p| polygon_area(out, p)).sum();
        // A ring between radii 0.6 and 1.4 (polygons of 48 sides).
        let ring = |r: f32| 24.0 * r * r * (std::f32::consts::TAU / 48.0).sin();
        let want = ring(1.4) - ring(0.6);
        assert!(
            (area - want).abs() < 1e-3 * want,
            "{mode:?}: {area} against {want}"
        );
        if mode == FillMode::Triangles {
            // Half a torus along its middle plane is still a ring:
            // closed, Euler characteristic 0.
            assert_eq!(euler_and_closed(out), (0, true));
            if let Some(t) = trimesh(out) {
                closed_and_wound(&t, "filled half torus");
            }
        }
    }
    // Off, as Houdini's PolyFill: each circle gets its own disc.
    let separate = FillOptions {
        holes: false,
        ..FillOptions::default()
    };
    let out = polyfill(&open, &separate, &never).unwrap().geometry;
    let filled = &out.prim_groups()["polyfill"];
    let area: f32 = filled.members().map(|p| polygon_area(&out, p)).sum();
    let disc = |r: f32| 24.0 * r * r * (std::f32::consts::TAU / 48.0).sin();
    assert!((area - (disc(1.4) + disc(0.6))).abs() < 1e-2, "{area}");
}

#[test]
fn a_fill_never_folds_back_onto_a_face_of_the_mesh() {
    // A quarter sphere: its one loop turns a right angle at the pole,
    // around the corner of one face, whose three points are consecutive on
    // the loop. An ear there would be that face again, wound the other way.
    let sphere = primitives::uv_sphere(1.0, 32, 16);
    let cut = |g: &Geometry, normal: Vec3| {
        let o = ClipOptions {
            normal,
            cap: Cap::None,
            ..ClipOptions::default()
        };
        clip(g, &o, &never).unwrap().geometry
    };
    let quarter = cut(&cut(&sphere, Vec3::Y), Vec3::X);
    for how in [Triangulation::MinWeight, Triangulation::EarClip] {
        let o = FillOptions {
            triangulation: how,
            ..FillOptions::default()
        };
        let out = polyfill(&quarter, &o, &never).unwrap().geometry;
        let filled = &out.prim_groups()["polyfill"];
        let topo = quarter.topology();
        for f in filled.members() {
            let q = out.prim_points(f);
            let shared = topo.point_prims(q[0] as usize).iter().any(|p| {
                topo.point_prims(q[1] as usize).contains(p)
                    && topo.point_prims(q[2] as usize).contains(p)
            });
            assert!(!shared, "{how:?}: fill triangle {f} lies on a face");
        }
        let t = ops::triangulate(&out, None);
        assert_eq!(euler_and_closed(&t), (2, true), "{how:?}");
    }
}

#[test]
fn a_sheets_hole_and_border_fill_on_their_own() {
    // The hole and the grid's outline share a plane, but the grid already
    // covers the ring between them: both are filled whole.
    let mut g = primitives::grid(Vec2::new(6.0, 6.0), 6, 6);
    let hole =
        Group::from_flags((0..36).map(|q| (2..4).contains(&(q % 6)) && (2..4).contains(&(q / 6))));
    ops::delete_prims(&mut g, &hole, true);
    let r = polyfill(&g, &FillOptions::default(), &never).unwrap();
    assert_eq!(r.holes_filled, 2);
    let out = &r.geometry;
    let filled = &out.prim_groups()["polyfill"];
    let area: f32 = filled.members().map(|p| polygon_area(out, p)).sum();
    assert!((area - 40.0).abs() < 1e-4, "{area}");
}

#[test]
fn the_fill_of_a_square_hole_has_the_holes_area() {
    let mut g = primitives::grid(Vec2::new(6.0, 6.0), 6, 6);
    // The 2x2 block of quads in the middle (columns and rows 2 and 3).
    let hole =
        Group::from_flags((0..36).map(|q| (2..4).contains(&(q % 6)) && (2..4).contains(&(q / 6))));
    ops::delete_prims(&mut g, &hole, true);
    for mode in [FillMode::Triangles, FillMode::Polygon, FillMode::Fan] {
        for how in [Triangulation::MinWeight, Triangulation::EarClip] {
            // The grid's outline is a loop too (24 points): left open.
            let o = FillOptions {
                mode,
                triangulation: how,
                max_points: 8,
                ..FillOptions::default()
            };
            let r = polyfill(&g, &o, &never).unwrap().geometry;
            let filled = &r.prim_groups()["polyfill"];
            let area: f32 = filled.members().map(|p| polygon_area(&r, p)).sum();
            // The grid faces +Y and so do the fills.
            assert!((area - 4.0).abs() < 1e-5, "{mode:?} {how:?}: {area}");
            for p in filled.members() {
                let n = ops::polygon_normal(r.positions(), r.prim_points(p));
                assert!(n.y > 0.999, "{mode:?}: {n}");
                if mode == FillMode::Triangles {
                    assert!(polygon_area(&r, p) > 0.1, "a sliver");
                }
            }
            let uv = r
                .attrib(AttribClass::Point, "uv")
                .unwrap()
                .as_vec2()
                .unwrap();
            if mode == FillMode::Fan {
                // The centre's uv is the mean of the loop's.
                assert!((uv[r.num_points() - 1] - Vec2::new(0.5, 0.5)).length() < 1e-6);
            }
        }
    }
}

// ----- convex hull -----
