//! The page and the API, one GET path each: what every request is
//! answered with. Only fixed paths are served; the only files read are
//! those the scene references, chosen by their index in the state's list,
//! so no request can name a path.

use super::rays::{Projection, segments};
use super::state::{Shared, state_json};
use serde_json::json;
use std::sync::Arc;

/// The page, with `{{TOKEN}}` where the token goes.
const PAGE: &str = include_str!("page.html");
/// The page's script.
const SCRIPT: &str = include_str!("page.js");
/// The page's style sheet.
const STYLE: &str = include_str!("page.css");
/// A referenced file larger than this is not served.
const MAX_FILE: u64 = 64 << 20;

/// A response body.
pub(crate) enum Body {
    /// Text or bytes made for this request.
    Owned(Vec<u8>),
    /// Bytes the state holds (a picture).
    Shared(Arc<Vec<u8>>),
    /// Bytes built into glint.
    Static(&'static str),
}

impl Body {
    /// The bytes.
    pub fn bytes(&self) -> &[u8] {
        match self {
            Body::Owned(b) => b,
            Body::Shared(b) => b,
            Body::Static(s) => s.as_bytes(),
        }
    }
}

/// What a request is answered with.
pub(crate) enum Reply {
    /// A status, a content type and a body.
    Done(u16, &'static str, Body),
    /// The event stream (`text/event-stream`), kept open.
    Events,
}

/// A plain-text reply.
pub(crate) fn text(status: u16, message: &str) -> Reply {
    Reply::Done(
        status,
        "text/plain; charset=utf-8",
        Body::Owned(format!("{message}\n").into_bytes()),
    )
}

fn json_reply(value: &serde_json::Value) -> Reply {
    Reply::Done(
        200,
        "application/json",
        Body::Owned(value.to_string().into_bytes()),
    )
}

/// The value of `key` in the decoded query pairs.
pub(crate) fn param<'q>(query: &'q [(String, String)], key: &str) -> Option<&'q str> {
    query
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

/// Answers GET `path` (already checked to be plain: no `..`, `%`, `\`)
/// with `query`, for a request that carried the token `token`.
pub(crate) fn route(shared: &Shared, token: &str, path: &str, query: &[(String, String)]) -> Reply {
    match path {
        "/" | "/index.html" => Reply::Done(
            200,
            "text/html; charset=utf-8",
            Body::Owned(PAGE.replace("{{TOKEN}}", token).into_bytes()),
        ),
        "/page.js" => Reply::Done(200, "text/javascript; charset=utf-8", Body::Static(SCRIPT)),
        "/page.css" => Reply::Done(200, "text/css; charset=utf-8", Body::Static(STYLE)),
        "/api/state" => {
            let s = shared.lock();
            json_reply(&state_json(&s, shared))
        }
        "/api/events" => Reply::Events,
        "/api/image.png" | "/api/ids" => picture_part(shared, path == "/api/ids", query),
        "/api/explain" => explain(shared, query),
        "/api/focus" => match param(query, "y").map(str::parse::<u32>) {
            Some(Ok(row)) => {
                shared.set_focus_row(row);
                text(
                    200,
                    "ok: the next render starts with the bands nearest that row",
                )
            }
            _ => text(
                400,
                "bad request: focus takes y=ROW, the picture's row under the pointer",
            ),
        },
        "/api/theirs.png" => match &shared.theirs {
            Some(png) => Reply::Done(200, "image/png", Body::Shared(png.clone())),
            None => text(404, "not found: glint serve was started without --compare"),
        },
        "/api/heat.png" => match shared.lock().compare.as_ref() {
            Some(c) if !c.heat.is_empty() => {
                Reply::Done(200, "image/png", Body::Shared(c.heat.clone()))
            }
            _ => text(404, "not found: no comparison (yet)"),
        },
        _ => {
            if let Some(name) = path
                .strip_prefix("/api/aov/")
                .and_then(|n| n.strip_suffix(".png"))
            {
                return aov_png(shared, name);
            }
            if let Some(index) = path.strip_prefix("/api/file/") {
                return file(shared, index);
            }
            text(404, "not found")
        }
    }
}

/// The current picture's PNG or id buffer (`?frame=ID`: only while that
/// picture is the current one, else 410 Gone: a newer one is announced).
fn picture_part(shared: &Shared, ids: bool, query: &[(String, String)]) -> Reply {
    let Some(picture) = shared.lock().picture.clone() else {
        return text(404, "no picture yet");
    };
    if let Some(want) = param(query, "frame") {
        match want.parse::<u64>() {
            Ok(id) if id == picture.id => {}
            Ok(_) => return text(410, "that frame is gone: a newer one is current"),
            Err(_) => return text(400, "bad request: frame= takes a frame number"),
        }
    }
    if ids {
        Reply::Done(
            200,
            "application/octet-stream",
            Body::Shared(picture.ids.clone()),
        )
    } else {
        Reply::Done(200, "image/png", Body::Shared(picture.png.clone()))
    }
}

/// An AOV of the last good version as PNG (`light:0` may be written `light-0`).
fn aov_png(shared: &Shared, name: &str) -> Reply {
    let s = shared.lock();
    let found = s
        .aovs
        .iter()
        .find(|(n, _)| n == name || n.replace(':', "-") == name);
    match found {
        Some((_, png)) => Reply::Done(200, "image/png", Body::Shared(png.clone())),
        None => text(404, "no such AOV (yet): see `aovs` in /api/state"),
    }
}

/// File `index` of the state's list (0: the scene file), as it is now.
fn file(shared: &Shared, index: &str) -> Reply {
    let Ok(i) = index.parse::<usize>() else {
        return text(
            400,
            "bad request: /api/file/N takes the file's index in /api/state",
        );
    };
    let Some(path) = shared.lock().files.get(i).cloned() else {
        return text(404, "no such file: see `files` in /api/state");
    };
    let read = std::fs::metadata(&path).and_then(|m| {
        if !m.is_file() || m.len() > MAX_FILE {
            return Err(std::io::Error::other(
                "not a regular file of at most 64 MiB",
            ));
        }
        std::fs::read(&path)
    });
    let kind = match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => "image/png",
        Some("bmp") => "image/bmp",
        Some("jpg" | "jpeg") => "image/jpeg",
        Some("txt" | "obj" | "mtl") => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    };
    match read {
        Ok(bytes) => Reply::Done(200, kind, Body::Owned(bytes)),
        Err(e) => text(404, &format!("cannot read {}: {e}", path.display())),
    }
}

