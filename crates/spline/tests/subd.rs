//! Catmull-Clark behaviour beyond OpenSubdiv's positions: limit normals,
//! holes, interpolated attributes, errors.

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{ops, primitives, AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_spline::subd::{subdivide, SubdError, SubdOptions};

fn opts(levels: u32, limit: bool) -> SubdOptions {
    SubdOptions {
        levels,
        boundary: None,
        crease: None,
        fvar: None,
        limit,
    }
}

#[test]
fn a_cube_becomes_a_closed_smooth_surface_with_outward_limit_normals() {
    let cube = primitives::cube(2.0);
    let g = subdivide(&cube, &opts(4, true), &|| false).unwrap();
    assert_eq!(g.num_prims(), 6 * 4usize.pow(4));
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    let n = g
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap()
        .to_vec();
    // Limit normals against the normals of the limit mesh's faces around
    // each point (which converge to them): within a few degrees at level 4.
    let mesh_normals = ops::point_normals(&g);
    let mut worst = 0.0f32;
    for (i, p) in g.positions().iter().enumerate() {
        assert!((n[i].length() - 1.0).abs() < 1e-5);
        assert!(n[i].dot(*p) > 0.0, "outward at {p}");
        worst = worst.max(n[i].angle_between(mesh_normals[i]));
    }
    assert!(worst.to_degrees() < 3.0, "worst {}", worst.to_degrees());
    // The limit surface of a cube lies inside it and is symmetric.
    let b = ops::bounds(&g).unwrap();
    assert!((b.max.x + b.min.x).abs() < 1e-5 && b.max.x < 1.0 && b.max.x > 0.5);
}

#[test]
fn holes_are_refined_but_not_output_and_attributes_follow() {
    let mut grid = primitives::grid(Vec2::splat(2.0), 2, 2);
    let n = grid.num_prims();
    grid.set_attrib(
        AttribClass::Primitive,
        "subd_hole",
        Attribute::from_data(
            AttribData::Int((0..n as i32).map(|i| i32::from(i == 0)).collect()),
            TypeInfo::None,
        ),
    )
    .unwrap();
    grid.set_attrib(
        AttribClass::Primitive,
        "id",
        Attribute::from_data(AttribData::Int((0..n as i32).collect()), TypeInfo::None),
    )
    .unwrap();
    let np = grid.num_points();
    grid.set_attrib(
        AttribClass::Point,
        "Cd",
        Attribute::from_data(
            AttribData::Vec3(vec![Vec3::new(0.2, 0.4, 0.6); np]),
            TypeInfo::Color,
        ),
    )
    .unwrap();
    let g = subdivide(&grid, &opts(2, false), &|| false).unwrap();
    assert_eq!(g.num_prims(), 3 * 16, "the hole's 16 children are left out");
    let id = g
        .attrib(AttribClass::Primitive, "id")
        .unwrap()
        .as_i32()
        .unwrap();
    assert!(id.iter().all(|&i| i != 0) && id.iter().filter(|&&i| i == 3).count() == 16);
    let cd = g
        .attrib(AttribClass::Point, "Cd")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert!(
        cd.iter()
            .all(|c| (*c - Vec3::new(0.2, 0.4, 0.6)).length() < 1e-6),
        "affine masks keep constants"
    );
}

#[test]
fn face_varying_uvs_are_interpolated_linearly_per_face() {
    // A grid with uvs equal to the XZ position on each corner: bilinear per
    // face, so every refined corner's uv is its own parametric position.
    let mut grid = primitives::grid(Vec2::splat(2.0), 3, 3);
    let uv: Vec<Vec2> = grid
        .vertex_points()
        .iter()
        .map(|&p| {
            let q = grid.positions()[p as usize];
            Vec2::new(q.x, q.z)
        })
        .collect();
    grid.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
    )
    .unwrap();
    let g = subdivide(&grid, &opts(2, false), &|| false).unwrap();
    let uv = g
        .attrib(AttribClass::Vertex, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    assert_eq!(uv.len(), g.num_vertices());
    // A refined interior face-corner sits where its uv says on the flat grid,
    // except along the boundary where creases pull points; check interior ones.
    let mut checked = 0;
    for (v, &p) in g.vertex_points().iter().enumerate() {
        let q = g.positions()[p as usize];
        if q.x.abs() < 0.3 && q.z.abs() < 0.3 {
            assert!(
                (Vec2::new(q.x, q.z) - uv[v]).length() < 0.05,
                "{q} vs {}",
                uv[v]
            );
            checked += 1;
        }
    }
    assert!(checked > 10);
}

#[test]
fn non_polygons_are_refused() {
    let mut g = Geometry::new();
    g.add_points(&[Vec3::ZERO, Vec3::X]);
    g.add_polyline(&[0, 1]).unwrap();
    assert_eq!(
        subdivide(&g, &opts(1, false), &|| false).unwrap_err(),
        SubdError::NotPolygon(0)
    );
    assert_eq!(
        subdivide(&primitives::cube(1.0), &opts(1, false), &|| true).unwrap_err(),
        SubdError::Cancelled
    );
}

/// A periodic uniform bicubic B-spline over a torus-shaped control grid is
/// the Catmull-Clark limit surface of that grid as a quad mesh: at every
/// control vertex, the spline's point at the matching knot equals the
/// subdivision limit position (the bicubic node point).
#[test]
fn a_bicubic_torus_equals_the_catmull_clark_limit_of_its_control_mesh() {
    use geode_geo::glam::DVec3;
    use geode_spline::bspline::{Knots, NurbsSurface};
    let (nu, nv) = (8, 12);
    let grid: Vec<DVec3> = (0..nu * nv)
        .map(|k| {
            let (i, j) = (k / nv, k % nv);
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / nu as f64,
                std::f64::consts::TAU * j as f64 / nv as f64,
            );
            // A lumpy torus so that no symmetry hides a mistake.
            let r = 0.5 + 0.1 * (3.0 * b).sin();
            DVec3::new(
                (2.0 + r * a.cos()) * b.cos(),
                r * a.sin() + 0.2 * (2.0 * b).cos(),
                (2.0 + r * a.cos()) * b.sin(),
            )
        })
        .collect();
    // The spline: wrap three rows and columns for periodic uniform knots.
    let wrapped: Vec<_> = (0..(nu + 3) * (nv + 3))
        .map(|k| grid[((k / (nv + 3)) % nu) * nv + (k % (nv + 3)) % nv].extend(1.0))
        .collect();
    let s = NurbsSurface::new(
        Knots::uniform(3, nu + 3),
        Knots::uniform(3, nv + 3),
        wrapped,
    )
    .unwrap();
    // The mesh: quads (i, j) (i+1, j) (i+1, j+1) (i, j+1), wrapping.
    let mut faces = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let id = |a: usize, b: usize| ((a % nu) * nv + b % nv) as u32;
            faces.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = Geometry::from_polygons(
        grid.iter().map(|p| p.as_vec3()).collect(),
        faces,
        &vec![4; nu * nv],
    )
    .unwrap();
    let limit = subdivide(&mesh, &opts(1, true), &|| false).unwrap();
    // The children of the original vertices come first, in order.
    let mut worst = 0.0f64;
    for i in 0..nu {
        for j in 0..nv {
            // Wrapped control point k peaks (weight 4/6) at knot k + 2; the
            // domain is [3, n + 3], so vertex 0 is taken as wrapped n.
            let (ku, kv) = ((i + nu - 1) % nu + 1, (j + nv - 1) % nv + 1);
            let spline = s.point((ku + 2) as f64, (kv + 2) as f64);
            let sub = limit.positions()[i * nv + j].as_dvec3();
            worst = worst.max((spline - sub).length());
        }
    }
    assert!(worst < 2e-6, "to float precision: worst {worst}");
}

/// The same bytes on one thread and on several, for every option's
/// face-varying path (linear passes and span rules) and the limit: the car
/// at level 3 (105k faces, creases, uv seams) splits every parallel step
/// into many blocks.
#[test]
fn the_same_output_on_one_thread_and_many() {
    let car = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../corpus/opensubdiv/catmark_car.obj");
    let g = geode_io::read(&car, &geode_io::NoProgress).unwrap();
    let on = |threads: usize, o: &SubdOptions| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| subdivide(&g, o, &|| false).unwrap().content_hash())
    };
    for fvar in [
        geode_spline::subd::FVarLinear::Boundaries,
        geode_spline::subd::FVarLinear::CornersPlus1,
    ] {
        for limit in [false, true] {
            let o = SubdOptions {
                fvar: Some(fvar),
                ..opts(3, limit)
            };
            let one = on(1, &o);
            assert_eq!(one, on(3, &o), "{fvar:?}, limit {limit}");
            assert_eq!(one, on(4, &o), "{fvar:?}, limit {limit}");
        }
    }
}
