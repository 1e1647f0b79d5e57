//! geode's studio server: `geode serve` opens a network in a live session and serves the browser studio (embedded in the binary) over HTTP and a WebSocket on loopback, behind a session token.
//!
//! Nothing depends on this crate but the CLI; it sits on graph, nodes and io.

mod cooker;
mod delta;
/// The document edits the studio sends (they live in `geode_graph::edit`).
pub use geode_graph::edit as edits;
mod hub;
mod info;
mod pick;
pub mod security;
pub mod session;
mod sheet;
mod studio;
mod vex_table;
pub mod viewport;

use geode_op::FileAccess;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use geode_graph::Cache;
use tokio::sync::broadcast::error::RecvError;

pub use session::Session;
pub use studio::Studio;

/// The largest message a studio may send (edits and requests are small;
/// a pasted network of a few hundred nodes fits).
pub const MAX_MESSAGE: usize = 1 << 20;

/// The studio's built front end (committed; CI checks it matches its sources).
mod assets {
    pub const INDEX: &[u8] = include_bytes!("../../../studio/dist/index.html");
    pub const JS: &[u8] = include_bytes!("../../../studio/dist/studio.js");
    pub const CSS: &[u8] = include_bytes!("../../../studio/dist/studio.css");
}

#[derive(Clone, Debug)]
pub struct Options {
    pub network: Option<PathBuf>,
    /// 0 picks a free port.
    pub port: u16,
    /// Loopback unless set explicitly.
    pub bind: Option<IpAddr>,
    /// The cook cache (the CLI's carries the disk cache); the environment's
    /// memory cache when none is given.
    pub cache: Option<Arc<Cache>>,
    /// Folders the studio may read and write files under besides the
    /// network's own (`--allow DIR`).
    pub allow: Vec<PathBuf>,
}

#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    #[error(transparent)]
    Session(#[from] session::SessionError),
    #[error("--allow {}: {source}", path.display())]
    Allow {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        source: std::io::Error,
    },
    #[error("cannot start the server's runtime: {0}")]
    Runtime(std::io::Error),
}

