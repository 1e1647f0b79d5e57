//! The studio's state behind the socket: the session, what is viewed (solo node, frame, auto-solo), and the requests a studio sends, each answered by a reply and, on change, a new state for everyone plus a latest-wins cook.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use geode_graph::Cache;
use geode_op::{CookEnv, FileAccess};
use serde::Deserialize;
use serde_json::{json, Value as Json};

use crate::cooker::{CookRequest, Cooker};
use crate::edits::Edit;
use crate::hub::Hub;
use crate::session::Session;
use crate::sheet;

/// What the viewport shows.
#[derive(Clone, Debug, Default)]
pub struct View {
    /// A node shown instead of the network's output (seed 004's solo view).
    pub solo: Option<String>,
    /// Whether `solo` was chosen by a tagged parameter (auto-solo).
    pub auto: bool,
    pub frame: f64,
}

/// A request from a studio.
#[derive(Debug, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case")]
pub enum Request {
    Edit {
        edit: Edit,
        #[serde(default)]
        merge: bool,
    },
    Undo,
    Redo,
    /// Solo view of a node (`null`: the network's output).
    View {
        node: Option<String>,
    },
    Frame {
        frame: f64,
    },
    Save {
        #[serde(default)]
        path: Option<PathBuf>,
    },
    /// Rows of the viewed result for the spreadsheet.
    Sheet {
        class: sheet::Class,
        start: usize,
        count: usize,
        #[serde(default)]
        entry: Option<String>,
    },
    /// A node's parameters as evaluated at the current frame (expressions
    /// beside their values).
    Values {
        path: String,
    },
    /// The point, vertex and primitive under a click in the viewport.
    Pick {
        #[serde(default)]
        entry: Option<String>,
        hit: crate::pick::Hit,
        at: [f32; 3],
    },
    /// Centres of the viewed geometry's first `limit` primitives (their
    /// numbers in the viewport).
    Centers {
        #[serde(default)]
        entry: Option<String>,
        limit: usize,
    },
    /// What the node info panel shows of a node at the viewed frame.
    Info {
        path: String,
    },
    /// Stop the cook in flight.
    Cancel,
}

#[derive(Debug, Deserialize)]
pub struct Envelope {
    #[serde(default)]
    pub id: Option<u64>,
    #[serde(flatten)]
    pub request: Request,
}

