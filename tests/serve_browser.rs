//! `glint serve`'s page in a real browser: Debian's headless Chromium,
//! driven over its DevTools protocol (a WebSocket). Loads the page, waits
//! for the picture, hovers and clicks a pixel of the sphere (its
//! `file:line` and its ray tree must show), saves a change (the new picture
//! must come), saves a broken file (its diagnostic with the line must show,
//! the picture stay), fixes it, switches to an AOV, takes a screenshot
//! (not blank), compares with a picture of "their own" on the slider
//! (the summary must name the sphere), and checks that the page threw no
//! JavaScript error. With
//! the shared corpus's scene1 at hand it also measures, on scene1, the
//! time from a save to the coarse preview and to the full image on the page.
//!
//! Without Chromium the test says it was skipped, unless
//! `GLINT_REQUIRE_BROWSER=1` (as in `.ci/run`), which makes that a failure.
//! `GLINT_SCREENSHOTS=DIR` also writes the screenshots to DIR (docs/serve).

#[path = "serve_support/mod.rs"]
mod support;

use serde_json::{Value, json};
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};
use support::*;
use tungstenite::{Message, WebSocket};

/// A generous bound on any wait (the machine may be busy): not a speed check.
const WAIT: Duration = Duration::from_secs(60);

/// The Chromium binary: `GLINT_CHROMIUM`, or the first of the usual names on PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("GLINT_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser", "google-chrome", "chrome"] {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// Milliseconds since the epoch (the page's `Date.now()`).
fn now_ms() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64() * 1e3)
}

/// A headless Chromium, killed when dropped.
struct Browser {
    child: Child,
    /// Removed when dropped, after the browser is gone.
    profile: tempfile::TempDir,
}

