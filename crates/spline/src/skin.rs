//! Skeleton enveloping (skinning): a joint hierarchy with rest and posed
//! local transforms, weights per point (automatic from the distance to each
//! bone, or given), and linear blend or dual quaternion skinning. Used on
//! meshes and on one level of an hspline, whose finer offsets then follow
//! in the deformed local frames (the thesis's remedy for joint collapse).

use geode_geo::glam::{DQuat, DVec3};

/// A joint: its parent (earlier in the list, or none), its rest position
/// in world space, and its posed rotation relative to its parent (about the
/// joint).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub name: String,
    pub parent: Option<usize>,
    pub rest: DVec3,
    pub rotation: DQuat,
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SkinError {
    #[error("joint {0} names parent {1}, which is not an earlier joint")]
    BadParent(usize, usize),
    #[error("the skeleton has no joints")]
    Empty,
}

/// A rigid motion: rotate, then translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    pub rotation: DQuat,
    pub translation: DVec3,
}

impl Rigid {
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }
}

/// Joints from the root outwards, each parent before its children.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    pub joints: Vec<Joint>,
}

impl Skeleton {
    pub fn new(joints: Vec<Joint>) -> Result<Skeleton, SkinError> {
        if joints.is_empty() {
            return Err(SkinError::Empty);
        }
        for (i, j) in joints.iter().enumerate() {
            if let Some(p) = j.parent {
                if p >= i {
                    return Err(SkinError::BadParent(i, p));
                }
            }
        }
        Ok(Skeleton { joints })
    }

    /// Each joint's motion from rest to pose: a joint turns its subtree about
    /// itself, after its parent's motion.
    pub fn motions(&self) -> Vec<Rigid> {
        let mut out: Vec<Rigid> = Vec::with_capacity(self.joints.len());
        for j in &self.joints {
            let parent = j.parent.map_or(
                Rigid {
                    rotation: DQuat::IDENTITY,
                    translation: DVec3::ZERO,
                },
                |p| out[p],
            );
            // Rotate about the joint's rest position, then follow the parent.
            let local = Rigid {
                rotation: j.rotation,
                translation: j.rest - j.rotation * j.rest,
            };
            out.push(Rigid {
                rotation: parent.rotation * local.rotation,
                translation: parent.rotation * local.translation + parent.translation,
            });
        }
        out
    }

    /// The bone of each joint: from it to its first child (a leaf: a point).
    fn bones(&self) -> Vec<(DVec3, DVec3)> {
        self.joints
            .iter()
            .enumerate()
            .map(|(i, j)| {
                let child = self
                    .joints
                    .iter()
                    .find(|c| c.parent == Some(i))
                    .map_or(j.rest, |c| c.rest);
                (j.rest, child)
            })
            .collect()
    }

