//! Spline patch primitives: a grid of control points (the primitive's
//! vertices, v fastest) with a knot vector and order each way, rational
//! weights in the point attribute `Pw`. The control points are ordinary
//! points, so every point operation applies to them, and a transform is
//! exact (B-splines are affine invariant).

use crate::error::GeoError;
use crate::geometry::{checked_u32, Geometry, PrimKind};

/// The point attribute holding rational weights (1 where absent).
pub const WEIGHT: &str = "Pw";

/// One direction of a patch: its order (degree + 1) and knots; the number
/// of control points that way is `knots.len() - order`.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    pub order: u32,
    pub knots: Vec<f64>,
}

impl KnotVector {
    pub fn count(&self) -> usize {
        self.knots.len().saturating_sub(self.order as usize)
    }

    fn check(&self, side: &str) -> Result<(), GeoError> {
        let bad = |why: String| GeoError::Invalid(format!("patch {side} knots: {why}"));
        if self.order < 2 {
            return Err(bad(format!("order {} (2 or more expected)", self.order)));
        }
        if self.count() < self.order as usize {
            return Err(bad(format!(
                "{} knots give {} control points for order {} (at least the order expected)",
                self.knots.len(),
                self.count(),
                self.order
            )));
        }
        if let Some(k) = self.knots.iter().position(|x| !x.is_finite()) {
            return Err(bad(format!("knot {k} is not finite")));
        }
        if let Some(k) = self.knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(bad(format!("knot {} is below knot {k}", k + 1)));
        }
        let o = self.order as usize;
        if self.knots[o - 1] >= self.knots[self.knots.len() - o] {
            return Err(bad("the domain is empty".into()));
        }
        Ok(())
    }
}

/// The knots of a patch primitive.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchBasis {
    pub u: KnotVector,
    pub v: KnotVector,
}

impl Geometry {
    /// Adds a spline patch over existing points: `points` is the control
    /// grid, `basis.u.count()` rows of `basis.v.count()`, v fastest.
    pub fn add_patch(&mut self, points: &[u32], basis: PatchBasis) -> Result<u32, GeoError> {
        basis.u.check("u")?;
        basis.v.check("v")?;
        let want = basis.u.count() * basis.v.count();
        if points.len() != want {
            return Err(GeoError::Invalid(format!(
                "a {} x {} patch needs {want} control points, not {}",
                basis.u.count(),
                basis.v.count(),
                points.len()
            )));
        }
        let index = checked_u32(self.patches.len(), "patch count")?;
        let prim = self.push_prim(PrimKind::Patch(index), points)?;
        self.patches.push(basis);
        Ok(prim)
    }

    /// The knots of a patch primitive.
    pub fn patch_basis(&self, prim: usize) -> Option<&PatchBasis> {
        match self.prim_kinds.get(prim)? {
            PrimKind::Patch(i) => self.patches.get(*i as usize),
            _ => None,
        }
    }

    /// Whether any primitive is a spline patch.
    pub fn has_patches(&self) -> bool {
        !self.patches.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};

    use super::*;
    use crate::ops;

    fn bilinear() -> (Geometry, PatchBasis) {
        let mut g = Geometry::new();
        let first = g.add_points(&[Vec3::ZERO, Vec3::Z, Vec3::X, Vec3::new(1.0, 1.0, 1.0)]);
        let basis = PatchBasis {
            u: KnotVector {
                order: 2,
                knots: vec![0.0, 0.0, 1.0, 1.0],
            },
            v: KnotVector {
                order: 2,
                knots: vec![0.0, 0.0, 1.0, 1.0],
            },
        };
        g.add_patch(&[first, first + 1, first + 2, first + 3], basis.clone())
            .unwrap();
        (g, basis)
    }

    #[test]
    fn patches_survive_transforms_merges_and_deletes() {
        let (g, basis) = bilinear();
        assert_eq!(g.prim_kind(0), PrimKind::Patch(0));
        let mut moved = g.clone();
        ops::transform(&mut moved, Mat4::from_translation(Vec3::Y));
        assert_eq!(moved.patch_basis(0), Some(&basis));
        assert_eq!(moved.positions()[3], Vec3::new(1.0, 2.0, 1.0));
        let line = Geometry::from_prims(
            vec![Vec3::ZERO, Vec3::X],
            vec![0, 1],
            &[2],
            vec![PrimKind::Polyline],
        )
        .unwrap();
        let (other, _) = bilinear();
        let merged = ops::merge(&[&line, &g, &other]).unwrap();
        assert_eq!(merged.prim_kind(1), PrimKind::Patch(0));
        assert_eq!(merged.prim_kind(2), PrimKind::Patch(1));
        assert_eq!(merged.prim_points(2), &[6, 7, 8, 9]);
        assert!(ops::validate(&merged).is_empty());
        let mut fewer = merged.clone();
        ops::delete_prims(&mut fewer, &crate::Group::from_members(3, [1]), true);
        assert_eq!(fewer.prim_kind(1), PrimKind::Patch(0));
        assert_eq!(fewer.patch_basis(1), Some(&basis));
        assert_eq!(fewer.num_points(), 6);
        assert!(ops::validate(&fewer).is_empty());
        // Knots are part of the content.
        let mut other_knots = bilinear().0;
        other_knots.patches[0].u.knots[3] = 2.0;
        assert_ne!(g.content_hash(), other_knots.content_hash());
    }

    #[test]
    fn bad_patches_are_errors() {
        let (mut g, basis) = bilinear();
        let e = g.add_patch(&[0, 1, 2], basis.clone()).unwrap_err();
        assert!(e.to_string().contains("needs 4 control points"), "{e}");
        let mut b = basis.clone();
        b.v.knots = vec![0.0, 1.0, 0.5, 1.0];
        let e = g.add_patch(&[0, 1, 2, 3], b).unwrap_err();
        assert!(e.to_string().contains("knot 2 is below knot 1"), "{e}");
        let mut b = basis;
        b.u.order = 1;
        assert!(g.add_patch(&[0, 1, 2, 3], b).is_err());
    }
}