/// A running server.
pub struct Running {
    pub addr: SocketAddr,
    /// The address to open, token included.
    pub url: String,
    pub token: String,
    shutdown: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Running {
    /// Blocks until the server stops (it stops when dropped from another thread or on Ctrl-C).
    pub fn wait(mut self) {
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Some(s) = self.shutdown.take() {
            let _ = s.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

#[derive(Clone)]
struct App {
    studio: Arc<Studio>,
    catalogue: Arc<str>,
}

/// Opens the session and starts serving on a thread of its own.
pub fn start(opts: Options) -> Result<Running, ServeError> {
    let registry = Arc::new(geode_nodes::registry());
    let session = Session::open(opts.network.as_deref(), registry.clone())?;
    let files = confinement(opts.network.as_deref(), &opts.allow)?;
    let catalogue: Arc<str> = geode_graph::catalogue::catalogue(&registry)
        .to_string()
        .into();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(ServeError::Runtime)?;
    let ip = opts.bind.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    let addr = SocketAddr::new(ip, opts.port);
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(addr))
        .map_err(|source| ServeError::Bind { addr, source })?;
    let addr = listener
        .local_addr()
        .map_err(|source| ServeError::Bind { addr, source })?;
    let token = security::new_token();
    let guard = Arc::new(security::Guard::new(token.clone(), addr));
    let app = App {
        studio: Studio::new(
            session,
            opts.cache.unwrap_or_else(|| Arc::new(Cache::from_env())),
            files,
        ),
        catalogue,
    };
    let router = Router::new()
        .route("/", get(index))
        .route(
            "/studio.js",
            get(|| asset(assets::JS, "text/javascript; charset=utf-8")),
        )
        .route(
            "/studio.css",
            get(|| asset(assets::CSS, "text/css; charset=utf-8")),
        )
        .route("/api/catalogue", get(catalogue_json))
        .route("/api/vex", get(vex_table::vex_json))
        .route("/api/state", get(state_json))
        .route("/api/trace.json", get(trace_json))
        .route("/api/export", get(export))
        .route("/api/geometry", get(last_geometry))
        .route("/ws", get(socket))
        .layer(axum::middleware::from_fn_with_state(guard, security::guard))
        .with_state(app);
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("geode-serve".into())
        .spawn(move || {
            runtime.block_on(async move {
                let stop = async {
                    tokio::select! {
                        _ = rx => {}
                        _ = tokio::signal::ctrl_c() => {}
                    }
                };
                // Small messages (a frame's state, then its result) must not
                // wait for the previous one's acknowledgement: Nagle's
                // algorithm with delayed ACKs held each played frame ~200 ms.
                let listener = axum::serve::ListenerExt::tap_io(listener, |tcp| {
                    let _ = tcp.set_nodelay(true);
                });
                let _ = axum::serve(listener, router)
                    .with_graceful_shutdown(stop)
                    .await;
            });
            runtime.shutdown_background();
        })
        .map_err(ServeError::Runtime)?;
    // Bound to every address, this machine's own browser still comes by loopback.
    let host = if ip.is_loopback() || ip.is_unspecified() {
        "127.0.0.1".to_owned()
    } else {
        std::net::SocketAddr::new(addr.ip(), 0)
            .to_string()
            .trim_end_matches(":0")
            .to_owned()
    };
    Ok(Running {
        url: format!("http://{host}:{}/?token={token}", addr.port()),
        addr,
        token,
        shutdown: Some(tx),
        thread: Some(thread),
    })
}

async fn index(Query(q): Query<std::collections::HashMap<String, String>>) -> Response {
    let mut r = asset_response(assets::INDEX, "text/html; charset=utf-8");
    if let Some(t) = q.get("token") {
        // The page's assets and socket then carry the token without it in every URL.
        let cookie = format!(
            "{}={t}; HttpOnly; SameSite=Strict; Path=/",
            security::COOKIE
        );
        if let Ok(v) = header::HeaderValue::from_str(&cookie) {
            r.headers_mut().insert(header::SET_COOKIE, v);
        }
    }
    r
}

async fn asset(body: &'static [u8], mime: &'static str) -> Response {
    asset_response(body, mime)
}

fn asset_response(body: &'static [u8], mime: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, mime),
            (header::CACHE_CONTROL, "no-cache"),
            (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        ],
        body,
    )
        .into_response()
}

fn json_response(body: String) -> Response {
    ([(header::CONTENT_TYPE, "application/json")], body).into_response()
}

async fn catalogue_json(State(app): State<App>) -> Response {
    json_response(app.catalogue.to_string())
}

async fn state_json(State(app): State<App>) -> Response {
    json_response(app.studio.state().to_string())
}

async fn trace_json(State(app): State<App>) -> Response {
    let events = app.studio.hub.last().map(|l| l.events).unwrap_or_default();
    let mut r = json_response(hub::chrome_trace(&events).to_string());
    r.headers_mut().insert(
        header::CONTENT_DISPOSITION,
        header::HeaderValue::from_static("attachment; filename=\"geode-trace.json\""),
    );
    r
}

/// The viewed result in a file format, as a download (nothing is written
/// anywhere the user did not ask).
/// The whole geometry message of the last result (a page that missed the
/// base of a delta asks for it).
async fn last_geometry(State(app): State<App>) -> Response {
    match app.studio.hub.last_geometry() {
        Some(bytes) => {
            ([(header::CONTENT_TYPE, "application/octet-stream")], bytes).into_response()
        }
        None => (StatusCode::NOT_FOUND, "nothing drawn yet").into_response(),
    }
}

async fn export(
    State(app): State<App>,
    Query(q): Query<std::collections::HashMap<String, String>>,
) -> Response {
    let format = q
        .get("format")
        .map(String::as_str)
        .unwrap_or("glb")
        .to_owned();
    let last = app.studio.hub.last();
    let result = tokio::task::spawn_blocking(move || export_bytes(last, &format)).await;
    match result {
        Ok(Ok((name, bytes, warnings))) => (
            [
                (header::CONTENT_TYPE, "application/octet-stream".to_owned()),
                (
                    header::CONTENT_DISPOSITION,
                    format!("attachment; filename=\"{name}\""),
                ),
                (
                    header::HeaderName::from_static("x-geode-warnings"),
                    ascii_json(&warnings),
                ),
            ],
            Bytes::from(bytes),
        )
            .into_response(),
        Ok(Err(e)) => (StatusCode::BAD_REQUEST, e).into_response(),
        Err(_) => (StatusCode::INTERNAL_SERVER_ERROR, "the export failed").into_response(),
    }
}

/// What a writer warned of while exporting (an attribute a format left out).
#[derive(Default)]
struct ExportWarnings(std::sync::Mutex<Vec<String>>);

impl geode_io::Progress for ExportWarnings {
    fn warn(&self, message: &str) {
        self.0
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(message.to_owned());
    }
}

/// The viewed geometry encoded in memory: the file name, its bytes and the
/// writer's warnings. Nothing is written to disk.
fn export_bytes(
    last: Option<hub::Last>,
    format: &str,
) -> Result<(String, Vec<u8>, Vec<String>), String> {
    let last = last.ok_or("nothing has cooked yet")?;
    let Some(geode_op::Value::Geometry(g)) = &last.value else {
        return Err("the viewed node has no geometry to export (bundles: extract an entry)".into());
    };
    let name = format!(
        "{}.{format}",
        last.node.trim_start_matches('/').replace('/', "_")
    );
    let path = std::path::Path::new(&name);
    let fmt = geode_io::Format::from_path(path)
        .filter(|f| f.can_write())
        .ok_or_else(|| {
            let all: Vec<&str> = geode_io::Format::ALL
                .iter()
                .filter(|f| f.can_write())
                .map(|f| f.extension())
                .collect();
            format!("cannot export to `{format}` ({})", all.join(", "))
        })?;
    let warnings = ExportWarnings::default();
    let bytes = geode_io::write_bytes(g, fmt, path, &warnings).map_err(|e| e.to_string())?;
    let warnings = warnings.0.into_inner().unwrap_or_else(|p| p.into_inner());
    Ok((name, bytes, warnings))
}

/// JSON text with every non-ASCII character escaped, so it fits a header.
fn ascii_json(v: &impl serde::Serialize) -> String {
    let text = serde_json::to_string(v).unwrap_or_else(|_| "[]".into());
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{u:04x}"));
            }
        }
    }
    out
}

