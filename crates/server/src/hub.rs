//! The hub: turns the cooker's reports into messages for every connected studio (progress, the cooked result with its geometry in binary) and keeps the last result for the spreadsheet, export and trace.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use axum::body::Bytes;
use geode_graph::CookEvent;
use geode_op::{CookError, Value};
use serde_json::{json, Value as Json};
use tokio::sync::broadcast;

use crate::cooker::{Finished, Reporter};
use crate::viewport;

/// A message to every studio.
#[derive(Clone, Debug)]
pub enum Out {
    Text(Arc<str>),
    Binary(Bytes),
}

/// The last delivered cook.
#[derive(Clone)]
pub struct Last {
    pub generation: u64,
    pub node: String,
    pub value: Option<Value>,
    pub events: Vec<CookEvent>,
    /// The messages that announced it (re-sent to a studio that connects later).
    pub messages: Vec<Out>,
}

pub struct Hub {
    tx: broadcast::Sender<Out>,
    last: Mutex<Option<Last>>,
    delivered: AtomicU64,
}

pub fn error_json(e: &CookError) -> Json {
    json!({"path": e.path, "param": e.param, "kind": e.kind.name(), "message": e.message,
        "line": e.position.map(|p| p.line), "column": e.position.map(|p| p.column)})
}

fn event_json(e: &CookEvent) -> Json {
    json!({"path": e.path, "type": e.node_type, "hit": e.hit, "start": e.start * 1e3, "ms": e.seconds * 1e3, "bytes": e.bytes, "warnings": &*e.warnings})
}

impl Hub {
    pub fn new() -> Arc<Hub> {
        let (tx, _) = broadcast::channel(1024);
        Arc::new(Hub {
            tx,
            last: Mutex::new(None),
            delivered: AtomicU64::new(0),
        })
    }

    pub fn subscribe(&self) -> broadcast::Receiver<Out> {
        self.tx.subscribe()
    }

    pub fn send_json(&self, j: &Json) {
        let _ = self.tx.send(Out::Text(j.to_string().into()));
    }

    pub fn last(&self) -> Option<Last> {
        self.last.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    /// Publishes a result unless a newer one was published already: its
    /// messages, with the geometry sent as a delta of the last result when
    /// only array contents changed (a page that connects later gets the
    /// whole geometry).
    fn publish(&self, last: Last) {
        let mut slot = self.last.lock().unwrap_or_else(|p| p.into_inner());
        if self.delivered.fetch_max(last.generation, Ordering::SeqCst) > last.generation {
            return;
        }
        let previous = slot.as_ref().and_then(|l| binary(&l.messages));
        for m in &last.messages {
            let sent = match (m, &previous) {
                (Out::Binary(next), Some(prev)) => crate::delta::delta(prev, next)
                    .map(|d| Out::Binary(Bytes::from(d)))
                    .unwrap_or_else(|| m.clone()),
                _ => m.clone(),
            };
            let _ = self.tx.send(sent);
        }
        *slot = Some(last);
    }

    /// The whole geometry message of the last result, for a page that missed
    /// the one a delta applies to.
    pub fn last_geometry(&self) -> Option<Bytes> {
        self.last().and_then(|l| binary(&l.messages))
    }

    /// The network cannot be cooked (it does not load): nothing to show.
    pub fn blocked(&self, generation: u64, node: Option<&str>, message: &str) {
        let j = json!({"type": "cooked", "generation": generation, "node": node, "ok": false,
            "errors": [{"path": node.unwrap_or("/"), "param": null, "kind": "network", "message": message}],
            "events": []});
        self.publish(Last {
            generation,
            node: node.unwrap_or("/").to_owned(),
            value: None,
            events: Vec::new(),
            messages: vec![Out::Text(j.to_string().into())],
        });
    }
}

impl Reporter for Hub {
    fn template(&self, generation: u64, node: &str, value: Option<Value>) {
        let header = json!({"generation": generation, "node": node, "template": true});
        // A template that fails or cannot be drawn is simply not shown: its own
        // errors show when it is viewed.
        if let Some(Ok(e)) = value.as_ref().map(|v| viewport::encode(v, header)) {
            let _ = self.tx.send(Out::Binary(Bytes::from(e.bytes)));
        }
    }

    fn progress(&self, generation: u64, node: &str, fraction: f32) {
        self.send_json(&json!({"type": "progress", "generation": generation, "node": node, "fraction": fraction}));
    }