impl Drop for Browser {
    /// Kills the browser's whole process group (its renderer and utility
    /// processes too: left alone, they write into the profile after it is
    /// removed), then removes the profile, trying again for 5 s while
    /// their last writes land.
    fn drop(&mut self) {
        let group = format!("-{}", self.child.id());
        let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
        let _ = self.child.kill();
        let _ = self.child.wait();
        let start = Instant::now();
        while self.profile.path().exists() && start.elapsed() < Duration::from_secs(5) {
            let _ = std::fs::remove_dir_all(self.profile.path());
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// One page's DevTools session.
struct Cdp {
    ws: WebSocket<TcpStream>,
    next: u64,
    /// Events received so far (method, params).
    events: Vec<(String, Value)>,
}

impl Cdp {
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next += 1;
        let id = self.next;
        let msg = json!({"id": id, "method": method, "params": params}).to_string();
        self.ws
            .send(Message::text(msg))
            .expect("send to the browser");
        loop {
            let m = self.ws.read().expect("read from the browser");
            let Ok(text) = m.to_text() else { continue };
            let v: Value = serde_json::from_str(text).unwrap_or(Value::Null);
            if v["id"] == id {
                assert!(v["error"].is_null(), "{method}: {}", v["error"]);
                return v["result"].clone();
            }
            if let Some(name) = v["method"].as_str() {
                self.events.push((name.to_string(), v["params"].clone()));
            }
        }
    }

    /// Evaluates `expr` in the page (promises awaited), returning its value.
    fn eval(&mut self, expr: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({"expression": expr, "returnByValue": true, "awaitPromise": true}),
        );
        assert!(
            r["exceptionDetails"].is_null(),
            "{expr}: {}",
            r["exceptionDetails"]
        );
        r["result"]["value"].clone()
    }

    /// Polls `expr` until it is truthy (up to [`WAIT`]); returns its value.
    fn wait(&mut self, what: &str, expr: &str) -> Value {
        let start = Instant::now();
        loop {
            let v = self.eval(expr);
            let truthy = !(v.is_null() || v == false || v == 0 || v == "");
            if truthy {
                return v;
            }
            if start.elapsed() > WAIT {
                let shown = self.eval("document.body.innerText");
                panic!("waited {WAIT:?} for {what} ({expr}); the page shows:\n{shown}");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn mouse(&mut self, kind: &str, x: f64, y: f64) {
        let mut p = json!({"type": kind, "x": x, "y": y});
        if kind != "mouseMoved" {
            p["button"] = json!("left");
            p["clickCount"] = json!(1);
        }
        self.call("Input.dispatchMouseEvent", p);
    }

    /// A screenshot of the page, decoded.
    fn screenshot(&mut self) -> (Vec<u8>, image::RgbImage) {
        let r = self.call("Page.captureScreenshot", json!({"format": "png"}));
        let png = base64(r["data"].as_str().unwrap_or_default());
        let img = image::load_from_memory(&png).expect("a PNG").to_rgb8();
        (png, img)
    }
}

/// Standard base64 decoded (what DevTools sends screenshots in).
fn base64(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0);
    for v in s.bytes().filter_map(value) {
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    out
}

/// Starts Chromium headless on `about:blank` and opens a DevTools session on its page.
fn launch(browser: &Path) -> (Browser, Cdp) {
    let profile = temp_dir("chromium-profile");
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            "--window-size=1400,900",
            "--remote-debugging-port=0",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg("about:blank")
        // Its singleton folder (org.chromium.Chromium.*), which a killed
        // browser leaves behind, goes into the profile folder too.
        .env("TMPDIR", profile.path())
        // A process group of its own, killed whole when dropped.
        .process_group(0)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("chromium starts");
    let stderr = child.stderr.take().expect("stderr");
    let browser = Browser { child, profile };
    // "DevTools listening on ws://127.0.0.1:PORT/devtools/browser/..."
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if let Some(url) = line.split("DevTools listening on ").nth(1) {
                let _ = tx.send(url.trim().to_string());
            }
        }
    });
    let ws_url = rx.recv_timeout(WAIT).expect("chromium's DevTools address");
    let host = ws_url
        .trim_start_matches("ws://")
        .split('/')
        .next()
        .unwrap_or_default()
        .to_string();
    // The page target's own WebSocket.
    let start = Instant::now();
    let page_ws = loop {
        let r = request(
            &host,
            "GET /json/list HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n",
        );
        let list: Value = serde_json::from_slice(&r.body).unwrap_or(Value::Null);
        let found = list
            .as_array()
            .into_iter()
            .flatten()
            .find(|t| t["type"] == "page");
        if let Some(url) = found.and_then(|t| t["webSocketDebuggerUrl"].as_str()) {
            break url.to_string();
        }
        assert!(start.elapsed() < WAIT, "no page target: {}", r.text());
        std::thread::sleep(Duration::from_millis(50));
    };
    let stream = TcpStream::connect(&host).expect("connect to DevTools");
    stream.set_read_timeout(Some(WAIT)).expect("timeout");
    let (ws, _) =
        tungstenite::client::client(page_ws.as_str(), stream).expect("DevTools handshake");
    let mut cdp = Cdp {
        ws,
        next: 0,
        events: Vec::new(),
    };
    for domain in ["Page.enable", "Runtime.enable", "Log.enable"] {
        cdp.call(domain, json!({}));
    }
    (browser, cdp)
}

/// Client coordinates of full-frame pixel (x, y)'s centre on the picture.
fn client_point(cdp: &mut Cdp, x: u32, y: u32) -> (f64, f64) {
    let r = cdp.eval(
        "(() => { const r = document.getElementById('picture').getBoundingClientRect(); \
         return [r.left, r.top, r.width, r.height, glint.frame.full[0], glint.frame.full[1]]; })()",
    );
    let n = |k: usize| r[k].as_f64().unwrap_or(0.0);
    (
        n(0) + (x as f64 + 0.5) * n(2) / n(4),
        n(1) + (y as f64 + 0.5) * n(3) / n(5),
    )
}

/// Writes a screenshot to `GLINT_SCREENSHOTS/NAME` when asked to.
fn keep(png: &[u8], name: &str) {
    if let Some(dir) = std::env::var_os("GLINT_SCREENSHOTS") {
        let dir = PathBuf::from(dir);
        let _ = std::fs::create_dir_all(&dir);
        std::fs::write(dir.join(name), png).expect("write the screenshot");
    }
}

/// Asserts that the page's own error list (`glint.errors`: `error` and
/// `unhandledrejection` events it caught) is empty, before leaving it.
fn no_page_errors(cdp: &mut Cdp) {
    let errors = cdp.eval("window.glint ? glint.errors : ['no glint page']");
    assert_eq!(errors, json!([]), "errors the page caught");
}

/// Whether a picture is more than a blank page: many colours, and spread.
fn not_blank(img: &image::RgbImage) -> (usize, bool) {
    let colours: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    (colours.len(), colours.len() > 50)
}

#[test]
fn the_page_in_a_real_browser() {
    let Some(browser) = chromium() else {
        let why =
            "no chromium on PATH (Debian: apt-get install -y chromium; or set GLINT_CHROMIUM)";
        assert!(
            std::env::var("GLINT_REQUIRE_BROWSER").as_deref() != Ok("1"),
            "GLINT_REQUIRE_BROWSER=1 but {why}"
        );
        eprintln!("serve_browser: SKIPPED: {why}");
        return;
    };
    let tmp = temp_dir("browser");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(320, 240, "1 0 0"));
    let served = Served::start(&scene, &[]);
    let (_chromium, mut cdp) = launch(&browser);
    cdp.call("Page.navigate", json!({"url": served.url}));
    cdp.wait(
        "the full picture",
        "window.glint && glint.last && glint.last.stage === 'final' && glint.last.version === 1",
    );

