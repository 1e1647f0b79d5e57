//! The `.hs` file: a versioned text format for hspline hierarchies (see
//! docs/hs-format.md). Numbers are written in Rust's shortest round-trip
//! form, so a save and load is exact; "optimize for space" writes only the
//! non-zero offsets. Malformed files are errors with their line.

use std::fmt::Write as _;

use geode_geo::glam::DVec3;

use super::{Envelope, Grid, Hspline, Overlay, Topology};
use crate::skin::{Joint, SkinMethod};

/// Version 2 adds enveloping data; version 1 files still load.
pub const VERSION: u32 = 2;

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("line {line}: {message}")]
pub struct HsError {
    pub line: usize,
    pub message: String,
}

fn err(line: usize, message: impl Into<String>) -> HsError {
    HsError {
        line,
        message: message.into(),
    }
}

/// The text of `h`; with `optimize`, zero offsets are left out.
pub fn save(h: &Hspline, optimize: bool) -> String {
    let mut s = format!("hspline {VERSION}\n");
    let topology = match h.topology {
        Topology::Plane => "plane",
        Topology::Cylinder => "cylinder",
        Topology::Torus => "torus",
    };
    let _ = writeln!(s, "topology {topology}");
    let _ = writeln!(s, "base {} {}", h.base.nu, h.base.nv);
    for p in &h.base.points {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for (k, o) in h.overlays.iter().enumerate() {
        let _ = writeln!(
            s,
            "level {} u {} {} v {} {}",
            k + 1,
            o.u.0,
            o.u.1,
            o.v.0,
            o.v.1
        );
        for i in o.u.0..o.u.1 {
            for j in o.v.0..o.v.1 {
                let d = o.offsets[o.index(i, j).expect("inside")];
                if !optimize || d != DVec3::ZERO {
                    let _ = writeln!(s, "o {i} {j} {} {} {}", d.x, d.y, d.z);
                }
            }
        }
    }
    if let Some(e) = &h.envelope {
        let method = match e.method {
            SkinMethod::Linear => "linear",
            SkinMethod::DualQuaternion => "dual_quaternion",
        };
        let _ = writeln!(s, "envelope level {} method {method}", e.level);
        for j in &e.joints {
            let parent = j.parent.map_or("-", |p| e.joints[p].name.as_str());
            let _ = writeln!(
                s,
                "joint {} {parent} {} {} {}",
                j.name, j.rest.x, j.rest.y, j.rest.z
            );
        }
        let nv = h.grid_size(e.level).map_or(1, |g| g.1);
        for (k, w) in e.weights.iter().enumerate() {
            let _ = write!(s, "w {} {}", k / nv, k % nv);
            for (joint, x) in w {
                let _ = write!(s, " {joint} {x}");
            }
            s.push('\n');
        }
    }
    s.push_str("end\n");
    s
}

/// Reads a hierarchy; offsets not listed are zero.
pub fn load(text: &str) -> Result<Hspline, HsError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let mut next = |what: &str| {
        lines.next().ok_or_else(|| {
            err(
                text.lines().count() + 1,
                format!("unexpected end of file: expected {what}"),
            )
        })
    };
    let (n, head) = next("`hspline 1`")?;
    match head.split_whitespace().collect::<Vec<_>>()[..] {
        ["hspline", v] => match v.parse::<u32>() {
            Ok(1..=VERSION) => {}
            Ok(v) if v > VERSION => {
                return Err(err(
                    n,
                    format!("version {v} is newer than this geode reads ({VERSION})"),
                ))
            }
            _ => return Err(err(n, format!("bad version `{v}`"))),
        },
        _ => return Err(err(n, "expected `hspline 1`")),
    }
    let (n, t) = next("`topology`")?;
    let topology = match t.split_whitespace().collect::<Vec<_>>()[..] {
        ["topology", "plane"] => Topology::Plane,
        ["topology", "cylinder"] => Topology::Cylinder,
        ["topology", "torus"] => Topology::Torus,
        _ => return Err(err(n, "expected `topology plane|cylinder|torus`")),
    };
    let num = |n: usize, s: &str| {
        s.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| err(n, format!("`{s}` is not a finite number")))
    };
    let int = |n: usize, s: &str| {
        s.parse::<usize>()
            .map_err(|_| err(n, format!("`{s}` is not a count or index")))
    };
    let (n, b) = next("`base nu nv`")?;
    let (nu, nv) = match b.split_whitespace().collect::<Vec<_>>()[..] {
        ["base", a, c] => (int(n, a)?, int(n, c)?),
        _ => return Err(err(n, "expected `base nu nv`")),
    };
    if nu < 4 || nv < 4 || nu.saturating_mul(nv) > 1 << 22 {
        return Err(err(
            n,
            format!("a base of {nu} x {nv}: each side needs 4, and 4M vertices at most in all"),
        ));
    }
    let mut points = Vec::with_capacity(nu * nv);
    for _ in 0..nu * nv {
        let (n, l) = next("a base vertex `v x y z`")?;
        match l.split_whitespace().collect::<Vec<_>>()[..] {
            ["v", x, y, z] => points.push(DVec3::new(num(n, x)?, num(n, y)?, num(n, z)?)),
            _ => return Err(err(n, "expected `v x y z`")),
        }
    }
    let mut h = Hspline {
        topology,
        base: Grid { nu, nv, points },
        overlays: Vec::new(),
        envelope: None,
    };
    // Enveloping data: the `envelope` line, its joints, and weight lines
    // (checked against the level's size at `end`).
    let mut envelope: Option<(usize, usize, SkinMethod, Vec<Joint>)> = None;
    let mut weight_lines: Vec<WeightLine> = Vec::new();
    loop {
        let (n, l) = next("`level` or `end`")?;
        let w: Vec<&str> = l.split_whitespace().collect();
        match w[..] {
            ["end"] => {
                if let Some((line, level, method, joints)) = envelope.take() {
                    h.envelope = Some(finish_envelope(
                        &h,
                        line,
                        level,
                        method,
                        joints,
                        weight_lines,
                    )?);
                }
                break;
            }
            ["envelope", "level", k, "method", m] => {
                if envelope.is_some() {
                    return Err(err(n, "a second `envelope`"));
                }
                let method = match m {
                    "linear" => SkinMethod::Linear,
                    "dual_quaternion" => SkinMethod::DualQuaternion,
                    _ => {
                        return Err(err(
                            n,
                            format!("method `{m}`: expected linear or dual_quaternion"),
                        ))
                    }
                };
                envelope = Some((n, int(n, k)?, method, Vec::new()));
            }
            ["joint", name, parent, x, y, z] => {
                let Some((_, _, _, joints)) = envelope.as_mut() else {
                    return Err(err(n, "a joint before `envelope`"));
                };
                if joints.iter().any(|j| j.name == name) {
                    return Err(err(n, format!("joint `{name}` twice")));
                }
                let parent =
                    match parent {
                        "-" => None,
                        p => Some(joints.iter().position(|j| j.name == p).ok_or_else(|| {
                            err(n, format!("parent `{p}` is not an earlier joint"))
                        })?),
                    };
                joints.push(Joint {
                    name: name.to_owned(),
                    parent,
                    rest: DVec3::new(num(n, x)?, num(n, y)?, num(n, z)?),
                    rotation: geode_geo::glam::DQuat::IDENTITY,
                });
            }
            ["w", i, j, ref pairs @ ..] => {
                let Some((_, _, _, joints)) = envelope.as_ref() else {
                    return Err(err(n, "weights before `envelope`"));
                };
                if pairs.len() % 2 != 0 {
                    return Err(err(n, "expected `w i j` then `joint weight` pairs"));
                }
                let mut weights = Vec::with_capacity(pairs.len() / 2);
                for pair in pairs.chunks(2) {
                    let joint = int(n, pair[0])?;
                    if joint >= joints.len() {
                        return Err(err(
                            n,
                            format!("joint {joint} does not exist ({} listed)", joints.len()),
                        ));
                    }
                    let x = num(n, pair[1])?;
                    if x < 0.0 {
                        return Err(err(n, format!("weight {x} is negative")));
                    }
                    weights.push((joint, x));
                }
                weight_lines.push((n, int(n, i)?, int(n, j)?, weights));
            }
            ["level", k, "u", u0, u1, "v", v0, v1] => {
                if int(n, k)? != h.overlays.len() + 1 {
                    return Err(err(n, format!("expected level {}", h.overlays.len() + 1)));
                }
                let (gu, gv) = super::level_size((nu, nv), topology.wraps(), h.overlays.len() + 1)
                    .ok_or_else(|| err(n, "a level past 16M vertices a side"))?;
                let (u, v) = ((int(n, u0)?, int(n, u1)?), (int(n, v0)?, int(n, v1)?));
                if u.0 >= u.1 || v.0 >= v.1 || u.1 > gu || v.1 > gv {
                    return Err(err(n, format!("overlay u {u:?} v {v:?} is empty or outside the level's {gu} x {gv} vertices")));
                }
                if (u.1 - u.0).saturating_mul(v.1 - v.0) > 1 << 22 {
                    return Err(err(n, "an overlay of more than 4M vertices"));
                }
                h.overlays.push(Overlay {
                    u,
                    v,
                    offsets: vec![DVec3::ZERO; (u.1 - u.0) * (v.1 - v.0)],
                });
            }
            ["o", i, j, x, y, z] => {
                let Some(o) = h.overlays.last_mut() else {
                    return Err(err(n, "an offset before any `level`"));
                };
                let (i, j) = (int(n, i)?, int(n, j)?);
                let k = o
                    .index(i, j)
                    .ok_or_else(|| err(n, format!("offset ({i}, {j}) is outside the overlay")))?;
                o.offsets[k] = DVec3::new(num(n, x)?, num(n, y)?, num(n, z)?);
            }
            _ => return Err(err(n, format!("unexpected `{l}`"))),
        }
    }
    if let Some((n, l)) = lines.next() {
        return Err(err(n, format!("`{l}` after `end`")));
    }
    Ok(h)
}

