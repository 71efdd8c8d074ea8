//! `glint serve` over HTTP: the token, refused and odd requests, many
//! clients at once, a save cancelling a render, a broken file and its fix,
//! explain, AOVs, watched textures, the comparison. Each test starts the
//! real binary on a scene written to a temporary folder.

#[path = "serve_support/mod.rs"]
mod support;

use std::time::{Duration, Instant};
use support::*;

const WAIT: Duration = Duration::from_secs(60);

fn final_of(s: &serde_json::Value, version: u64) -> bool {
    s["frame"]["stage"] == "final" && s["frame"]["version"] == version
}

#[test]
fn every_request_needs_the_token_and_only_the_scenes_files_are_served() {
    let tmp = temp_dir("token");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(32, 24, "1 0 0"));
    let s = Served::start(&scene, &[]);
    assert!(s.url.starts_with("http://127.0.0.1:"), "{}", s.url);
    assert_eq!(s.token.len(), 32);
    let raw = |path: &str| {
        request(
            &s.host,
            &format!("GET {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"),
        )
    };
    // A token that differs from the real one in its first character (a
    // fixed "0" would be the real token one time in 16).
    let first = if s.token.starts_with('0') { '1' } else { '0' };
    let wrong = format!("{first}{}", &s.token[1..]);
    assert_ne!(wrong, s.token);
    for path in [
        "/",
        "/api/state",
        "/page.js",
        "/api/events",
        "/api/image.png",
        "/api/file/0",
    ] {
        assert_eq!(raw(path).status, 403, "{path} without the token");
        assert_eq!(
            raw(&format!("{path}?token={wrong}")).status,
            403,
            "{path}, wrong token"
        );
    }
    let tok = format!("?token={}", s.token);
    // The token as a header does too.
    let r = request(
        &s.host,
        &format!(
            "GET /api/state HTTP/1.1\r\nHost: x\r\nX-Glint-Token: {}\r\nConnection: close\r\n\r\n",
            s.token
        ),
    );
    assert_eq!(r.status, 200);
    let page = s.get("/");
    assert_eq!(page.status, 200);
    assert!(page.text().contains(&format!("/page.js{tok}")));
    assert!(page.head.contains("Content-Security-Policy"));
    // The scene file is file 0, as it is on disk.
    let f = s.get("/api/file/0");
    assert_eq!(f.status, 200);
    assert_eq!(f.text(), scene_text(32, 24, "1 0 0"));
    std::fs::write(dir.join("secret.txt"), "root:secret").expect("write");
    for path in [
        "/../secret.txt",
        "/api/file/../secret.txt",
        "/api/file/..%2Fsecret.txt",
        "/api/file/%2e%2e/secret.txt",
        "/api/file/0/../../secret.txt",
        "/api//file/0",
        "/api/file/\\..\\secret.txt",
    ] {
        let r = raw(&format!("{path}{tok}"));
        assert_eq!(r.status, 400, "{path}: {}", r.text());
        assert!(!r.text().contains("root:"), "{path}");
    }
    for path in [
        "/secret.txt",
        "/api/file/1",
        "/api/file/99999999999999999999",
        "/etc/passwd",
        "/api/aov/nope.png",
    ] {
        let r = raw(&format!("{path}{tok}"));
        assert!(r.status == 404 || r.status == 400, "{path}: {}", r.status);
        assert!(!r.text().contains("root:"), "{path}");
    }
}

