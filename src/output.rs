//! Rendered images and writing them to disk atomically.

use glam::DVec3;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A rendered picture: linear RGB floats, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<[f32; 3]>,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The extension names no format glint writes.
    #[error("{path}: unknown image format `{ext}` (use .png, .bmp, .exr or .hdr)")]
    UnknownFormat {
        /// The output path.
        path: PathBuf,
        /// Its extension.
        ext: String,
    },
    /// Encoding or writing failed.
    #[error("{path}: {message}")]
    Write {
        /// The output path.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// Output formats, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// 8-bit PNG.
    Png,
    /// 24-bit BMP.
    Bmp,
    /// OpenEXR, 32-bit float.
    Exr,
    /// Radiance HDR.
    Hdr,
}

impl Format {
    /// The format for a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, SaveError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            "png" => Ok(Format::Png),
            "bmp" => Ok(Format::Bmp),
            "exr" => Ok(Format::Exr),
            "hdr" => Ok(Format::Hdr),
            _ => Err(SaveError::UnknownFormat {
                path: path.to_path_buf(),
                ext,
            }),
        }
    }
}

impl Image {
    /// An image whose pixel (x, y) (y from the top) is `f(x, y)`.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> DVec3) -> Image {
        let mut pixels = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x, y).as_vec3().to_array());
            }
        }
        Image {
            width,
            height,
            pixels,
        }
    }

    /// An image from its pixels, rows from the top (`pixels.len()` must be width × height).
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Image {
        // invariant: callers build the buffer from the same width and height.
        assert_eq!(
            pixels.len(),
            width as usize * height as usize,
            "pixel count"
        );
        Image {
            width,
            height,
            pixels,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The linear colour of pixel (x, y), y from the top.
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The framework's 8-bit output: floor(255 · clamp(c, 0, 1)) per channel, no gamma.
    pub fn to_rgb8(&self) -> Vec<u8> {
        // A flat, sized iterator: one allocation, no copies as it grows.
        self.pixels
            .as_flattened()
            .iter()
            .map(|&c| to_byte(c))
            .collect()
    }

    /// Writes the image in the format its extension names, through a
    /// temporary file in the same folder renamed into place: a failed write
    /// leaves no partial file and does not touch an existing one.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), SaveError> {
        self.save_unless(path, &AtomicBool::new(false))
    }

    /// [`Image::save`], giving up (the temporary file removed, `path`
    /// untouched) if `cancel` is set before the file is renamed into place.
    pub fn save_unless(
        &self,
        path: impl AsRef<Path>,
        cancel: &AtomicBool,
    ) -> Result<(), SaveError> {
        let path = path.as_ref();
        let format = Format::from_path(path)?;
        let bytes = self.encode(format).map_err(|message| SaveError::Write {
            path: path.to_path_buf(),
            message,
        })?;
        write_atomically(path, &bytes, cancel).map_err(|e| SaveError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }

    /// The encoded file contents.
    pub fn encode(&self, format: Format) -> Result<Vec<u8>, String> {
        use ::image::{ImageFormat, Rgb32FImage};
        let mut out = std::io::Cursor::new(Vec::new());
        let result = match format {
            Format::Png | Format::Bmp => {
                return encode_rgb8(self.width, self.height, self.to_rgb8(), format);
            }
            Format::Exr | Format::Hdr => {
                let raw = self.pixels.as_flattened().to_vec();
                let img = Rgb32FImage::from_raw(self.width, self.height, raw)
                    .ok_or("image buffer has the wrong size")?;
                let f = if format == Format::Exr {
                    ImageFormat::OpenExr
                } else {
                    ImageFormat::Hdr
                };
                img.write_to(&mut out, f)
            }
        };
        result.map_err(|e| e.to_string())?;
        Ok(out.into_inner())
    }
}

/// A linear value in [0, 1] as a byte: the floor of 255·v, clamped (NaN
/// gives 0). The cast truncates, which is the floor on [0, 255], without a
/// call to `floorf`.
#[inline]
pub fn to_byte(v: f32) -> u8 {
    (255.0 * v.clamp(0.0, 1.0)) as u8
}

/// The encoded file contents of an 8-bit RGB picture, `width` × `height`,
/// rows from the top (`.exr` and `.hdr`: each byte b as b/255).
pub fn encode_rgb8(
    width: u32,
    height: u32,
    bytes: Vec<u8>,
    format: Format,
) -> Result<Vec<u8>, String> {
    use ::image::{ImageFormat, RgbImage};
    let f = match format {
        Format::Png => ImageFormat::Png,
        Format::Bmp => ImageFormat::Bmp,
        Format::Exr | Format::Hdr => {
            let pixels = bytes
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]].map(|b| f32::from(b) / 255.0))
                .collect::<Vec<[f32; 3]>>();
            if pixels.len() != width as usize * height as usize {
                return Err("image buffer has the wrong size".into());
            }
            return Image::from_pixels(width, height, pixels).encode(format);
        }
    };
    let img = RgbImage::from_raw(width, height, bytes).ok_or("image buffer has the wrong size")?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, f).map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

