//! Who may talk to the studio: a random session token on every request and socket (as Jupyter's), `Host` checked against the addresses served (no DNS rebinding), `Origin` against the studio's own (no cross-site requests).

use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

/// The cookie the studio page sets so that its assets and socket carry the token.
pub const COOKIE: &str = "geode_token";

/// What requests must show.
#[derive(Clone, Debug)]
pub struct Guard {
    pub token: String,
    /// `host:port` values the `Host` header may take.
    pub hosts: Vec<String>,
    /// Bound beyond loopback (`--bind`): any IP literal with this port is
    /// also a valid `Host`/`Origin` (rebinding needs a domain name, so IP
    /// literals stay safe).
    ip_hosts: Option<u16>,
}

/// A token of 128 random bits, as hex.
pub fn new_token() -> String {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).expect("the operating system gives random bytes");
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Equal strings in time independent of where they differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

impl Guard {
    /// Loopback names for `port` (and the bound address when it is another).
    pub fn new(token: String, bound: std::net::SocketAddr) -> Guard {
        let port = bound.port();
        let mut hosts = vec![
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ];
        let own = bound.to_string();
        if !hosts.contains(&own) {
            hosts.push(own);
        }
        let ip_hosts = (!bound.ip().is_loopback()).then_some(port);
        Guard {
            token,
            hosts,
            ip_hosts,
        }
    }

    /// Whether `host` (a `Host` value or an origin without its scheme) names this studio.
    fn is_own(&self, host: &str) -> bool {
        self.hosts.iter().any(|ok| ok.eq_ignore_ascii_case(host))
            || self.ip_hosts.is_some_and(|port| {
                host.parse::<std::net::SocketAddr>()
                    .is_ok_and(|a| a.port() == port)
            })
    }

    fn token_in(&self, headers: &HeaderMap, query: Option<&str>) -> bool {
        let from_query = query
            .into_iter()
            .flat_map(|q| q.split('&'))
            .filter_map(|kv| kv.strip_prefix("token="));
        let from_header = headers
            .get("x-geode-token")
            .and_then(|v| v.to_str().ok())
            .into_iter();
        let from_cookie = headers
            .get_all(header::COOKIE)
            .iter()
            .filter_map(|v| v.to_str().ok())
            .flat_map(|c| c.split(';'))
            .filter_map(|kv| {
                kv.trim()
                    .strip_prefix(COOKIE)
                    .and_then(|r| r.strip_prefix('='))
            });
        from_query
            .chain(from_header)
            .chain(from_cookie)
            .any(|t| same(t, &self.token))
    }

    /// Why a request is refused, if it is.
    pub fn check(
        &self,
        headers: &HeaderMap,
        query: Option<&str>,
    ) -> Result<(), (StatusCode, &'static str)> {
        let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
        if !host.is_some_and(|h| self.is_own(h)) {
            return Err((
                StatusCode::FORBIDDEN,
                "refused: the Host header is not this studio's address",
            ));
        }
        if let Some(origin) = headers.get(header::ORIGIN) {
            let ok = origin.to_str().ok().and_then(|o| o.strip_prefix("http://"));
            if !ok.is_some_and(|o| self.is_own(o)) {
                return Err((StatusCode::FORBIDDEN, "refused: cross-origin request"));
            }
        }
        if !self.token_in(headers, query) {
            return Err((StatusCode::UNAUTHORIZED, "refused: this studio needs the token printed when it started (open the URL `geode serve` printed)"));
        }
        Ok(())
    }
}

/// Middleware: every request passes the guard or is refused.
pub async fn guard(State(g): State<std::sync::Arc<Guard>>, req: Request, next: Next) -> Response {
    match g.check(req.headers(), req.uri().query()) {
        Ok(()) => next.run(req).await,
        Err((status, why)) => (status, why).into_response(),
    }
}
