//! Sending only what changed: when a new cook of the viewed node keeps the
//! topology of the result sent last (the same parts with the same index
//! arrays), the page gets a message with only the arrays that differ
//! (`deltaOf` names the generation it applies to), and updates what it
//! already holds in place: a deforming mesh sends its positions, a recoloured
//! one its colours.

use serde_json::{json, Value as Json};

use crate::viewport::MAGIC;

/// Arrays that are the topology: a delta needs them byte for byte unchanged.
const TOPOLOGY: &[&str] = &[
    "triangles",
    "cornerTriangles",
    "lines",
    "points",
    "instances",
];

/// A message split into its header and array body.
fn split(message: &[u8]) -> Option<(Json, &[u8])> {
    if message.len() < 8 || &message[..4] != MAGIC {
        return None;
    }
    let n = u32::from_le_bytes(message[4..8].try_into().ok()?) as usize;
    let header = serde_json::from_slice(message.get(8..8 + n)?).ok()?;
    Some((header, message.get(8 + n..)?))
}

/// An array's bytes from its `[offset, count]` entry (4-byte elements).
fn array<'b>(body: &'b [u8], at: &Json) -> Option<&'b [u8]> {
    let offset = at.get(0)?.as_u64()? as usize;
    let count = at.get(1)?.as_u64()? as usize;
    body.get(offset..offset + count * 4)
}

fn is_array(v: &Json) -> bool {
    v.as_array()
        .is_some_and(|a| a.len() == 2 && a.iter().all(Json::is_u64))
}

/// The delta taking the page from `prev` to `next` (both full messages), or
/// None when the topology (or anything else but array contents) differs.
pub fn delta(prev: &[u8], next: &[u8]) -> Option<Vec<u8>> {
    let (ph, pbody) = split(prev)?;
    let (mut nh, nbody) = split(next)?;
    if ph["node"] != nh["node"] {
        return None;
    }
    let pparts = ph["parts"].as_array()?;
    let nparts = nh["parts"].as_array_mut()?;
    if pparts.len() != nparts.len() {
        return None;
    }
    let mut body: Vec<u8> = Vec::new();
    for (p, n) in pparts.iter().zip(nparts.iter_mut()) {
        let (p, n) = (p.as_object()?, n.as_object_mut()?);
        // The same keys, and every non-array field (name, uniform colours,
        // reduction) the same.
        if p.len() != n.len() || p.keys().zip(n.keys()).any(|(a, b)| a != b) {
            return None;
        }
        let mut unchanged = Vec::new();
        for (key, nv) in n.iter_mut() {
            let pv = &p[key];
            if !is_array(nv) {
                if pv != nv {
                    return None;
                }
                continue;
            }
            let (a, b) = (array(pbody, pv)?, array(nbody, nv)?);
            if a == b {
                unchanged.push(key.clone());
                continue;
            }
            if a.len() != b.len() || TOPOLOGY.contains(&key.as_str()) {
                return None;
            }
            let offset = body.len();
            body.extend_from_slice(b);
            *nv = json!([offset, b.len() / 4]);
        }
        for key in unchanged {
            n.remove(&key);
        }
    }
    nh["deltaOf"] = ph["generation"].clone();
    let mut head = serde_json::to_vec(&nh).ok()?;
    while head.len() % 4 != 0 {
        head.push(b' ');
    }
    let mut out = Vec::with_capacity(8 + head.len() + body.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&(head.len() as u32).to_le_bytes());
    out.extend_from_slice(&head);
    out.extend_from_slice(&body);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::Vec3;
    use geode_geo::Geometry;
    use geode_op::Value;
    use std::sync::Arc;

    fn quad(lift: f32, generation: u64) -> Vec<u8> {
        let mut g = Geometry::new();
        g.set_positions(vec![
            Vec3::new(0.0, lift, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]);
        g.add_polygon(&[0, 1, 2, 3]).unwrap();
        crate::viewport::encode(
            &Value::Geometry(Arc::new(g)),
            json!({"generation": generation, "node": "/q"}),
        )
        .unwrap()
        .bytes
    }

    #[test]
    fn a_moved_point_sends_positions_only() {
        let (a, b) = (quad(0.0, 1), quad(0.5, 2));
        let d = delta(&a, &b).expect("same topology");
        let (h, body) = split(&d).unwrap();
        assert_eq!(h["deltaOf"], 1);
        assert_eq!(h["generation"], 2);
        let part = h["parts"][0].as_object().unwrap();
        assert!(part.contains_key("positions"));
        assert!(!part.contains_key("polygons"), "unchanged: left out");
        assert_eq!(body.len(), 4 * 3 * 4);
        assert_eq!(
            array(body, &part["positions"]).unwrap()[4..8],
            0.5f32.to_le_bytes()
        );
        assert!(d.len() < b.len());
    }

    #[test]
    fn another_topology_or_node_needs_the_whole_message() {
        let a = quad(0.0, 1);
        let mut g = Geometry::new();
        g.set_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        g.add_polygon(&[0, 1, 2]).unwrap();
        let tri = crate::viewport::encode(
            &Value::Geometry(Arc::new(g)),
            json!({"generation": 2, "node": "/q"}),
        )
        .unwrap()
        .bytes;
        assert!(delta(&a, &tri).is_none());
        let mut other = quad(0.0, 2);
        // The same geometry from another node is a new thing to frame.
        let renamed = String::from_utf8_lossy(&other).replace("\"/q\"", "\"/r\"");
        other = renamed.into_bytes();
        assert!(delta(&a, &other).is_none());
    }
}
