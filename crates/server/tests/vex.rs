//! `GET /api/vex`, the wrangle function table the studio completes from: behind the session token like every route, and the same table geode-vex checks against its resolver.

use std::io::{Read, Write};
use std::net::TcpStream;

use geode_server::{start, Options, Running};

/// A raw HTTP/1.1 GET from loopback with the server's own `Host`; the status and body.
fn get(r: &Running, path: &str, token: Option<&str>) -> (u16, String) {
    let mut s = TcpStream::connect(r.addr).unwrap();
    let mut req = format!(
        "GET {path} HTTP/1.1\r\nConnection: close\r\nHost: 127.0.0.1:{}\r\n",
        r.addr.port()
    );
    if let Some(t) = token {
        req.push_str(&format!("X-Geode-Token: {t}\r\n"));
    }
    req.push_str("\r\n");
    s.write_all(req.as_bytes()).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let text = String::from_utf8_lossy(&out).into_owned();
    let status = text[9..12].parse().unwrap();
    let body = text
        .split_once("\r\n\r\n")
        .map(|x| x.1.to_owned())
        .unwrap_or_default();
    (status, body)
}

#[test]
fn the_function_table_is_served_with_the_token_only() {
    let r = start(Options {
        network: None,
        port: 0,
        bind: None,
        cache: None,
        allow: Vec::new(),
    })
    .unwrap();
    assert_eq!(get(&r, "/api/vex", None).0, 401);
    assert_eq!(get(&r, "/api/vex", Some("wrong")).0, 401);
    let (status, body) = get(&r, "/api/vex", Some(&r.token));
    assert_eq!(status, 200, "{body}");
    let table: serde_json::Value = serde_json::from_str(&body).unwrap();
    let functions = table["functions"].as_array().unwrap();
    assert_eq!(functions.len(), geode_nodes::vex_signatures().len());
    let noise = functions.iter().find(|f| f["name"] == "noise").unwrap();
    assert_eq!(noise["display"], "float noise(<float|vector> pos)");
}
