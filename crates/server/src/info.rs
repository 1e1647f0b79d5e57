//! The node info panel's content (Houdini's middle-click info): the node
//! cooked at the viewed frame through the shared cache (a hit when the
//! viewed cook already pulled it), with its key, time, memory, counts,
//! attributes, groups, warnings or errors.

use std::time::Duration;

use geode_geo::{AttribClass, Geometry};
use geode_graph::{Cache, CookOptions, Engine, Network};
use geode_op::{CancelToken, CookEnv, Value};
use serde_json::{json, Value as Json};

/// How long an info request may cook before it gives up (the panel is no
/// place to wait for a long cook: view the node instead).
const INFO_BUDGET: Duration = Duration::from_secs(10);

/// Attributes and groups of a geometry, by class.
pub fn geometry_info(g: &Geometry) -> Json {
    let classes = [
        ("point", AttribClass::Point),
        ("vertex", AttribClass::Vertex),
        ("primitive", AttribClass::Primitive),
        ("detail", AttribClass::Detail),
    ];
    let attributes: Vec<Json> = classes
        .iter()
        .flat_map(|(label, c)| {
            g.attribs(*c)
                .iter()
                .map(move |(name, a)| json!({"class": label, "name": name, "type": a.attrib_type().to_string()}))
        })
        .collect();
    let mut stats = crate::viewport::geometry_stats(g);
    stats["attributes"] = json!(attributes);
    stats["pointGroups"] = json!(g.point_groups().keys().collect::<Vec<_>>());
    stats["primGroups"] = json!(g.prim_groups().keys().collect::<Vec<_>>());
    stats
}

/// The info of node `path` at `frame`.
pub fn node_info(net: &Network, cache: &Cache, path: &str, frame: f64, env: &CookEnv) -> Json {
    let engine = Engine::new(net.clone(), cache);
    let cancel = CancelToken::new();
    let watchdog = {
        let cancel = cancel.clone();
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        std::thread::spawn(move || {
            if rx.recv_timeout(INFO_BUDGET).is_err() {
                cancel.cancel();
            }
        });
        tx
    };
    let opts = CookOptions {
        frame,
        cancel,
        progress: None,
        env: env.clone(),
        writes: false,
    };
    let result = engine.cook(path, &opts);
    drop(watchdog);
    let mut out = json!({"path": path, "type": net.node_type(path), "frame": frame,
        "animated": net.is_animated(path)});
    match result {
        Ok(r) => {
            if let Some(e) = r.events.iter().find(|e| e.path == path) {
                out["key"] = json!(format!("{:032x}", e.key));
                out["hit"] = json!(e.hit);
                out["ms"] = json!(e.seconds * 1e3);
                out["bytes"] = json!(e.bytes);
                out["warnings"] = json!(&*e.warnings);
            }
            out["upstreamMs"] = json!(r.events.iter().map(|e| e.seconds).sum::<f64>() * 1e3);
            out["value"] = match &r.value {
                Value::Geometry(g) => geometry_info(g),
                Value::Bundle(b) => json!({"bundle": b.entries.iter()
                    .map(|(n, g)| (n.clone(), geometry_info(g))).collect::<serde_json::Map<_, _>>()}),
                _ => json!({"field": true}),
            };
        }
        Err(errors) => {
            out["errors"] = json!(errors
                .iter()
                .map(crate::hub::error_json)
                .collect::<Vec<_>>());
        }
    }
    out
}
