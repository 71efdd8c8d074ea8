//! The HTTP side: a fixed pool of threads answers the requests that
//! tiny_http reads (behind the gate, which bounds connections and hands
//! on one complete request head a connection). Every request is checked
//! before it is routed: the size of the request, the method, a plain
//! path, and the token; a handler that panics answers 500 and the server
//! goes on. Event streams get a thread each, up to a bound.

use super::events::format;
use super::routes::{Reply, route, text};
use super::state::{Shared, state_json};
use std::io::Write;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// Threads answering requests.
pub(crate) const WORKERS: usize = 8;
/// Event streams open at once at most (503 past them).
pub(crate) const MAX_STREAMS: usize = 16;
/// The longest URL taken (414 past it).
pub(crate) const MAX_URL: usize = 4096;
/// The most header bytes taken (431 past them).
pub(crate) const MAX_HEADERS: usize = 16 << 10;
/// A comment is sent on an idle event stream this often, to notice a
/// page that went away.
const KEEP_ALIVE: Duration = Duration::from_secs(10);

/// What the request threads share.
pub(crate) struct App {
    /// The state.
    pub shared: Arc<Shared>,
    /// The token every request must carry.
    pub token: String,
    /// The server.
    pub server: tiny_http::Server,
    /// Event streams open now.
    streams: AtomicUsize,
}

impl App {
    /// The request side of `shared`, served by `server`, guarded by `token`.
    pub fn new(shared: Arc<Shared>, token: String, server: tiny_http::Server) -> App {
        App {
            shared,
            token,
            server,
            streams: AtomicUsize::new(0),
        }
    }
}

/// Answers requests for ever on this thread.
pub(crate) fn serve_loop(app: &Arc<App>) {
    loop {
        match app.server.recv() {
            // A panic drops the request (tiny_http answers 500); the thread goes on.
            Ok(rq) => {
                let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| handle(app, rq)));
            }
            Err(_) => std::thread::sleep(Duration::from_millis(10)),
        }
    }
}

/// Whether two strings are equal, in time that does not depend on where they differ.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// `%XX` and `+` decoded; `None` for a bad escape or text that is not UTF-8.
pub(crate) fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' => {
                let hex = bytes.get(i + 1..i + 3)?;
                let hex = std::str::from_utf8(hex).ok()?;
                out.push(u8::from_str_radix(hex, 16).ok()?);
                i += 3;
            }
            b'+' => {
                out.push(b' ');
                i += 1;
            }
            b => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok()
}

/// The query's pairs, decoded (`None`: a bad escape).
pub(crate) fn parse_query(query: &str) -> Option<Vec<(String, String)>> {
    query
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (k, v) = p.split_once('=').unwrap_or((p, ""));
            Some((percent_decode(k)?, percent_decode(v)?))
        })
        .collect()
}

/// What a request is answered with, from its method, URL, header size and
/// token header, before any state is read: `Err` for a refusal.
pub(crate) fn check(
    token: &str,
    method: &str,
    url: &str,
    header_bytes: usize,
    body: bool,
    token_header: Option<&str>,
) -> Result<(String, Vec<(String, String)>), Reply> {
    if url.len() > MAX_URL {
        return Err(text(414, "URI too long"));
    }
    if header_bytes > MAX_HEADERS {
        return Err(text(431, "request header fields too large"));
    }
    if body {
        return Err(text(
            413,
            "payload too large: the API takes no request body",
        ));
    }
    if method != "GET" && method != "HEAD" {
        return Err(text(405, "method not allowed: the API is GET only"));
    }
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    let Some(query) = parse_query(query) else {
        return Err(text(400, "bad request: a bad %-escape in the query"));
    };
    let given = token_header.or_else(|| super::routes::param(&query, "token"));
    if !given.is_some_and(|t| same(t, token)) {
        return Err(text(
            403,
            "forbidden: this page needs the token of the URL glint serve printed",
        ));
    }
    let plain = path.starts_with('/')
        && !path.contains("..")
        && !path.contains("//")
        && !path.contains(['%', '\\', '\0']);
    if !plain {
        return Err(text(
            400,
            "bad request: the path must be plain (no `..`, `%`, `\\` or `//`)",
        ));
    }
    Ok((path.to_string(), query))
}

/// Answers one request.
fn handle(app: &Arc<App>, rq: tiny_http::Request) {
    let header_bytes: usize = rq
        .headers()
        .iter()
        .map(|h| h.field.as_str().as_str().len() + h.value.as_str().len() + 4)
        .sum();
    let token_header = rq
        .headers()
        .iter()
        .find(|h| h.field.equiv("X-Glint-Token"))
        .map(|h| h.value.as_str().to_string());
    let body = rq.body_length().is_some_and(|n| n > 0)
        || rq
            .headers()
            .iter()
            .any(|h| h.field.equiv("Transfer-Encoding"));
    let method = rq.method().as_str().to_string();
    let checked = check(
        &app.token,
        &method,
        rq.url(),
        header_bytes,
        body,
        token_header.as_deref(),
    );
    let (path, query) = match checked {
        Ok(c) => c,
        Err(reply) => return respond(rq, reply),
    };
    let shared = app.shared.clone();
    let token = app.token.clone();
    let reply = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        route(&shared, &token, &path, &query)
    }))
    .unwrap_or_else(|_| text(500, "internal error (a bug in glint); the server goes on"));
    match reply {
        Reply::Events => stream(app, rq),
        reply => respond(rq, reply),
    }
}

