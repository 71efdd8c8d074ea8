//! What the `glint serve` tests share: a server started on a scene written
//! to a temporary folder, plain HTTP over std's TcpStream, and an event
//! stream reader.
#![allow(dead_code)] // each test file uses a part

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

/// A small scene: a sphere on a plane under a point light, `w` × `h`,
/// the sphere (block 0, its header on line 12) coloured `r g b`.
pub fn scene_text(w: u32, h: u32, colour: &str) -> String {
    format!(
        "background\n color= 0.1 0.1 0.2\nend\n\
         camera\n O= 0 -6 2\n N= 0 1 -0.25\n image_W= {w}\n image_H= {h}\n lens_W= 1\n lens_H= 0.75\nend\n\
         primitive sphere\n O= 0 0 1\n R= 1\n color= {colour}\n diff= 0.8\n spec= 0.2\n refl= 0.2\nend\n\
         primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.7\nend\n\
         light point\n O= 3 -4 6\n color= 1 1 1\nend\n"
    )
}

/// A fresh folder for one test, removed when dropped (a failing test's too).
pub fn temp_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("glint-serve-test-{name}-"))
        .tempdir()
        .expect("temp dir")
}

/// Writes `text` to `path` as editors do: a temporary file renamed over it.
pub fn save(path: &Path, text: &str) {
    let tmp = path.with_extension("tmp~");
    std::fs::write(&tmp, text).expect("write");
    std::fs::rename(&tmp, path).expect("rename");
}

/// A running `glint serve`, killed when dropped.
pub struct Served {
    pub child: Child,
    pub url: String,
    pub host: String,
    pub token: String,
}

impl Served {
    /// Starts `glint serve SCENE ARGS...` and reads the URL it prints.
    pub fn start(scene: &Path, args: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
            .arg("serve")
            .arg(scene)
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("glint serve starts");
        let mut line = String::new();
        let stdout = child.stdout.take().expect("stdout");
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("the URL line");
        let url = line.trim().to_string();
        let rest = url.strip_prefix("http://").expect("an http URL");
        let (host, query) = rest.split_once('/').expect("a path");
        let token = query.strip_prefix("?token=").expect("a token").to_string();
        Served {
            child,
            url: url.clone(),
            host: host.to_string(),
            token,
        }
    }

    /// `path` with the token added.
    pub fn with_token(&self, path: &str) -> String {
        let sep = if path.contains('?') { '&' } else { '?' };
        format!("{path}{sep}token={}", self.token)
    }

    /// GET `path` with the token.
    pub fn get(&self, path: &str) -> Reply {
        request(
            &self.host,
            &format!(
                "GET {} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
                self.with_token(path)
            ),
        )
    }

    /// The state as JSON.
    pub fn state(&self) -> serde_json::Value {
        let r = self.get("/api/state");
        assert_eq!(r.status, 200, "{}", r.text());
        serde_json::from_slice(&r.body).expect("state JSON")
    }

    /// Waits (up to `limit`) until the state satisfies `ok`; returns it.
    pub fn wait_state(
        &self,
        limit: Duration,
        ok: impl Fn(&serde_json::Value) -> bool,
    ) -> serde_json::Value {
        let start = Instant::now();
        loop {
            let s = self.state();
            if ok(&s) {
                return s;
            }
            assert!(
                start.elapsed() < limit,
                "waited {limit:?} for the state; it is {s:#}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Opens the event stream: (event name, JSON data) as they come.
    pub fn events(&self) -> Receiver<(String, serde_json::Value)> {
        let mut s = TcpStream::connect(&self.host).expect("connect");
        let req = format!(
            "GET {} HTTP/1.1\r\nHost: x\r\n\r\n",
            self.with_token("/api/events")
        );
        s.write_all(req.as_bytes()).expect("send");
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut name = String::new();
            for line in BufReader::new(s).lines() {
                let Ok(line) = line else { return };
                if let Some(n) = line.strip_prefix("event: ") {
                    name = n.to_string();
                } else if let Some(d) = line.strip_prefix("data: ") {
                    let value = serde_json::from_str(d).unwrap_or(serde_json::Value::Null);
                    if tx.send((std::mem::take(&mut name), value)).is_err() {
                        return;
                    }
                }
            }
        });
        rx
    }

    /// The server's resident memory in KiB (Linux).
    pub fn rss_kib(&self) -> Option<u64> {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).ok()?;
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.split_whitespace().next()?.parse().ok())
    }
}

impl Drop for Served {
    /// SIGTERM first (the server then removes its private socket folder),
    /// SIGKILL if it has not ended within 5 s.
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status();
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(5) {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Waits up to `limit` for an event that satisfies `ok`, returning it.
pub fn wait_event(
    rx: &Receiver<(String, serde_json::Value)>,
    limit: Duration,
    ok: impl Fn(&str, &serde_json::Value) -> bool,
) -> (String, serde_json::Value) {
    let start = Instant::now();
    loop {
        let left = limit.saturating_sub(start.elapsed());
        match rx.recv_timeout(left) {
            Ok((n, d)) if ok(&n, &d) => return (n, d),
            Ok(_) => {}
            Err(e) => panic!("no such event within {limit:?}: {e}"),
        }
    }
}

/// An HTTP response.
pub struct Reply {
    pub status: u16,
    pub head: String,
    pub body: Vec<u8>,
}

impl Reply {
    /// The body as text.
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }
}

/// Sends raw `request` bytes to `host` and reads the response to its end
/// (the server closes: every request here says `Connection: close`).
pub fn request(host: &str, request: &str) -> Reply {
    request_bytes(host, request.as_bytes())
}

/// [`request`] of raw bytes.
pub fn request_bytes(host: &str, request: &[u8]) -> Reply {
    let mut s = TcpStream::connect(host).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(20)))
        .expect("timeout");
    // The server may answer and close before taking all of a large request.
    let _ = s.write_all(request);
    let mut raw = Vec::new();
    if let Err(e) = s.read_to_end(&mut raw)
        && raw.is_empty()
    {
        raw = format!("(no answer: {e})").into_bytes();
    }
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map_or(raw.len(), |p| p + 4);
    let head = String::from_utf8_lossy(&raw[..split]).into_owned();
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let mut body = raw[split..].to_vec();
    if head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked")
    {
        body = dechunk(&body);
    }
    Reply { status, head, body }
}

fn dechunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    while let Some(p) = b.windows(2).position(|w| w == b"\r\n") {
        let n = usize::from_str_radix(String::from_utf8_lossy(&b[..p]).trim(), 16).unwrap_or(0);
        if n == 0 || p + 2 + n > b.len() {
            break;
        }
        out.extend_from_slice(&b[p + 2..p + 2 + n]);
        b = &b[(p + 4 + n).min(b.len())..];
    }
    out
}
