//! What a part was rendered from: glint's version and build, the scene
//! file and every texture and mesh it read (their checksums), and every
//! option that changes a pixel. Parts of one picture share it exactly.

use crate::render::{RenderError, RenderOptions, Renderer, TILE_BAND};
use serde_json::{Value, json};
use std::path::Path;

/// What a part was rendered from, as a JSON object (stored in its file).
#[derive(Clone, Debug, PartialEq)]
pub struct Fingerprint(Value);

impl Fingerprint {
    /// The fingerprint of a render of `renderer`'s scene with `options`,
    /// cut into `count` parts; an error when a file it read cannot be read again.
    pub fn of(
        renderer: &Renderer,
        options: &RenderOptions,
        count: u32,
    ) -> Result<Fingerprint, FingerprintError> {
        let (w, h) = renderer.frame_size(options)?;
        let scene = renderer.scene();
        let file = |path: &Path| -> Result<Value, FingerprintError> {
            let bytes = std::fs::read(path).map_err(|e| FingerprintError::Read {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
            Ok(json!({
                "name": path.file_name().map(|n| n.to_string_lossy().into_owned()),
                "bytes": bytes.len(),
                "crc32": crc32fast::hash(&bytes),
            }))
        };
        let scene_file = scene.path().map(file).transpose()?;
        let inputs: Vec<Value> = scene
            .files()
            .iter()
            .map(|p| file(p))
            .collect::<Result<_, _>>()?;
        let region = options.region.map(|r| [r.x, r.y, r.width, r.height]);
        let p = &options.photons;
        Ok(Fingerprint(json!({
            "glint": env!("CARGO_PKG_VERSION"),
            "build": build(),
            "scene": scene_file,
            "inputs": inputs,
            "dialect": scene.dialect().dialect.name(),
            "width": w,
            "height": h,
            "region": region,
            "sampling": options.spp.map_or(json!("adaptive"), |n| json!({"spp": n})),
            "seed": options.seed,
            "photons": {
                "mode": p.mode.map(|m| m.name()),
                "iterations": p.iterations,
                "emit": p.emit,
                "filter": p.filter.name(),
            },
            "aovs": options.aovs.iter().map(|a| a.name()).collect::<Vec<_>>(),
            "parts": count,
            "band": TILE_BAND,
        })))
    }

    /// The fingerprint stored as `value` (a JSON object).
    pub(super) fn from_json(value: Value) -> Option<Fingerprint> {
        value.is_object().then_some(Fingerprint(value))
    }

    /// As JSON.
    pub fn to_json(&self) -> &Value {
        &self.0
    }

    /// The parts it was cut into.
    pub fn parts(&self) -> Option<u32> {
        self.0["parts"].as_u64().and_then(|n| u32::try_from(n).ok())
    }

    /// What differs from `other`, key by key: `seed 8, not 7`.
    pub fn differences(&self, other: &Fingerprint) -> Vec<String> {
        let (Some(a), Some(b)) = (self.0.as_object(), other.0.as_object()) else {
            return vec!["not a fingerprint".to_string()];
        };
        let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
        keys.sort();
        keys.dedup();
        keys.into_iter()
            .filter(|k| a.get(*k) != b.get(*k))
            .map(|k| {
                let v = |m: &serde_json::Map<String, Value>| {
                    m.get(k).map_or("nothing".to_string(), Value::to_string)
                };
                format!("{k} {}, not {}", v(a), v(b))
            })
            .collect()
    }
}

/// This program's build: its version and a checksum of its executable (the
/// same binary on every node gives the same bytes).
fn build() -> Value {
    let exe = std::env::current_exe().and_then(std::fs::read);
    match exe {
        Ok(bytes) => json!({"bytes": bytes.len(), "crc32": crc32fast::hash(&bytes)}),
        Err(_) => Value::Null,
    }
}

/// Why a fingerprint could not be taken.
#[derive(Debug, thiserror::Error)]
pub enum FingerprintError {
    /// The render's options are not valid for the scene.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A file the scene read cannot be read again.
    #[error("{path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
}
