//! What the server knows now, shared by the render worker (which writes
//! it) and the request handlers (which read it): the scene's version, the
//! diagnostics, the stage and progress of the render, the latest picture,
//! the last good renderer with its AOVs and comparison.

use super::events::Events;
use super::picture::Picture;
use crate::RenderOptions;
use crate::Renderer;
use crate::scene::{Diagnostic, Severity};
use serde_json::{Value, json};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

/// Where the render of the current version is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Phase {
    /// Reading the scene file.
    Reading,
    /// Rendering the coarse preview.
    Coarse,
    /// Rendering the full image.
    Final,
    /// Rendering the AOVs.
    Aovs,
    /// Comparing with their picture.
    Compare,
    /// Done: everything of this version is there.
    Idle,
    /// The scene has errors: the last good picture stays.
    Broken,
}

impl Phase {
    /// Its name in the API.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Reading => "reading",
            Phase::Coarse => "coarse",
            Phase::Final => "final",
            Phase::Aovs => "aovs",
            Phase::Compare => "compare",
            Phase::Idle => "idle",
            Phase::Broken => "broken",
        }
    }

    /// Whether a render is under way.
    pub fn rendering(self) -> bool {
        matches!(
            self,
            Phase::Reading | Phase::Coarse | Phase::Final | Phase::Aovs | Phase::Compare
        )
    }
}

/// The comparison with their picture, of the last good version.
pub(crate) struct Compared {
    /// `glint compare --json`'s object.
    pub summary: Value,
    /// The heat map as PNG.
    pub heat: Arc<Vec<u8>>,
}

/// The state the page and the API show.
pub(crate) struct State {
    /// Counts the scene's reads (each save makes a new version).
    pub version: u64,
    /// The version the last good picture was rendered from.
    pub good_version: Option<u64>,
    /// The full image's size (width, height) of the last good version.
    pub size: Option<(u32, u32)>,
    /// The render's stage.
    pub phase: Phase,
    /// The current version's errors and warnings.
    pub diagnostics: Vec<Diagnostic>,
    /// The latest picture shown (of the last good version).
    pub picture: Option<Arc<Picture>>,
    /// The last good scene, prepared, for `explain`.
    pub renderer: Option<Arc<Renderer>>,
    /// The AOVs of the last good version, as PNG, by name.
    pub aovs: Vec<(String, Arc<Vec<u8>>)>,
    /// The comparison with their picture, when asked for.
    pub compare: Option<Compared>,
    /// The files the page may fetch: the scene file, then what it read.
    pub files: Vec<PathBuf>,
    /// Milliseconds from noticing the save to each stage's image.
    pub timings: Vec<(&'static str, f64)>,
}

/// The state behind a lock, and the event streams it is announced on.
pub(crate) struct Shared {
    state: Mutex<State>,
    /// The pages' event streams.
    pub events: Events,
    /// The scene file as given.
    pub scene: PathBuf,
    /// Their picture as PNG (`--compare`).
    pub theirs: Option<Arc<Vec<u8>>>,
    /// How every version is rendered (and explained).
    pub options: RenderOptions,
    /// Camera rays done and in all, of the running stage.
    pub progress: [AtomicU64; 2],
    /// The last picture's number.
    pictures: AtomicU64,
    /// The row the pointer was last over on a page, plus one (0: none).
    focus: AtomicU64,
}

impl Shared {
    /// The state before the first read of `scene`.
    pub fn new(scene: PathBuf, theirs: Option<Arc<Vec<u8>>>, options: RenderOptions) -> Shared {
        Shared {
            state: Mutex::new(State {
                version: 0,
                good_version: None,
                size: None,
                phase: Phase::Reading,
                diagnostics: Vec::new(),
                picture: None,
                renderer: None,
                aovs: Vec::new(),
                compare: None,
                files: vec![scene.clone()],
                timings: Vec::new(),
            }),
            events: Events::default(),
            scene,
            theirs,
            options,
            progress: [AtomicU64::new(0), AtomicU64::new(0)],
            pictures: AtomicU64::new(0),
            focus: AtomicU64::new(0),
        }
    }

    /// Notes the row of the picture the pointer is over: the next render
    /// starts with the bands nearest it.
    pub fn set_focus_row(&self, row: u32) {
        self.focus.store(u64::from(row) + 1, Ordering::Relaxed);
    }

    /// The row the pointer was last over, if it was.
    pub fn focus_row(&self) -> Option<u32> {
        match self.focus.load(Ordering::Relaxed) {
            0 => None,
            r => u32::try_from(r - 1).ok(),
        }
    }

    /// The state, locked (a handler that panicked holding it left it usable).
    pub fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new picture's number.
    pub fn next_picture_id(&self) -> u64 {
        self.pictures.fetch_add(1, Ordering::Relaxed) + 1
    }

    /// Changes the state with `f` and announces the new state.
    pub fn update(&self, f: impl FnOnce(&mut State)) {
        let json = {
            let mut s = self.lock();
            f(&mut s);
            state_json(&s, self).to_string()
        };
        self.events.send("state", &json);
    }
}

/// A diagnostic as the API gives it, with its `file:line:col` and the
/// text `render` prints (line and caret).
pub(crate) fn diagnostic_json(d: &Diagnostic) -> Value {
    json!({
        "severity": match d.severity { Severity::Error => "error", Severity::Warning => "warning" },
        "message": d.message,
        "file": d.file,
        "line": d.line,
        "column": d.column,
        "len": d.len,
        "source_line": d.source_line,
        "help": d.help,
        "place": if d.line == 0 { d.file.clone() } else { format!("{}:{}:{}", d.file, d.line, d.column) },
        "text": d.render(false),
    })
}

/// The state as the API gives it (`GET /api/state`, the `state` event).
pub(crate) fn state_json(s: &State, shared: &Shared) -> Value {
    let done = shared.progress[0].load(Ordering::Relaxed);
    let total = shared.progress[1].load(Ordering::Relaxed);
    json!({
        "glint": env!("CARGO_PKG_VERSION"),
        "file": shared.scene.display().to_string(),
        "version": s.version,
        "good_version": s.good_version,
        "size": s.size.map(|(w, h)| [w, h]),
        "stage": s.phase.name(),
        "rendering": s.phase.rendering(),
        "progress": {
            "done": done,
            "total": total,
            "fraction": if total > 0 { done as f64 / total as f64 } else { 0.0 },
        },
        "errors": s.diagnostics.iter().filter(|d| d.severity == Severity::Error).count(),
        "diagnostics": s.diagnostics.iter().map(diagnostic_json).collect::<Vec<_>>(),
        "frame": s.picture.as_ref().map(|p| p.summary()),
        "aovs": s.aovs.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
        "compare": s.compare.as_ref().map(|c| &c.summary),
        "theirs": shared.theirs.is_some(),
        "files": s.files.iter().enumerate().map(|(i, p)| json!({"index": i, "path": p.display().to_string()})).collect::<Vec<_>>(),
        "timings_ms": s.timings.iter().map(|(k, v)| (k.to_string(), json!(v))).collect::<serde_json::Map<_, _>>(),
    })
}