/// `explain` of pixel `?x=&y=` of the last good version: `glint explain
/// --json`'s object, and its rays projected onto the picture.
fn explain(shared: &Shared, query: &[(String, String)]) -> Reply {
    let coord = |k: &str| param(query, k).and_then(|v| v.parse::<u32>().ok());
    let (Some(x), Some(y)) = (coord("x"), coord("y")) else {
        return text(
            400,
            "bad request: /api/explain takes ?x=COLUMN&y=ROW (whole numbers)",
        );
    };
    let (renderer, version) = {
        let s = shared.lock();
        (s.renderer.clone(), s.good_version)
    };
    let Some(renderer) = renderer else {
        return text(409, "no picture yet: the scene has not been rendered");
    };
    let options = crate::RenderOptions {
        threads: Some(1),
        aovs: Vec::new(),
        region: None,
        ..shared.options.clone()
    };
    let e = match renderer.explain(&options, x, y) {
        Ok(e) => e,
        Err(err) => return text(400, &format!("bad request: {err}")),
    };
    let Ok((w, h)) = renderer.frame_size(&options) else {
        return text(400, "bad request: the frame size is out of range");
    };
    let scene = renderer.scene();
    let lens = crate::integrator::Model::of(scene.dialect().dialect, scene.camera()).lens;
    let view = Projection::new(scene.camera(), lens, w, h);
    let rays = segments(&e.samples, scene.lights(), &view);
    let tree: serde_json::Value = serde_json::from_str(&e.to_json(false)).unwrap_or_default();
    json_reply(&json!({
        "version": version,
        "size": [w, h],
        "explain": tree,
        "text": e.to_text(false),
        "rays": rays,
    }))
}