#[test]
fn oversized_and_odd_requests_are_refused_and_the_server_goes_on() {
    let tmp = temp_dir("odd");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(32, 24, "1 0 0"));
    let s = Served::start(&scene, &["--spp", "1"]);
    s.wait_state(WAIT, |st| final_of(st, 1));
    let tok = format!("token={}", s.token);
    let long = format!(
        "GET /api/state?{tok}&x={} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
        "a".repeat(5000)
    );
    assert_eq!(request(&s.host, &long).status, 414);
    let header = |n: usize| {
        format!(
            "GET /api/state?{tok} HTTP/1.1\r\nHost: x\r\nX-Big: {}\r\nConnection: close\r\n\r\n",
            "b".repeat(n)
        )
    };
    assert_eq!(
        request(&s.host, &header(20 << 10)).status,
        431,
        "past the handler's bound"
    );
    assert_eq!(
        request(&s.host, &header(200 << 10)).status,
        431,
        "past the gate's bound"
    );
    let post = format!(
        "POST /api/state?{tok} HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\nConnection: close\r\n\r\nhello"
    );
    assert_eq!(request(&s.host, &post).status, 413);
    let put = format!("PUT /api/state?{tok} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!(request(&s.host, &put).status, 405);
    // A huge body is cut off at the gate.
    let mut big =
        format!("GET /api/state?{tok} HTTP/1.1\r\nHost: x\r\nContent-Length: 10000000\r\n\r\n")
            .into_bytes();
    big.extend(std::iter::repeat_n(b'z', 1 << 20));
    let r = request_bytes(&s.host, &big);
    // Refused: with a status, or, when the server's close overtakes the
    // rest of the body on a loaded machine, by a reset before the client
    // read the answer (the requests below check the server goes on).
    let reset = r.status == 0 && r.head.to_ascii_lowercase().contains("reset");
    assert!(
        r.status == 413 || r.status == 431 || reset,
        "{} {}",
        r.status,
        r.head
    );
    for q in [
        "x=a&y=1",
        "x=1",
        "x=-1&y=2",
        "x=99999&y=1",
        "x=1&y=4294967296",
        "x=%ff&y=1",
    ] {
        let r = s.get(&format!("/api/explain?{q}"));
        assert_eq!(r.status, 400, "{q}: {}", r.text());
    }
    assert_eq!(s.get("/api/image.png?frame=abc").status, 400);
    assert_eq!(s.get("/api/image.png?frame=0").status, 410);
    // Garbage instead of HTTP, and a connection closed half-way.
    let _ = request(&s.host, "HELLO\r\n\r\n");
    let _ = request(&s.host, "GET /api/st");
    assert_eq!(s.get("/api/state").status, 200, "the server goes on");
}

#[test]
fn no_connection_is_held_open_after_its_answer() {
    // A connection the server kept open (keep-alive, a slow head) would
    // hold one of tiny_http's pool threads, behind which its pool can
    // queue new connections for as long as it stays open (CI once saw 12
    // requests wait 20 s that way): each is answered and closed instead.
    let tmp = temp_dir("close");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(32, 24, "1 0 0"));
    let s = Served::start(&scene, &["--spp", "1"]);
    s.wait_state(WAIT, |st| final_of(st, 1));
    for connection in [
        "",
        "Connection: keep-alive\r\n",
        "Connection: Keep-Alive, Upgrade\r\n",
    ] {
        let mut c = std::net::TcpStream::connect(&s.host).expect("connect");
        c.set_read_timeout(Some(Duration::from_secs(10)))
            .expect("timeout");
        let rq = format!(
            "GET {} HTTP/1.1\r\nHost: x\r\n{connection}\r\n",
            s.with_token("/api/state")
        );
        std::io::Write::write_all(&mut c, rq.as_bytes()).expect("send");
        let mut raw = Vec::new();
        let read = std::io::Read::read_to_end(&mut c, &mut raw);
        let text = String::from_utf8_lossy(&raw).to_ascii_lowercase();
        assert!(
            read.is_ok(),
            "{connection:?}: not closed after its answer: {read:?} {text}"
        );
        assert!(text.starts_with("http/1.1 200"), "{connection:?}: {text}");
        assert!(
            text.contains("\r\nconnection: close\r\n"),
            "{connection:?}: {text}"
        );
    }
    // A head that never ends is answered 408 (after the gate's 10 s).
    let r = request(&s.host, "GET /api/state?token=x HTTP/1.1\r\nHost: x\r\n");
    assert_eq!(r.status, 408, "{}", r.head);
    assert_eq!(s.get("/api/state").status, 200, "the server goes on");
}