    // Hover over a pixel of the sphere (block 0, its header on line 12).
    let at = cdp.eval(
        "(() => { const g = glint, w = g.ids.w, h = g.ids.h; let best = null, bd = 1e9; \
         for (let k = 0; k < w * h; k++) { if (g.ids.ids[k] !== 0) continue; \
           const x = k % w, y = Math.floor(k / w), d = Math.abs(x - w / 2) + Math.abs(y - h * 0.4); \
           if (d < bd) { bd = d; best = [x, y]; } } return best; })()",
    );
    let (px, py) = (
        at[0].as_u64().expect("a sphere pixel") as u32,
        at[1].as_u64().unwrap_or(0) as u32,
    );
    let (cx, cy) = client_point(&mut cdp, px, py);
    cdp.mouse("mouseMoved", cx, cy);
    let hover = cdp.wait(
        "the hover line",
        "(() => { const t = document.getElementById('hover').textContent; return t.includes('sphere #0') && t; })()",
    );
    let hover = hover.as_str().unwrap_or_default().to_string();
    let file_line = format!("{}:12", scene.display());
    assert!(hover.contains(&file_line), "{hover}");
    // The pixel the page says is under the pointer (mouse events come in
    // whole client pixels, so it may be a neighbour of the one aimed at).
    let (px, py) = hover
        .strip_prefix('(')
        .and_then(|t| t.split_once(')'))
        .and_then(|(xy, _)| xy.split_once(", "))
        .and_then(|(x, y)| Some((x.parse::<u32>().ok()?, y.parse::<u32>().ok()?)))
        .expect("the hover line starts with the pixel");
    let bytes_at = |cdp: &mut Cdp| {
        cdp.eval(&format!(
            "(() => {{ const k = {py} * glint.ids.w + {px}; return [glint.pixels[4*k], glint.pixels[4*k+1], glint.pixels[4*k+2]]; }})()"
        ))
    };
    let bytes = bytes_at(&mut cdp);
    let b = |k: usize| bytes[k].as_u64().unwrap_or(0);
    assert!(
        hover.contains(&format!("bytes {} {} {}", b(0), b(1), b(2))),
        "{hover} / {bytes}"
    );
    assert!(b(0) > 100 && b(1) < 60, "the sphere is red: {bytes}");

    // Click: the explain tree and the rays.
    cdp.mouse("mousePressed", cx, cy);
    cdp.mouse("mouseReleased", cx, cy);
    cdp.wait(
        "the explain tree",
        "window.glint.explained && glint.raysDrawn > 0",
    );
    let tree = cdp.eval("document.getElementById('explain').innerText");
    let tree = tree.as_str().unwrap_or_default();
    assert!(tree.contains(&format!("pixel ({px}, {py})")), "{tree}");
    assert!(
        tree.contains("camera") && tree.contains("sphere #0") && tree.contains(&file_line),
        "{tree}"
    );
    assert!(tree.contains("light #0"), "{tree}");
    let drawn = cdp.eval(
        "(() => { const c = document.getElementById('overlay'); const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let n = 0; for (let k = 3; k < d.length; k += 4) if (d[k] > 0) n++; return n; })()",
    );
    assert!(
        drawn.as_u64() > Some(20),
        "rays drawn over the picture: {drawn} pixels"
    );
    let (png, _) = cdp.screenshot();
    keep(&png, "explain.png");

