//! The door in front of the HTTP server. tiny_http neither bounds its
//! connections (a thread each) nor the size or time of a request's head,
//! and a connection it holds open (an idle keep-alive, a slow client)
//! keeps one of its pool's threads, behind which the pool can queue new
//! connections for as long as that one stays open. So the public socket
//! is ours: each connection, up to a bound, has its request head read
//! here (bounded in size and time), marked `Connection: close`, and only
//! then handed to tiny_http's private Unix socket, followed by the end of
//! input: tiny_http reads exactly one complete head a connection, and
//! none of its threads ever waits on a client.

use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::os::unix::net::UnixStream;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Connections relayed at once at most; past them, 503 and close.
pub(crate) const MAX_CONNECTIONS: usize = 64;
/// The most bytes a request head (request line and headers) may take;
/// past them, 431 and close.
pub(crate) const MAX_HEAD: usize = 32 << 10;
/// How long a client may take to send its request head; past it, 408.
pub(crate) const HEAD_TIMEOUT: Duration = Duration::from_secs(10);

/// Refusals being answered at once at most; past them, a plain close.
const MAX_REFUSING: usize = 16;
/// How long a connection is drained, once answered, before it is closed.
const LINGER: Duration = Duration::from_secs(2);
/// The most bytes drained then.
const DRAIN: usize = 16 << 20;

/// One of a bounded number of connections, counted until dropped.
struct Open(Arc<AtomicUsize>);

impl Open {
    /// One more on `count`, unless `max` are open already.
    fn take(count: &Arc<AtomicUsize>, max: usize) -> Option<Open> {
        if count.fetch_add(1, Ordering::SeqCst) >= max {
            count.fetch_sub(1, Ordering::SeqCst);
            return None;
        }
        Some(Open(count.clone()))
    }
}