#[test]
fn many_clients_at_once_are_answered() {
    let tmp = temp_dir("many");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(48, 36, "0 1 0"));
    let s = Served::start(&scene, &[]);
    let st = s.wait_state(WAIT, |st| final_of(st, 1));
    let png_len = s.get("/api/image.png").body.len();
    assert!(png_len > 8);
    let streams: Vec<_> = (0..4).map(|_| s.events()).collect();
    let threads: Vec<_> = (0..12)
        .map(|_| {
            let (host, token) = (s.host.clone(), s.token.clone());
            std::thread::spawn(move || {
                let mut ok = Vec::new();
                for k in 0..10 {
                    let path = ["/api/state", "/api/image.png", "/api/ids", "/api/explain?x=3&y=4"][k % 4];
                    let sep = if path.contains('?') { '&' } else { '?' };
                    let r = request(&host, &format!("GET {path}{sep}token={token} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
                    ok.push((r.status, path, r.head.chars().take(120).collect::<String>()));
                }
                ok
            })
        })
        .collect();
    let answers: Vec<_> = threads
        .into_iter()
        .flat_map(|t| t.join().unwrap_or_default())
        .collect();
    assert_eq!(answers.len(), 120);
    let refused: Vec<_> = answers.iter().filter(|a| a.0 != 200).collect();
    assert!(refused.is_empty(), "{refused:?}");
    // Each stream opened with the state and the current frame.
    for rx in &streams {
        wait_event(rx, WAIT, |n, _| n == "state");
        let (_, f) = wait_event(rx, WAIT, |n, _| n == "frame");
        assert_eq!(f["id"], st["frame"]["id"]);
    }
}

#[test]
fn a_save_during_a_render_cancels_it_and_the_new_version_is_shown() {
    let tmp = temp_dir("cancel");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    // Slow: 1000×750 at 64 samples a pixel takes many seconds on two cores.
    save(&scene, &scene_text(1000, 750, "1 0 0"));
    let s = Served::start(&scene, &["--spp", "64"]);
    let rx = s.events();
    wait_event(&rx, WAIT, |n, d| {
        n == "frame" && d["stage"] == "coarse" && d["version"] == 1
    });
    wait_event(&rx, WAIT, |n, d| {
        n == "progress" && d["version"] == 1 && d["done"].as_u64() > Some(0)
    });
    let saved = Instant::now();
    save(&scene, &scene_text(40, 30, "0 0 1"));
    let (_, coarse) = wait_event(&rx, WAIT, |n, d| n == "frame" && d["version"] == 2);
    let preview = saved.elapsed();
    assert_eq!(coarse["stage"], "coarse");
    // Everything from here on: no full image of version 1 ever comes.
    let (_, done) = wait_event(&rx, WAIT, |n, d| {
        assert!(
            !(n == "frame" && d["version"] == 1),
            "version 1's render went on: {d}"
        );
        n == "frame" && d["stage"] == "final"
    });
    assert_eq!(done["version"], 2);
    assert_eq!(done["width"], 40);
    eprintln!(
        "save to the new version's coarse frame event: {:.0} ms",
        preview.as_secs_f64() * 1e3
    );
}

#[test]
fn a_broken_file_keeps_the_last_picture_and_lists_its_diagnostics_until_fixed() {
    let tmp = temp_dir("broken");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(32, 24, "1 0 0"));
    let s = Served::start(&scene, &[]);
    s.wait_state(WAIT, |st| final_of(st, 1));
    let good = s.get("/api/image.png").body;
    let broken = scene_text(32, 24, "1 0 0").replace(" R= 1\n", " R= one\n");
    let line = broken
        .lines()
        .position(|l| l == " R= one")
        .map(|i| i + 1)
        .unwrap_or(0);
    save(&scene, &broken);
    let st = s.wait_state(WAIT, |st| st["stage"] == "broken");
    assert_eq!(st["version"], 2);
    assert_eq!(st["good_version"], 1);
    let d = &st["diagnostics"][0];
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], line as u64);
    assert_eq!(d["column"], 5);
    let place = format!("{}:{line}:5", scene.display());
    assert_eq!(d["place"], place.as_str());
    let text = d["text"].as_str().unwrap_or("");
    assert!(
        text.contains(&place) && text.contains("R= one") && text.contains('^'),
        "{text}"
    );
    // The last good picture stays, and explains as before.
    assert_eq!(s.get("/api/image.png").body, good);
    assert_eq!(s.get("/api/explain?x=16&y=12").status, 200);
    save(&scene, &scene_text(32, 24, "0 1 0"));
    let st = s.wait_state(WAIT, |st| final_of(st, 3));
    assert_eq!(st["errors"], 0);
    assert_eq!(st["diagnostics"].as_array().map(Vec::len), Some(0));
    assert_ne!(
        s.get("/api/image.png").body,
        good,
        "the green sphere is shown"
    );
}

