//! Shelf packing of rectangles into the unit square at the largest common
//! scale: first fit by decreasing height (FFDH), the scale found by
//! bisection.

/// Open shelves a rectangle may go on (the most recent ones): keeps the
/// first-fit search linear in the number of rectangles.
const SHELVES_TRIED: usize = 64;

/// Bisection steps on the scale (each halves the interval).
const BISECTIONS: usize = 60;

/// A layout: each rectangle's lower-left corner in the unit square, at
/// `scale` times its size, `margin` apart and from the square's sides.
#[derive(Clone, Debug, PartialEq)]
pub struct ShelfLayout {
    pub corners: Vec<[f64; 2]>,
    pub scale: f64,
    pub margin: f64,
}

/// Packs rectangles of `sizes` (width, height) at the largest scale that
/// fits. The margin shrinks (halving) when even points `margin` apart do
/// not fit.
pub fn pack_shelves(sizes: &[[f64; 2]], margin: f64) -> ShelfLayout {
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by(|&a, &b| {
        sizes[b][1]
            .total_cmp(&sizes[a][1])
            .then(sizes[b][0].total_cmp(&sizes[a][0]))
            .then(a.cmp(&b))
    });
    let mut margin = margin;
    for _ in 0..BISECTIONS {
        if layout(sizes, &order, 0.0, margin).is_some() {
            break;
        }
        margin *= 0.5;
    }
    let upper = scale_bound(sizes, margin);
    let scale = if layout(sizes, &order, upper, margin).is_some() {
        upper
    } else {
        let (mut lo, mut hi) = (0.0, upper);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if layout(sizes, &order, mid, margin).is_some() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let corners =
        layout(sizes, &order, scale, margin).unwrap_or_else(|| vec![[margin; 2]; sizes.len()]);
    ShelfLayout {
        corners,
        scale,
        margin,
    }
}

/// A scale no layout can beat: each rectangle within the square, and
/// their total area within it. 1 when every rectangle is a point.
fn scale_bound(sizes: &[[f64; 2]], margin: f64) -> f64 {
    let room = 1.0 - 2.0 * margin;
    let largest = sizes.iter().fold(0.0f64, |m, s| m.max(s[0]).max(s[1]));
    let area: f64 = sizes.iter().map(|s| s[0] * s[1]).sum();
    let mut bound = f64::INFINITY;
    if largest > 0.0 {
        bound = room / largest;
    }
    if area > 0.0 {
        bound = bound.min(room / area.sqrt());
    }
    if bound.is_finite() {
        bound.max(0.0)
    } else {
        1.0
    }
}

/// The lower-left corners of the rectangles at `scale`, shelves filled
/// bottom up in `order`, or None when they do not fit. Each rectangle's
/// footprint is its scaled size plus `margin`, laid in the square inset
/// by half the margin: islands end up `margin` apart and `margin` from
/// the sides.
fn layout(sizes: &[[f64; 2]], order: &[usize], scale: f64, margin: f64) -> Option<Vec<[f64; 2]>> {
    let side = 1.0 - margin;
    let slack = 1e-12;
    // (bottom, height, used width) of each shelf.
    let mut shelves: Vec<(f64, f64, f64)> = Vec::new();
    let mut top = 0.0;
    let mut corners = vec![[0.0; 2]; sizes.len()];
    for &i in order {
        let (w, h) = (sizes[i][0] * scale + margin, sizes[i][1] * scale + margin);
        if w > side + slack {
            return None;
        }
        let first = shelves.len().saturating_sub(SHELVES_TRIED);
        let shelf = (first..shelves.len()).find(|&k| shelves[k].2 + w <= side + slack);
        let k = match shelf {
            Some(k) => k,
            None => {
                if top + h > side + slack {
                    return None;
                }
                shelves.push((top, h, 0.0));
                top += h;
                shelves.len() - 1
            }
        };
        let (bottom, _, used) = shelves[k];
        corners[i] = [used + margin, bottom + margin];
        shelves[k].2 += w;
    }
    Some(corners)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_square_fills_the_room() {
        let l = pack_shelves(&[[2.0, 2.0]], 0.1);
        assert!((l.scale - 0.4).abs() < 1e-12, "{l:?}");
        assert_eq!(l.corners, vec![[0.1, 0.1]]);
    }

    #[test]
    fn four_squares_make_a_grid() {
        let l = pack_shelves(&[[1.0, 1.0]; 4], 0.0);
        assert!((l.scale - 0.5).abs() < 1e-9, "{l:?}");
    }

    #[test]
    fn too_large_a_margin_shrinks() {
        let l = pack_shelves(&[[1.0, 1.0]; 100], 0.2);
        assert!(l.margin < 0.1 && l.margin > 0.0 && l.scale > 0.0, "{l:?}");
    }
}
