//! One part's file, `tile-I-of-N.glt`: a signature, the format's version,
//! a JSON header (the part, its fingerprint, the command that rendered it,
//! its runs of bands, its AOVs, the primitives its `primitive` AOV shows,
//! its figures), the runs' linear f32 pixels (colour, then each AOV), and
//! a CRC-32 of all that.

use super::fingerprint::{Fingerprint, FingerprintError};
use crate::output::{PrimitiveTable, write_atomically};
use crate::render::{Aov, Control, Film, Region, RenderOptions, RenderStats, Renderer, Tile};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// The first bytes of every tile file.
const SIGNATURE: &[u8; 8] = b"\x89GLT\r\n\x1a\n";

/// The version of the format this glint writes (and the newest it reads).
pub const TILE_FORMAT: u32 = 1;

/// A part of a render as its file holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct TileFile {
    /// Which part.
    pub tile: Tile,
    /// What it was rendered from.
    pub fingerprint: Fingerprint,
    /// The command line that rendered it.
    pub command: Vec<String>,
    /// The scene's file name as the command gave it (named in AOV legends).
    pub scene_file: Option<String>,
    /// The full frame's size (width, height).
    pub frame: (u32, u32),
    /// The films of its runs of bands, top to bottom.
    pub films: Vec<Film>,
    /// The kind and line of each primitive its `primitive` AOV shows.
    pub legend: BTreeMap<u32, (String, Option<u32>)>,
    /// Its figures: counts of rays and pixels (free-form, for people; no
    /// times, so that a part rendered again writes the same bytes).
    pub figures: Value,
}

/// Why a file is not a tile glint can read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TileError {
    /// Not a tile file at all.
    #[error("not a glint tile file (its first bytes are not a tile's)")]
    NotATile,
    /// Written by a newer glint.
    #[error("written by a newer glint (tile format {0}; this glint reads up to {TILE_FORMAT})")]
    Newer(u32),
    /// Its checksum or its structure is wrong (cut short, changed).
    #[error("{0}")]
    Corrupt(String),
}

impl TileFile {
    /// The file name of `tile`: `tile-I-of-N.glt`.
    pub fn name(tile: Tile) -> String {
        format!("tile-{}-of-{}.glt", tile.index, tile.count)
    }

    /// The part named by a file name `tile-I-of-N.glt`, if it is one.
    pub fn parse_name(name: &str) -> Option<Tile> {
        let rest = name.strip_prefix("tile-")?.strip_suffix(".glt")?;
        let (i, n) = rest.split_once("-of-")?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        if !digits(i) || !digits(n) {
            return None;
        }
        Tile::new(i.parse().ok()?, n.parse().ok()?)
    }

    /// The primitive table of its legend, for the AOVs' pictures.
    pub fn primitive_table(&self) -> PrimitiveTable {
        self.legend
            .iter()
            .map(|(&i, (kind, line))| (i, (crate::geometry::kind_name_of(kind), *line)))
            .collect()
    }