impl Drop for Open {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Accepts on `listener` for ever, handing each connection's request to
/// the Unix socket `inner`. Nothing here waits on a client.
pub(crate) fn accept_loop(listener: &TcpListener, inner: &Path) {
    let open = Arc::new(AtomicUsize::new(0));
    let refusing = Arc::new(AtomicUsize::new(0));
    loop {
        let client = match listener.accept() {
            Ok((c, _)) => c,
            // Out of descriptors, a connection reset before accept: go on.
            Err(_) => {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
        };
        let Some(guard) = Open::take(&open, MAX_CONNECTIONS) else {
            refuse_aside(client, &refusing);
            continue;
        };
        let inner = inner.to_path_buf();
        // Out of threads: the connection closes as it drops.
        let _ = std::thread::Builder::new()
            .name("glint-gate".to_string())
            .spawn(move || {
                relay(client, &inner);
                drop(guard);
            });
    }
}

/// Answers 503 on a thread of its own (the answer is drained, see
/// [`drain`]), or, when many are being answered already, just closes.
fn refuse_aside(client: TcpStream, refusing: &Arc<AtomicUsize>) {
    let Some(guard) = Open::take(refusing, MAX_REFUSING) else {
        let _ = client.shutdown(Shutdown::Both);
        return;
    };
    let _ = std::thread::Builder::new()
        .name("glint-gate".to_string())
        .spawn(move || {
            let mut client = client;
            refuse(
                &mut client,
                "503 Service Unavailable",
                "too many connections",
            );
            drop(guard);
        });
}

/// One connection: its request head read (bounded), marked
/// `Connection: close` and sent to tiny_http with nothing after it, then
/// the answer relayed back. A body is never relayed (the API takes none:
/// tiny_http sees its length and answers 413).
fn relay(mut client: TcpStream, inner: &Path) {
    let head = match read_head(&mut client) {
        Ok(head) => head,
        Err(Head::TooLarge) => {
            return refuse(
                &mut client,
                "431 Request Header Fields Too Large",
                "request too large",
            );
        }
        Err(Head::TimedOut) => {
            return refuse(
                &mut client,
                "408 Request Timeout",
                "the request head did not come in time",
            );
        }
        Err(Head::Closed) => return,
    };
    if has_body(&head) {
        return refuse(
            &mut client,
            "413 Payload Too Large",
            "payload too large: the API takes no request body",
        );
    }
    let handed =
        UnixStream::connect(inner).and_then(|mut s| s.write_all(&closing_head(&head)).map(|()| s));
    let Ok(mut server) = handed else {
        return refuse(
            &mut client,
            "503 Service Unavailable",
            "the server is not ready",
        );
    };
    let _ = client.set_read_timeout(None);
    let _ = server.shutdown(Shutdown::Write);
    // tiny_http never says the connection ends (it drops a `Connection`
    // header given to it): the gate says so after the status line.
    let mut start = Vec::with_capacity(256);
    let mut chunk = [0u8; 4096];
    let line_end = loop {
        match server.read(&mut chunk) {
            Ok(0) | Err(_) => break None,
            Ok(n) => start.extend_from_slice(&chunk[..n]),
        }
        if let Some(p) = start.windows(2).position(|w| w == b"\r\n") {
            break Some(p + 2);
        }
        if start.len() > MAX_HEAD {
            break None;
        }
    };
    let sent = match line_end {
        Some(p) => client
            .write_all(&start[..p])
            .and_then(|()| client.write_all(b"Connection: close\r\n"))
            .and_then(|()| client.write_all(&start[p..])),
        None => client.write_all(&start),
    };
    if sent.is_ok() {
        let _ = std::io::copy(&mut server, &mut client);
    }
    let _ = client.shutdown(Shutdown::Write);
    drain(&mut client);
}

/// Why no request head was read.
#[derive(Debug, PartialEq)]
enum Head {
    /// Past [`MAX_HEAD`].
    TooLarge,
    /// Not complete within [`HEAD_TIMEOUT`].
    TimedOut,
    /// The client closed (or the connection broke) before its end.
    Closed,
}

/// Reads a request head from `client`: the bytes through its first blank
/// line (`\r\n\r\n`, as tiny_http reads it). What comes after is left unread.
fn read_head(client: &mut TcpStream) -> Result<Vec<u8>, Head> {
    let deadline = Instant::now() + HEAD_TIMEOUT;
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 4096];
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(Head::TimedOut);
        }
        let _ = client.set_read_timeout(Some(left));
        // Peeked, so that only the head is taken off the socket.
        let n = match client.peek(&mut chunk) {
            Ok(0) => return Err(Head::Closed),
            Ok(n) => n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                return Err(Head::TimedOut);
            }
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            Err(_) => return Err(Head::Closed),
        };
        let seen = buf.len();
        buf.extend_from_slice(&chunk[..n]);
        // The end may start in the last 3 bytes already seen.
        let from = seen.saturating_sub(3);
        let end = head_end(&buf[from..]).map(|e| from + e);
        let take = end.map_or(n, |e| e - seen);
        buf.truncate(seen + take);
        if client.read_exact(&mut chunk[..take]).is_err() {
            return Err(Head::Closed);
        }
        if end.is_some() {
            return Ok(buf);
        }
        if buf.len() > MAX_HEAD {
            return Err(Head::TooLarge);
        }
    }
}

/// The index just past the first `\r\n\r\n` in `bytes`.
fn head_end(bytes: &[u8]) -> Option<usize> {
    bytes
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map(|p| p + 4)
}

/// The header lines of `head` (without the request line), split on CRLF
/// as tiny_http splits them.
fn header_lines(head: &[u8]) -> impl Iterator<Item = &[u8]> {
    // Without the blank line's CRLF, every line ends in CRLF.
    let body = &head[..head.len().saturating_sub(2)];
    let mut rest = body;
    std::iter::from_fn(move || {
        let p = rest.windows(2).position(|w| w == b"\r\n")?;
        let line = &rest[..p + 2];
        rest = &rest[p + 2..];
        Some(line)
    })
}

/// Whether header `line` is the field `name` (any case).
fn is_field(line: &[u8], name: &[u8]) -> bool {
    line.contains(&b':')
        && line
            .split(|&b| b == b':')
            .next()
            .is_some_and(|n| n.eq_ignore_ascii_case(name))
}