    fn finished(&self, done: Finished) {
        let (value, events, mut errors) = match done.result {
            Ok((v, ev)) => (Some(v), ev, Vec::new()),
            Err(errs) => (None, Vec::new(), errs.iter().map(error_json).collect()),
        };
        let mut messages = Vec::new();
        let mut stats = Json::Null;
        let mut geometry = None;
        let mut encode_ms = 0.0;
        if let Some(v) = &value {
            stats = viewport::stats(v);
            let header = json!({"generation": done.generation, "node": done.node});
            let began = std::time::Instant::now();
            let encoded = viewport::encode(v, header);
            encode_ms = began.elapsed().as_secs_f64() * 1e3;
            match encoded {
                Ok(e) => {
                    stats["bounds"] = e.bounds;
                    geometry = Some(Bytes::from(e.bytes));
                }
                Err(e) => errors.push(json!({"path": done.node, "param": null, "kind": "resource", "message": e.to_string()})),
            }
        }
        let j = json!({
            "type": "cooked",
            "generation": done.generation,
            "node": done.node,
            "frame": done.frame,
            "ok": errors.is_empty(),
            "errors": errors,
            "events": events.iter().map(event_json).collect::<Vec<_>>(),
            "stats": stats,
            "ms": done.seconds * 1e3,
            "hasGeometry": geometry.is_some(),
            "encodeMs": encode_ms,
        });
        // The geometry first: the page decodes and uploads it while it reads the rest.
        messages.extend(geometry.map(Out::Binary));
        messages.push(Out::Text(j.to_string().into()));
        self.publish(Last {
            generation: done.generation,
            node: done.node,
            value,
            events,
            messages,
        });
    }
}

/// The geometry message among a result's messages.
fn binary(messages: &[Out]) -> Option<Bytes> {
    messages.iter().find_map(|m| match m {
        Out::Binary(b) => Some(b.clone()),
        Out::Text(_) => None,
    })
}

/// The last cook as a Chrome trace (`chrome://tracing`, Perfetto): one span
/// per node, laid in lanes so that parallel cooks do not overlap.
pub fn chrome_trace(events: &[CookEvent]) -> Json {
    let mut sorted: Vec<&CookEvent> = events.iter().collect();
    sorted.sort_by(|a, b| a.start.total_cmp(&b.start));
    let mut lane_ends: Vec<f64> = Vec::new();
    let spans: Vec<Json> = sorted
        .iter()
        .map(|e| {
            let end = e.start + e.seconds;
            let lane = match lane_ends.iter().position(|&t| t <= e.start) {
                Some(l) => {
                    lane_ends[l] = end;
                    l
                }
                None => {
                    lane_ends.push(end);
                    lane_ends.len() - 1
                }
            };
            json!({"name": e.path, "cat": if e.hit { "hit" } else { "cook" }, "ph": "X",
                "ts": e.start * 1e6, "dur": e.seconds * 1e6, "pid": 1, "tid": lane + 1,
                "args": {"type": e.node_type, "hit": e.hit, "bytes": e.bytes}})
        })
        .collect();
    json!({"traceEvents": spans, "displayTimeUnit": "ms"})
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(generation: u64) -> Last {
        Last {
            generation,
            node: "/n".into(),
            value: None,
            events: Vec::new(),
            messages: vec![Out::Text(format!("{generation}").into())],
        }
    }

    #[test]
    fn a_stale_result_never_replaces_a_newer_one() {
        let hub = Hub::new();
        let mut rx = hub.subscribe();
        hub.publish(result(5));
        hub.publish(result(3));
        assert_eq!(hub.last().unwrap().generation, 5);
        assert!(matches!(rx.try_recv(), Ok(Out::Text(t)) if &*t == "5"));
        assert!(rx.try_recv().is_err(), "the stale result was not sent");
    }

    #[test]
    fn errors_travel_as_fields_not_debug_text() {
        let e = CookError::param("/w", "snippet", "undeclared variable").at_position(2, 9);
        assert_eq!(
            error_json(&e),
            json!({"path": "/w", "param": "snippet", "kind": "parameter",
                "message": "undeclared variable", "line": 2, "column": 9})
        );
        let e = CookError::new("/f", geode_op::ErrorKind::Io, "cannot read");
        assert_eq!(error_json(&e)["kind"], "io");
        assert_eq!(error_json(&e)["line"], Json::Null);
    }

    #[test]
    fn the_chrome_trace_lays_overlapping_spans_in_lanes() {
        let ev = |path: &str, start: f64, seconds: f64| CookEvent {
            path: path.into(),
            node_type: "box",
            key: 0,
            hit: false,
            from_store: false,
            start,
            seconds,
            bytes: 0,
            warnings: std::sync::Arc::from([]),
        };
        let t = chrome_trace(&[ev("/a", 0.0, 1.0), ev("/b", 0.5, 1.0), ev("/c", 1.2, 0.1)]);
        let lanes: Vec<u64> = t["traceEvents"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["tid"].as_u64().unwrap())
            .collect();
        assert_eq!(lanes, vec![1, 2, 1]);
        assert_eq!(t["traceEvents"][1]["ts"], 500000.0);
        assert_eq!(t["traceEvents"][1]["ph"], "X");
    }
}