#[test]
fn explain_is_glint_explains_json_and_its_rays_start_at_the_pixel() {
    let tmp = temp_dir("explain");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(40, 30, "1 1 1"));
    let s = Served::start(&scene, &["--spp", "1"]);
    s.wait_state(WAIT, |st| final_of(st, 1));
    let r = s.get("/api/explain?x=20&y=16");
    assert_eq!(r.status, 200, "{}", r.text());
    let got: serde_json::Value = serde_json::from_slice(&r.body).expect("JSON");
    let cli = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["explain", "--spp", "1", "--pixel", "20,16", "--json"])
        .arg(&scene)
        .output()
        .expect("glint explain");
    let want: serde_json::Value = serde_json::from_slice(&cli.stdout).expect("explain JSON");
    assert_eq!(got["explain"], want);
    assert_eq!(
        got["explain"]["samples"][0]["hit"]["primitive"], 0,
        "the sphere"
    );
    // The camera ray projects to the pixel's centre, both ends.
    let rays = got["rays"].as_array().cloned().unwrap_or_default();
    let camera = rays
        .iter()
        .find(|r| r["kind"] == "camera")
        .expect("a camera ray");
    for end in ["from", "to"] {
        let (x, y) = (
            camera[end][0].as_f64().unwrap_or(-1.0),
            camera[end][1].as_f64().unwrap_or(-1.0),
        );
        assert!(
            (x - 20.5).abs() < 1e-6 && (y - 16.5).abs() < 1e-6,
            "{end}: {x} {y}"
        );
    }
    assert!(
        rays.iter().any(|r| r["kind"] == "reflection"),
        "refl= 0.2 makes a reflected ray"
    );
    assert!(rays.iter().any(|r| r["kind"] == "shadow"));
}