async fn socket(State(app): State<App>, ws: WebSocketUpgrade) -> Response {
    ws.max_message_size(MAX_MESSAGE)
        .max_frame_size(MAX_MESSAGE)
        .on_upgrade(move |s| talk(app.studio, s))
}

/// Where the studio's cooks and saves may touch files: the network's folder
/// (the current one without a network) and the `--allow` folders.
fn confinement(network: Option<&Path>, allow: &[PathBuf]) -> Result<FileAccess, ServeError> {
    let own = match network.and_then(Path::parent) {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    for dir in allow {
        if let Err(source) = dir.canonicalize() {
            return Err(ServeError::Allow {
                path: dir.clone(),
                source,
            });
        }
    }
    FileAccess::confined(std::iter::once(own.clone()).chain(allow.iter().cloned()))
        .map_err(|source| ServeError::Allow { path: own, source })
}

/// The `id` of a request, read from its text even when the rest of it is
/// not a request this server knows.
fn request_id(text: &str) -> Option<u64> {
    #[derive(serde::Deserialize)]
    struct Id {
        id: Option<u64>,
    }
    serde_json::from_str::<Id>(text).ok().and_then(|i| i.id)
}

/// A failed reply: the request's id, a kind and the message.
fn failed_reply(id: Option<u64>, kind: &str, message: String) -> serde_json::Value {
    serde_json::json!({"type": "reply", "id": id, "ok": false, "error": message, "kind": kind})
}

fn to_message(o: hub::Out) -> Message {
    match o {
        hub::Out::Text(t) => Message::Text(t.as_ref().into()),
        hub::Out::Binary(b) => Message::Binary(b),
    }
}

/// One studio's socket: the current state and last result first, then
/// requests in and broadcasts out until either side closes.
/// Numbers the sockets: each tab undoes its own edits.
static CLIENTS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

async fn talk(studio: Arc<Studio>, mut ws: WebSocket) {
    let client = CLIENTS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut rx = studio.hub.subscribe();
    let mut hello = vec![
        Message::Text(
            serde_json::json!({"type": "hello", "client": client})
                .to_string()
                .into(),
        ),
        Message::Text(studio.state().to_string().into()),
    ];
    if let Some(last) = studio.hub.last() {
        hello.extend(last.messages.into_iter().map(to_message));
    }
    for m in hello {
        if ws.send(m).await.is_err() {
            return;
        }
    }
    loop {
        tokio::select! {
            incoming = ws.recv() => {
                let Some(Ok(msg)) = incoming else { return };
                let reply = match msg {
                    Message::Text(t) => {
                        let s = studio.clone();
                        let text = t.to_string();
                        // Every reply carries the request's id, so the page's
                        // promise settles even for a request it got wrong.
                        let id = request_id(&text);
                        tokio::task::spawn_blocking(move || match serde_json::from_str::<studio::Envelope>(&text) {
                            Ok(env) => s.handle(env, client),
                            Err(e) => failed_reply(id, "protocol", format!("bad request: {e}")),
                        })
                        .await
                        .unwrap_or_else(|_| failed_reply(id, "internal", "the request failed".into()))
                    }
                    Message::Close(_) => return,
                    _ => continue,
                };
                if ws.send(Message::Text(reply.to_string().into())).await.is_err() {
                    return;
                }
            }
            out = rx.recv() => {
                let msg = match out {
                    Ok(o) => to_message(o),
                    // Too slow to keep up: catch up with the newest state and result.
                    Err(RecvError::Lagged(_)) => {
                        let mut catch_up = vec![Message::Text(studio.state().to_string().into())];
                        if let Some(last) = studio.hub.last() {
                            catch_up.extend(last.messages.into_iter().map(to_message));
                        }
                        let last = catch_up.pop().expect("one message at least");
                        for m in catch_up {
                            if ws.send(m).await.is_err() { return; }
                        }
                        last
                    }
                    Err(RecvError::Closed) => return,
                };
                if ws.send(msg).await.is_err() {
                    return;
                }
            }
        }
    }
}
