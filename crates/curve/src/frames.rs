//! Frames along a curve: tangents (central difference, previous or next
//! edge, or exact ones from a spline), then a normal carried along by
//! rotation-minimizing transport: the double-reflection method (Wang,
//! Juttler, Zheng, Liu 2008; fourth order with exact tangents), discrete
//! parallel transport (each step rotates the normal by the quaternion that
//! turns one tangent into the next, as the seed composes them), or an up
//! vector. A closed curve's frame is corrected so it closes: the holonomy
//! angle left after one lap is spread along the curve by arc length.

use crate::polyline::{
    arc_lengths,
    glam_d::{DMat3, DQuat, DVec3},
};

/// An orthonormal right-handed frame: `bitangent = normal x tangent`, so
/// (bitangent, normal, tangent) are the images of (X, Y, Z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub tangent: DVec3,
    pub normal: DVec3,
    pub bitangent: DVec3,
}

impl Frame {
    fn new(tangent: DVec3, normal: DVec3) -> Frame {
        let normal = (normal - normal.dot(tangent) * tangent).normalize();
        Frame {
            tangent,
            normal,
            bitangent: normal.cross(tangent),
        }
    }

    /// The rotation taking X, Y, Z to bitangent, normal, tangent (Houdini's
    /// `orient`: a copy's +Z follows the curve, its +Y the normal).
    pub fn orient(&self) -> DQuat {
        DQuat::from_mat3(&DMat3::from_cols(self.bitangent, self.normal, self.tangent)).normalize()
    }