#[test]
fn aovs_ids_and_a_watched_texture() {
    let tmp = temp_dir("aovs");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    let tex = dir.join("t.bmp");
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 0, 0]))
        .save(&tex)
        .expect("bmp");
    let text = scene_text(32, 24, "1 1 1").replace(" diff= 0.7\n", " diff= 0.7\n texture= t.bmp\n");
    save(&scene, &text);
    let s = Served::start(&scene, &["--spp", "1"]);
    let st = s.wait_state(WAIT, |st| st["stage"] == "idle" && st["good_version"] == 1);
    let files: Vec<String> = st["files"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|f| f["path"].as_str().map(String::from))
        .collect();
    assert_eq!(files.len(), 2, "{files:?}");
    assert!(files[1].ends_with("t.bmp"));
    assert_eq!(
        s.get("/api/file/1").body,
        std::fs::read(&tex).expect("read")
    );
    let aovs: Vec<&str> = st["aovs"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|p| p.as_str())
        .collect();
    for p in ["normal", "depth", "primitive", "albedo", "why", "light:0"] {
        assert!(aovs.contains(&p), "{p} in {aovs:?}");
    }
    for p in ["normal", "light-0", "light:0", "why"] {
        let r = s.get(&format!("/api/aov/{p}.png"));
        assert_eq!(r.status, 200, "{p}");
        assert_eq!(&r.body[1..4], b"PNG");
    }
    // The AOVs (rendered in bands) are glint render --aov's pictures.
    let out = dir.join("out.png");
    let rendered = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args([
            "render",
            "--quiet",
            "--spp",
            "1",
            "--aov",
            "normal,depth,why,light:0,primitive",
            "-o",
        ])
        .arg(&out)
        .arg(&scene)
        .status()
        .expect("glint render");
    assert!(rendered.success());
    for p in ["normal", "depth", "why", "light-0", "primitive"] {
        let ours = image::load_from_memory(&s.get(&format!("/api/aov/{p}.png")).body)
            .expect("png")
            .to_rgb8();
        let theirs = image::open(dir.join(format!("out.{p}.png")))
            .expect("AOV file")
            .to_rgb8();
        assert!(ours == theirs, "{p} differs from glint render --aov's");
    }
    // The id buffer: GLID, the size, runs covering every pixel; the sphere (0) and the plane (1) are seen.
    let ids = s.get("/api/ids").body;
    assert_eq!(&ids[..4], b"GLID");
    let word = |k: usize| u32::from_le_bytes([ids[k], ids[k + 1], ids[k + 2], ids[k + 3]]);
    assert_eq!((word(4), word(8)), (32, 24));
    let mut total = 0;
    let mut seen = std::collections::BTreeSet::new();
    for k in (12..ids.len()).step_by(8) {
        seen.insert(word(k) as i32);
        total += word(k + 4);
    }
    assert_eq!(total, 32 * 24);
    assert!(seen.contains(&0) && seen.contains(&1), "{seen:?}");
    let legend = &st["frame"]["legend"];
    assert_eq!(legend["0"]["type"], "sphere");
    assert_eq!(legend["0"]["line"], 12);
    // Saving the texture (rename-on-save) renders again.
    let before = s.get("/api/image.png").body;
    let tmp = dir.join("t.new.bmp");
    image::RgbImage::from_pixel(2, 2, image::Rgb([0, 0, 255]))
        .save(&tmp)
        .expect("bmp");
    std::fs::rename(&tmp, &tex).expect("rename");
    s.wait_state(WAIT, |st| final_of(st, 2));
    assert_ne!(s.get("/api/image.png").body, before);
}

#[test]
fn their_render_is_compared() {
    let tmp = temp_dir("compare");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(32, 24, "1 0 0"));
    let theirs = dir.join("theirs.png");
    image::RgbImage::new(32, 24).save(&theirs).expect("png");
    let s = Served::start(&scene, &["--compare", theirs.to_str().unwrap_or_default()]);
    let st = s.wait_state(WAIT, |st| st["stage"] == "idle" && !st["compare"].is_null());
    assert_eq!(st["theirs"], true);
    assert!(
        st["compare"]["differing"].as_u64() > Some(0),
        "theirs is black"
    );
    assert_eq!(st["compare"]["size"], serde_json::json!([32, 24]));
    for p in ["/api/theirs.png", "/api/heat.png"] {
        let r = s.get(p);
        assert_eq!(r.status, 200, "{p}");
        assert_eq!(&r.body[1..4], b"PNG");
    }
}