    /// Automatic weights: the inverse fourth power of the distance to each
    /// bone (at rest), the four strongest kept and normalized.
    pub fn auto_weights(&self, points: &[DVec3]) -> Vec<Vec<(usize, f64)>> {
        let bones = self.bones();
        points
            .iter()
            .map(|p| {
                let mut w: Vec<(usize, f64)> = bones
                    .iter()
                    .enumerate()
                    .map(|(i, (a, b))| {
                        let ab = *b - *a;
                        let t = if ab.length_squared() > 0.0 {
                            ((*p - *a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                        } else {
                            0.0
                        };
                        let d = p.distance(*a + ab * t).max(1e-9);
                        (i, d.powi(-4))
                    })
                    .collect();
                w.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
                w.truncate(4);
                let sum: f64 = w.iter().map(|x| x.1).sum();
                w.iter_mut().for_each(|x| x.1 /= sum);
                w
            })
            .collect()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkinMethod {
    /// Linear blend: the weighted sum of the moved points.
    Linear,
    /// Dual quaternions: the weighted, normalized sum of the motions.
    DualQuaternion,
}

/// Moves `points` by the skeleton's pose with `weights` per point.
pub fn skin(
    points: &[DVec3],
    weights: &[Vec<(usize, f64)>],
    motions: &[Rigid],
    method: SkinMethod,
) -> Vec<DVec3> {
    points
        .iter()
        .zip(weights)
        .map(|(p, w)| match method {
            SkinMethod::Linear => w.iter().map(|&(j, x)| motions[j].apply(*p) * x).sum(),
            SkinMethod::DualQuaternion => {
                // Real part q, dual part d = 0.5 t q; blended in q's hemisphere.
                let pivot = w
                    .first()
                    .map_or(DQuat::IDENTITY, |&(j, _)| motions[j].rotation);
                let (mut real, mut dual) = (
                    DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                    DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
                );
                for &(j, x) in w {
                    let m = motions[j];
                    let s = if m.rotation.dot(pivot) < 0.0 { -x } else { x };
                    let d =
                        DQuat::from_xyzw(m.translation.x, m.translation.y, m.translation.z, 0.0)
                            * m.rotation
                            * 0.5;
                    real += m.rotation * s;
                    dual += d * s;
                }
                let len = real.length();
                if len == 0.0 {
                    return *p;
                }
                let (real, dual) = (real / len, dual / len);
                let t = (dual * real.conjugate()) * 2.0;
                real * *p + DVec3::new(t.x, t.y, t.z)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arm along +X: shoulder at 0, elbow at 1, wrist at 2.
    fn arm(bend: f64) -> Skeleton {
        let joint = |name: &str, parent, x: f64, rotation| Joint {
            name: name.into(),
            parent,
            rest: DVec3::new(x, 0.0, 0.0),
            rotation,
        };
        Skeleton::new(vec![
            joint("shoulder", None, 0.0, DQuat::IDENTITY),
            joint("elbow", Some(0), 1.0, DQuat::from_rotation_z(bend)),
            joint("wrist", Some(1), 2.0, DQuat::IDENTITY),
        ])
        .unwrap()
    }

    fn tube() -> Vec<DVec3> {
        (0..=40)
            .flat_map(|i| {
                (0..16).map(move |k| {
                    let a = std::f64::consts::TAU * k as f64 / 16.0;
                    DVec3::new(i as f64 / 20.0, 0.2 * a.cos(), 0.2 * a.sin())
                })
            })
            .collect()
    }

    #[test]
    fn the_rest_pose_moves_nothing_and_a_rigid_pose_moves_rigidly() {
        let pts = tube();
        let s = arm(0.0);
        let w = s.auto_weights(&pts);
        for m in [SkinMethod::Linear, SkinMethod::DualQuaternion] {
            let out = skin(&pts, &w, &s.motions(), m);
            assert!(
                pts.iter().zip(&out).all(|(a, b)| a.distance(*b) < 1e-12),
                "{m:?}"
            );
        }
        // Turning the root turns everything rigidly, whatever the weights.
        let mut turned = arm(0.0);
        turned.joints[0].rotation = DQuat::from_rotation_y(0.8);
        for m in [SkinMethod::Linear, SkinMethod::DualQuaternion] {
            let out = skin(&pts, &w, &turned.motions(), m);
            for (a, b) in pts.iter().zip(&out) {
                assert!(
                    (DQuat::from_rotation_y(0.8) * *a).distance(*b) < 1e-9,
                    "{m:?}"
                );
            }
        }
        assert_eq!(
            Skeleton::new(vec![Joint {
                name: "x".into(),
                parent: Some(0),
                rest: DVec3::ZERO,
                rotation: DQuat::IDENTITY
            }]),
            Err(SkinError::BadParent(0, 0))
        );
    }

    #[test]
    fn dual_quaternions_keep_the_elbow_thicker_than_linear_blending() {
        let pts = tube();
        let s = arm(std::f64::consts::FRAC_PI_2 * 1.2);
        let w = s.auto_weights(&pts);
        // Thickness at the elbow: the distance from the elbow joint of the
        // ring that sat at x = 1.
        let ring = |out: &[DVec3]| {
            out.iter()
                .zip(&pts)
                .filter(|(_, p)| (p.x - 1.0).abs() < 1e-9)
                .map(|(q, _)| q.distance(DVec3::X))
                .fold(f64::MAX, f64::min)
        };
        let lbs = ring(&skin(&pts, &w, &s.motions(), SkinMethod::Linear));
        let dqs = ring(&skin(&pts, &w, &s.motions(), SkinMethod::DualQuaternion));
        assert!(dqs > lbs * 1.2, "dual quaternions {dqs} vs linear {lbs}");
        assert!(dqs > 0.15, "close to the rest radius 0.2: {dqs}");
    }
}
