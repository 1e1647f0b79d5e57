//! The seed examples look like their seeds: the chains of seed 003
//! (`examples/chain_vex.json`, `examples/chain.json`) interlock, each link a
//! quarter turn from the next, and the coral of seed 001
//! (`examples/coral_vex.json`) is one continuous tube per branch.

use std::sync::Arc;

use geode_geo::glam::{DMat3, DVec3};
use geode_geo::{AttribClass, Geometry, PrimKind};

fn example(name: &str) -> String {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn cook(text: &str, nodes: &[&str], frame: f64) -> Vec<Arc<Geometry>> {
    let net = geode_graph::load_str(text, &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::new(1 << 29);
    let engine = geode_graph::Engine::new(net, &cache);
    let opts = geode_graph::CookOptions::at_frame(frame);
    nodes
        .iter()
        .map(|n| {
            let r = engine.cook(n, &opts).unwrap_or_else(|e| panic!("{e:?}"));
            r.value.as_geometry().unwrap().clone()
        })
        .collect()
}

/// Connected pieces (points joined by primitives), as point lists in order
/// of their lowest point.
fn pieces(g: &Geometry) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..g.num_points()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        for w in pts.windows(2) {
            let (a, b) = (
                root(&mut parent, w[0] as usize),
                root(&mut parent, w[1] as usize),
            );
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for i in 0..g.num_points() {
        let r = root(&mut parent, i);
        by_root.entry(r).or_default().push(i);
    }
    by_root.into_values().collect()
}

/// Eigenvalues (ascending) and unit eigenvectors of a symmetric 3x3 matrix
/// by cyclic Jacobi rotations.
fn symmetric_eigen(m: DMat3) -> ([f64; 3], [DVec3; 3]) {
    let mut a = m.to_cols_array_2d();
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            // (signum(0) is 1: a 45 degree turn when the diagonal is equal.)
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // a = J^T a J, v = v J with J the rotation in the (p, q) plane.
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // Column k of v (rows indexed first) is the eigenvector of a[k][k].
    let mut pairs: Vec<(f64, DVec3)> = (0..3)
        .map(|k| (a[k][k], DVec3::new(v[0][k], v[1][k], v[2][k]).normalize()))
        .collect();
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    (
        [pairs[0].0, pairs[1].0, pairs[2].0],
        [pairs[0].1, pairs[1].1, pairs[2].1],
    )
}

/// The normal of the best-fit plane of the points (the covariance's
/// eigenvector of least variance) and the centroid.
fn plane(g: &Geometry, points: &[usize]) -> (DVec3, DVec3) {
    let p: Vec<DVec3> = points
        .iter()
        .map(|&i| g.positions()[i].as_dvec3())
        .collect();
    let c = p.iter().copied().sum::<DVec3>() / p.len() as f64;
    let mut cov = DMat3::ZERO;
    for q in &p {
        let d = *q - c;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let (values, vectors) = symmetric_eigen(cov / p.len() as f64);
    assert!(
        values[0] < 0.5 * values[1],
        "a link is not flat: variances {values:?}"
    );
    (vectors[0], c)
}

#[test]
fn the_eigen_solver_finds_a_known_plane() {
    // Points on the plane through the origin with normal (1, 2, 2) / 3,
    // spread more along one in-plane direction than the other.
    let n = DVec3::new(1.0, 2.0, 2.0) / 3.0;
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let mut g = Geometry::new();
    for k in 0..40 {
        let t = k as f64 * std::f64::consts::TAU / 40.0;
        g.add_point((u * 3.0 * t.cos() + w * t.sin() + n * 0.01 * (k % 2) as f64).as_vec3());
    }
    let all: Vec<usize> = (0..40).collect();
    let (normal, _) = plane(&g, &all);
    assert!(normal.dot(n).abs() > 1.0 - 1e-6, "{normal}");
}

/// Neighbouring links' planes in degrees, link by link.
fn link_angles(chain: &Geometry) -> Vec<f64> {
    let links = pieces(chain);
    let normals: Vec<DVec3> = links.iter().map(|l| plane(chain, l).0).collect();
    normals
        .windows(2)
        .map(|w| w[0].dot(w[1]).abs().min(1.0).acos().to_degrees())
        .collect()
}

/// The links' tube: the examples' sweep radius and sides.
const TUBE: f64 = 0.022;
const SIDES: usize = 10;

/// Checks that `name`'s chain has `links` flat links, none cutting into
/// its neighbours, whose neighbouring planes are 90 degrees apart within
/// `slack(tangent j, tangent j + 1)`.
fn assert_interlocked(name: &str, links: usize, frames: &str, slack: impl Fn(DVec3, DVec3) -> f64) {
    let cooked = cook(&example(name), &["/chain", frames], 1.0);
    let (chain, frames) = (&cooked[0], &cooked[1]);
    assert_eq!(pieces(chain).len(), links, "{name}: one piece per link");
    let t = frames
        .attrib(AttribClass::Point, "T")
        .and_then(|a| a.as_vec3())
        .expect("tangents T on the template points");
    // No link cuts into the next or the one after: their centrelines (the
    // mean of each ring of the sweep's 10 sides) stay a tube's diameter
    // apart.
    let centreline = |l: &Vec<usize>| -> Vec<DVec3> {
        l.chunks(SIDES)
            .map(|r| {
                r.iter()
                    .map(|&i| chain.positions()[i].as_dvec3())
                    .sum::<DVec3>()
                    / SIDES as f64
            })
            .collect()
    };
    let lines: Vec<Vec<DVec3>> = pieces(chain).iter().map(centreline).collect();
    let apart = |a: &[DVec3], b: &[DVec3]| {
        a.iter()
            .flat_map(|p| b.iter().map(move |q| p.distance(*q)))
            .fold(f64::INFINITY, f64::min)
    };
    let mut closest = [f64::INFINITY; 2];
    for j in 0..links - 1 {
        for k in [j + 1, j + 2].into_iter().filter(|&k| k < links) {
            closest[k - j - 1] = closest[k - j - 1].min(apart(&lines[j], &lines[k]));
        }
    }
    eprintln!(
        "{name}: centrelines of neighbours {:.4} apart, of next-but-one {:.4}",
        closest[0], closest[1]
    );
    for j in 0..links - 1 {
        for k in [j + 1, j + 2].into_iter().filter(|&k| k < links) {
            let d = apart(&lines[j], &lines[k]);
            assert!(
                d > 2.0 * TUBE,
                "{name}: links {j} and {k} cut into each other ({d:.4} between centrelines)"
            );
        }
    }
    let angles = link_angles(chain);
    let worst = angles
        .iter()
        .map(|a| (a - 90.0).abs())
        .fold(0.0f64, f64::max);
    eprintln!("{name}: neighbouring link planes 90 deg +- {worst:.3}");
    for (j, a) in angles.iter().enumerate() {
        let allowed = slack(t[j].as_dvec3(), t[j + 1].as_dvec3());
        assert!(
            (a - 90.0).abs() <= allowed,
            "{name}: links {j} and {} are {a:.3} deg apart (allowed 90 +- {allowed:.3})",
            j + 1
        );
    }
}

/// Seed 003's chain as VEX: the orient its wrangles write (a vector4) turns
/// every link, so each link's plane is a quarter turn from its neighbours'.
#[test]
fn seed_003_vex_chain_links_interlock() {
    assert_interlocked("chain_vex.json", 140, "/compute_tangent", |_, _| 1.0);
}

/// The polyframe chain on the trefoil: link j + 1 is link j rolled a
/// quarter turn about the tangent and carried along the curve by the turn
/// between their tangents (angle theta about an axis a across the tangent).
/// Carrying adds (a.Y)(a.Z)(1 - cos theta) <= (1 - cos theta) / 2 to the
/// cosine of the angle between the planes' normals Y and Z (Rodrigues'
/// formula; the first-order term a.X sin theta is zero). The knot is
/// closed, and polyframe closes its frames by spreading the turn they are
/// short of meeting (at most half a turn) evenly over the points: at most
/// 180 / 96 degrees of twist per link on top. So the planes are 90 degrees
/// apart within that sum, not within 1 degree.
#[test]
fn seed_003_polyframe_chain_links_interlock() {
    let links = 96;
    assert_interlocked("chain.json", links, "/frames", |a, b| {
        let cos = a.normalize().dot(b.normalize()).clamp(-1.0, 1.0);
        180.0 / links as f64 + (0.5 * (1.0 - cos)).asin().to_degrees() + 0.05
    });
}

/// Seed 001's coral as VEX: the growth's two-point segments are joined
/// into one polyline per branch before framing and sweeping, so the sweep
/// makes one continuous tube per branch. The branches are counted from the
/// growth's own segments: every path of a forest runs between two points
/// that are not on exactly two segments, so there are half as many as the
/// segment ends at such points.
#[test]
fn seed_001_vex_coral_is_one_tube_per_branch() {
    let cooked = cook(
        &example("coral_vex.json"),
        &["/grow", "/paths", "/orient", "/coral"],
        90.0,
    );
    let (grow, paths, orient, coral) = (&cooked[0], &cooked[1], &cooked[2], &cooked[3]);
    let mut degree = vec![0usize; grow.num_points()];
    for prim in 0..grow.num_prims() {
        assert_eq!(grow.prim_kind(prim), PrimKind::Polyline);
        let pts = grow.prim_points(prim);
        assert_eq!(pts.len(), 2, "the growth writes two-point segments");
        degree[pts[0] as usize] += 1;
        degree[pts[1] as usize] += 1;
    }
    let ends: usize = degree.iter().filter(|&&d| d != 2).sum();
    let branches = ends / 2;
    assert!(branches > 10, "only {branches} branches grew");
    assert_eq!(paths.num_prims(), branches, "one polyline per branch");
    let longest = (0..paths.num_prims())
        .map(|p| paths.prim_points(p).len())
        .max()
        .unwrap();
    let long = (0..paths.num_prims())
        .filter(|&p| paths.prim_points(p).len() > 2)
        .count();
    eprintln!(
        "{} segments joined into {branches} branches ({long} of more than one segment, the longest {longest} points)",
        grow.num_prims()
    );
    assert!(longest > 10, "the longest branch has {longest} points");
    assert!(long * 2 > branches, "most branches span several segments");
    // Every segment is in exactly one path.
    let joined: usize = (0..paths.num_prims())
        .map(|p| paths.prim_points(p).len() - 1)
        .sum();
    assert_eq!(joined, grow.num_prims());
    // The seed's frames are per branch: each point's orient turns +Z onto
    // its branch's tangent there (towards the next point; at the last, the
    // last segment's direction), so every ring of the tube faces along its
    // branch. A point shared by several branches would keep one branch's
    // frame only.
    let q = match orient
        .attrib(AttribClass::Point, "orient")
        .map(|a| a.data())
    {
        Some(geode_geo::AttribData::Vec4(v)) => v,
        other => panic!("orient is {:?}", other.map(|d| d.attrib_type())),
    };
    assert_eq!(orient.num_prims(), branches);
    let mut worst = 1.0f64;
    for prim in 0..orient.num_prims() {
        let pts = orient.prim_points(prim);
        let at = |k: usize| orient.positions()[pts[k] as usize].as_dvec3();
        for k in 0..pts.len() {
            let tangent = if k + 1 < pts.len() {
                at(k + 1) - at(k)
            } else {
                at(k) - at(k - 1)
            }
            .normalize();
            let z = geode_geo::glam::DQuat::from_vec4(q[pts[k] as usize].as_dvec4()).normalize()
                * DVec3::Z;
            worst = worst.min(z.dot(tangent));
        }
    }
    assert!(
        worst > 1.0 - 1e-5,
        "a ring turns away from its branch (cos {worst})"
    );
    assert_eq!(
        pieces(coral).len(),
        branches,
        "the sweep makes one tube per branch"
    );
    assert!(coral.attrib(AttribClass::Point, "P").is_some());
}
