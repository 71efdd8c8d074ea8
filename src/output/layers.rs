//! Writing a film's AOVs: as layers of one `.exr` beside the picture, or
//! (any other format) one image per AOV beside it, `OUT.AOV.EXT`, mapped
//! to 8 bits (normals as 0.5 + 0.5·n; depth, position and rays normalised,
//! their range in a sidecar `OUT.AOV.json`; primitives as false colours with a
//! legend `OUT.primitive.json`, the verdict's kinds likewise in `OUT.why.json`).

use super::atomic::write_atomically;
use super::picture::{Format, SaveError, encode_rgb8};
use crate::image::to_byte;
use crate::render::{Aov, AovImage, Cause, Film};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// What the legend says of a primitive block: its kind and header line.
pub type PrimitiveTable = BTreeMap<u32, (&'static str, Option<u32>)>;

/// The false colour of a primitive plane's value: black on a miss; a
/// block's index k maps to (k + 1)·0x9E3779B mod 2^24 (odd, so distinct
/// for up to 2^24 − 1 blocks); light n's surface to 2^24 − 1 − n.
pub fn primitive_colour(value: f32) -> [u8; 3] {
    let code: u32 = if value >= 0.0 {
        (value as u32).wrapping_add(1).wrapping_mul(0x09E3_779B) & 0xFF_FFFF
    } else if value <= -2.0 {
        0xFF_FFFF - ((-2.0 - value) as u32 & 0xFF_FFFF)
    } else {
        0
    };
    [(code >> 16) as u8, (code >> 8) as u8, code as u8]
}

/// `picture` with `.PASS` before its extension: `shot.png` -> `shot.normal.png`
/// (`light:N` is written `light-N`, a colon being no file name's on Windows).
pub fn aov_path(picture: &Path, aov: &str, ext: &str) -> PathBuf {
    let stem = picture.file_stem().unwrap_or_default().to_string_lossy();
    let aov = aov.replace(':', "-");
    picture.with_file_name(format!("{stem}.{aov}.{ext}"))
}

fn write_err(path: &Path, message: impl ToString) -> SaveError {
    SaveError::Write {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Writes what `render` writes of `film` at `picture`: with AOVs and an
/// `.exr`, one file of layers; otherwise the picture in its format and
/// each AOV beside it ([`save_aov_images`], `table()` naming the primitives,
/// `file` the scene's file name). Nothing more is written once `cancel` is set.
pub fn save_film(
    film: &Film,
    picture: &Path,
    table: impl FnOnce() -> PrimitiveTable,
    file: Option<&str>,
    cancel: &AtomicBool,
) -> Result<(), SaveError> {
    let exr = Format::from_path(picture)? == Format::Exr;
    if exr && !film.aovs().is_empty() {
        return save_exr_layers(film, picture, cancel);
    }
    film.image().save_unless(picture, cancel)?;
    if !film.aovs().is_empty() && !cancel.load(std::sync::atomic::Ordering::Relaxed) {
        save_aov_images(film, picture, &table(), file, cancel)?;
    }
    Ok(())
}

/// Writes the film's picture and its planes as the layers of one OpenEXR
/// file at `path` (`color`: R G B; then each plane under its name); nothing
/// is left when `cancel` is set before the file is in place.
pub fn save_exr_layers(film: &Film, path: &Path, cancel: &AtomicBool) -> Result<(), SaveError> {
    use exr::prelude::*;
    let img = film.image();
    let size = (img.width() as usize, img.height() as usize);
    let n = size.0 * size.1;
    let column = |data: &[f32], channels: usize, c: usize| -> Vec<f32> {
        (0..n).map(|i| data[i * channels + c]).collect()
    };
    let color: Vec<f32> = (0..n)
        .flat_map(|i| img.pixel((i % size.0) as u32, (i / size.0) as u32))
        .collect();
    let layer = |name: &str, data: &[f32], channels: &[&str]| {
        let list: Vec<AnyChannel<FlatSamples>> = channels
            .iter()
            .enumerate()
            .map(|(c, &ch)| AnyChannel::new(ch, FlatSamples::F32(column(data, channels.len(), c))))
            .collect();
        Layer::new(
            size,
            LayerAttributes::named(name),
            Encoding::FAST_LOSSLESS,
            AnyChannels::sort(SmallVec::from_vec(list)),
        )
    };
    let mut layers = vec![layer("color", &color, &["R", "G", "B"])];
    for p in film.aovs() {
        let names: &[&str] = match p.channels() {
            1 => &["Y"],
            2 => &["U", "V"],
            3 => &["X", "Y", "Z"],
            _ => continue,
        };
        layers.push(layer(&p.aov.name(), &p.data, names));
    }
    let image = Image::from_layers(
        ImageAttributes::new(IntegerBounds::from_dimensions(size)),
        layers,
    );
    let mut out = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut out)
        .map_err(|e| write_err(path, e))?;
    write_atomically(path, &out.into_inner(), cancel).map_err(|e| write_err(path, e))
}

/// The range of the finite values of channel `c` among the pixels `hit`.
fn range(p: &AovImage, c: usize, hit: &[bool]) -> (f32, f32) {
    let mut lo = f32::INFINITY;
    let mut hi = f32::NEG_INFINITY;
    for (px, &h) in p.data.chunks(p.channels()).zip(hit) {
        if h && px[c].is_finite() {
            lo = lo.min(px[c]);
            hi = hi.max(px[c]);
        }
    }
    if lo > hi { (0.0, 0.0) } else { (lo, hi) }
}

/// Writes each AOV of `film` beside `picture` as an 8-bit image of the
/// picture's format (with its sidecar or legend); returns the files written.
/// `table` names the primitives; `file` is the scene's file name; a file not
/// yet in place when `cancel` is set is not written.
pub fn save_aov_images(
    film: &Film,
    picture: &Path,
    table: &PrimitiveTable,
    file: Option<&str>,
    cancel: &AtomicBool,
) -> Result<Vec<PathBuf>, SaveError> {
    let format = Format::from_path(picture)?;
    let ext = picture
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    let hit = hit_mask(film);
    let (w, h) = (film.image().width(), film.image().height());
    // The AOVs are mapped, encoded and written on every core, as the
    // render's rows are (one after another, they left all cores but one idle).
    let each: Vec<Result<Vec<PathBuf>, SaveError>> = film
        .aovs()
        .par_iter()
        .map(|p| {
            let (rgb, sidecar) = aov_picture(p, &hit, table, file);
            let path = aov_path(picture, &p.aov.name(), &ext);
            let bytes = encode_rgb8(w, h, rgb, format).map_err(|e| write_err(&path, e))?;
            write_atomically(&path, &bytes, cancel).map_err(|e| write_err(&path, e))?;
            let mut written = vec![path];
            if let Some(json) = sidecar {
                let path = aov_path(picture, &p.aov.name(), "json");
                write_atomically(&path, format!("{json:#}\n").as_bytes(), cancel)
                    .map_err(|e| write_err(&path, e))?;
                written.push(path);
            }
            Ok(written)
        })
        .collect();
    // In the AOVs' order: their files, or the first one's error.
    let mut written = Vec::new();
    for files in each {
        written.extend(files?);
    }
    Ok(written)
}

/// Which pixels' centre ray hit something, from the film's primitive or
/// depth plane (all of them when it has neither).
pub(crate) fn hit_mask(film: &Film) -> Vec<bool> {
    let (w, h) = (film.image().width(), film.image().height());
    // The pixels whose centre ray hit something, from the primitive or depth plane.
    match (film.aov(Aov::Primitive), film.aov(Aov::Depth)) {
        (Some(p), _) => p.data.iter().map(|&v| v != -1.0).collect(),
        (None, Some(d)) => d.data.iter().map(|&v| v > 0.0).collect(),
        _ => vec![true; (w * h) as usize],
    }
}

/// AOV `p` of a film as the 8-bit RGB picture `save_aov_images` writes
/// (the film's size, rows from the top), with its sidecar or legend (`hit`
/// from [`hit_mask`]).
pub(crate) fn aov_picture(
    p: &AovImage,
    hit: &[bool],
    table: &PrimitiveTable,
    file: Option<&str>,
) -> (Vec<u8>, Option<serde_json::Value>) {
    // Each pixel's three bytes, written in place (black where nothing was hit).
    let mut bytes = vec![0u8; hit.len() * 3];
    let pixels = bytes.chunks_exact_mut(3);
    let sidecar = match p.aov {
        Aov::Why => {
            let mut legend = serde_json::Map::new();
            let mut seen = Seen::default();
            for (o, &v) in pixels.zip(&p.data) {
                let kind = Cause::ALL
                    .get(v as usize)
                    .copied()
                    .unwrap_or(Cause::Background);
                let c = kind.colour();
                if seen.first(v) {
                    legend.entry(colour_key(c)).or_insert_with(
                        || serde_json::json!({"index": v as u32, "kind": kind.name()}),
                    );
                }
                o.copy_from_slice(&c);
            }
            Some(serde_json::Value::Object(legend))
        }
        Aov::Primitive => {
            let mut legend = serde_json::Map::new();
            let mut seen = Seen::default();
            for (o, &v) in pixels.zip(&p.data) {
                let c = primitive_colour(v);
                if v != -1.0 && seen.first(v) {
                    legend
                        .entry(colour_key(c))
                        .or_insert_with(|| legend_entry(v, table, file));
                }
                o.copy_from_slice(&c);
            }
            Some(serde_json::Value::Object(legend))
        }
        aov => {
            let scaled = matches!(aov, Aov::Depth | Aov::Position | Aov::Rays | Aov::Cost);
            let channels = p.channels();
            let last = channels - 1;
            let hits = pixels
                .zip(p.data.chunks_exact(channels))
                .zip(hit)
                .filter(|(_, h)| **h);
            if scaled {
                let ranges: Vec<(f32, f32)> = (0..channels).map(|c| range(p, c, hit)).collect();
                for ((o, v), _) in hits {
                    for (c, b) in o.iter_mut().enumerate() {
                        let ch = c.min(last);
                        let (lo, hi) = ranges[ch];
                        *b = to_byte(if hi > lo {
                            (v[ch] - lo) / (hi - lo)
                        } else {
                            1.0
                        });
                    }
                }
                Some(serde_json::json!({
                    "min": ranges.iter().map(|r| r.0).collect::<Vec<_>>(),
                    "max": ranges.iter().map(|r| r.1).collect::<Vec<_>>(),
                    "mapping": "byte = floor(255 * (value - min) / (max - min)); pixels that hit nothing are black",
                }))
            } else {
                // Normals as 0.5 + 0.5·n, the rest as they are.
                let (base, gain) = if aov == Aov::Normal {
                    (0.5, 0.5)
                } else {
                    (0.0, 1.0)
                };
                for ((o, v), _) in hits {
                    for (b, x) in o.iter_mut().zip(v) {
                        *b = to_byte(base + gain * x);
                    }
                }
                None
            }
        }
    };
    (bytes, sidecar)
}

/// A legend's key: the colour as `#rrggbb`.
fn colour_key(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The values of a plane met so far, so that each is put in the legend
/// once (neighbouring pixels mostly repeat the last one).
#[derive(Default)]
struct Seen {
    last: Option<u32>,
    all: std::collections::HashSet<u32>,
}

impl Seen {
    /// Whether `v` is met for the first time.
    fn first(&mut self, v: f32) -> bool {
        let bits = v.to_bits();
        if self.last == Some(bits) {
            return false;
        }
        self.last = Some(bits);
        self.all.insert(bits)
    }
}

/// The legend's entry for a primitive plane's value.
fn legend_entry(v: f32, table: &PrimitiveTable, file: Option<&str>) -> serde_json::Value {
    if v <= -2.0 {
        return serde_json::json!({"light": (-2.0 - v) as u32, "type": "light", "file": file});
    }
    let index = v as u32;
    let (kind, line) = table.get(&index).copied().unwrap_or(("?", None));
    serde_json::json!({"index": index, "type": kind, "file": file, "line": line})
}
