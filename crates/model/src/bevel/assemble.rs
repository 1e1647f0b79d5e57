//! The bevelled mesh put together from every bevelled point's corner: the
//! faces with their corners replaced by chains, a strip of quads along
//! each bevelled edge between its two end profiles, and the patches; a
//! `carry::Plan` so every attribute and group follows.

use geode_geo::{Geometry, Group, PrimKind};

use super::corner::{Corner, VSrc};
use super::mesh::{HalfEdges, NONE};
use crate::carry::{self, copy, Plan};
use crate::ModelError;

/// The output: faces (in input order), then edge strips (in half-edge
/// order), then patches (in point order), with the two groups.
pub(super) fn assemble(
    g: &Geometry,
    he: &HalfEdges,
    bevelled: &[bool],
    corners: &[Corner],
    affected: &[bool],
    groups: (&str, &str),
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let stop = || ModelError::unless_cancelled(cancel);
    let mut plan = Plan::default();
    // Points not bevelled keep their place in order; each corner's new
    // points follow, corner by corner.
    let mut map = vec![NONE; g.num_points()];
    for p in 0..g.num_points() {
        if p % 8192 == 0 {
            stop()?;
        }
        if !affected[p] {
            map[p] = plan.positions.len() as u32;
            plan.positions.push(g.positions()[p]);
            plan.point_sources.push(copy(p as u32));
        }
    }
    let mut base = Vec::with_capacity(corners.len());
    // Per half-edge leaving a bevelled point: (corner, its fan position).
    let mut slot = vec![(NONE, NONE); g.num_vertices()];
    let mut profile_of = vec![(NONE, NONE); g.num_vertices()];
    for (c, corner) in corners.iter().enumerate() {
        if c % 2048 == 0 {
            stop()?;
        }
        base.push(plan.positions.len() as u32);
        for &(at, src) in &corner.points {
            plan.positions.push(at);
            plan.point_sources.push(src);
        }
        for (i, &h) in corner.fan.iter().enumerate() {
            slot[h as usize] = (c as u32, i as u32);
        }
        for (k, &(h, _)) in corner.profiles.iter().enumerate() {
            profile_of[h as usize] = (c as u32, k as u32);
        }
    }
    stop()?;
    faces(g, he, corners, &base, &slot, &map, &mut plan);
    stop()?;
    plan.first_new_prim = plan.prim_counts.len();
    let first_strip = plan.prim_counts.len();
    strips(g, he, bevelled, corners, &base, &profile_of, &mut plan);
    stop()?;
    let first_patch = plan.prim_counts.len();
    for (c, corner) in corners.iter().enumerate() {
        for (src, poly) in &corner.patches {
            add_prim(
                &mut plan,
                *src,
                poly.iter().map(|&(k, v)| (base[c] + k, copy(v))),
            );
        }
    }
    let total = plan.prim_counts.len();
    let mut out = carry::build(g, plan, "polybevel", cancel)?;
    let (edge_group, corner_group) = groups;
    for (name, range) in [
        (edge_group, first_strip..first_patch),
        (corner_group, first_patch..total),
    ] {
        if name.is_empty() {
            continue;
        }
        let members = Group::from_flags((0..total).map(|k| range.contains(&k)));
        out.set_prim_group(name, members)
            .map_err(|e| ModelError::Failed {
                op: "polybevel",
                why: e.to_string(),
            })?;
    }
    Ok(out)
}

fn add_prim(plan: &mut Plan, src: u32, verts: impl Iterator<Item = (u32, carry::Blend)>) {
    let mut count = 0;
    for (p, v) in verts {
        plan.vertex_points.push(p);
        plan.vertex_sources.push(v);
        count += 1;
    }
    plan.prim_counts.push(count);
    plan.prim_kinds.push(PrimKind::Polygon);
    plan.prim_sources.push(src);
}

/// Every input face, each corner at a bevelled point replaced by its
/// chain.
fn faces(
    g: &Geometry,
    he: &HalfEdges,
    corners: &[Corner],
    base: &[u32],
    slot: &[(u32, u32)],
    map: &[u32],
    plan: &mut Plan,
) {
    for f in 0..g.num_prims() {
        let mut verts = Vec::new();
        for h in g.prim_vertex_range(f) {
            let h32 = h as u32;
            let (c, i) = slot[h];
            if c == NONE {
                verts.push((map[g.vertex_points()[h] as usize], copy(h32)));
                continue;
            }
            for &(k, src) in &corners[c as usize].chains[i as usize] {
                let blend = match src {
                    VSrc::Copy => copy(h32),
                    VSrc::Prev(t) => (h32, he.prev(g, h32), t),
                    VSrc::Next(t) => (h32, he.next(g, h32), t),
                };
                verts.push((base[c as usize] + k, blend));
            }
        }
        add_prim(plan, f as u32, verts.into_iter());
    }
}

/// A strip of quads along each bevelled edge: from the profile at its
/// first half-edge's origin to the one at its end, both read from the
/// first half-edge's face to its twin's, each quad's corners blending the
/// two faces' corners by where they are across the profile.
fn strips(
    g: &Geometry,
    he: &HalfEdges,
    bevelled: &[bool],
    corners: &[Corner],
    base: &[u32],
    profile_of: &[(u32, u32)],
    plan: &mut Plan,
) {
    let ids = |h: u32| -> Vec<u32> {
        let (c, k) = profile_of[h as usize];
        let corner = &corners[c as usize];
        corner.profiles[k as usize]
            .1
            .iter()
            .map(|&x| base[c as usize] + x)
            .collect()
    };
    for h in 0..g.num_vertices() as u32 {
        let t = he.twin[h as usize];
        if !bevelled[h as usize] || t < h {
            continue;
        }
        let at_v = ids(h);
        let mut at_w = ids(t);
        at_w.reverse();
        let n = at_v.len() - 1;
        // Corners of the two faces at each end.
        let (a_v, b_v) = (h, he.next(g, t));
        let (a_w, b_w) = (he.next(g, h), t);
        for j in 0..n {
            let (s0, s1) = (j as f32 / n as f32, (j + 1) as f32 / n as f32);
            let quad = [
                (at_w[j], (a_w, b_w, s0)),
                (at_v[j], (a_v, b_v, s0)),
                (at_v[j + 1], (a_v, b_v, s1)),
                (at_w[j + 1], (a_w, b_w, s1)),
            ];
            add_prim(plan, he.face[h as usize], quad.into_iter());
        }
    }
}