/// Writes `bytes` to a hidden temporary file beside `path`, syncs it and
/// renames it over `path`; the temporary file is removed on failure, and
/// when `cancel` is set before the rename (an `Interrupted` error).
pub fn write_atomically(path: &Path, bytes: &[u8], cancel: &AtomicBool) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let tmp = dir.join(temporary_name(path));
    let result = (|| {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        if cancel.load(Ordering::Relaxed) {
            return Err(std::io::Error::from(std::io::ErrorKind::Interrupted));
        }
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// `.glint-<16 hex digits>.tmp` (27 bytes, so any legal output name has a
/// legal temporary name): a hash of the output path, the host name, the
/// process, the time and a per-process counter, unique across the hosts
/// that share a folder.
fn temporary_name(path: &Path) -> String {
    use std::hash::{BuildHasher, Hash, Hasher};
    use std::sync::atomic::AtomicU64;
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    // RandomState is seeded from the system's randomness.
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    path.hash(&mut h);
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| std::env::var("HOSTNAME"))
        .unwrap_or_default()
        .hash(&mut h);
    std::process::id().hash(&mut h);
    COUNTER.fetch_add(1, Ordering::Relaxed).hash(&mut h);
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or_default()
        .hash(&mut h);
    format!(".glint-{:016x}.tmp", h.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantises_like_the_framework() {
        let img = Image::from_fn(4, 1, |x, _| DVec3::splat([-0.5, 0.5, 1.0, 7.0][x as usize]));
        assert_eq!(
            img.to_rgb8(),
            vec![0, 0, 0, 127, 127, 127, 255, 255, 255, 255, 255, 255]
        );
        // Just below a step stays below it (254.745, 0.9945); NaN is black.
        let img = Image::from_pixels(1, 1, vec![[0.999, 0.0039, f32::NAN]]);
        assert_eq!(img.to_rgb8(), vec![254, 0, 0]);
    }

    #[test]
    fn unknown_extension_is_an_error_and_writes_nothing() -> Result<(), Box<dyn std::error::Error>>
    {
        let dir = std::env::temp_dir().join(format!("glint-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let p = dir.join("x.tiff");
        let img = Image::from_fn(2, 2, |_, _| DVec3::ONE);
        assert!(matches!(img.save(&p), Err(SaveError::UnknownFormat { .. })));
        assert!(!p.exists());
        // A folder that does not exist: an error, nothing left behind.
        assert!(img.save(dir.join("missing/x.png")).is_err());
        // Round trip through PNG.
        let p = dir.join("x.png");
        img.save(&p)?;
        let back = ::image::open(&p)?.to_rgb8();
        assert_eq!(back.as_raw(), &vec![255u8; 12]);
        assert_eq!(
            std::fs::read_dir(&dir)?.count(),
            1,
            "no temporary file left"
        );
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn long_names_save_and_a_cancelled_write_leaves_nothing()
    -> Result<(), Box<dyn std::error::Error>> {
        let dir = std::env::temp_dir().join(format!("glint-long-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir)?;
        let img = Image::from_fn(2, 2, |_, _| DVec3::ONE);
        // 254 bytes: legal, and so must be the temporary name beside it.
        let p = dir.join(format!("{}.png", "a".repeat(250)));
        img.save(&p)?;
        assert!(p.is_file());
        let q = dir.join("cancelled.png");
        let cancel = AtomicBool::new(true);
        assert!(img.save_unless(&q, &cancel).is_err());
        assert!(!q.exists());
        assert_eq!(
            std::fs::read_dir(&dir)?.count(),
            1,
            "no temporary file left"
        );
        let (a, b) = (temporary_name(&p), temporary_name(&p));
        assert!(a != b && a.len() < 32, "{a} {b}");
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }
}
