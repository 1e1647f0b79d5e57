//! Catmull-Clark at scale: a 100k-quad sphere refined to levels 2 and 3
//! (topology and positions), next to OpenSubdiv's uniform refinement of the
//! same mesh on the same machine when `GEODE_OSD_REF` names the reference
//! program (tools/test.sh builds tools/osd_ref/osd_ref).
//! Run: GEODE_OSD_REF=tools/osd_ref/osd_ref cargo bench -p geode-spline --bench subd

use geode_geo::primitives;
use geode_spline::subd::{base_level, refine_levels, SubdOptions};

fn sphere() -> geode_geo::Geometry {
    primitives::uv_sphere(1.0, 400, 250)
}

fn flat(g: &geode_geo::Geometry) -> Vec<f64> {
    g.positions()
        .iter()
        .flat_map(|p| p.as_dvec3().to_array())
        .collect()
}

fn opts() -> SubdOptions {
    SubdOptions {
        levels: 0,
        boundary: None,
        crease: None,
        fvar: None,
        limit: false,
    }
}

fn opensubdiv_ms(g: &geode_geo::Geometry, levels: u32) -> Option<String> {
    use std::io::Write;
    let bin = std::env::var("GEODE_OSD_REF").ok()?;
    let mut text = format!(
        "boundary 1 crease 0 levels {levels}\nverts {}\n",
        g.num_points()
    );
    for p in g.positions() {
        text += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    text += &format!("faces {}\n", g.num_prims());
    for f in 0..g.num_prims() {
        let pts = g.prim_points(f);
        text += &pts.len().to_string();
        for p in pts {
            text += &format!(" {p}");
        }
        text += "\n";
    }
    text += "creases 0\ncorners 0\nholes 0\n";
    let mut child = std::process::Command::new(bin)
        .env("OSD_REF_TIME", "5")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .ok()?;
    child.stdin.take()?.write_all(text.as_bytes()).ok()?;
    let out = child.wait_with_output().ok()?;
    Some(String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

fn main() {
    let g = sphere();
    for levels in [2, 3] {
        if let Some(ms) = opensubdiv_ms(&g, levels) {
            eprintln!(
                "OpenSubdiv (Far, one thread): {} faces to level {levels}: {ms} ms (median of 5)",
                g.num_prims()
            );
        }
    }
    let t = std::time::Instant::now();
    let (base, _, method) = base_level(&g, &opts()).unwrap();
    let build = t.elapsed();
    let t = std::time::Instant::now();
    let _ = refine_levels(base, flat(&g), 2, method, false);
    eprintln!(
        "geode: base level {:.1} ms, two levels {:.1} ms",
        build.as_secs_f64() * 1e3,
        t.elapsed().as_secs_f64() * 1e3
    );
    divan::main();
}

#[divan::bench(args = [2, 3], sample_count = 5)]
fn refine_100k_quads(bencher: divan::Bencher, levels: u32) {
    let g = sphere();
    bencher.bench(|| {
        let (base, _, method) = base_level(&g, &opts()).unwrap();
        refine_levels(base, flat(&g), levels, method, false)
    });
}

/// NURBS evaluation throughput: a million points with normals on an exact
/// rational torus (tessellated as a 1000 x 1000 grid, in parallel).
#[divan::bench(sample_count = 5)]
fn nurbs_torus_1m_points_with_normals(bencher: divan::Bencher) {
    let s = geode_spline::bspline::NurbsSurface::torus(1.5, 0.5);
    bencher
        .counter(divan::counter::ItemsCount::new(1_000_000usize))
        .bench(|| s.tessellate(1000, 1000));
}

/// Hierarchical spline throughput: a torus of 8 x 12 vertices refined three
/// times (a 64 x 96 finest grid, one local edit), its finest level
/// tessellated at 512 x 512 points with normals.
#[divan::bench(sample_count = 5)]
fn hspline_torus_3_levels_512x512(bencher: divan::Bencher) {
    use geode_spline::hspline::{Hspline, Topology};
    let mut h = Hspline::new(Topology::Torus, 8, 12, [3.0, 1.0]).unwrap();
    for _ in 0..3 {
        h.refine(None).unwrap();
    }
    h.move_cv(3, 30, 40, geode_geo::glam::DVec3::new(0.2, 0.0, 0.1))
        .unwrap();
    bencher
        .counter(divan::counter::ItemsCount::new(512usize * 512))
        .bench(|| h.tessellate(512, 512));
}

/// The sphere with spherical uvs per corner, seamed where u wraps.
fn sphere_with_uvs() -> geode_geo::Geometry {
    use geode_geo::glam::Vec2;
    use geode_geo::{AttribClass, AttribData, Attribute, TypeInfo};
    let mut g = sphere();
    let p = g.positions().to_vec();
    let mut uvs = Vec::with_capacity(g.num_vertices());
    for f in 0..g.num_prims() {
        let corner: Vec<Vec2> = g
            .prim_points(f)
            .iter()
            .map(|&i| {
                let q = p[i as usize];
                let u = q.z.atan2(q.x) / std::f32::consts::TAU + 0.5;
                Vec2::new(u, q.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI)
            })
            .collect();
        let wraps = corner.iter().any(|c| c.x > 0.75) && corner.iter().any(|c| c.x < 0.25);
        uvs.extend(
            corner
                .into_iter()
                .map(|c| if wraps && c.x < 0.25 { c + Vec2::X } else { c }),
        );
    }
    g.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec2(uvs), TypeInfo::TexCoord),
    )
    .unwrap();
    g
}

/// Face-varying uvs: the 100k-quad sphere (uv seam and poles) subdivided
/// twice with smooth uv boundaries (OpenSubdiv's `none`, the most work).
#[divan::bench(sample_count = 5)]
fn subdivide_100k_quads_with_smooth_uvs(bencher: divan::Bencher) {
    let g = sphere_with_uvs();
    let opts = SubdOptions {
        levels: 2,
        boundary: None,
        crease: None,
        fvar: Some(geode_spline::subd::FVarLinear::None),
        limit: false,
    };
    bencher.bench(|| geode_spline::subdivide(&g, &opts, &|| false).unwrap());
}

/// Attachments: a 10 x 12 palm with four fingers side by side and a thumb
/// (each refined once), placed and refined to the finest level plus three
/// (about 120k limit points with normals).
#[divan::bench(sample_count = 5)]
fn attach_hand_five_limbs(bencher: divan::Bencher) {
    use geode_spline::hspline::attach::{attach, Limb};
    use geode_spline::hspline::{Hspline, Topology};
    let mut palm = Hspline::new(Topology::Plane, 10, 12, [4.0, 5.0]).unwrap();
    palm.refine(None).unwrap();
    let finger = |rows: usize| {
        let mut h = Hspline::new(Topology::Cylinder, rows, 6, [0.55, 2.0]).unwrap();
        h.refine(None).unwrap();
        h
    };
    let mut limbs: Vec<Limb> = (0..4)
        .map(|k| Limb {
            surface: finger(7),
            region: ((7, 8), (2 + 2 * k, 4 + 2 * k)),
        })
        .collect();
    limbs.push(Limb {
        surface: finger(6),
        region: ((3, 5), (1, 2)),
    });
    let points = attach(&palm, &limbs, true, 3).unwrap().positions.len();
    bencher
        .counter(divan::counter::ItemsCount::new(points))
        .bench(|| attach(&palm, &limbs, true, 3).unwrap());
}
