//! The `Geometry` container: points, vertices, primitives, attributes, groups, packed instances.

use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock};

use glam::{Mat4, Vec3};

use crate::attrib::{AttribClass, AttribData, AttribTable, AttribValue, Attribute, TypeInfo};
use crate::error::GeoError;
use crate::group::Group;
use crate::shared::Shared;
use crate::topology::Topology;

mod build;

/// The name of the point position attribute, always present.
pub const P: &str = "P";

/// What a primitive is. Every primitive owns a contiguous run of vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PrimKind {
    /// A closed polygon (3 or more vertices).
    Polygon,
    /// An open polyline (2 or more vertices).
    Polyline,
    /// A packed instance: one vertex (its point gives the translation) and an
    /// entry in the instance table.
    Packed(u32),
    /// A spline patch: a control grid of vertices (v fastest) and an entry
    /// in the patch table (its knots).
    Patch(u32),
}

impl PrimKind {
    pub fn name(&self) -> &'static str {
        match self {
            PrimKind::Polygon => "polygon",
            PrimKind::Polyline => "polyline",
            PrimKind::Packed(_) => "packed",
            PrimKind::Patch(_) => "patch",
        }
    }
}

/// A shared reference to another geometry placed with a transform. Its world
/// transform is `translate(P of its point) * transform`, as Houdini's packed
/// primitives: moving the point moves the instance.
#[derive(Clone, Debug)]
pub struct PackedInstance {
    pub source: Arc<Geometry>,
    pub transform: Mat4,
}

/// Houdini's geometry model. Vertices are corners of primitives referencing
/// points; each primitive's vertices are contiguous (`prim_offsets`).
///
/// Cloning is cheap: the connectivity arrays and every attribute column are
/// shared (copy on write, `shared.rs`), as are the cached topology and
/// content hash; a clone that writes one column copies that column only.
#[derive(Clone, Debug)]
pub struct Geometry {
    pub(crate) points: AttribTable,
    pub(crate) vertices: AttribTable,
    pub(crate) prims: AttribTable,
    pub(crate) detail: AttribTable,
    pub(crate) vertex_point: Shared<Vec<u32>>,
    pub(crate) prim_offsets: Shared<Vec<u32>>,
    pub(crate) prim_kinds: Shared<Vec<PrimKind>>,
    pub(crate) packed: Shared<Vec<PackedInstance>>,
    pub(crate) patches: Vec<crate::patch::PatchBasis>,
    pub(crate) point_groups: BTreeMap<String, Group>,
    pub(crate) prim_groups: BTreeMap<String, Group>,
    /// Typed values carried whole (see `payload.rs`).
    pub(crate) payloads: BTreeMap<String, crate::payload::Payload>,
    pub(crate) topology: OnceLock<Arc<Topology>>,
    pub(crate) content_hash: OnceLock<u128>,
}

impl Default for Geometry {
    fn default() -> Self {
        Geometry::new()
    }
}

impl PartialEq for Geometry {
    fn eq(&self, other: &Self) -> bool {
        self.content_hash() == other.content_hash()
    }
}

pub(crate) fn checked_u32(n: usize, what: &'static str) -> Result<u32, GeoError> {
    u32::try_from(n).map_err(|_| GeoError::TooLarge { what })
}

impl Geometry {
    /// An empty geometry with the `P` attribute.
    pub fn new() -> Geometry {
        let mut points = AttribTable::new(AttribClass::Point, 0);
        points
            .insert(
                P,
                Attribute::new(AttribValue::Vec3(Vec3::ZERO), TypeInfo::Position, 0),
            )
            .expect("empty column fits empty table");
        Geometry {
            points,
            vertices: AttribTable::new(AttribClass::Vertex, 0),
            prims: AttribTable::new(AttribClass::Primitive, 0),
            detail: AttribTable::new(AttribClass::Detail, 1),
            vertex_point: Shared::default(),
            prim_offsets: Shared::new(vec![0]),
            prim_kinds: Shared::default(),
            packed: Shared::default(),
            patches: Vec::new(),
            point_groups: BTreeMap::new(),
            prim_groups: BTreeMap::new(),
            payloads: BTreeMap::new(),
            topology: OnceLock::new(),
            content_hash: OnceLock::new(),
        }
    }

    /// A polygon mesh from positions and faces given as a flat list of point
    /// indices with a vertex count per face. Indices are checked.
    pub fn from_polygons(
        positions: Vec<Vec3>,
        face_points: Vec<u32>,
        face_counts: &[u32],
    ) -> Result<Geometry, GeoError> {
        let kinds = vec![PrimKind::Polygon; face_counts.len()];
        Geometry::from_prims(positions, face_points, face_counts, kinds)
    }