    /// The file's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let region = |r: &Region| json!([r.x, r.y, r.width, r.height]);
        let aovs: Vec<_> = self
            .films
            .first()
            .map(|f| f.aovs().iter().map(|a| a.aov.name()).collect())
            .unwrap_or_default();
        let legend: Vec<Value> = self
            .legend
            .iter()
            .map(|(i, (kind, line))| json!([i, kind, line]))
            .collect();
        let header = json!({
            "tile": [self.tile.index, self.tile.count],
            "fingerprint": self.fingerprint.to_json(),
            "command": self.command,
            "scene_file": self.scene_file,
            "frame": [self.frame.0, self.frame.1],
            "runs": self.films.iter().map(|f| region(&f.region())).collect::<Vec<_>>(),
            "aovs": aovs,
            "legend": legend,
            "figures": self.figures,
        })
        .to_string();
        let mut out = Vec::new();
        out.extend_from_slice(SIGNATURE);
        out.extend_from_slice(&TILE_FORMAT.to_le_bytes());
        out.extend_from_slice(&(header.len() as u64).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        for film in &self.films {
            for p in film.image().pixels() {
                p.iter()
                    .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
            }
            for aov in film.aovs() {
                aov.data
                    .iter()
                    .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
            }
        }
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Reads a tile file's bytes.
    pub fn decode(bytes: &[u8]) -> Result<TileFile, TileError> {
        let corrupt = |why: &str| TileError::Corrupt(why.to_string());
        if bytes.len() < SIGNATURE.len() || &bytes[..SIGNATURE.len()] != SIGNATURE {
            return Err(TileError::NotATile);
        }
        let word = |at: usize| bytes.get(at..at + 4).map(|b| [b[0], b[1], b[2], b[3]]);
        let version = u32::from_le_bytes(word(8).ok_or_else(|| corrupt("cut short"))?);
        if version > TILE_FORMAT {
            return Err(TileError::Newer(version));
        }
        if bytes.len() < 12 + 8 + 4 {
            return Err(corrupt("cut short"));
        }
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        if crc32fast::hash(body) != u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]) {
            return Err(corrupt(
                "its checksum does not match its content (cut short or changed)",
            ));
        }
        let mut at: usize = 12;
        let mut take = |n: usize| -> Result<&[u8], TileError> {
            let part = at
                .checked_add(n)
                .and_then(|end| body.get(at..end))
                .ok_or_else(|| corrupt("cut short"))?;
            at += n;
            Ok(part)
        };
        let len = take(8)?;
        let len = u64::from_le_bytes([
            len[0], len[1], len[2], len[3], len[4], len[5], len[6], len[7],
        ]);
        let len = usize::try_from(len).map_err(|_| corrupt("a header past the file's end"))?;
        let header: Value = serde_json::from_slice(take(len)?)
            .map_err(|e| TileError::Corrupt(format!("its header is not JSON: {e}")))?;
        let bad = |what: &str| TileError::Corrupt(format!("its header has no valid `{what}`"));
        let pair = |v: &Value, what: &str| -> Result<(u32, u32), TileError> {
            match v
                .as_array()
                .map(|a| a.iter().map(|x| x.as_u64()).collect::<Vec<_>>())
            {
                Some(a) if a.len() == 2 => match (a[0], a[1]) {
                    (Some(x), Some(y)) => Ok((
                        u32::try_from(x).map_err(|_| bad(what))?,
                        u32::try_from(y).map_err(|_| bad(what))?,
                    )),
                    _ => Err(bad(what)),
                },
                _ => Err(bad(what)),
            }
        };
        let (index, count) = pair(&header["tile"], "tile")?;
        let tile = Tile::new(index, count).ok_or_else(|| bad("tile"))?;
        let frame = pair(&header["frame"], "frame")?;
        let fingerprint = Fingerprint::from_json(header["fingerprint"].clone())
            .ok_or_else(|| bad("fingerprint"))?;
        let strings = |v: &Value, what: &str| -> Result<Vec<String>, TileError> {
            v.as_array()
                .ok_or_else(|| bad(what))?
                .iter()
                .map(|s| s.as_str().map(str::to_string).ok_or_else(|| bad(what)))
                .collect()
        };
        let command = strings(&header["command"], "command")?;
        let aov_names = strings(&header["aovs"], "aovs")?;
        let aovs = match aov_names.is_empty() {
            true => Vec::new(),
            false => Aov::parse_list(&aov_names.join(",")).map_err(|_| bad("aovs"))?,
        };
        let scene_file = header["scene_file"].as_str().map(str::to_string);
        let mut legend = BTreeMap::new();
        for entry in header["legend"].as_array().ok_or_else(|| bad("legend"))? {
            let (Some(i), Some(kind)) = (entry[0].as_u64(), entry[1].as_str()) else {
                return Err(bad("legend"));
            };
            let line = entry[2].as_u64().and_then(|l| u32::try_from(l).ok());
            legend.insert(
                u32::try_from(i).map_err(|_| bad("legend"))?,
                (kind.to_string(), line),
            );
        }
        let mut films = Vec::new();
        for run in header["runs"].as_array().ok_or_else(|| bad("runs"))? {
            let n: Vec<u32> = run
                .as_array()
                .ok_or_else(|| bad("runs"))?
                .iter()
                .map(|v| v.as_u64().and_then(|v| u32::try_from(v).ok()))
                .collect::<Option<_>>()
                .ok_or_else(|| bad("runs"))?;
            let [x, y, width, height] = n[..] else {
                return Err(bad("runs"));
            };
            let region = Region {
                x,
                y,
                width,
                height,
            };
            if !region.fits(frame.0, frame.1) {
                return Err(bad("runs"));
            }
            let pixels = region.area() as usize;
            let mut floats = |n: usize| -> Result<Vec<f32>, TileError> {
                let raw = take(n.checked_mul(4).ok_or_else(|| corrupt("cut short"))?)?;
                Ok(raw
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect())
            };
            let color = floats(pixels * 3)?;
            let rgb = color.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let image = crate::image::Image::from_pixels(width, height, rgb);
            let mut film = Film::new(frame, region, image);
            for &aov in &aovs {
                let data = floats(pixels * aov.channels())?;
                film.set_aov(aov, data);
            }
            films.push(film);
        }
        if at != body.len() {
            return Err(corrupt("bytes past its last run"));
        }
        Ok(TileFile {
            tile,
            fingerprint,
            command,
            scene_file,
            frame,
            films,
            legend,
            figures: header["figures"].clone(),
        })
    }

    /// Renders part `options.tile` of `renderer`'s picture (all of it, one
    /// part of one, without) into a tile file recording `command`, with the
    /// render's figures; an error when the render fails or a file the
    /// scene read cannot be read again for its fingerprint.
    pub fn render(
        renderer: &Renderer,
        options: &RenderOptions,
        control: Control<'_>,
        command: Vec<String>,
    ) -> Result<(TileFile, RenderStats), FingerprintError> {
        let tile = options.tile.unwrap_or(Tile { index: 0, count: 1 });
        let fingerprint = Fingerprint::of(renderer, options, tile.count)?;
        let options = RenderOptions {
            tile: Some(tile),
            ..options.clone()
        };
        let (films, stats) = renderer.render_parts(&options, control)?;
        // The primitives its `primitive` AOV shows, for the legend.
        let shown: BTreeSet<u32> = films
            .iter()
            .filter_map(|f| f.aov(Aov::Primitive))
            .flat_map(|p| p.data.iter().copied())
            .filter(|&v| v >= 0.0)
            .map(|v| v as u32)
            .collect();
        let table = renderer.primitive_table();
        let file = TileFile {
            tile,
            fingerprint,
            command,
            scene_file: renderer.scene_file(),
            frame: renderer.frame_size(&options)?,
            films,
            legend: shown
                .into_iter()
                .filter_map(|i| table.get(&i).map(|(k, l)| (i, (k.to_string(), *l))))
                .collect(),
            // Counts only: the times go to the summary line, so a part
            // rendered again (a requeue, a duplicate) writes the same bytes.
            figures: json!({
                "rays": stats.rays.total(),
                "refined_pixels": stats.refined_pixels,
                "photon_rays": stats.photons.rays,
            }),
        };
        Ok((file, stats))
    }

    /// Writes it as `dir/tile-I-of-N.glt`, atomically (a temporary file
    /// named for this host and process, synced, renamed), unless `cancel`
    /// is set first; the path written.
    pub fn write(&self, dir: &Path, cancel: &AtomicBool) -> std::io::Result<PathBuf> {
        let path = dir.join(TileFile::name(self.tile));
        write_atomically(&path, &self.encode(), cancel)?;
        // The rename itself, durable on the folder's disk.
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(path)
    }

    /// Reads the tile file at `path`.
    pub fn read(path: &Path) -> Result<TileFile, ReadError> {
        let bytes = std::fs::read(path).map_err(|e| ReadError::Io(e.to_string()))?;
        TileFile::decode(&bytes).map_err(ReadError::Tile)
    }
}

