//! A new geometry made of an old one's elements, one by one: each new
//! point, primitive and vertex names the element of the source whose
//! attributes and group memberships it takes (a `carry::Plan` of copies),
//! so a modelling operation only says where things go and every attribute
//! follows without the operation knowing it.

use geode_geo::glam::Vec3;
use geode_geo::{Geometry, Group, PrimKind};

use crate::carry::{self, copy, Plan};
use crate::ModelError;

/// The output under construction: a `carry::Plan` whose elements each
/// copy one source element, with groups of its own.
#[derive(Default)]
pub struct Rebuild {
    plan: Plan,
    /// Extra primitive groups: name, members by output primitive.
    groups: Vec<(String, Vec<bool>)>,
}

impl Rebuild {
    pub fn new() -> Rebuild {
        Rebuild {
            plan: Plan {
                // Every primitive made here keeps its source's groups.
                first_new_prim: usize::MAX,
                ..Plan::default()
            },
            groups: Vec::new(),
        }
    }

    /// A point at `at` with the attributes of source point `src`.
    pub fn point(&mut self, src: u32, at: Vec3) -> u32 {
        self.plan.positions.push(at);
        self.plan.point_sources.push(copy(src));
        self.plan.positions.len() as u32 - 1
    }

    pub fn num_points(&self) -> usize {
        self.plan.positions.len()
    }

    /// A primitive of `kind` with the attributes of source primitive `src`
    /// through `points`, its vertices taking those of source vertices
    /// `vertices` (one per point).
    pub fn prim(&mut self, src: u32, kind: PrimKind, points: &[u32], vertices: &[u32]) -> u32 {
        debug_assert_eq!(points.len(), vertices.len());
        let plan = &mut self.plan;
        plan.prim_sources.push(src);
        plan.prim_kinds.push(kind);
        plan.prim_counts.push(points.len() as u32);
        plan.vertex_points.extend_from_slice(points);
        plan.vertex_sources
            .extend(vertices.iter().map(|&v| copy(v)));
        plan.prim_kinds.len() as u32 - 1
    }

    /// Marks primitive `prim` as a member of group `name` (made on first
    /// use; members are the primitives marked).
    pub fn mark(&mut self, name: &str, prim: u32) {
        let k = match self.groups.iter().position(|(n, _)| n == name) {
            Some(k) => k,
            None => {
                self.groups.push((name.to_string(), Vec::new()));
                self.groups.len() - 1
            }
        };
        let members = &mut self.groups[k].1;
        if members.len() <= prim as usize {
            members.resize(prim as usize + 1, false);
        }
        members[prim as usize] = true;
    }

    /// Names group `name` even if nothing was marked (an empty group says
    /// the operation ran).
    pub fn declare(&mut self, name: &str) {
        if !self.groups.iter().any(|(n, _)| n == name) {
            self.groups.push((name.to_string(), Vec::new()));
        }
    }

    /// The geometry, every attribute and group carried from `src` (see
    /// `carry::build`), with the groups marked here.
    pub fn finish(
        self,
        src: &Geometry,
        op: &'static str,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Geometry, ModelError> {
        let mut out = carry::build(src, self.plan, op, cancel)?;
        let n = out.num_prims();
        for (name, mut members) in self.groups {
            members.resize(n, false);
            out.set_prim_group(&name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op,
                    why: e.to_string(),
                })?;
        }
        Ok(out)
    }
}