    /// Polygons and polylines in bulk: positions, the flat point index of every
    /// vertex, a vertex count per primitive and each primitive's kind (packed
    /// primitives are added with [`Geometry::add_packed`]). Everything is checked.
    pub fn from_prims(
        positions: Vec<Vec3>,
        vertex_points: Vec<u32>,
        counts: &[u32],
        kinds: Vec<PrimKind>,
    ) -> Result<Geometry, GeoError> {
        let mut g = Geometry::new();
        g.set_positions(positions);
        let n = g.num_points();
        if let Some(&bad) = vertex_points.iter().find(|&&p| p as usize >= n) {
            return Err(GeoError::PointOutOfRange {
                index: bad,
                count: n,
            });
        }
        if kinds.len() != counts.len() {
            return Err(GeoError::Invalid(format!(
                "{} primitive kinds for {} vertex counts",
                kinds.len(),
                counts.len()
            )));
        }
        let mut offsets = Vec::with_capacity(counts.len() + 1);
        offsets.push(0u32);
        let mut acc = 0u64;
        for (&c, kind) in counts.iter().zip(&kinds) {
            match kind {
                PrimKind::Polygon if c < 3 => return Err(GeoError::PolygonTooSmall(c as usize)),
                PrimKind::Polyline if c < 2 => return Err(GeoError::PolylineTooSmall(c as usize)),
                PrimKind::Packed(_) | PrimKind::Patch(_) => {
                    return Err(GeoError::Invalid(format!(
                        "{} primitives cannot be built in bulk from indices",
                        kind.name()
                    )))
                }
                _ => {}
            }
            acc += c as u64;
            offsets.push(checked_u32(acc as usize, "vertex count")?);
        }
        if acc as usize != vertex_points.len() {
            return Err(GeoError::Invalid(format!(
                "vertex counts sum to {acc} but {} vertices were given",
                vertex_points.len()
            )));
        }
        g.prim_kinds = kinds.into();
        g.vertex_point = vertex_points.into();
        g.prim_offsets = offsets.into();
        g.vertices.resize(g.vertex_point.len());
        g.prims.resize(g.prim_kinds.len());
        Ok(g)
    }

    /// A triangle mesh from positions and index triples.
    pub fn from_triangles(
        positions: Vec<Vec3>,
        triangles: &[[u32; 3]],
    ) -> Result<Geometry, GeoError> {
        let flat: Vec<u32> = bytemuck::cast_slice(triangles).to_vec();
        let counts = vec![3u32; triangles.len()];
        Geometry::from_polygons(positions, flat, &counts)
    }

    pub(crate) fn invalidate_topology(&mut self) {
        self.topology = OnceLock::new();
        self.content_hash = OnceLock::new();
    }

    pub(crate) fn invalidate_content(&mut self) {
        self.content_hash = OnceLock::new();
    }

    /// A copy whose attribute tables `f` makes from this one's (same
    /// classes and lengths); connectivity (shared), groups and instances are
    /// copied.
    pub(crate) fn clone_with_tables(&self, f: impl Fn(&AttribTable) -> AttribTable) -> Geometry {
        Geometry {
            points: f(&self.points),
            vertices: f(&self.vertices),
            prims: f(&self.prims),
            detail: f(&self.detail),
            vertex_point: self.vertex_point.clone(),
            prim_offsets: self.prim_offsets.clone(),
            prim_kinds: self.prim_kinds.clone(),
            packed: self.packed.clone(),
            patches: self.patches.clone(),
            point_groups: self.point_groups.clone(),
            prim_groups: self.prim_groups.clone(),
            payloads: self.payloads.clone(),
            topology: self.topology.clone(),
            content_hash: OnceLock::new(),
        }
    }

    // ----- counts and raw access -----

    pub fn num_points(&self) -> usize {
        self.points.len()
    }

    pub fn num_vertices(&self) -> usize {
        self.vertex_point.len()
    }

    pub fn num_prims(&self) -> usize {
        self.prim_kinds.len()
    }

    pub fn positions(&self) -> &[Vec3] {
        self.points
            .get(P)
            .and_then(|a| a.as_vec3())
            .expect("P is always a vector3 point attribute")
    }

    pub fn positions_mut(&mut self) -> &mut [Vec3] {
        self.invalidate_content();
        self.points
            .get_mut(P)
            .and_then(|a| a.as_vec3_mut())
            .expect("P is always a vector3 point attribute")
    }

