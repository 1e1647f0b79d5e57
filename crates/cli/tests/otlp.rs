//! With the `otlp` feature, cook spans reach an OpenTelemetry collector over
//! OTLP/HTTP. A stand-in collector on the loopback interface receives them.
#![cfg(feature = "otlp")]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::path::Path;
use std::process::Command;

#[test]
fn cook_spans_are_exported_over_otlp_http() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let url = format!("http://{}/v1/traces", listener.local_addr().unwrap());
    let collector = std::thread::spawn(move || {
        let mut bodies = Vec::new();
        listener.set_nonblocking(false).unwrap();
        // Spans are exported one request at a time (simple exporter): read a few.
        for _ in 0..64 {
            let (stream, _) = match listener.accept() {
                Ok(s) => s,
                Err(_) => break,
            };
            stream
                .set_read_timeout(Some(std::time::Duration::from_secs(5)))
                .unwrap();
            let mut reader = BufReader::new(stream.try_clone().unwrap());
            let mut request_line = String::new();
            reader.read_line(&mut request_line).unwrap();
            let mut length = 0usize;
            let mut content_type = String::new();
            loop {
                let mut h = String::new();
                reader.read_line(&mut h).unwrap();
                let h = h.trim_end();
                if h.is_empty() {
                    break;
                }
                let lower = h.to_ascii_lowercase();
                if let Some(v) = lower.strip_prefix("content-length:") {
                    length = v.trim().parse().unwrap();
                }
                if let Some(v) = lower.strip_prefix("content-type:") {
                    content_type = v.trim().to_owned();
                }
            }
            let mut body = vec![0u8; length];
            reader.read_exact(&mut body).unwrap();
            let mut s = stream;
            s.write_all(b"HTTP/1.1 200 OK\r\ncontent-type: application/x-protobuf\r\ncontent-length: 0\r\n\r\n").unwrap();
            bodies.push((request_line, content_type, body));
            if bodies.iter().map(|b| b.2.len()).sum::<usize>() > 0 && bodies.len() >= 9 {
                break;
            }
        }
        bodies
    });
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = Command::new(env!("CARGO_BIN_EXE_geode"))
        .args(["--otlp", &url, "cook", "examples/primitives.json"])
        .env("GEODE_CACHE", "off")
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bodies = collector.join().unwrap();
    assert!(!bodies.is_empty(), "the collector received no export");
    let all: Vec<u8> = bodies.iter().flat_map(|b| b.2.clone()).collect();
    for (line, ctype, _) in &bodies {
        assert!(line.starts_with("POST /v1/traces"), "{line}");
        assert_eq!(ctype, "application/x-protobuf");
    }
    // The protobuf carries the span name and the node paths as strings.
    let text = String::from_utf8_lossy(&all);
    for needle in ["cook", "/ring", "/out", "geode"] {
        assert!(text.contains(needle), "`{needle}` not exported");
    }
}