/// A header made of two ASCII strings (they all are, here).
fn header(field: &str, value: &str) -> Option<tiny_http::Header> {
    tiny_http::Header::from_bytes(field.as_bytes(), value.as_bytes()).ok()
}

/// Sends `reply` (the gate adds `Connection: close`: tiny_http drops it).
fn respond(rq: tiny_http::Request, reply: Reply) {
    let Reply::Done(status, kind, body) = reply else {
        return;
    };
    let bytes = body.bytes();
    let mut response = tiny_http::Response::new(
        tiny_http::StatusCode(status),
        Vec::new(),
        bytes,
        Some(bytes.len()),
        None,
    );
    let headers = [
        ("Content-Type", kind),
        ("Cache-Control", "no-store"),
        ("X-Content-Type-Options", "nosniff"),
        ("Referrer-Policy", "no-referrer"),
        (
            "Content-Security-Policy",
            "default-src 'self'; img-src 'self' data: blob:; connect-src 'self'; frame-ancestors 'none'",
        ),
    ];
    for (f, v) in headers {
        if let Some(h) = header(f, v) {
            response.add_header(h);
        }
    }
    // A client that went away is no error of ours.
    let _ = rq.respond(response);
}

/// Keeps an event stream open on a thread of its own: the state and the
/// current picture (a `frame` event) first, then every event until the page goes away.
fn stream(app: &Arc<App>, rq: tiny_http::Request) {
    if app.streams.fetch_add(1, Ordering::SeqCst) >= MAX_STREAMS {
        app.streams.fetch_sub(1, Ordering::SeqCst);
        return respond(rq, text(503, "too many event streams"));
    }
    let app = app.clone();
    let spawned = std::thread::Builder::new()
        .name("glint-events".to_string())
        .spawn({
            let app = app.clone();
            move || {
                let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_stream(&app, rq);
                }));
                app.streams.fetch_sub(1, Ordering::SeqCst);
            }
        });
    if spawned.is_err() {
        app.streams.fetch_sub(1, Ordering::SeqCst);
    }
}

fn run_stream(app: &App, rq: tiny_http::Request) {
    let events = app.shared.events.subscribe();
    let (state, picture) = {
        let s = app.shared.lock();
        (
            state_json(&s, &app.shared).to_string(),
            s.picture.as_ref().map(|p| p.summary().to_string()),
        )
    };
    let mut w = rq.into_writer();
    let mut first = String::from(
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
         X-Content-Type-Options: nosniff\r\n\r\nretry: 500\n\n",
    );
    first.push_str(&format("state", &state));
    if let Some(p) = picture {
        first.push_str(&format("frame", &p));
    }
    if w.write_all(first.as_bytes())
        .and_then(|()| w.flush())
        .is_err()
    {
        return;
    }
    loop {
        let event = match events.recv_timeout(KEEP_ALIVE) {
            Ok(e) => e,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => ": alive\n\n".to_string(),
            // Dropped for falling behind: the page reconnects.
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => return,
        };
        if w.write_all(event.as_bytes())
            .and_then(|()| w.flush())
            .is_err()
        {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(r: Result<(String, Vec<(String, String)>), Reply>) -> u16 {
        match r {
            Ok(_) => 200,
            Err(Reply::Done(s, _, _)) => s,
            Err(Reply::Events) => 0,
        }
    }

    #[test]
    fn requests_are_checked_before_they_are_routed() {
        let t = "abc123";
        let ok = |url: &str| status(check(t, "GET", url, 100, false, None));
        assert_eq!(ok("/api/state?token=abc123"), 200);
        assert_eq!(ok("/api/state"), 403);
        assert_eq!(ok("/api/state?token=abc124"), 403);
        assert_eq!(ok("/api/state?token=abc12"), 403);
        assert_eq!(ok("/../etc/passwd?token=abc123"), 400);
        assert_eq!(ok("/api/file/%2e%2e?token=abc123"), 400);
        assert_eq!(ok("/api//file?token=abc123"), 400);
        assert_eq!(ok("/api/state?token=%zz"), 400);
        assert_eq!(
            ok(&format!("/?token=abc123&x={}", "a".repeat(MAX_URL))),
            414
        );
        assert_eq!(
            status(check(t, "POST", "/?token=abc123", 100, false, None)),
            405
        );
        assert_eq!(
            status(check(t, "GET", "/?token=abc123", 100, true, None)),
            413
        );
        assert_eq!(
            status(check(
                t,
                "GET",
                "/?token=abc123",
                MAX_HEADERS + 1,
                false,
                None
            )),
            431
        );
        assert_eq!(
            status(check(t, "GET", "/", 100, false, Some("abc123"))),
            200
        );
    }

    #[test]
    fn queries_are_decoded_and_bad_escapes_refused() {
        assert_eq!(
            parse_query("a=1&b=x%2Fy+z&c"),
            Some(vec![
                ("a".into(), "1".into()),
                ("b".into(), "x/y z".into()),
                ("c".into(), String::new())
            ])
        );
        assert_eq!(parse_query("a=%4"), None);
        assert_eq!(parse_query("a=%ff"), None);
        assert_eq!(percent_decode("%41%42"), Some("AB".to_string()));
    }
}