    /// Replaces all points' positions; the point count becomes `positions.len()`.
    pub fn set_positions(&mut self, positions: Vec<Vec3>) {
        let n = positions.len();
        // Not filled first only to be replaced.
        self.points.remove(P);
        self.resize_points(n);
        let attr = Attribute::from_data(AttribData::Vec3(positions), TypeInfo::Position);
        self.points.insert(P, attr).expect("same length");
        self.invalidate_content();
    }

    /// Point index of every vertex.
    pub fn vertex_points(&self) -> &[u32] {
        &self.vertex_point
    }

    /// Vertex offsets: primitive `i` owns vertices `offsets[i]..offsets[i+1]`.
    pub fn prim_offsets(&self) -> &[u32] {
        &self.prim_offsets
    }

    pub fn prim_kinds(&self) -> &[PrimKind] {
        &self.prim_kinds
    }

    pub fn prim_kind(&self, prim: usize) -> PrimKind {
        self.prim_kinds[prim]
    }

    /// The vertex range of a primitive.
    pub fn prim_vertex_range(&self, prim: usize) -> std::ops::Range<usize> {
        self.prim_offsets[prim] as usize..self.prim_offsets[prim + 1] as usize
    }

    /// The points of a primitive's vertices, in order.
    pub fn prim_points(&self, prim: usize) -> &[u32] {
        &self.vertex_point[self.prim_vertex_range(prim)]
    }

    pub fn packed_instances(&self) -> &[PackedInstance] {
        &self.packed
    }

    pub fn packed_instance(&self, prim: usize) -> Option<&PackedInstance> {
        match self.prim_kinds[prim] {
            PrimKind::Packed(i) => self.packed.get(i as usize),
            _ => None,
        }
    }

    /// World transform of a packed primitive (see [`PackedInstance`]).
    pub fn packed_world_transform(&self, prim: usize) -> Option<Mat4> {
        let inst = self.packed_instance(prim)?;
        let pt = *self.prim_points(prim).first()?;
        let p = *self.positions().get(pt as usize)?;
        Some(Mat4::from_translation(p) * inst.transform)
    }

    /// Indices of the primitives whose kind satisfies `pred`, in order.
    pub fn prims_where(&self, pred: impl Fn(PrimKind) -> bool) -> Vec<usize> {
        (0..self.num_prims())
            .filter(|&i| pred(self.prim_kinds[i]))
            .collect()
    }

    pub fn is_packed(kind: PrimKind) -> bool {
        matches!(kind, PrimKind::Packed(_))
    }

    /// Whether any primitive is a packed instance.
    pub fn has_packed(&self) -> bool {
        !self.packed.is_empty()
    }

    pub fn is_polygon_mesh(&self) -> bool {
        self.prim_kinds.iter().all(|k| *k == PrimKind::Polygon)
    }

    // ----- attributes -----

    pub fn attribs(&self, class: AttribClass) -> &AttribTable {
        match class {
            AttribClass::Point => &self.points,
            AttribClass::Vertex => &self.vertices,
            AttribClass::Primitive => &self.prims,
            AttribClass::Detail => &self.detail,
        }
    }

    /// Mutable attribute table. Column lengths stay tied to element counts.
    pub fn attribs_mut(&mut self, class: AttribClass) -> &mut AttribTable {
        self.invalidate_content();
        match class {
            AttribClass::Point => &mut self.points,
            AttribClass::Vertex => &mut self.vertices,
            AttribClass::Primitive => &mut self.prims,
            AttribClass::Detail => &mut self.detail,
        }
    }

    pub fn attrib(&self, class: AttribClass, name: &str) -> Option<&Attribute> {
        self.attribs(class).get(name)
    }

    /// Adds or replaces an attribute (P cannot be replaced by a non-vector3).
    pub fn set_attrib(
        &mut self,
        class: AttribClass,
        name: &str,
        attrib: Attribute,
    ) -> Result<(), GeoError> {
        if class == AttribClass::Point
            && name == P
            && attrib.attrib_type() != crate::AttribType::Vec3
        {
            return Err(GeoError::PositionRequired);
        }
        self.attribs_mut(class).insert(name, attrib)
    }

    pub fn remove_attrib(
        &mut self,
        class: AttribClass,
        name: &str,
    ) -> Result<Option<Attribute>, GeoError> {
        if class == AttribClass::Point && name == P {
            return Err(GeoError::PositionRequired);
        }
        Ok(self.attribs_mut(class).remove(name))
    }

    // ----- groups -----

    pub fn point_groups(&self) -> &BTreeMap<String, Group> {
        &self.point_groups
    }

    pub fn prim_groups(&self) -> &BTreeMap<String, Group> {
        &self.prim_groups
    }

