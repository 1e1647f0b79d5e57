//! Keyframed channels: constant, linear, Bezier (cubic Hermite with tangents) and ease keys, at fractional frames.

use serde::{Deserialize, Serialize};

/// How a segment is interpolated from its starting key to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Interp {
    /// Holds the key's value until the next key.
    Constant,
    #[default]
    Linear,
    /// Cubic Hermite using `slope_out` of this key and `slope_in` of the next
    /// (per frame); a missing slope is set automatically (Catmull-Rom).
    Bezier,
    /// Cubic with zero slopes at both ends (ease in and out).
    Ease,
}

/// One keyframe.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Key {
    pub frame: f64,
    pub value: f64,
    #[serde(default, skip_serializing_if = "is_default_interp")]
    pub interp: Interp,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope_in: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope_out: Option<f64>,
}

fn is_default_interp(i: &Interp) -> bool {
    *i == Interp::Linear
}

/// Keys sorted by frame (at least one).
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    keys: Vec<Key>,
}

impl Channel {
    /// A channel from keys; None when there are none or a frame repeats or is not finite.
    pub fn new(mut keys: Vec<Key>) -> Result<Channel, String> {
        if keys.is_empty() {
            return Err("a channel needs at least one key".into());
        }
        if keys
            .iter()
            .any(|k| !k.frame.is_finite() || !k.value.is_finite())
        {
            return Err("key frames and values must be finite numbers".into());
        }
        keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
        if let Some(w) = keys.windows(2).find(|w| w[0].frame == w[1].frame) {
            return Err(format!("two keys at frame {}", w[0].frame));
        }
        Ok(Channel { keys })
    }

    pub fn keys(&self) -> &[Key] {
        &self.keys
    }

    /// The automatic slope at key `i` (finite differences of the neighbours).
    fn auto_slope(&self, i: usize) -> f64 {
        let k = &self.keys;
        let (a, b) = (i.saturating_sub(1), (i + 1).min(k.len() - 1));
        if a == b {
            0.0
        } else {
            (k[b].value - k[a].value) / (k[b].frame - k[a].frame)
        }
    }

    /// The value at `frame`; before the first key and after the last the
    /// nearest key's value holds.
    pub fn eval(&self, frame: f64) -> f64 {
        let k = &self.keys;
        if frame <= k[0].frame {
            return k[0].value;
        }
        let last = k.len() - 1;
        if frame >= k[last].frame {
            return k[last].value;
        }
        let i = k.partition_point(|key| key.frame <= frame) - 1;
        let (a, b) = (&k[i], &k[i + 1]);
        let span = b.frame - a.frame;
        let t = (frame - a.frame) / span;
        match a.interp {
            Interp::Constant => a.value,
            Interp::Linear => a.value + (b.value - a.value) * t,
            Interp::Ease => hermite(a.value, b.value, 0.0, 0.0, t),
            Interp::Bezier => {
                let m0 = a.slope_out.unwrap_or_else(|| self.auto_slope(i)) * span;
                let m1 = b.slope_in.unwrap_or_else(|| self.auto_slope(i + 1)) * span;
                hermite(a.value, b.value, m0, m1, t)
            }
        }
    }

    /// True when the value never changes (one key, or all keys equal and held).
    pub fn is_constant(&self) -> bool {
        self.keys.iter().all(|k| k.value == self.keys[0].value)
            && self.keys.iter().all(|k| {
                k.interp != Interp::Bezier
                    || (k.slope_out == Some(0.0) && k.slope_in == Some(0.0))
                    || self.keys.len() == 1
            })
    }
}

fn hermite(p0: f64, p1: f64, m0: f64, m1: f64, t: f64) -> f64 {
    let t2 = t * t;
    let t3 = t2 * t;
    (2.0 * t3 - 3.0 * t2 + 1.0) * p0
        + (t3 - 2.0 * t2 + t) * m0
        + (-2.0 * t3 + 3.0 * t2) * p1
        + (t3 - t2) * m1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(frame: f64, value: f64, interp: Interp) -> Key {
        Key {
            frame,
            value,
            interp,
            slope_in: None,
            slope_out: None,
        }
    }

    #[test]
    fn interpolation_kinds() {
        let lin = Channel::new(vec![
            key(10.0, 0.0, Interp::Linear),
            key(20.0, 100.0, Interp::Linear),
        ])
        .unwrap();
        assert_eq!(lin.eval(0.0), 0.0);
        assert_eq!(lin.eval(12.5), 25.0);
        assert_eq!(lin.eval(99.0), 100.0);
        let con = Channel::new(vec![
            key(1.0, 3.0, Interp::Constant),
            key(5.0, 7.0, Interp::Linear),
        ])
        .unwrap();
        assert_eq!(con.eval(4.999), 3.0);
        assert_eq!(con.eval(5.0), 7.0);
        let ease = Channel::new(vec![
            key(0.0, 0.0, Interp::Ease),
            key(10.0, 10.0, Interp::Linear),
        ])
        .unwrap();
        assert_eq!(ease.eval(5.0), 5.0);
        assert!(ease.eval(1.0) < 1.0, "slow start");
        // Bezier with explicit slopes: slope 1 per frame at both ends on a
        // 0..10 rise of 10 is a straight line.
        let mut a = key(0.0, 0.0, Interp::Bezier);
        a.slope_out = Some(1.0);
        let mut b = key(10.0, 10.0, Interp::Linear);
        b.slope_in = Some(1.0);
        let bez = Channel::new(vec![a, b]).unwrap();
        for f in [0.5, 3.3, 7.25] {
            assert!((bez.eval(f) - f).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_channels_are_rejected() {
        assert!(Channel::new(vec![]).is_err());
        assert_eq!(
            Channel::new(vec![
                key(1.0, 0.0, Interp::Linear),
                key(1.0, 2.0, Interp::Linear)
            ])
            .unwrap_err(),
            "two keys at frame 1"
        );
    }
}
