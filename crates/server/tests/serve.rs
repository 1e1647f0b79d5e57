//! `geode serve` over HTTP: security (the token on every request and on the socket, `Host` and `Origin` checks, bounded messages, loopback by default), export of the viewed node and the Chrome trace.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;

use geode_server::{start, Options, Running};
use tokio_tungstenite::tungstenite::{self, client::IntoClientRequest, http::HeaderValue, Message};

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn server() -> (Running, tempfile::TempDir) {
    server_on(None)
}

/// A studio on a copy of the primitives example, bound to `bind` (loopback by default).
fn server_on(bind: Option<std::net::IpAddr>) -> (Running, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let net = dir.path().join("primitives.json");
    std::fs::copy(example("primitives.json"), &net).unwrap();
    let running = start(Options {
        network: Some(net),
        port: 0,
        bind,
        cache: None,
        allow: Vec::new(),
    })
    .unwrap();
    (running, dir)
}

/// A raw HTTP/1.1 GET with the given headers; the status code and body.
fn get(r: &Running, path: &str, headers: &[(&str, String)]) -> (u16, String) {
    let (status, _, body) = get_with_head(r, path, headers);
    (status, body)
}

/// [`get`], with the response's head (status line and headers) too.
fn get_with_head(r: &Running, path: &str, headers: &[(&str, String)]) -> (u16, String, String) {
    let mut s = TcpStream::connect(r.addr).unwrap();
    let mut req = format!("GET {path} HTTP/1.1\r\nConnection: close\r\n");
    for (k, v) in headers {
        req.push_str(&format!("{k}: {v}\r\n"));
    }
    req.push_str("\r\n");
    s.write_all(req.as_bytes()).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let text = String::from_utf8_lossy(&out).into_owned();
    let status = text[9..12].parse().unwrap();
    let (head, body) = text.split_once("\r\n\r\n").unwrap_or((&text, ""));
    (status, head.to_owned(), body.to_owned())
}

fn host(r: &Running) -> (&'static str, String) {
    ("Host", format!("127.0.0.1:{}", r.addr.port()))
}

#[test]
fn the_default_address_is_loopback() {
    let (r, _d) = server();
    assert!(r.addr.ip().is_loopback());
    assert!(r.url.starts_with("http://127.0.0.1:"));
    assert!(r.url.contains(&format!("token={}", r.token)));
    assert_eq!(r.token.len(), 32);
}

#[test]
fn requests_without_the_right_token_are_refused() {
    let (r, _d) = server();
    let (status, body) = get(&r, "/", &[host(&r)]);
    assert_eq!(status, 401, "{body}");
    assert!(body.contains("token"));
    assert_eq!(
        get(&r, "/?token=0123456789abcdef0123456789abcdef", &[host(&r)]).0,
        401
    );
    assert_eq!(
        get(
            &r,
            "/api/catalogue",
            &[host(&r), ("X-Geode-Token", "nope".into())]
        )
        .0,
        401
    );
    assert_eq!(
        get(
            &r,
            "/api/state",
            &[host(&r), ("Cookie", "geode_token=wrong".into())]
        )
        .0,
        401
    );
    // The right token, three ways.
    assert_eq!(get(&r, &format!("/?token={}", r.token), &[host(&r)]).0, 200);
    assert_eq!(
        get(
            &r,
            "/api/catalogue",
            &[host(&r), ("X-Geode-Token", r.token.clone())]
        )
        .0,
        200
    );
    let (status, body) = get(
        &r,
        "/api/state",
        &[host(&r), ("Cookie", format!("geode_token={}", r.token))],
    );
    assert_eq!(status, 200);
    assert!(body.contains("\"document\""));
}

#[test]
fn foreign_hosts_and_origins_are_refused() {
    let (r, _d) = server();
    let auth = ("X-Geode-Token", r.token.clone());
    let port = r.addr.port();
    // DNS rebinding: the attacker's name resolving to 127.0.0.1.
    let (status, body) = get(
        &r,
        "/api/state",
        &[("Host", format!("evil.example:{port}")), auth.clone()],
    );
    assert_eq!(status, 403, "{body}");
    assert_eq!(
        get(&r, "/api/state", std::slice::from_ref(&auth)).0,
        403,
        "no Host at all"
    );
    let with_origin = |origin: String| {
        get(
            &r,
            "/api/state",
            &[host(&r), auth.clone(), ("Origin", origin)],
        )
    };
    let (status, body) = with_origin("http://evil.example".into());
    assert_eq!(status, 403, "{body}");
    assert_eq!(with_origin(format!("http://127.0.0.1:{}", port + 1)).0, 403);
    assert_eq!(with_origin(format!("http://localhost:{port}")).0, 200);
    assert_eq!(
        get(
            &r,
            "/api/state",
            &[("Host", format!("localhost:{port}")), auth]
        )
        .0,
        200
    );
}

