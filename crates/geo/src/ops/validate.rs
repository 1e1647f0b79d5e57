//! Consistency checks that report every problem instead of panicking.

use std::fmt;

use crate::attrib::AttribClass;
use crate::geometry::{Geometry, PrimKind};

/// One inconsistency found in a geometry.
#[derive(Clone, Debug, PartialEq)]
pub enum ValidationIssue {
    BadOffsets(String),
    VertexPointOutOfRange {
        vertex: usize,
        point: u32,
        points: usize,
    },
    TooFewVertices {
        prim: usize,
        kind: &'static str,
        count: usize,
    },
    PackedOutOfRange {
        prim: usize,
        index: u32,
    },
    PatchOutOfRange {
        prim: usize,
        index: u32,
    },
    PatchGrid {
        prim: usize,
        count: usize,
        expected: usize,
    },
    AttribLength {
        class: AttribClass,
        name: String,
        len: usize,
        expected: usize,
    },
    GroupLength {
        name: String,
        len: usize,
        expected: usize,
    },
    NonFinitePosition {
        point: usize,
    },
}

impl fmt::Display for ValidationIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValidationIssue::BadOffsets(m) => write!(f, "primitive offsets: {m}"),
            ValidationIssue::VertexPointOutOfRange {
                vertex,
                point,
                points,
            } => write!(
                f,
                "vertex {vertex} references point {point} but there are {points} points"
            ),
            ValidationIssue::TooFewVertices { prim, kind, count } => {
                write!(f, "{kind} {prim} has only {count} vertices")
            }
            ValidationIssue::PatchOutOfRange { prim, index } => {
                write!(f, "patch primitive {prim} references missing knots {index}")
            }
            ValidationIssue::PatchGrid {
                prim,
                count,
                expected,
            } => write!(
                f,
                "patch primitive {prim} has {count} vertices but its knots need {expected}"
            ),
            ValidationIssue::PackedOutOfRange { prim, index } => {
                write!(
                    f,
                    "packed primitive {prim} references missing instance {index}"
                )
            }
            ValidationIssue::AttribLength {
                class,
                name,
                len,
                expected,
            } => write!(
                f,
                "{class} attribute `{name}` has {len} elements, expected {expected}"
            ),
            ValidationIssue::GroupLength {
                name,
                len,
                expected,
            } => {
                write!(f, "group `{name}` has {len} flags, expected {expected}")
            }
            ValidationIssue::NonFinitePosition { point } => {
                write!(f, "point {point} has a non-finite position")
            }
        }
    }
}

/// Every inconsistency in `g` (empty when it is sound).
pub fn validate(g: &Geometry) -> Vec<ValidationIssue> {
    let mut out = Vec::new();
    let off = &g.prim_offsets;
    if off.len() != g.prim_kinds.len() + 1 {
        out.push(ValidationIssue::BadOffsets(format!(
            "{} offsets for {} primitives",
            off.len(),
            g.prim_kinds.len()
        )));
        return out;
    }
    if off.first() != Some(&0) || off.windows(2).any(|w| w[1] < w[0]) {
        out.push(ValidationIssue::BadOffsets("not increasing from 0".into()));
        return out;
    }
    if *off.last().expect("non-empty") as usize != g.vertex_point.len() {
        out.push(ValidationIssue::BadOffsets(format!(
            "last offset {} but {} vertices",
            off.last().expect("non-empty"),
            g.vertex_point.len()
        )));
        return out;
    }
    let np = g.num_points();
    for (v, &p) in g.vertex_point.iter().enumerate() {
        if p as usize >= np {
            out.push(ValidationIssue::VertexPointOutOfRange {
                vertex: v,
                point: p,
                points: np,
            });
        }
    }
    for (prim, kind) in g.prim_kinds.iter().enumerate() {
        let count = (off[prim + 1] - off[prim]) as usize;
        let min = match kind {
            PrimKind::Polygon => 3,
            PrimKind::Polyline => 2,
            PrimKind::Packed(i) => {
                if *i as usize >= g.packed.len() {
                    out.push(ValidationIssue::PackedOutOfRange { prim, index: *i });
                }
                1
            }
            PrimKind::Patch(i) => {
                match g.patches.get(*i as usize) {
                    None => out.push(ValidationIssue::PatchOutOfRange { prim, index: *i }),
                    Some(b) if b.u.count() * b.v.count() != count => {
                        out.push(ValidationIssue::PatchGrid {
                            prim,
                            count,
                            expected: b.u.count() * b.v.count(),
                        })
                    }
                    Some(_) => {}
                }
                0
            }
        };
        if count < min {
            out.push(ValidationIssue::TooFewVertices {
                prim,
                kind: kind.name(),
                count,
            });
        }
    }
    for (class, expected) in [
        (AttribClass::Point, np),
        (AttribClass::Vertex, g.num_vertices()),
        (AttribClass::Primitive, g.num_prims()),
        (AttribClass::Detail, 1),
    ] {
        for (name, a) in g.attribs(class).iter() {
            if a.len() != expected {
                out.push(ValidationIssue::AttribLength {
                    class,
                    name: name.to_owned(),
                    len: a.len(),
                    expected,
                });
            }
        }
    }
    for (groups, expected) in [(&g.point_groups, np), (&g.prim_groups, g.num_prims())] {
        for (name, grp) in groups {
            if grp.len() != expected {
                out.push(ValidationIssue::GroupLength {
                    name: name.clone(),
                    len: grp.len(),
                    expected,
                });
            }
        }
    }
    for (i, p) in g.positions().iter().enumerate() {
        if !p.is_finite() {
            out.push(ValidationIssue::NonFinitePosition { point: i });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cube;

    #[test]
    fn reports_instead_of_panicking() {
        let mut g = cube(1.0);
        assert!(validate(&g).is_empty());
        g.vertex_point.make_mut()[3] = 99;
        g.positions_mut()[0].x = f32::NAN;
        g.prim_kinds.make_mut()[1] = PrimKind::Packed(7);
        let issues: Vec<String> = validate(&g).iter().map(|i| i.to_string()).collect();
        assert_eq!(
            issues,
            vec![
                "vertex 3 references point 99 but there are 8 points",
                "packed primitive 1 references missing instance 7",
                "point 0 has a non-finite position",
            ]
        );
        g.prim_offsets.make_mut().pop();
        assert!(matches!(validate(&g)[0], ValidationIssue::BadOffsets(_)));
    }
}