pub struct Studio {
    session: Mutex<Session>,
    view: Mutex<View>,
    generation: AtomicU64,
    /// Held while a change is published and its cook started, so that cooks
    /// start in the order of their generations.
    order: Mutex<()>,
    cooker: Cooker,
    pub hub: Arc<Hub>,
    env: CookEnv,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Why a request was refused, as the page reads it: a kind (`edit`, `io`,
/// `request`), the node it concerns and the message.
struct Refusal {
    kind: &'static str,
    path: Option<String>,
    message: String,
}

impl Refusal {
    fn request(message: impl Into<String>) -> Refusal {
        Refusal {
            kind: "request",
            path: None,
            message: message.into(),
        }
    }
}

impl Studio {
    /// A studio on `session` whose cooks and saves touch files as `files` allows.
    pub fn new(session: Session, cache: Arc<Cache>, files: FileAccess) -> Arc<Studio> {
        let hub = Hub::new();
        let env = match session.path() {
            Some(p) => CookEnv::for_network(p),
            None => CookEnv::from_process(),
        }
        .with_files(files);
        let studio = Arc::new(Studio {
            session: Mutex::new(session),
            view: Mutex::new(View {
                frame: 1.0,
                ..View::default()
            }),
            generation: AtomicU64::new(0),
            order: Mutex::new(()),
            cooker: Cooker::new(cache, hub.clone()),
            hub,
            env,
        });
        studio.changed(None);
        studio
    }

    /// The state every studio shows: the session and the view.
    pub fn state(&self) -> Json {
        let mut s = lock(&self.session).state();
        let v = lock(&self.view).clone();
        s["view"] = json!({"solo": v.solo, "auto": v.auto, "frame": v.frame});
        s["generation"] = json!(self.generation.load(Ordering::SeqCst));
        s
    }

    /// After any change: re-point the view, publish the state, cook what is viewed.
    fn changed(&self, tagged: Option<(&str, &str)>) {
        let _order = lock(&self.order);
        let session = lock(&self.session);
        let mut view = lock(&self.view);
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let net = session.network().as_ref().ok();
        if let (Some(net), Some((node, param))) = (net, tagged) {
            if let Some(target) = net.tagged_target(node, param) {
                view.solo = Some(target);
                view.auto = true;
            }
        }
        if let (Some(net), Some(solo)) = (net, view.solo.clone()) {
            if !net.paths().any(|p| p == solo) {
                view.solo = None;
                view.auto = false;
            }
        }
        let target = view
            .solo
            .clone()
            .or_else(|| net.and_then(|n| n.output().map(str::to_owned)));
        let frame = view.frame;
        drop(view);
        let request = match (session.network(), &target) {
            (Ok(net), Some(node)) => Some(CookRequest {
                generation,
                network: net.clone(),
                node: node.clone(),
                frame,
                env: self.env.clone(),
                templates: geode_graph::document::templated(&session.document().network, ""),
            }),
            _ => None,
        };
        let load_failed = session.network().is_err();
        drop(session);
        self.hub.send_json(&self.state());
        match request {
            Some(r) => self.cooker.start(r),
            None => {
                let _ = self.cooker.cancel(generation);
                let why = if load_failed {
                    "the file is not a network this geode can read"
                } else {
                    "nothing to show: set a display flag or view a node"
                };
                self.hub.blocked(generation, target.as_deref(), why);
            }
        }
    }

    /// Handles one request; the reply goes to the sender only.
    pub fn handle(&self, env: Envelope, client: u64) -> Json {
        match self.dispatch(env.request, client) {
            Ok(extra) => {
                let mut j = json!({"type": "reply", "id": env.id, "ok": true});
                if let Json::Object(m) = extra {
                    j.as_object_mut().expect("object").extend(m);
                }
                j
            }
            Err(r) => json!({"type": "reply", "id": env.id, "ok": false, "error": r.message,
                "kind": r.kind, "path": r.path}),
        }
    }

    fn dispatch(&self, request: Request, client: u64) -> Result<Json, Refusal> {
        match request {
            Request::Edit { edit, merge } => {
                lock(&self.session)
                    .edit_by(&edit, merge, client)
                    .map_err(|e| Refusal {
                        kind: "edit",
                        path: Some(e.path.clone()),
                        message: e.to_string(),
                    })?;
                let tagged = match &edit {
                    Edit::SetParam { path, param, .. } | Edit::SetKey { path, param, .. } => {
                        Some((path.as_str(), param.as_str()))
                    }
                    _ => None,
                };
                self.changed(tagged);
            }
            Request::Undo | Request::Redo => {
                let mut s = lock(&self.session);
                let done = if matches!(request, Request::Undo) {
                    s.undo_by(client)
                } else {
                    s.redo_by(client)
                };
                drop(s);
                done.map_err(|e| Refusal {
                    kind: "history",
                    path: None,
                    message: e.to_string(),
                })?;
                self.changed(None);
            }
            Request::View { node } => {
                {
                    let mut v = lock(&self.view);
                    v.solo = node;
                    v.auto = false;
                }
                self.changed(None);
            }
            Request::Frame { frame } => {
                if !frame.is_finite() {
                    return Err(Refusal::request("the frame must be a finite number"));
                }
                lock(&self.view).frame = frame;
                self.changed(None);
            }
            Request::Save { path } => {
                if let Some(p) = &path {
                    self.env.files.writable(p).map_err(|e| Refusal {
                        kind: "io",
                        path: None,
                        message: e.to_string(),
                    })?;
                }
                let saved = lock(&self.session)
                    .save(path.as_deref())
                    .map_err(|e| Refusal {
                        kind: "io",
                        path: None,
                        message: e.to_string(),
                    })?;
                self.hub.send_json(&self.state());
                return Ok(json!({"saved": saved.display().to_string()}));
            }
            Request::Sheet {
                class,
                start,
                count,
                entry,
            } => {
                return self
                    .sheet(class, start, count, entry.as_deref())
                    .map_err(Refusal::request)
            }
            Request::Values { path } => return self.values(&path).map_err(Refusal::request),
            Request::Info { path } => {
                let frame = lock(&self.view).frame;
                let net = lock(&self.session)
                    .network()
                    .as_ref()
                    .map_err(|_| Refusal::request("the network does not load"))?
                    .clone();
                if !net.paths().any(|p| p == path) {
                    return Err(Refusal::request(format!("no node {path}")));
                }
                let info =
                    crate::info::node_info(&net, self.cooker.cache(), &path, frame, &self.env);
                return Ok(json!({ "info": info }));
            }
            Request::Pick { entry, hit, at } => {
                let (geo, generation) = self.viewed(entry.as_deref()).map_err(Refusal::request)?;
                let picked = crate::pick::pick(&geo, hit, geode_geo::glam::Vec3::from_array(at))
                    .ok_or_else(|| Refusal::request("nothing drawn there"))?;
                return Ok(json!({"picked": picked, "generation": generation}));
            }
            Request::Centers { entry, limit } => {
                let (geo, generation) = self.viewed(entry.as_deref()).map_err(Refusal::request)?;
                let limit = limit.min(200_000);
                return Ok(json!({"centers": crate::pick::prim_centers(&geo, limit),
                    "total": geo.num_prims(), "generation": generation}));
            }
            Request::Cancel => {
                let _order = lock(&self.order);
                let g = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
                if let Some(stopped) = self.cooker.cancel(g) {
                    // The page marks its viewport: it shows an older result.
                    self.hub
                        .send_json(&json!({"type": "cancelled", "generation": stopped}));
                }
            }
        }
        Ok(Json::Null)
    }

    /// `{"values": {name: value}}` at the viewed frame; a parameter that
    /// fails gives `{"error": message, "column": c}`.
    fn values(&self, path: &str) -> Result<Json, String> {
        let frame = lock(&self.view).frame;
        let session = lock(&self.session);
        let net = session
            .network()
            .as_ref()
            .map_err(|_| "the network does not load")?;
        let values = net
            .param_values(path, frame, &self.env)
            .ok_or_else(|| format!("no node {path}"))?;
        let out: serde_json::Map<String, Json> = values
            .into_iter()
            .map(|(name, v)| {
                let j = match v {
                    Ok(v) => param_json(&v),
                    Err(e) => json!({"error": e.message, "column": e.position.map(|p| p.column)}),
                };
                (name, j)
            })
            .collect();
        Ok(json!({"values": out, "frame": frame}))
    }

    fn sheet(
        &self,
        class: sheet::Class,
        start: usize,
        count: usize,
        entry: Option<&str>,
    ) -> Result<Json, String> {
        let (geo, generation) = self.viewed(entry)?;
        let mut j = sheet::window(&geo, class, start, count);
        j["generation"] = json!(generation);
        j["node"] = json!(self.hub.last().map(|l| l.node));
        Ok(j)
    }

    /// The viewed result's geometry (a bundle's entry, by name or the first)
    /// and the generation that cooked it.
    fn viewed(&self, entry: Option<&str>) -> Result<(Arc<geode_geo::Geometry>, u64), String> {
        let last = self.hub.last().ok_or("nothing has cooked yet")?;
        let geo = match (&last.value, entry.filter(|e| !e.is_empty())) {
            (Some(geode_op::Value::Geometry(g)), _) => g.clone(),
            (Some(geode_op::Value::Bundle(b)), Some(e)) => b
                .entries
                .get(e)
                .cloned()
                .ok_or_else(|| format!("the bundle has no entry `{e}`"))?,
            (Some(geode_op::Value::Bundle(b)), None) => b
                .entries
                .values()
                .next()
                .cloned()
                .ok_or("the bundle is empty")?,
            _ => return Err("the viewed node has no geometry".into()),
        };
        Ok((geo, last.generation))
    }
}

/// A parameter value as the page reads it.
fn param_json(v: &geode_op::ParamValue) -> Json {
    use geode_op::ParamValue as V;
    match v {
        V::Float(x) => json!(x),
        V::Int(i) => json!(i),
        V::Toggle(b) => json!(b),
        V::Vector(v) => json!(v),
        V::String(s) => json!(s),
        V::List(rows) => Json::Array(
            rows.iter()
                .map(|r| Json::Array(r.iter().map(param_json).collect()))
                .collect(),
        ),
        V::Ramp(r) => geode_graph::catalogue::ramp_keys_json(r.kind(), r.keys()),
    }
}