/// A `w` line: its line number, the vertex (i, j) and its weights.
type WeightLine = (usize, usize, usize, Vec<(usize, f64)>);

/// The envelope read so far, checked against its level once the levels
/// are known: every vertex of the level has one weight line.
fn finish_envelope(
    h: &Hspline,
    line: usize,
    level: usize,
    method: SkinMethod,
    joints: Vec<Joint>,
    weight_lines: Vec<WeightLine>,
) -> Result<Envelope, HsError> {
    let (nu, nv) = h.grid_size(level).map_err(|_| {
        err(
            line,
            format!(
                "envelope level {level} does not exist ({} levels)",
                h.levels()
            ),
        )
    })?;
    if joints.is_empty() {
        return Err(err(line, "an envelope without joints"));
    }
    let mut weights: Vec<Option<Vec<(usize, f64)>>> = vec![None; nu * nv];
    for (n, i, j, w) in weight_lines {
        if i >= nu || j >= nv {
            return Err(err(
                n,
                format!("vertex ({i}, {j}) is outside level {level}'s {nu} x {nv}"),
            ));
        }
        if weights[i * nv + j].replace(w).is_some() {
            return Err(err(n, format!("vertex ({i}, {j}) weighted twice")));
        }
    }
    let weights = weights
        .into_iter()
        .enumerate()
        .map(|(k, w)| {
            w.ok_or_else(|| {
                err(
                    line,
                    format!(
                        "vertex ({}, {}) of level {level} has no weights",
                        k / nv,
                        k % nv
                    ),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(Envelope {
        level,
        method,
        joints,
        weights,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edited() -> Hspline {
        let mut h = Hspline::new(Topology::Cylinder, 6, 8, [2.0, 3.0]).unwrap();
        h.refine(None).unwrap();
        h.refine(Some(((2, 7), (3, 9)))).unwrap();
        h.move_cv(1, 4, 5, DVec3::new(0.1, 0.2 / 3.0, -0.7))
            .unwrap();
        let o = h.overlays[1].clone();
        h.move_cv(2, o.u.0 + 2, o.v.0 + 3, DVec3::new(1e-17, 0.3, 0.0))
            .unwrap();
        h
    }

    #[test]
    fn saving_and_loading_is_exact_with_or_without_zero_offsets() {
        let h = edited();
        for optimize in [false, true] {
            let text = save(&h, optimize);
            assert_eq!(load(&text).unwrap(), h, "optimize {optimize}");
        }
        assert!(save(&h, true).len() < save(&h, false).len());
    }

    #[test]
    fn enveloping_data_round_trips_and_bends_the_loaded_surface_alike() {
        use crate::skin::{Joint, Skeleton};
        let mut h = edited();
        let skeleton = Skeleton::new(vec![
            Joint {
                name: "hip".into(),
                parent: None,
                rest: DVec3::new(0.0, -1.5, 0.0),
                rotation: geode_geo::glam::DQuat::IDENTITY,
            },
            Joint {
                name: "knee".into(),
                parent: Some(0),
                rest: DVec3::ZERO,
                rotation: geode_geo::glam::DQuat::IDENTITY,
            },
        ])
        .unwrap();
        h.set_envelope(1, SkinMethod::DualQuaternion, &skeleton);
        let text = save(&h, true);
        assert!(text.starts_with("hspline 2\n") && text.contains("joint knee hip 0 0 0"));
        let back = load(&text).unwrap();
        assert_eq!(back, h);
        // The loaded envelope bends the surface exactly as the original.
        let mut posed = skeleton.clone();
        posed.joints[1].rotation = geode_geo::glam::DQuat::from_rotation_z(1.2);
        let motions = posed.motions();
        assert_eq!(back.enveloped_grid(&motions), h.enveloped_grid(&motions));
        assert_ne!(h.enveloped_grid(&motions).unwrap(), h.grid(2).unwrap());
        // Errors name their line.
        let cases = [
            (
                text.replacen("method dual_quaternion", "method squash", 1),
                "method `squash`",
            ),
            (
                text.replacen("joint knee hip", "joint knee thigh", 1),
                "parent `thigh`",
            ),
            (
                text.replacen("w 0 0 0", "w 0 0 7", 1),
                "joint 7 does not exist",
            ),
            (
                text.replacen("envelope level 1", "envelope level 5", 1),
                "envelope level 5 does not exist",
            ),
            (text.replacen("\nw 0 0 ", "\nw 0 1 ", 1), "weighted twice"),
        ];
        for (bad, want) in cases {
            let e = load(&bad).unwrap_err().to_string();
            assert!(
                e.starts_with("line ") && e.contains(want),
                "{e} (wanted {want})"
            );
        }
    }

    #[test]
    fn the_fuzz_seed_loads() {
        let text = include_str!("../../../../fuzz/seeds/read_hs/plane.hs");
        let h = load(text).unwrap();
        assert_eq!((h.levels(), h.nonzero_offsets(1)), (2, vec![(2, 2)]));
        assert_eq!(load(&save(&h, false)).unwrap(), h);
    }

    #[test]
    fn the_enveloped_fuzz_seed_loads_and_round_trips() {
        let text = include_str!("../../../../fuzz/seeds/read_hs/enveloped.hs");
        let h = load(text).unwrap();
        let e = h.envelope.as_ref().unwrap();
        assert_eq!((e.level, e.joints.len(), e.weights.len()), (0, 2, 16));
        assert_eq!(e.weights[5], vec![(0, 0.75), (1, 0.25)]);
        assert_eq!(load(&save(&h, true)).unwrap(), h);
    }

    #[test]
    fn malformed_files_name_their_line() {
        let good = save(&edited(), true);
        let cases = [
            (
                good.replacen("hspline 2", "hspline 9", 1),
                "line 1: version 9 is newer",
            ),
            (
                good.replacen("topology cylinder", "topology klein", 1),
                "line 2: expected `topology",
            ),
            (
                good.replacen("base 6 8", "base 6 2", 1),
                "line 3: a base of 6 x 2",
            ),
            (good.replacen("v ", "v x ", 1), "line 4: expected `v x y z`"),
            (good.replacen("level 2", "level 3", 1), "expected level 2"),
            (good.replace("end\n", ""), "unexpected end of file"),
            (format!("{good}v 1 2 3\n"), "after `end`"),
        ];
        for (text, want) in cases {
            let e = load(&text).unwrap_err().to_string();
            assert!(e.contains(want), "{e} (wanted {want})");
        }
        assert!(load("").unwrap_err().to_string().starts_with("line 1:"));
    }
}