fn ws_request(
    r: &Running,
    token: Option<&str>,
    origin: Option<&str>,
) -> tungstenite::handshake::client::Request {
    let url = match token {
        Some(t) => format!("ws://127.0.0.1:{}/ws?token={t}", r.addr.port()),
        None => format!("ws://127.0.0.1:{}/ws", r.addr.port()),
    };
    let mut req = url.into_client_request().unwrap();
    if let Some(o) = origin {
        req.headers_mut()
            .insert("Origin", HeaderValue::from_str(o).unwrap());
    }
    req
}

fn refused_status(e: tungstenite::Error) -> u16 {
    match e {
        tungstenite::Error::Http(resp) => resp.status().as_u16(),
        other => panic!("expected an HTTP refusal, got {other}"),
    }
}

#[test]
fn the_socket_needs_the_token_and_the_studio_origin() {
    let (r, _d) = server();
    let connect = |req| {
        tungstenite::connect(req)
            .map(|_| ())
            .map_err(refused_status)
    };
    assert_eq!(connect(ws_request(&r, None, None)), Err(401));
    assert_eq!(connect(ws_request(&r, Some("bad"), None)), Err(401));
    assert_eq!(
        connect(ws_request(&r, Some(&r.token), Some("http://evil.example"))),
        Err(403)
    );
    let own = format!("http://127.0.0.1:{}", r.addr.port());
    let (mut ws, _) = tungstenite::connect(ws_request(&r, Some(&r.token), Some(&own))).unwrap();
    // The first messages are the tab's number and the session's state.
    let first = ws.read().unwrap();
    assert!(first.to_text().unwrap().contains("\"type\":\"hello\""));
    let second = ws.read().unwrap();
    assert!(second.to_text().unwrap().contains("\"type\":\"state\""));
}

#[test]
fn an_oversized_message_closes_the_socket_unanswered() {
    let (r, _d) = server();
    let (mut ws, _) = tungstenite::connect(ws_request(&r, Some(&r.token), None)).unwrap();
    let big = format!(
        r#"{{"op":"edit","id":1,"edit":{{"kind":"set_param","path":"/box","param":"size","value":"{}"}}}}"#,
        "x".repeat(geode_server::MAX_MESSAGE + 1)
    );
    let _ = ws.send(Message::text(big));
    loop {
        match ws.read() {
            Ok(Message::Text(t)) => assert!(
                !t.contains("\"type\":\"reply\""),
                "the oversized request was answered: {t}"
            ),
            Ok(Message::Close(_)) | Err(_) => break,
            Ok(_) => {}
        }
    }
    // The session is untouched.
    let (status, body) = get(
        &r,
        "/api/state",
        &[host(&r), ("X-Geode-Token", r.token.clone())],
    );
    assert_eq!(status, 200);
    assert!(!body.contains("xxxxxxxx"));
}

/// Reads messages until the reply to request `id`.
fn reply_to(
    ws: &mut tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<std::net::TcpStream>>,
    id: u64,
) -> serde_json::Value {
    loop {
        if let Message::Text(t) = ws.read().unwrap() {
            let v: serde_json::Value = serde_json::from_str(&t).unwrap();
            if v["type"] == "reply" && v["id"] == id {
                return v;
            }
        }
    }
}

