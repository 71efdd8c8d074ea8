//! A picture as the page receives it: the PNG, the id buffer (the
//! primitive under each pixel, run-length coded, so that hovering needs no
//! request) and the legend of the primitives it shows.

use crate::output::Format;
use crate::render::{Aov, Film, Renderer};
use serde_json::{Value, json};
use std::collections::BTreeSet;
use std::sync::Arc;

/// One picture of a version: the coarse preview or the full image (the
/// API calls it a frame: the `frame` event, `?frame=ID`).
pub(crate) struct Picture {
    /// Counts every picture made (the page asks for this one's files by it).
    pub id: u64,
    /// The scene's version it shows.
    pub version: u64,
    /// `coarse` or `final`.
    pub stage: &'static str,
    /// Its size in pixels.
    pub width: u32,
    /// Its height in pixels.
    pub height: u32,
    /// The full image's size it stands for (the coarse preview is a quarter of it).
    pub full: (u32, u32),
    /// The picture as PNG.
    pub png: Arc<Vec<u8>>,
    /// The id buffer: `GLID`, width and height (u32), then runs of (id,
    /// count) as i32 and u32, all little-endian, rows from the top; an id is
    /// the primitive block's index, −1 for nothing, −2 − n for light n's surface.
    pub ids: Arc<Vec<u8>>,
    /// What each id it holds is: `{"3": {"type": "sphere", "line": 12}, ...}`.
    pub legend: Value,
}

impl Picture {
    /// The picture of `film` (which holds a `primitive` plane) rendered by
    /// `renderer`, numbered `id`, of scene version `version`, standing for
    /// a `full`-sized image.
    pub fn new(
        id: u64,
        version: u64,
        stage: &'static str,
        full: (u32, u32),
        film: &Film,
        renderer: &Renderer,
    ) -> Result<Picture, String> {
        let image = film.image();
        let (width, height) = (image.width(), image.height());
        let png = image.encode(Format::Png)?;
        let values: Vec<i32> = match film.aov(Aov::Primitive) {
            Some(p) => p.data.iter().map(|&v| v as i32).collect(),
            None => vec![-1; width as usize * height as usize],
        };
        let ids = run_lengths(width, height, &values);
        let shown: BTreeSet<i32> = values.iter().copied().collect();
        let table = renderer.primitive_table();
        let mut legend = serde_json::Map::new();
        for id in shown {
            let entry = match id {
                -1 => continue,
                i if i >= 0 => {
                    let (kind, line) = table.get(&(i as u32)).copied().unwrap_or(("?", None));
                    json!({"type": kind, "line": line})
                }
                i => {
                    let light = (-2 - i) as u32;
                    json!({"type": "light", "light": light, "line": renderer.scene().light_line(light)})
                }
            };
            legend.insert(id.to_string(), entry);
        }
        Ok(Picture {
            id,
            version,
            stage,
            width,
            height,
            full,
            png: Arc::new(png),
            ids: Arc::new(ids),
            legend: Value::Object(legend),
        })
    }

    /// What the `frame` event and the state say of it.
    pub fn summary(&self) -> Value {
        json!({
            "id": self.id,
            "version": self.version,
            "stage": self.stage,
            "width": self.width,
            "height": self.height,
            "full": [self.full.0, self.full.1],
            "image": format!("/api/image.png?frame={}", self.id),
            "ids": format!("/api/ids?frame={}", self.id),
            "legend": self.legend,
        })
    }
}

/// `values` (row by row) as the id buffer's bytes (see [`Picture::ids`]).
pub(crate) fn run_lengths(width: u32, height: u32, values: &[i32]) -> Vec<u8> {
    let mut out = Vec::with_capacity(12 + 64);
    out.extend_from_slice(b"GLID");
    out.extend_from_slice(&width.to_le_bytes());
    out.extend_from_slice(&height.to_le_bytes());
    let mut i = 0;
    while i < values.len() {
        let v = values[i];
        let run = values[i..].iter().take_while(|&&x| x == v).count();
        out.extend_from_slice(&v.to_le_bytes());
        out.extend_from_slice(&(run as u32).to_le_bytes());
        i += run;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The page's decoder, in Rust: the runs expanded.
    fn expand(bytes: &[u8]) -> Vec<i32> {
        let word = |k: usize| [bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]];
        let mut out = Vec::new();
        let mut k = 12;
        while k + 8 <= bytes.len() {
            let v = i32::from_le_bytes(word(k));
            let n = u32::from_le_bytes(word(k + 4));
            out.extend(std::iter::repeat_n(v, n as usize));
            k += 8;
        }
        out
    }

    #[test]
    fn run_lengths_round_trip() {
        let values = vec![-1, -1, 3, 3, 3, -2, 0, -1, -1];
        let bytes = run_lengths(3, 3, &values);
        assert_eq!(&bytes[..4], b"GLID");
        assert_eq!(
            u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]),
            3
        );
        assert_eq!(expand(&bytes), values);
        assert_eq!(bytes.len(), 12 + 5 * 8);
        assert_eq!(expand(&run_lengths(0, 0, &[])), Vec::<i32>::new());
    }
}
