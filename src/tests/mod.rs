//! The crate's own test suites for its internals (geometry, the
//! acceleration structure, the Bézier root search, light sampling),
//! against independent references: closed forms, dense root scans,
//! brute force. The reference helpers are shared with the integration tests.

#[path = "../../tests/common/mod.rs"]
pub(crate) mod common;

mod accel;
mod bezier;
mod colon;
mod families;
/// The geometry suite, one file per shape; its helpers serve the OBJ reader's tests too.
pub(crate) mod geometry;
mod lights;
mod lineages;
mod parser;
mod photons;

use crate::Scene;
use crate::scene::Severity;

/// The messages of a scene's warnings (notes left out).
fn warnings(s: &Scene) -> Vec<String> {
    s.warnings()
        .iter()
        .filter(|d| d.severity == Severity::Warning)
        .map(|d| d.message.clone())
        .collect()
}