/// Whether `head` announces a body: a `Content-Length` other than 0, or
/// any `Transfer-Encoding`.
fn has_body(head: &[u8]) -> bool {
    header_lines(head).skip(1).any(|line| {
        let value = line.splitn(2, |&b| b == b':').nth(1).unwrap_or_default();
        let value = String::from_utf8_lossy(value);
        is_field(line, b"transfer-encoding")
            || (is_field(line, b"content-length") && value.trim() != "0")
    })
}

/// `head` (through its blank line) with any `Connection` and `Keep-Alive`
/// header dropped and `Connection: close` added, its lines split on CRLF
/// as tiny_http splits them: tiny_http then takes no second request on
/// the connection, and the client knows the connection ends.
fn closing_head(head: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(head.len() + 19);
    for (i, line) in header_lines(head).enumerate() {
        let hop = i > 0 && (is_field(line, b"connection") || is_field(line, b"keep-alive"));
        if !hop {
            out.extend_from_slice(line);
        }
    }
    out.extend_from_slice(b"Connection: close\r\n\r\n");
    out
}

/// Writes a short response with status `status` and closes the connection.
fn refuse(client: &mut TcpStream, status: &str, message: &str) {
    answer(client, status, message);
    drain(client);
}

/// Reads and drops what the client still sends, for a while, then closes:
/// closing with unread bytes would reset the connection, and the client
/// could lose the answer before reading it.
fn drain(client: &mut TcpStream) {
    let _ = client.set_read_timeout(Some(LINGER));
    let mut buf = [0u8; 8192];
    let mut left = DRAIN;
    let until = Instant::now() + LINGER;
    while left > 0 && Instant::now() < until {
        match client.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => left = left.saturating_sub(n),
        }
    }
    let _ = client.shutdown(Shutdown::Both);
}

/// Writes a short response with status `status` and says the connection ends.
fn answer(client: &mut TcpStream, status: &str, message: &str) {
    let body = format!("{message}\n");
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let _ = client.write_all(head.as_bytes());
    let _ = client.write_all(body.as_bytes());
    let _ = client.shutdown(Shutdown::Write);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_head_is_marked_to_close_and_its_hop_headers_dropped() {
        let head = b"GET /api/state?token=x HTTP/1.1\r\nHost: a\r\nconnection: keep-alive\r\nKeep-Alive: timeout=5\r\nX-Connection: y\r\n\r\n";
        assert_eq!(
            String::from_utf8_lossy(&closing_head(head)),
            "GET /api/state?token=x HTTP/1.1\r\nHost: a\r\nX-Connection: y\r\nConnection: close\r\n\r\n"
        );
        // A bare LF stays inside its line, as tiny_http reads it.
        let odd = b"GET / HTTP/1.1\r\nX: a\nConnection: keep-alive\r\n\r\n";
        assert_eq!(
            String::from_utf8_lossy(&closing_head(odd)),
            "GET / HTTP/1.1\r\nX: a\nConnection: keep-alive\r\nConnection: close\r\n\r\n"
        );
        assert_eq!(closing_head(b"\r\n"), b"Connection: close\r\n\r\n");
        assert_eq!(
            closing_head(b"HELLO\r\n\r\n"),
            b"HELLO\r\nConnection: close\r\n\r\n"
        );
    }

    #[test]
    fn a_body_is_seen_in_the_head() {
        assert!(has_body(b"POST / HTTP/1.1\r\nContent-Length: 5\r\n\r\n"));
        assert!(has_body(
            b"GET / HTTP/1.1\r\ntransfer-encoding: chunked\r\n\r\n"
        ));
        assert!(!has_body(b"GET / HTTP/1.1\r\ncontent-length:  0 \r\n\r\n"));
        assert!(!has_body(b"GET / HTTP/1.1\r\nX-Content-Length: 5\r\n\r\n"));
        assert!(!has_body(b"GET /Content-Length: 5 HTTP/1.1\r\n\r\n"));
    }

    #[test]
    fn the_head_ends_at_the_first_blank_line() {
        assert_eq!(head_end(b"GET / HTTP/1.1\r\n\r\nbody"), Some(18));
        assert_eq!(head_end(b"GET / HTTP/1.1\n\n"), None);
        assert_eq!(head_end(b"\r\n\r"), None);
    }
}
