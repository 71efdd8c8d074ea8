//! `glint check`: a linter for scene files, without a full render. Each
//! lint is one concept in a file of its own; each [`Finding`] names the
//! block's `file:line`, what is wrong and what to change. Findings are
//! warnings: the scene renders, but probably not as its author meant.
//!
//! The lints, in the order they run:
//!
//! - [`materials`]: `rindex=` below 1 with `refr=`, all-zero materials,
//!   `diff + refl + refr` above 1;
//! - [`inside`]: a light inside a closed object or inside glass, the camera
//!   inside an object;
//! - [`view`]: objects behind the camera or outside the view, a lens whose
//!   aspect is not the image's;
//! - [`faces`]: coincident faces, squares whose edges do not meet (the
//!   cracks of six-square cubes), degenerate shapes;
//! - [`lighting`]: a coarse grid of camera rays: primitives seen only from
//!   the side that faces away from every light, and visible primitives that
//!   no light reaches;
//!
//! The report also says which dialect the file is read in, and why (not a
//! finding: every file has one).
//!
//! The reader's own warnings (and, when a scene cannot be read, its errors)
//! come first, as findings of code [`Code::Format`].

mod faces;
mod finding;
mod inside;
mod lighting;
mod materials;
mod primitive_blocks;
mod view;

pub use finding::{Code, Finding, from_diagnostic};

use crate::render::{Driver, RenderOptions, Renderer};
use crate::scene::{Diagnostic, DialectChoice, Severity};
use finding::Findings;
use serde_json::{Value, json};
use std::fmt::Write;

/// What `check` says of a scene: its findings and what a render would cost.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckReport {
    /// The scene file's name as given.
    pub file: Option<String>,
    /// Every finding, in the order the lints ran (the reader's first).
    pub findings: Vec<Finding>,
    /// Rays a default render traces (about), `None` when the scene could not be read.
    pub rays: Option<u64>,
    /// What drives that count (image size, qualities).
    pub drivers: Vec<Driver>,
    /// The dialect the file is read in and why, `None` when it could not be read.
    pub dialect: Option<DialectChoice>,
}

/// Rays a second the estimate of time assumes (what glint does on 2 cores).
pub const ESTIMATE_RAYS_PER_SECOND: f64 = 1e7;

/// Checks the scene `renderer` holds (read with `warnings`, the reader's):
/// every lint, and the estimate of a default render.
pub fn check(renderer: &Renderer) -> CheckReport {
    let scene = renderer.scene();
    let file = renderer.scene_file();
    let mut findings = Findings {
        scene,
        file: file.clone(),
        list: scene.warnings().iter().map(from_diagnostic).collect(),
    };
    let blocks = primitive_blocks::blocks(renderer);
    materials::check(&blocks, &mut findings);
    inside::check(renderer, &blocks, &mut findings);
    view::check(renderer, &blocks, &mut findings);
    faces::check(renderer, &blocks, &mut findings);
    lighting::check(renderer, &mut findings);
    let (rays, drivers) = match renderer.estimate(&RenderOptions::default()) {
        Ok(w) => (Some(w.rays), w.drivers),
        Err(_) => (None, Vec::new()),
    };
    CheckReport {
        file,
        findings: findings.list,
        rays,
        drivers,
        dialect: Some(scene.dialect().clone()),
    }
}

impl CheckReport {
    /// The report of a scene that could not be read: its diagnostics.
    pub fn unreadable(file: Option<String>, diagnostics: &[Diagnostic]) -> CheckReport {
        CheckReport {
            file,
            findings: diagnostics.iter().map(from_diagnostic).collect(),
            rays: None,
            drivers: Vec::new(),
            dialect: None,
        }
    }

    /// Findings that are warnings.
    pub fn warnings(&self) -> usize {
        self.count(Severity::Warning)
    }

    /// Findings that are errors.
    pub fn errors(&self) -> usize {
        self.count(Severity::Error)
    }

    fn count(&self, s: Severity) -> usize {
        self.findings.iter().filter(|f| f.severity == s).count()
    }

    /// The findings of the lints (those of code [`Code::Format`] left out:
    /// the reader prints its own diagnostics), one `file:line: warning[code]:
    /// message` with its help below each, then the dialect and the estimate.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        if let Some(d) = &self.dialect {
            let _ = writeln!(s, "{d}");
        }
        for f in self.findings.iter().filter(|f| f.code != Code::Format) {
            let at = crate::render::place(f.file.as_deref(), f.line);
            let _ = writeln!(s, "{at}: warning[{}]: {}", f.code.name(), f.message);
            if !f.help.is_empty() {
                let _ = writeln!(s, "  help: {}", f.help);
            }
        }
        if let Some(rays) = self.rays {
            let _ = writeln!(
                s,
                "estimate: about {:.1e} rays, {} at 10 Mrays/s ({})",
                rays as f64,
                seconds(rays as f64 / ESTIMATE_RAYS_PER_SECOND),
                joined(&self.drivers)
            );
        }
        let (e, w) = (self.errors(), self.warnings());
        let _ = writeln!(s, "{e} error(s), {w} warning(s)");
        s
    }

    /// One JSON object (schema: docs/debugging.md): `file`, `findings`
    /// (each `severity`, `code`, `file`, `line`, `message`, `help`),
    /// `errors`, `warnings`, `estimate` (`rays`, `seconds`, `drivers`; null
    /// when the scene could not be read).
    pub fn to_json(&self) -> Value {
        let findings: Vec<Value> = self
            .findings
            .iter()
            .map(|f| {
                json!({
                    "severity": match f.severity { Severity::Error => "error", Severity::Warning => "warning" },
                    "code": f.code.name(),
                    "file": f.file,
                    "line": f.line,
                    "message": f.message,
                    "help": f.help,
                })
            })
            .collect();
        let estimate = self.rays.map(|rays| {
            json!({
                "rays": rays,
                "seconds": rays as f64 / ESTIMATE_RAYS_PER_SECOND,
                "drivers": self.drivers.iter().map(Driver::to_string).collect::<Vec<_>>(),
            })
        });
        let dialect = self.dialect.as_ref().map(|d| {
            json!({
                "name": d.dialect.name(),
                "reason": d.reason,
                "caveat": d.caveat,
            })
        });
        json!({
            "file": self.file,
            "dialect": dialect,
            "findings": findings,
            "errors": self.errors(),
            "warnings": self.warnings(),
            "estimate": estimate,
        })
    }
}

/// The drivers as the estimate's line lists them.
fn joined(drivers: &[Driver]) -> String {
    let texts: Vec<String> = drivers.iter().map(Driver::to_string).collect();
    texts.join(", ")
}

/// Seconds as people say them.
fn seconds(s: f64) -> String {
    match s {
        s if s < 1.0 => "under a second".to_string(),
        s if s < 120.0 => format!("about {s:.0} s"),
        s if s < 7200.0 => format!("about {:.0} minutes", s / 60.0),
        s => format!("about {:.1} hours", s / 3600.0),
    }
}