/// Why a tile file could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// The file could not be read.
    #[error("{0}")]
    Io(String),
    /// Its content is not a tile glint reads.
    #[error(transparent)]
    Tile(#[from] TileError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{Renderer, Tile};
    use crate::scene::Scene;

    fn tile() -> TileFile {
        let text = include_str!("../../tests/data/events.txt");
        let renderer = Renderer::new(Scene::parse(text, ".").expect("the test's scene parses")); // invariant: the project's own test scene parses (tests/render.rs renders it too)
        let options = RenderOptions {
            width: Some(12),
            height: Some(70),
            spp: Some(1),
            aovs: vec![Aov::Normal, Aov::Primitive],
            tile: Some(Tile { index: 1, count: 2 }),
            ..RenderOptions::default()
        };
        let command = vec!["glint".to_string(), "render".to_string()];
        TileFile::render(&renderer, &options, Control::default(), command)
            .expect("renders") // invariant: a 12×70 part of that scene, never cancelled, renders
            .0
    }

    #[test]
    fn a_tile_reads_back_as_written_and_any_damage_is_an_error_not_a_panic() {
        let file = tile();
        assert_eq!(
            file.legend.values().map(|(k, _)| k.as_str()).next(),
            Some("plane")
        );
        let bytes = file.encode();
        assert_eq!(TileFile::decode(&bytes).as_ref(), Ok(&file));
        // Every cut, and a changed byte at many places: an error each.
        for n in (0..bytes.len()).step_by(7) {
            assert!(TileFile::decode(&bytes[..n]).is_err(), "cut at {n}");
        }
        for at in (0..bytes.len()).step_by(5) {
            let mut changed = bytes.clone();
            changed[at] ^= 0x5a;
            assert!(TileFile::decode(&changed).is_err(), "byte {at} changed");
        }
        // A header that lies, with a checksum that matches: refused, no
        // allocation of what it claims.
        let len = u64::from_le_bytes(bytes[12..20].try_into().expect("8 bytes")) as usize; // invariant: a slice of 8 bytes makes a [u8; 8]
        let header = std::str::from_utf8(&bytes[20..20 + len]).expect("a JSON header"); // invariant: `encode` writes the header as JSON text, checked by the decode above
        assert!(header.contains("[0,32,12,32]"), "{header}");
        let lie = header.replace("[0,32,12,32]", "[0,32,12,4000000000]");
        let mut forged = bytes[..12].to_vec();
        forged.extend_from_slice(&(lie.len() as u64).to_le_bytes());
        forged.extend_from_slice(lie.as_bytes());
        forged.extend_from_slice(&bytes[20 + len..bytes.len() - 4]);
        let crc = crc32fast::hash(&forged);
        forged.extend_from_slice(&crc.to_le_bytes());
        assert!(matches!(
            TileFile::decode(&forged),
            Err(TileError::Corrupt(_))
        ));
    }
}
