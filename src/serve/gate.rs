//! The door in front of the HTTP server. tiny_http neither bounds its
//! connections (a thread each) nor the size of a request's head, so the
//! public socket is ours: each connection, up to a bound, is relayed to
//! tiny_http's private Unix socket, and one whose request head grows past
//! a bound is answered 431 and closed.

use std::io::{Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::os::unix::net::UnixStream;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// Connections relayed at once at most; past them, 503 and close.
pub(crate) const MAX_CONNECTIONS: usize = 64;
/// The most bytes a request head (request line and headers), or anything
/// sent after one (a body), may take; past them, 431 and close.
pub(crate) const MAX_HEAD: usize = 32 << 10;

/// How long a connection is drained, once answered, before it is closed.
const LINGER: Duration = Duration::from_secs(2);
/// The most bytes drained then.
const DRAIN: usize = 16 << 20;

/// Counts a connection open until both directions of its relay end.
struct Open(Arc<AtomicUsize>);

impl Drop for Open {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Accepts on `listener` for ever, relaying each connection to the Unix socket `inner`.
pub(crate) fn accept_loop(listener: &TcpListener, inner: &PathBuf) {
    let open = Arc::new(AtomicUsize::new(0));
    loop {
        let mut client = match listener.accept() {
            Ok((c, _)) => c,
            // Out of descriptors, a connection reset before accept: go on.
            Err(_) => {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            }
        };
        if open.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::SeqCst);
            refuse(
                &mut client,
                "503 Service Unavailable",
                "too many connections",
            );
            continue;
        }
        let guard = Arc::new(Open(open.clone()));
        let Ok(server) = UnixStream::connect(inner) else {
            refuse(
                &mut client,
                "503 Service Unavailable",
                "the server is not ready",
            );
            continue;
        };
        let (Ok(client_w), Ok(server_w)) = (client.try_clone(), server.try_clone()) else {
            continue;
        };
        let up_guard = guard.clone();
        let up = std::thread::Builder::new()
            .name("glint-gate".to_string())
            .spawn(move || {
                relay_up(client, server_w);
                drop(up_guard);
            });
        if up.is_err() {
            continue;
        }
        let _ = std::thread::Builder::new()
            .name("glint-gate".to_string())
            .spawn(move || {
                relay_down(server, client_w);
                drop(guard);
            });
    }
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
    while left > 0 {
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

/// Client to server, counting the bytes since the last blank line (the
/// end of a request head).
fn relay_up(mut client: TcpStream, mut server: UnixStream) {
    let mut buf = [0u8; 8192];
    let mut window = 0u32;
    let mut since = 0usize;
    loop {
        let n = match client.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        for &b in &buf[..n] {
            window = (window << 8) | u32::from(b);
            since += 1;
            if window == u32::from_be_bytes(*b"\r\n\r\n") {
                since = 0;
            }
        }
        if since > MAX_HEAD {
            let _ = server.shutdown(Shutdown::Both);
            refuse(
                &mut client,
                "431 Request Header Fields Too Large",
                "request too large",
            );
            return;
        }
        if server.write_all(&buf[..n]).is_err() {
            break;
        }
    }
    let _ = server.shutdown(Shutdown::Write);
}

/// Server to client; once the server's side ends, the client's is
/// drained for a while (see [`drain`]) and closed, which also ends the
/// other direction.
fn relay_down(mut server: UnixStream, mut client: TcpStream) {
    let _ = std::io::copy(&mut server, &mut client);
    let _ = client.shutdown(Shutdown::Write);
    drain(&mut client);
}