    /// The frame turned by `angle` radians about its tangent.
    pub fn rolled(&self, angle: f64) -> Frame {
        let q = DQuat::from_axis_angle(self.tangent, angle);
        Frame::new(self.tangent, q * self.normal)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangentMode {
    /// Towards the next point minus from the previous (second order).
    Central,
    /// Along the edge arriving at the point.
    Previous,
    /// Along the edge leaving the point.
    Next,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrameMethod {
    DoubleReflection,
    ParallelTransport,
    /// The normal is the up vector made perpendicular to the tangent
    /// (where they are parallel, the previous normal is carried over).
    UpVector(DVec3),
}

/// Unit tangents of a polyline. Repeated points are skipped (their tangent
/// is their distinct neighbours'), so zero-length segments give no NaN; a
/// curve with no extent gets +Z.
pub fn tangents(points: &[DVec3], closed: bool, mode: TangentMode) -> Vec<DVec3> {
    let n = points.len();
    let distinct = |from: usize, step: isize| -> Option<usize> {
        let mut j = from as isize;
        for _ in 0..n {
            j += step;
            if closed {
                j = j.rem_euclid(n as isize);
            } else if j < 0 || j >= n as isize {
                return None;
            }
            if points[j as usize] != points[from] {
                return Some(j as usize);
            }
        }
        None
    };
    let mut out: Vec<Option<DVec3>> = (0..n)
        .map(|i| {
            let prev = distinct(i, -1).map(|j| points[i] - points[j]);
            let next = distinct(i, 1).map(|j| points[j] - points[i]);
            let t = match (mode, prev, next) {
                (TangentMode::Central, Some(a), Some(b)) => a.normalize() + b.normalize(),
                (TangentMode::Previous, Some(a), _) | (_, Some(a), None) => a,
                (_, _, Some(b)) => b,
                (_, None, None) => return None,
            };
            // Opposite edges (a hairpin) cancel: fall back to the next edge.
            let t = if t.length_squared() > 1e-24 {
                t
            } else {
                next.or(prev)?
            };
            Some(t.normalize())
        })
        .collect();
    // Fill what is left from the nearest defined tangent.
    let first = out.iter().flatten().next().copied().unwrap_or(DVec3::Z);
    let mut last = first;
    for t in out.iter_mut() {
        match t {
            Some(v) => last = *v,
            None => *t = Some(last),
        }
    }
    out.into_iter().map(|t| t.unwrap_or(DVec3::Z)).collect()
}

/// Some vector perpendicular to `t`: the axis least aligned with it, made
/// perpendicular.
fn any_normal(t: DVec3) -> DVec3 {
    let a = t.abs();
    let axis = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (axis - axis.dot(t) * t).normalize()
}

/// The next normal by double reflection: reflect in the bisector plane of
/// the two points, then in the plane that takes the reflected tangent to the
/// next tangent.
fn double_reflection(x0: DVec3, t0: DVec3, r0: DVec3, x1: DVec3, t1: DVec3) -> DVec3 {
    let v1 = x1 - x0;
    let c1 = v1.dot(v1);
    if c1 < 1e-300 {
        return parallel_transport(t0, r0, t1);
    }
    let r_l = r0 - (2.0 / c1) * v1.dot(r0) * v1;
    let t_l = t0 - (2.0 / c1) * v1.dot(t0) * v1;
    let v2 = t1 - t_l;
    let c2 = v2.dot(v2);
    if c2 < 1e-300 {
        return r_l;
    }
    r_l - (2.0 / c2) * v2.dot(r_l) * v2
}

fn parallel_transport(t0: DVec3, r0: DVec3, t1: DVec3) -> DVec3 {
    DQuat::from_rotation_arc(t0, t1) * r0
}

/// A frame per point. `initial` is the first normal (made perpendicular to
/// the first tangent); without it, the axis least aligned with the tangent.
pub fn frames(
    points: &[DVec3],
    tangents: &[DVec3],
    closed: bool,
    method: FrameMethod,
    initial: Option<DVec3>,
) -> Vec<Frame> {
    let n = points.len().min(tangents.len());
    if n == 0 {
        return Vec::new();
    }
    let t0 = tangents[0];
    let start = match (method, initial) {
        (FrameMethod::UpVector(up), _) if (up - up.dot(t0) * t0).length_squared() > 1e-20 => up,
        (_, Some(v)) if (v - v.dot(t0) * t0).length_squared() > 1e-20 => v,
        _ => any_normal(t0),
    };
    let mut out = vec![Frame::new(t0, start)];
    let step = |i: usize, j: usize, prev: &Frame| -> DVec3 {
        match method {
            FrameMethod::DoubleReflection => {
                double_reflection(points[i], prev.tangent, prev.normal, points[j], tangents[j])
            }
            FrameMethod::ParallelTransport => {
                parallel_transport(prev.tangent, prev.normal, tangents[j])
            }
            FrameMethod::UpVector(up) => {
                let t = tangents[j];
                if (up - up.dot(t) * t).length_squared() > 1e-20 {
                    up
                } else {
                    parallel_transport(prev.tangent, prev.normal, t)
                }
            }
        }
    };
    for j in 1..n {
        let next = step(j - 1, j, &out[j - 1]);
        out.push(Frame::new(tangents[j], next));
    }
    if closed && n > 2 && !matches!(method, FrameMethod::UpVector(_)) {
        // Carry the last frame across the closing segment and measure how far
        // it turned from the first about the first tangent.
        let back = Frame::new(tangents[0], step(n - 1, 0, &out[n - 1]));
        let angle = signed_angle(back.normal, out[0].normal, tangents[0]);
        let (acc, total) = arc_lengths(&points[..n], true);
        if total > 0.0 {
            for (f, s) in out.iter_mut().zip(acc) {
                *f = f.rolled(angle * s / total);
            }
        }
    }
    out
}

/// The angle turning `a` into `b` about `axis` (both perpendicular to it).
fn signed_angle(a: DVec3, b: DVec3, axis: DVec3) -> f64 {
    a.cross(b).dot(axis).atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_and_repeated_points_give_no_nan() {
        let pts = [
            DVec3::ZERO,
            DVec3::ZERO,
            DVec3::X,
            DVec3::X,
            DVec3::new(2.0, 0.0, 0.0),
        ];
        for mode in [
            TangentMode::Central,
            TangentMode::Previous,
            TangentMode::Next,
        ] {
            let t = tangents(&pts, false, mode);
            assert!(
                t.iter().all(|v| (*v - DVec3::X).length() < 1e-12),
                "{mode:?}: {t:?}"
            );
        }
        for method in [
            FrameMethod::DoubleReflection,
            FrameMethod::ParallelTransport,
            FrameMethod::UpVector(DVec3::X),
        ] {
            let f = frames(
                &pts,
                &tangents(&pts, false, TangentMode::Central),
                false,
                method,
                None,
            );
            assert!(f
                .iter()
                .all(|f| f.normal.is_finite() && (f.normal.length() - 1.0).abs() < 1e-12));
            // A straight line does not twist.
            assert!(f.iter().all(|g| g.normal.distance(f[0].normal) < 1e-12));
        }
        let single = tangents(&[DVec3::ONE; 3], false, TangentMode::Central);
        assert_eq!(single, vec![DVec3::Z; 3]);
    }

    #[test]
    fn orient_maps_axes_to_the_frame() {
        let f = Frame::new(DVec3::new(0.0, 0.6, 0.8), DVec3::X);
        let q = f.orient();
        assert!((q * DVec3::Z).distance(f.tangent) < 1e-12);
        assert!((q * DVec3::Y).distance(f.normal) < 1e-12);
        assert!((q * DVec3::X).distance(f.bitangent) < 1e-12);
    }
}