    // A save: the new picture comes.
    let saved = now_ms();
    save(&scene, &scene_text(320, 240, "0 1 0"));
    cdp.wait(
        "version 2's full picture",
        "glint.last.version === 2 && glint.last.stage === 'final'",
    );
    let shown = cdp.eval("glint.shown[2]");
    let coarse_ms = shown["coarse"].as_f64().map(|t| t - saved);
    let final_ms = shown["final"].as_f64().map(|t| t - saved);
    let bytes = cdp.eval(&format!(
        "(() => {{ const k = {py} * glint.ids.w + {px}; return [glint.pixels[4*k], glint.pixels[4*k+1], glint.pixels[4*k+2]]; }})()"
    ));
    assert!(
        bytes[1].as_u64() > Some(100) && bytes[0].as_u64() < Some(60),
        "now green: {bytes}"
    );

    // A broken file: the diagnostic with its line; the picture stays.
    let broken = scene_text(320, 240, "0 1 0").replace(" R= 1\n", " R= one\n");
    let line = broken
        .lines()
        .position(|l| l == " R= one")
        .map_or(0, |i| i + 1);
    save(&scene, &broken);
    let place = format!("{}:{line}:5", scene.display());
    let diag = cdp.wait(
        "the diagnostic",
        &format!(
            "(() => {{ const b = document.getElementById('diagnostics-box'); const t = b.innerText; \
             return !b.hidden && t.includes({}) && t; }})()",
            json!(place)
        ),
    );
    let diag = diag.as_str().unwrap_or_default();
    assert!(diag.contains("R= one") && diag.contains('^'), "{diag}");
    assert_eq!(
        cdp.eval("glint.last.version"),
        2,
        "the last good picture stays"
    );
    let (png, _) = cdp.screenshot();
    keep(&png, "broken.png");

    // Fixed: the picture again, the diagnostics gone.
    save(&scene, &scene_text(320, 240, "0 0.6 1"));
    cdp.wait(
        "the fixed file's picture",
        "glint.last.version === 4 && glint.last.stage === 'final' && document.getElementById('diagnostics-box').hidden",
    );

    // An AOV.
    cdp.wait("the AOVs", "document.querySelector('[data-view=normal]')");
    cdp.eval("document.querySelector('[data-view=normal]').click()");
    cdp.wait(
        "the normal AOV",
        "(() => { const i = document.getElementById('aov'); return !i.hidden && i.complete && i.naturalWidth === 320; })()",
    );
    cdp.eval("document.querySelector('[data-view=picture]').click()");
    let aov_display = cdp.eval("getComputedStyle(document.getElementById('aov')).display");
    assert_eq!(
        aov_display, "none",
        "the picture is shown again, not the AOV"
    );

    let (png, img) = cdp.screenshot();
    let (colours, ok) = not_blank(&img);
    assert!(ok, "the screenshot is blank: {colours} colours");
    keep(&png, "page.png");

    // --compare: their (black) picture on a slider, with the summary beside it.
    let theirs = dir.join("theirs.png");
    image::RgbImage::new(320, 240).save(&theirs).expect("png");
    let compared = Served::start(&scene, &["--compare", theirs.to_str().unwrap_or_default()]);
    no_page_errors(&mut cdp);
    cdp.call("Page.navigate", json!({"url": compared.url}));
    let summary = cdp.wait(
        "the comparison",
        "(() => { const e = document.getElementById('compare-summary'); const t = e ? e.textContent : ''; return t.includes('pixels differ') && t; })()",
    );
    let summary = summary.as_str().unwrap_or_default();
    assert!(
        summary.contains("sphere #0") && summary.contains(&file_line),
        "{summary}"
    );
    cdp.wait(
        "their picture",
        "(() => { const i = document.getElementById('theirs'); return !document.getElementById('theirs-clip').hidden && i.complete && i.naturalWidth === 320; })()",
    );
    cdp.eval(
        "(() => { const s = document.getElementById('compare'); s.value = 30; s.dispatchEvent(new Event('input')); })()",
    );
    let clip = cdp.eval("document.getElementById('theirs-clip').style.clipPath");
    assert_eq!(clip, "inset(0px 0px 0px 30%)");
    let (png, _) = cdp.screenshot();
    keep(&png, "compare.png");
    no_page_errors(&mut cdp);
    cdp.call("Page.navigate", json!({"url": "about:blank"}));
    drop(compared);