    pub fn set_point_group(&mut self, name: &str, group: Group) -> Result<(), GeoError> {
        if group.len() != self.num_points() {
            return Err(GeoError::GroupLength {
                name: name.to_owned(),
                expected: self.num_points(),
                found: group.len(),
            });
        }
        self.invalidate_content();
        self.point_groups.insert(name.to_owned(), group);
        Ok(())
    }

    pub fn set_prim_group(&mut self, name: &str, group: Group) -> Result<(), GeoError> {
        if group.len() != self.num_prims() {
            return Err(GeoError::GroupLength {
                name: name.to_owned(),
                expected: self.num_prims(),
                found: group.len(),
            });
        }
        self.invalidate_content();
        self.prim_groups.insert(name.to_owned(), group);
        Ok(())
    }

    pub fn remove_point_group(&mut self, name: &str) -> Option<Group> {
        self.invalidate_content();
        self.point_groups.remove(name)
    }

    pub fn remove_prim_group(&mut self, name: &str) -> Option<Group> {
        self.invalidate_content();
        self.prim_groups.remove(name)
    }

    /// The topology (edges, adjacency, half-edges), built on first use and
    /// cached until the connectivity changes.
    pub fn topology(&self) -> Arc<Topology> {
        Arc::clone(
            self.topology
                .get_or_init(|| Arc::new(Topology::build(self))),
        )
    }

