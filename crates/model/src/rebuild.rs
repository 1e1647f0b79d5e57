//! A new geometry made of an old one's elements: each new point, primitive
//! and vertex names the element of the source whose attributes and group
//! memberships it takes, so a modelling operation only says where things
//! go and every attribute follows without the operation knowing it.

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, GeoError, Geometry, Group, PrimKind};

/// The output under construction: per element, its source's number.
#[derive(Default)]
pub struct Rebuild {
    positions: Vec<Vec3>,
    point_src: Vec<u32>,
    prim_src: Vec<u32>,
    kinds: Vec<PrimKind>,
    counts: Vec<u32>,
    vertex_points: Vec<u32>,
    vertex_src: Vec<u32>,
    /// Extra primitive groups: name, members by output primitive.
    groups: Vec<(String, Vec<bool>)>,
}

impl Rebuild {
    pub fn new() -> Rebuild {
        Rebuild::default()
    }

    /// A point at `at` with the attributes of source point `src`.
    pub fn point(&mut self, src: u32, at: Vec3) -> u32 {
        self.positions.push(at);
        self.point_src.push(src);
        self.positions.len() as u32 - 1
    }

    pub fn num_points(&self) -> usize {
        self.positions.len()
    }

    pub fn num_prims(&self) -> usize {
        self.kinds.len()
    }

    /// A primitive of `kind` with the attributes of source primitive `src`
    /// through `points`, its vertices taking those of source vertices
    /// `vertices` (one per point).
    pub fn prim(&mut self, src: u32, kind: PrimKind, points: &[u32], vertices: &[u32]) -> u32 {
        debug_assert_eq!(points.len(), vertices.len());
        self.prim_src.push(src);
        self.kinds.push(kind);
        self.counts.push(points.len() as u32);
        self.vertex_points.extend_from_slice(points);
        self.vertex_src.extend_from_slice(vertices);
        self.kinds.len() as u32 - 1
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

    /// The geometry, every attribute and group gathered from `src`
    /// (positions are the new ones; detail attributes are copied).
    pub fn finish(self, src: &Geometry) -> Result<Geometry, GeoError> {
        let mut out =
            Geometry::from_prims(self.positions, self.vertex_points, &self.counts, self.kinds)?;
        for (class, sources) in [
            (AttribClass::Point, &self.point_src),
            (AttribClass::Primitive, &self.prim_src),
            (AttribClass::Vertex, &self.vertex_src),
        ] {
            for (name, attr) in src.attribs(class).iter() {
                if class == AttribClass::Point && name == "P" {
                    continue;
                }
                out.set_attrib(class, name, attr.gather(sources))?;
            }
        }
        for (name, attr) in src.attribs(AttribClass::Detail).iter() {
            out.set_attrib(AttribClass::Detail, name, attr.clone())?;
        }
        for (name, group) in src.point_groups() {
            out.set_point_group(name, group.gather(&self.point_src))?;
        }
        for (name, group) in src.prim_groups() {
            out.set_prim_group(name, group.gather(&self.prim_src))?;
        }
        let n = out.num_prims();
        for (name, mut members) in self.groups {
            members.resize(n, false);
            out.set_prim_group(&name, Group::from_flags(members))?;
        }
        Ok(out)
    }
}