    // scene1 of the shared corpus, when at hand: the save-to-picture times.
    let corpus = std::env::var_os("GLINT_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes"));
    let scene1 = corpus.join("framework/scene1.txt");
    let mut scene1_times = Vec::new();
    if scene1.is_file() {
        let copy_tmp = temp_dir("browser-scene1");
        let copy = copy_tmp.path();
        std::fs::create_dir_all(copy.join("framework")).expect("mkdir");
        std::fs::create_dir_all(copy.join("textures")).expect("mkdir");
        for t in std::fs::read_dir(corpus.join("textures"))
            .expect("textures")
            .flatten()
        {
            let _ = std::fs::copy(t.path(), copy.join("textures").join(t.file_name()));
        }
        let text = std::fs::read_to_string(&scene1).expect("scene1");
        let path = copy.join("framework/scene1.txt");
        save(&path, &text);
        let served1 = Served::start(&path, &[]);
        cdp.call("Page.navigate", json!({"url": served1.url}));
        cdp.wait(
            "scene1's picture",
            "window.glint && glint.last && glint.last.stage === 'final'",
        );
        for k in 2..=4 {
            let saved = now_ms();
            save(&path, &format!("{text}\n# save {k}\n"));
            cdp.wait(
                "scene1's new picture",
                &format!("glint.last.version === {k} && glint.last.stage === 'final'"),
            );
            let s = cdp.eval(&format!("glint.shown[{k}]"));
            scene1_times.push((
                s["coarse"].as_f64().unwrap_or(0.0) - saved,
                s["final"].as_f64().unwrap_or(0.0) - saved,
            ));
        }
        // Its AOVs would share the cores with the render timed here.
        no_page_errors(&mut cdp);
        cdp.call("Page.navigate", json!({"url": "about:blank"}));
        drop(served1);
        let start = Instant::now();
        let out = Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(["render", "--quiet", "-o"])
            .arg(copy.join("out.png"))
            .arg(&path)
            .output()
            .expect("glint render");
        assert!(out.status.success());
        eprintln!(
            "scene1: glint render takes {:.0} ms",
            start.elapsed().as_secs_f64() * 1e3
        );
    } else {
        eprintln!("scene1: not measured ({} is not there)", scene1.display());
    }

    // No JavaScript error (the page's own list was checked before leaving each page).
    let thrown: Vec<&Value> = cdp
        .events
        .iter()
        .filter(|(m, p)| {
            m == "Runtime.exceptionThrown"
                || (m == "Runtime.consoleAPICalled" && p["type"] == "error")
                || (m == "Log.entryAdded"
                    && p["entry"]["level"] == "error"
                    && p["entry"]["source"] == "javascript")
        })
        .map(|(_, p)| p)
        .collect();
    assert!(thrown.is_empty(), "JavaScript errors: {thrown:#?}");
    let network: Vec<&Value> = cdp
        .events
        .iter()
        .filter(|(m, p)| m == "Log.entryAdded" && p["entry"]["level"] == "error")
        .map(|(_, p)| &p["entry"]["text"])
        .collect();
    eprintln!("other console errors (network): {network:?}");
    eprintln!(
        "small scene: save to coarse preview on the page {:.0} ms, to the full picture {:.0} ms",
        coarse_ms.unwrap_or(f64::NAN),
        final_ms.unwrap_or(f64::NAN)
    );
    for (c, f) in &scene1_times {
        eprintln!(
            "scene1: save to coarse preview on the page {c:.0} ms, to the full picture {f:.0} ms"
        );
    }
    drop(served);
}