    /// Bytes held by this geometry's own columns (packed sources counted once
    /// per distinct source, not per instance).
    pub fn memory_bytes(&self) -> usize {
        fn table_bytes(t: &AttribTable) -> usize {
            t.iter()
                .map(|(_, a)| match a.data() {
                    AttribData::String(s) => {
                        s.indices.len() * 4 + s.table.iter().map(|x| x.len()).sum::<usize>()
                    }
                    d => d.as_bytes().map_or(0, |b| b.len()),
                })
                .sum()
        }
        let mut seen = std::collections::HashSet::new();
        let mut sources = 0;
        let mut last = std::ptr::null();
        for inst in &self.packed {
            // Runs of instances of one source are the rule: one lookup each.
            let source = Arc::as_ptr(&inst.source);
            if source != last && seen.insert(source) {
                sources += inst.source.memory_bytes();
            }
            last = source;
        }
        table_bytes(&self.points)
            + table_bytes(&self.vertices)
            + table_bytes(&self.prims)
            + table_bytes(&self.detail)
            + self.vertex_point.len() * 4
            + self.prim_offsets.len() * 4
            + self.prim_kinds.len() * std::mem::size_of::<PrimKind>()
            + self.payloads.values().map(|p| p.bytes()).sum::<usize>()
            + self.packed.len() * std::mem::size_of::<PackedInstance>()
            + self
                .point_groups
                .values()
                .chain(self.prim_groups.values())
                .map(|g| g.words().len() * 8)
                .sum::<usize>()
            + sources
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::torus;

    #[test]
    fn many_primitives_at_once_equal_one_at_a_time() {
        let mut one = Geometry::new();
        one.add_points(&[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z]);
        one.set_prim_group("g", Group::new(0)).unwrap();
        let mut many = one.clone();
        one.add_polygon(&[0, 1, 2]).unwrap();
        one.add_polyline(&[2, 3]).unwrap();
        one.add_polygon(&[0, 1, 2, 3]).unwrap();
        let first = many
            .add_polys(
                &[(true, 3), (false, 2), (true, 4)],
                &[0, 1, 2, 2, 3, 0, 1, 2, 3],
            )
            .unwrap();
        assert_eq!(first, 0);
        assert_eq!(many.content_hash(), one.content_hash());
        assert_eq!(many.prim_groups().get("g").map(Group::len), Some(3));
        assert!(crate::ops::validate(&many).is_empty());
        // Nothing is added when any primitive is wrong.
        let before = many.content_hash();
        let errors = [
            many.add_polys(&[(true, 2)], &[0, 1]).unwrap_err(),
            many.add_polys(&[(false, 1)], &[0]).unwrap_err(),
            many.add_polys(&[(true, 3)], &[0, 1]).unwrap_err(),
            many.add_polys(&[(true, 3)], &[0, 1, 9]).unwrap_err(),
        ];
        assert!(matches!(errors[0], GeoError::PolygonTooSmall(2)));
        assert!(matches!(errors[1], GeoError::PolylineTooSmall(1)));
        assert!(matches!(
            errors[2],
            GeoError::VertexCountMismatch {
                counted: 3,
                given: 2
            }
        ));
        assert!(matches!(
            errors[3],
            GeoError::PointOutOfRange { index: 9, .. }
        ));
        assert_eq!(many.content_hash(), before);
    }

    #[test]
    fn packed_instances_cost_a_transform_not_a_copy() {
        // A 10k-triangle source, 100k instances.
        let src = Arc::new(crate::ops::triangulate(&torus(1.0, 0.3, 100, 50), None));
        assert_eq!(src.num_prims(), 10_000);
        let n = 100_000;
        let positions: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let mut g = Geometry::new();
        g.add_packed_many(&src, &positions, &vec![Mat4::IDENTITY; n])
            .unwrap();
        let per_instance = (g.memory_bytes() - src.memory_bytes()) as f64 / n as f64;
        assert!(per_instance < 128.0, "{per_instance} bytes per instance");
        assert!(
            src.memory_bytes() > 100 * 1024,
            "the source itself is large"
        );
        assert!(crate::ops::validate(&g).is_empty());
    }

    /// The same content in arrays no geometry has hashed (a round trip
    /// through the binary form).
    fn fresh(g: &Geometry) -> Geometry {
        let mut bytes = Vec::new();
        crate::codec::encode(g, &mut bytes, &mut |_| {}).unwrap();
        crate::codec::decode(&bytes, &|_| None).unwrap()
    }

    #[test]
    fn a_clone_copies_and_rehashes_only_what_it_writes() {
        let mut a = crate::primitives::grid(glam::Vec2::ONE, 40, 30);
        let n = Attribute::new(AttribValue::Vec3(Vec3::Y), TypeInfo::Normal, a.num_points());
        a.set_attrib(AttribClass::Point, "N", n).unwrap();
        let hash = a.content_hash();
        let topology = a.topology();
        let mut b = a.clone();
        assert_eq!(b.content_hash(), hash);
        b.positions_mut()[7].y = 0.5;
        let col = |g: &Geometry, name: &str| g.attrib(AttribClass::Point, name).unwrap().clone();
        assert!(!col(&b, P).shares_values(&col(&a, P)), "P written: copied");
        for name in ["N", "uv"] {
            assert!(col(&b, name).shares_values(&col(&a, name)), "{name}");
        }
        assert!(Shared::ptr_eq(&a.vertex_point, &b.vertex_point));
        assert!(Shared::ptr_eq(&a.prim_offsets, &b.prim_offsets));
        assert!(Shared::ptr_eq(&a.prim_kinds, &b.prim_kinds));
        // Positions are no connectivity: the topology stays, shared.
        assert!(Arc::ptr_eq(&topology, &b.topology()));
        // Cached digests give what hashing everything afresh gives.
        assert_ne!(b.content_hash(), hash);
        assert_eq!(b.content_hash(), fresh(&b).content_hash());
        assert_eq!(a.content_hash(), hash);
        assert_eq!(fresh(&a).content_hash(), hash);
        // Written in place once unshared: the column's digest goes with it.
        let before = b.content_hash();
        b.attribs_mut(AttribClass::Point)
            .get_mut("N")
            .and_then(|a| a.as_vec3_mut())
            .unwrap()[3] = Vec3::X;
        assert!(!col(&b, "N").shares_values(&col(&a, "N")));
        assert_ne!(b.content_hash(), before);
        assert_eq!(b.content_hash(), fresh(&b).content_hash());
        // New connectivity: a new topology, the input's untouched.
        b.add_polygon(&[0, 1, 2]).unwrap();
        assert!(!Shared::ptr_eq(&a.vertex_point, &b.vertex_point));
        assert_eq!(b.topology().edges().len(), topology.edges().len() + 1);
        assert_eq!(a.num_prims(), 40 * 30);
        assert_eq!(b.content_hash(), fresh(&b).content_hash());
    }

    #[test]
    fn building_checks_indices_and_sizes() {
        let e = Geometry::from_polygons(vec![Vec3::ZERO; 3], vec![0, 1, 5], &[3]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "point index 5 out of range (geometry has 3 points)"
        );
        let e = Geometry::from_polygons(vec![Vec3::ZERO; 3], vec![0, 1], &[2]).unwrap_err();
        assert_eq!(e.to_string(), "a polygon needs at least 3 vertices, got 2");
        let mut g = Geometry::new();
        assert!(g.add_polyline(&[0, 1]).is_err());
        g.add_points(&[Vec3::ZERO, Vec3::X]);
        assert_eq!(g.add_polyline(&[0, 1]).unwrap(), 0);
        assert_eq!(
            g.remove_attrib(AttribClass::Point, P).unwrap_err(),
            GeoError::PositionRequired
        );
    }
}