#[test]
fn a_request_the_server_cannot_read_is_answered_under_its_id() {
    let (r, _d) = server();
    let (mut ws, _) = tungstenite::connect(ws_request(&r, Some(&r.token), None)).unwrap();
    ws.send(Message::text(r#"{"op":"no_such_op","id":41}"#))
        .unwrap();
    let reply = reply_to(&mut ws, 41);
    assert_eq!(reply["ok"], false);
    assert_eq!(reply["kind"], "protocol");
    assert!(
        reply["error"]
            .as_str()
            .unwrap()
            .starts_with("bad request: "),
        "{reply}"
    );
    ws.send(Message::text(
        r#"{"op":"edit","id":42,"edit":{"kind":"set_param","path":"/box","param":7}}"#,
    ))
    .unwrap();
    assert_eq!(reply_to(&mut ws, 42)["kind"], "protocol");
}

/// Waits until the session's first cook is done (its trace has spans).
fn cooked(r: &Running) -> serde_json::Value {
    let auth = [host(r), ("X-Geode-Token", r.token.clone())];
    for _ in 0..600 {
        let (status, body) = get(r, "/api/trace.json", &auth);
        assert_eq!(status, 200);
        let trace: serde_json::Value = serde_json::from_str(&body).unwrap();
        if trace["traceEvents"]
            .as_array()
            .is_some_and(|e| !e.is_empty())
        {
            return trace;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    panic!("the first cook did not finish in a minute");
}

#[test]
fn the_trace_names_every_node_of_the_cook() {
    let (r, _d) = server();
    let trace = cooked(&r);
    let names: Vec<&str> = trace["traceEvents"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    for node in ["/ring", "/spin", "/all", "/out"] {
        assert!(names.contains(&node), "{node} missing from {names:?}");
    }
    assert!(trace["traceEvents"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e["ph"] == "X" && e["dur"].as_f64().unwrap() >= 0.0));
}

#[test]
fn export_downloads_the_viewed_node_in_the_asked_format() {
    let (r, dir) = server();
    cooked(&r);
    let auth = [host(&r), ("X-Geode-Token", r.token.clone())];
    let (status, body) = get(&r, "/api/export?format=obj", &auth);
    assert_eq!(status, 200);
    let vertices = body.lines().filter(|l| l.starts_with("v ")).count();
    assert!(vertices > 100, "{vertices} vertices");
    let (status, body) = get(&r, "/api/export?format=xyz", &auth);
    assert_eq!(status, 400);
    assert_eq!(
        body,
        "cannot export to `xyz` (obj, stl, ply, glb, usda, geo, bgeo)"
    );
    // Houdini's formats too; a writer's warnings come in a header.
    let (status, _, body) = get_with_head(&r, "/api/export?format=geo", &auth);
    assert_eq!(status, 200);
    assert!(
        body.contains("\"pointcount\""),
        "{}",
        &body[..200.min(body.len())]
    );
    let (status, head, _) = get_with_head(&r, "/api/export?format=ply", &auth);
    assert_eq!(status, 200);
    let warnings = head
        .lines()
        .find_map(|l| l.strip_prefix("x-geode-warnings: "))
        .expect("a warnings header");
    let warnings: Vec<String> = serde_json::from_str(warnings).unwrap();
    assert_eq!(
        warnings,
        vec!["out.ply: PLY cannot hold primitive group `cap`; not written"]
    );
    // Nothing was written beside the network.
    let files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(files, vec![std::ffi::OsString::from("primitives.json")]);
}

#[test]
fn bound_beyond_loopback_it_answers_ip_hosts_but_not_names() {
    let (r, _d) = server_on(Some("0.0.0.0".parse().unwrap()));
    let port = r.addr.port();
    let auth = ("X-Geode-Token", r.token.clone());
    let status = |h: String| get(&r, "/api/state", &[("Host", h), auth.clone()]).0;
    assert_eq!(status(format!("192.0.2.7:{port}")), 200);
    assert_eq!(status(format!("[2001:db8::1]:{port}")), 200);
    assert_eq!(status(format!("192.0.2.7:{}", port + 1)), 403);
    assert_eq!(status(format!("evil.example:{port}")), 403);
    assert_eq!(
        get(&r, "/api/state", &[("Host", format!("192.0.2.7:{port}"))]).0,
        401
    );
}

#[test]
fn a_file_that_is_not_json_is_refused_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let net = dir.path().join("bad.json");
    std::fs::write(&net, "{\"geode\": \"network\",\n \"version\": }").unwrap();
    let e = start(Options {
        network: Some(net.clone()),
        port: 0,
        bind: None,
        cache: None,
        allow: Vec::new(),
    })
    .err()
    .unwrap();
    assert_eq!(
        e.to_string(),
        format!("{}: line 2, column 13: expected value", net.display())
    );
    assert!(
        std::error::Error::source(&e).is_none(),
        "the cause is printed once"
    );
}

/// A message reduced to its shape: numbers 0, free text empty (the `type`,
/// `kind`, `level` and `name` tags kept), an array's distinct element shapes sorted
/// (vectors and tuples of numbers keep their length).
fn shape(v: &serde_json::Value, key: &str) -> serde_json::Value {
    use serde_json::Value as J;
    match v {
        J::Number(_) => J::from(0),
        J::String(s) if ["type", "kind", "level", "name"].contains(&key) => J::String(s.clone()),
        J::String(_) => J::String(String::new()),
        J::Array(items) => {
            let mut shapes: Vec<J> = items.iter().map(|x| shape(x, key)).collect();
            if items.iter().all(|x| x.is_number() || x.is_array()) {
                return J::Array(shapes); // a vector or tuple: its length is its type
            }
            shapes.sort_by_key(|x| x.to_string());
            shapes.dedup();
            J::Array(shapes)
        }
        J::Object(m) => J::Object(m.iter().map(|(k, x)| (k.clone(), shape(x, k))).collect()),
        other => other.clone(),
    }
}

/// Reads messages until one of `ty` that `pick` accepts.
fn next_of(
    ws: &mut tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<std::net::TcpStream>>,
    ty: &str,
    pick: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    loop {
        if let Message::Text(t) = ws.read().unwrap() {
            let v: serde_json::Value = serde_json::from_str(&t).unwrap();
            if v["type"] == ty && pick(&v) {
                return v;
            }
        }
    }
}

/// The server's messages, as real cooks and edits produce them, written as
/// typed constants of studio/src/protocol.ts: `tsc` (the studio's lint)
/// then checks every field both ways (a field the page does not declare is
/// an excess property, one it requires and the server does not send is
/// missing). Set GEODE_BLESS=1 to rewrite the file after a protocol change.
#[test]
fn the_page_declares_exactly_the_fields_the_server_sends() {
    let (r, _d) = server();
    let (mut ws, _) = tungstenite::connect(ws_request(&r, Some(&r.token), None)).unwrap();
    let hello = next_of(&mut ws, "hello", |_| true);
    let state = next_of(&mut ws, "state", |_| true);
    let cooked = next_of(&mut ws, "cooked", |v| v["ok"] == true);
    ws.send(Message::text(
        r#"{"op":"edit","id":1,"edit":{"kind":"set_param","path":"/top","param":"expression","value":"y > "}}"#,
    ))
    .unwrap();
    let applied = reply_to(&mut ws, 1);
    let failed = next_of(&mut ws, "cooked", |v| v["ok"] == false);
    assert_eq!(failed["errors"][0]["column"], 5, "{failed}");
    ws.send(Message::text(
        r#"{"op":"edit","id":2,"edit":{"kind":"set_param","path":"/nope","param":"x","value":1}}"#,
    ))
    .unwrap();
    let refused = reply_to(&mut ws, 2);
    assert_eq!(refused["kind"], "edit");
    assert_eq!(refused["path"], "/nope");
    let (_, body) = get(
        &r,
        "/api/catalogue",
        &[host(&r), ("X-Geode-Token", r.token.clone())],
    );
    let catalogue: serde_json::Value = serde_json::from_str(&body).unwrap();
    let nodes = catalogue["nodes"].as_array().unwrap();
    let has = |n: &serde_json::Value, ty: &str| {
        n["params"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p["type"] == ty)
    };
    // One node type of each kind of declaration the page reads.
    let picks: Vec<serde_json::Value> = [
        nodes.iter().find(|n| n["network"] == true),
        nodes.iter().find(|n| has(n, "menu")),
        nodes.iter().find(|n| has(n, "list")),
        nodes.iter().find(|n| {
            n["params"]
                .as_array()
                .unwrap()
                .iter()
                .any(|p| p["code"] == true)
        }),
    ]
    .into_iter()
    .map(|n| shape(n.expect("a node type of each kind"), ""))
    .collect();
    let constant = |name: &str, ty: &str, v: &serde_json::Value| {
        format!(
            "export const {name}: {ty} = {};\n",
            serde_json::to_string_pretty(v).unwrap()
        )
    };
    let text = [
        "// Generated by crates/server/tests/serve.rs from the server's real messages (shapes only): tsc checks them against protocol.ts.\n\nimport type { CookedMsg, HelloMsg, NodeType, ReplyMsg, StateMsg } from '../src/protocol';\n\n".to_string(),
        constant("hello", "HelloMsg", &shape(&hello, "")),
        constant("state", "StateMsg", &shape(&state, "")),
        constant("cooked", "CookedMsg", &shape(&cooked, "")),
        constant("failed", "CookedMsg", &shape(&failed, "")),
        constant("applied", "ReplyMsg", &shape(&applied, "")),
        constant("refused", "ReplyMsg", &shape(&refused, "")),
        constant("nodeTypes", "NodeType[]", &serde_json::Value::Array(picks)),
    ]
    .join("\n");
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../studio/tests/protocol.fixture.ts");
    if std::env::var_os("GEODE_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "studio/tests/protocol.fixture.ts is not what the server sends: rerun with GEODE_BLESS=1, then `cd studio && npm run lint`\n{text}"
    );
}

/// A studio on `network` (text) in a fresh folder, with `allow` folders.
fn server_with(network: &str, allow: Vec<PathBuf>) -> (Running, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let net = dir.path().join("net.json");
    std::fs::write(&net, network).unwrap();
    let running = start(Options {
        network: Some(net),
        port: 0,
        bind: None,
        cache: None,
        allow,
    })
    .unwrap();
    (running, dir)
}

type Socket = tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<std::net::TcpStream>>;

/// Views `node` and returns its cook's errors (empty when it cooked).
fn view_errors(ws: &mut Socket, id: u64, node: &str) -> Vec<serde_json::Value> {
    ws.send(Message::text(format!(
        r#"{{"op":"view","id":{id},"node":"{node}"}}"#
    )))
    .unwrap();
    let cooked = next_of(ws, "cooked", |v| v["node"] == node);
    cooked["errors"].as_array().unwrap().clone()
}

#[test]
fn the_studio_touches_files_only_under_its_folders() {
    let outside = tempfile::tempdir().unwrap();
    let secret = outside.path().join("secret.obj");
    std::fs::write(&secret, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let allowed = tempfile::tempdir().unwrap();
    let shared = allowed.path().join("shared.obj");
    std::fs::copy(&secret, &shared).unwrap();
    let network = format!(
        r#"{{"geode": "network", "version": 1, "nodes": {{
        "own": {{"type": "file", "params": {{"file": "$HIP/own.obj"}}}},
        "secret": {{"type": "file", "params": {{"file": {secret:?}}}}},
        "shared": {{"type": "file", "params": {{"file": {shared:?}}}}},
        "zero": {{"type": "file", "params": {{"file": "$HIP/zero.obj"}}}},
        "out": {{"type": "write", "inputs": ["own"], "params": {{"file": {:?}}}}}}}}}"#,
        outside.path().join("written.obj")
    );
    let (r, dir) = server_with(&network, vec![allowed.path().to_owned()]);
    std::fs::copy(&secret, dir.path().join("own.obj")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.obj")).unwrap();
    let (mut ws, _) = tungstenite::connect(ws_request(&r, Some(&r.token), None)).unwrap();
    assert_eq!(
        view_errors(&mut ws, 1, "/own"),
        Vec::<serde_json::Value>::new()
    );
    assert_eq!(
        view_errors(&mut ws, 2, "/shared"),
        Vec::<serde_json::Value>::new()
    );
    let e = &view_errors(&mut ws, 3, "/secret")[0];
    assert_eq!((&e["kind"], &e["param"]), (&"io".into(), &"file".into()));
    assert!(
        e["message"]
            .as_str()
            .unwrap()
            .contains("outside the folders this studio may read"),
        "{e}"
    );
    let started = std::time::Instant::now();
    let e = &view_errors(&mut ws, 4, "/zero")[0];
    let message = e["message"].as_str().unwrap();
    assert!(
        message.contains("zero.obj (which leads to /dev/zero): outside the folders"),
        "{e}"
    );
    assert!(started.elapsed().as_secs() < 10);
    let e = &view_errors(&mut ws, 5, "/out")[0];
    assert!(
        e["message"]
            .as_str()
            .unwrap()
            .contains("outside the folders this studio may write"),
        "{e}"
    );
    assert!(!outside.path().join("written.obj").exists());
    // Save As is confined too; inside, it writes.
    let away = outside.path().join("copy.json");
    ws.send(Message::text(format!(
        r#"{{"op":"save","id":6,"path":{away:?}}}"#
    )))
    .unwrap();
    let reply = reply_to(&mut ws, 6);
    assert_eq!(
        (reply["ok"].clone(), reply["kind"].clone()),
        (false.into(), "io".into()),
        "{reply}"
    );
    assert!(!away.exists());
    let near = allowed.path().join("copy.json");
    ws.send(Message::text(format!(
        r#"{{"op":"save","id":7,"path":{near:?}}}"#
    )))
    .unwrap();
    assert_eq!(reply_to(&mut ws, 7)["ok"], true);
    assert!(near.exists());
}