#[test]
fn a_missing_scene_or_picture_is_exit_2() {
    let tmp = temp_dir("missing");
    let dir = tmp.path();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["serve", "--port", "0"])
        .arg(dir.join("nope.txt"))
        .output()
        .expect("glint");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope.txt"));
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(8, 8, "1 0 0"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["serve", "--port", "0", "--compare"])
        .arg(dir.join("nope.bmp"))
        .arg(&scene)
        .output()
        .expect("glint");
    assert_eq!(out.status.code(), Some(2));
}

/// `cargo test --release --test serve -- --ignored --nocapture`: the
/// server's memory over 1000 saves (the figure in docs/serve.md).
#[test]
#[ignore]
fn memory_over_a_thousand_saves() {
    let tmp = temp_dir("soak");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    save(&scene, &scene_text(64, 48, "1 0 0"));
    let s = Served::start(&scene, &[]);
    let rx = s.events();
    let mut version = 1;
    let step = |version: u64| {
        let c = format!("{} 0.5 0", (version % 10) as f64 / 10.0);
        save(&scene, &scene_text(64, 48, &c));
        wait_event(&rx, WAIT, |n, d| {
            n == "state" && d["version"] == version && d["stage"] == "idle"
        });
    };
    s.wait_state(WAIT, |st| st["stage"] == "idle");
    for _ in 0..20 {
        version += 1;
        step(version);
    }
    let before = s.rss_kib();
    let start = Instant::now();
    for _ in 0..1000 {
        version += 1;
        step(version);
    }
    let after = s.rss_kib();
    eprintln!(
        "RSS after 20 saves: {before:?} KiB; after 1000 more: {after:?} KiB ({:.1} s, {:.0} ms a save)",
        start.elapsed().as_secs_f64(),
        start.elapsed().as_secs_f64() // 1000 saves: this many ms each
    );
}

#[test]
fn the_picture_sharpens_band_by_band_into_renders_bytes() {
    let tmp = temp_dir("bands");
    let dir = tmp.path();
    let scene = dir.join("scene.txt");
    // 320×640 at 16 samples a pixel: about a second on two cores, 20 bands.
    save(&scene, &scene_text(320, 640, "1 0.5 0"));
    let s = Served::start(&scene, &["--spp", "16"]);
    let rx = s.events();
    // The row under the pointer, for the next render; a bad one is refused.
    assert_eq!(s.get("/api/focus?y=600").status, 200);
    assert_eq!(s.get("/api/focus?y=top").status, 400);
    let stages = std::cell::RefCell::new(Vec::new());
    wait_event(&rx, WAIT, |n, d| {
        if n == "frame" && d["version"] == 1 {
            stages
                .borrow_mut()
                .push(d["stage"].as_str().unwrap_or("").to_string());
            // Every frame stands for the full size; the bands are full size too.
            assert_eq!(d["full"], serde_json::json!([320, 640]), "{d}");
            if d["stage"] == "bands" {
                assert_eq!(
                    (d["width"].as_u64(), d["height"].as_u64()),
                    (Some(320), Some(640))
                );
            }
        }
        n == "frame" && d["stage"] == "final" && d["version"] == 1
    });
    let stages = stages.into_inner();
    assert_eq!(
        stages.first().map(String::as_str),
        Some("coarse"),
        "{stages:?}"
    );
    assert_eq!(
        stages.last().map(String::as_str),
        Some("final"),
        "{stages:?}"
    );
    assert!(
        stages[1..stages.len() - 1].iter().all(|s| s == "bands") && stages.len() >= 3,
        "the bands come between the preview and the whole: {stages:?}"
    );
    // The whole is the very bytes of glint render.
    let out = dir.join("out.png");
    let rendered = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", "--quiet", "--spp", "16", "-o"])
        .arg(&out)
        .arg(&scene)
        .status()
        .expect("glint render");
    assert!(rendered.success());
    assert!(
        s.get("/api/image.png").body == std::fs::read(&out).expect("rendered"),
        "the page's final picture is not glint render's bytes"
    );
}
