//! Packing islands into the unit square: each island turned to its
//! minimal-area bounding rectangle (`rect.rs`), then all laid on shelves
//! at one common scale, the largest that fits (`shelf.rs`), so that
//! their relative sizes (texel density) are kept.
//!
//! With rotation on, two layouts are tried, every rectangle lying (wider
//! than tall) and every one standing, and the one with the larger scale
//! is kept (lying on a tie).

mod rect;
mod shelf;

pub use rect::{convex_hull, minimal_area, Oriented};
pub use shelf::{pack_shelves, ShelfLayout};

use crate::error::UvError;

/// Where one island goes: `uv' = corner + scale * (rotate(uv) - min)`
/// with the rectangle's `rotate` and `min`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub rect: Oriented,
    pub corner: [f64; 2],
    pub scale: f64,
}

impl Placement {
    pub fn apply(&self, uv: [f64; 2]) -> [f64; 2] {
        let q = self.rect.rotate(uv);
        [
            self.corner[0] + self.scale * (q[0] - self.rect.min[0]),
            self.corner[1] + self.scale * (q[1] - self.rect.min[1]),
        ]
    }
}

/// How islands are packed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackOptions {
    /// The least gap between two islands, and between an island and the
    /// square's sides, as a fraction of the square's side ([0, 0.5)).
    /// Shrunk when the islands are too many for it (see
    /// [`Packed::margin`]).
    pub margin: f64,
    /// Turn each island to its minimal-area rectangle (and a quarter
    /// turn more when that packs better); otherwise islands keep their
    /// orientation.
    pub rotate: bool,
}

impl Default for PackOptions {
    fn default() -> Self {
        PackOptions {
            margin: 0.01,
            rotate: true,
        }
    }
}

/// The packing of all islands.
#[derive(Clone, Debug, PartialEq)]
pub struct Packed {
    pub placements: Vec<Placement>,
    /// uv units per island unit, the same for every island.
    pub scale: f64,
    /// The margin used (less than asked for when it did not fit).
    pub margin: f64,
}

/// Packs islands, each given by its points (uv of its wedges), into
/// [0,1]^2.
pub fn pack_islands(islands: &[&[[f64; 2]]], options: &PackOptions) -> Result<Packed, UvError> {
    if !(0.0..0.5).contains(&options.margin) {
        return Err(UvError::Invalid(format!(
            "the margin {} is not in [0, 0.5)",
            options.margin
        )));
    }
    let rects: Vec<Oriented> = islands
        .iter()
        .map(|points| {
            if options.rotate {
                minimal_area(points)
            } else {
                rect::axis_aligned(points)
            }
        })
        .collect();
    let candidates: Vec<Vec<Oriented>> = if options.rotate {
        vec![
            rects.iter().map(|r| orient(r, true)).collect(),
            rects.iter().map(|r| orient(r, false)).collect(),
        ]
    } else {
        vec![rects]
    };
    let mut best: Option<(Vec<Oriented>, ShelfLayout)> = None;
    for rects in candidates {
        let sizes: Vec<[f64; 2]> = rects.iter().map(|r| r.size).collect();
        let layout = pack_shelves(&sizes, options.margin);
        if best.as_ref().is_none_or(|(_, b)| layout.scale > b.scale) {
            best = Some((rects, layout));
        }
    }
    let (rects, layout) = best.ok_or_else(|| UvError::Invalid("no layout".into()))?;
    Ok(Packed {
        placements: rects
            .iter()
            .zip(&layout.corners)
            .map(|(&rect, &corner)| Placement {
                rect,
                corner,
                scale: layout.scale,
            })
            .collect(),
        scale: layout.scale,
        margin: layout.margin,
    })
}

/// The rectangle lying (wider than tall) or standing.
fn orient(rect: &Oriented, lying: bool) -> Oriented {
    let wide = rect.size[0] >= rect.size[1];
    if wide == lying {
        *rect
    } else {
        rect.turned()
    }
}
