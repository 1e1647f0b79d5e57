//! Clip phase 5: the pieces and caps numbered into the output geometry,
//! attributes and groups carried (see the clip module doc).

use geode_geo::{AttribClass, Geometry, Group, PrimKind, TypeInfo};

use super::{Cap, ClipOptions, Parts, Splitter, ABOVE, BELOW};
use crate::carry::{self, copy, Plan};
use crate::ModelError;

impl Splitter<'_> {
    pub(super) fn assemble(
        &self,
        parts: Parts,
        first_cap: usize,
        options: &ClipOptions,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Geometry, ModelError> {
        let index = self.number_points(&parts);
        let mut plan = Plan {
            first_new_prim: first_cap,
            ..Plan::default()
        };
        let refs = self.references();
        let np = self.g.num_points();
        for (r, &i) in index.iter().enumerate() {
            if i == u32::MAX {
                continue;
            }
            let base = r % refs;
            if base < np {
                plan.positions.push(self.g.positions()[base]);
                plan.point_sources.push(copy(base as u32));
            } else {
                let j = base - np;
                let key = self.cuts.keys[j];
                plan.positions.push(self.cuts.positions[j].as_vec3());
                plan.point_sources
                    .push(((key >> 32) as u32, key as u32, self.cuts.t[j] as f32));
            }
        }
        plan.vertex_points = parts.corners.iter().map(|c| index[c.r as usize]).collect();
        plan.vertex_sources = parts.corners.iter().map(|c| c.vb).collect();
        plan.prim_counts = parts.pieces.iter().map(|p| p.count).collect();
        plan.prim_kinds = parts
            .pieces
            .iter()
            .map(|p| {
                if p.closed {
                    PrimKind::Polygon
                } else {
                    PrimKind::Polyline
                }
            })
            .collect();
        plan.prim_sources = parts.pieces.iter().map(|p| p.source).collect();
        let mut out = carry::build(self.g, plan, "clip", cancel)?;
        let sides: Vec<u8> = parts.pieces.iter().map(|p| p.side).collect();
        self.mark_groups(&mut out, &sides, first_cap, options)?;
        self.face_caps_out(&mut out, &sides, first_cap);
        Ok(out)
    }

    /// The output number of every reference (u32::MAX: not in the output),
    /// in reference order: points used by a piece or a cap, and points no
    /// primitive used that lie on a kept side.
    fn number_points(&self, parts: &Parts) -> Vec<u32> {
        let refs = self.references();
        let space = if self.split_points { 2 * refs } else { refs };
        let mut used = vec![false; space];
        for c in &parts.corners {
            used[c.r as usize] = true;
        }
        let np = self.g.num_points();
        let mut referenced = vec![false; np];
        for &p in self.g.vertex_points() {
            referenced[p as usize] = true;
        }
        for (p, r) in referenced.iter().enumerate() {
            let side = match self.field.class[p] {
                1 => self.kept(ABOVE),
                -1 => self.kept(BELOW),
                _ => true,
            };
            if !r && side {
                used[p] = true;
            }
        }
        let mut next = 0u32;
        used.iter()
            .map(|&u| {
                if u {
                    next += 1;
                    next - 1
                } else {
                    u32::MAX
                }
            })
            .collect()
    }

    fn mark_groups(
        &self,
        out: &mut Geometry,
        sides: &[u8],
        first_cap: usize,
        options: &ClipOptions,
    ) -> Result<(), ModelError> {
        let failed = |e: geode_geo::GeoError| ModelError::Failed {
            op: "clip",
            why: e.to_string(),
        };
        for (side, name) in [(ABOVE, &options.above_group), (BELOW, &options.below_group)] {
            if self.kept(side) && !name.is_empty() {
                let group = Group::from_flags(sides.iter().map(|&s| s == side));
                out.set_prim_group(name, group).map_err(failed)?;
            }
        }
        if options.cap != Cap::None && !options.cap_group.is_empty() {
            let group = Group::from_flags((0..sides.len()).map(|p| p >= first_cap));
            out.set_prim_group(&options.cap_group, group)
                .map_err(failed)?;
        }
        Ok(())
    }

    /// Vertex normals on caps point out of the cap (they were copied from
    /// the faces around it).
    fn face_caps_out(&self, out: &mut Geometry, sides: &[u8], first_cap: usize) {
        if first_cap == sides.len() {
            return;
        }
        let names: Vec<String> = out
            .attribs(AttribClass::Vertex)
            .iter()
            .filter(|(_, a)| a.type_info == TypeInfo::Normal && a.as_vec3().is_some())
            .map(|(n, _)| n.to_string())
            .collect();
        let ranges: Vec<(std::ops::Range<usize>, u8)> = (first_cap..sides.len())
            .map(|p| (out.prim_vertex_range(p), sides[p]))
            .collect();
        let n = self.field.normal.as_vec3();
        for name in names {
            let attr = out
                .attribs_mut(AttribClass::Vertex)
                .get_mut(&name)
                .expect("listed above");
            let values = attr.as_vec3_mut().expect("checked above");
            for (range, side) in &ranges {
                let outward = if *side == ABOVE { -n } else { n };
                values[range.clone()].fill(outward);
            }
        }
    }
}
