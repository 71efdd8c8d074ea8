//! Writing a picture: the formats glint writes, chosen by extension, and
//! their encoding.

use super::atomic::write_atomically;
use crate::image::Image;
use crate::render::Encoding;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

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
    /// What writing a picture (and its AOVs) in this format takes a pixel,
    /// beside the film (measured, film included, at 2400×1800 and 600×450:
    /// .png 20 B a pixel and 4 B an AOV channel, .exr 35 B and 10.5 B).
    pub fn encoding(self) -> Encoding {
        match self {
            Format::Png | Format::Bmp => Encoding {
                pixel: 8,
                channel: 2,
            },
            Format::Hdr => Encoding {
                pixel: 16,
                channel: 4,
            },
            Format::Exr => Encoding::LARGEST,
        }
    }

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
                return encode_rgb8(self.width(), self.height(), self.to_rgb8(), format);
            }
            Format::Exr | Format::Hdr => {
                let raw = self.pixels().as_flattened().to_vec();
                let img = Rgb32FImage::from_raw(self.width(), self.height(), raw)
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

#[cfg(test)]
mod tests {
    use super::super::atomic::temporary_name;
    use super::*;
    use glam::DVec3;

    #[test]
    fn unknown_extension_is_an_error_and_writes_nothing() -> Result<(), Box<dyn std::error::Error>>
    {
        let tmp = tempfile::Builder::new().prefix("glint-out-").tempdir()?;
        let dir = tmp.path();
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
        assert_eq!(std::fs::read_dir(dir)?.count(), 1, "no temporary file left");
        Ok(())
    }

    #[test]
    fn long_names_save_and_a_cancelled_write_leaves_nothing()
    -> Result<(), Box<dyn std::error::Error>> {
        let tmp = tempfile::Builder::new().prefix("glint-long-").tempdir()?;
        let dir = tmp.path();
        let img = Image::from_fn(2, 2, |_, _| DVec3::ONE);
        // 254 bytes: legal, and so must be the temporary name beside it.
        let p = dir.join(format!("{}.png", "a".repeat(250)));
        img.save(&p)?;
        assert!(p.is_file());
        let q = dir.join("cancelled.png");
        let cancel = AtomicBool::new(true);
        assert!(img.save_unless(&q, &cancel).is_err());
        assert!(!q.exists());
        assert_eq!(std::fs::read_dir(dir)?.count(), 1, "no temporary file left");
        let (a, b) = (temporary_name(&p), temporary_name(&p));
        assert!(a != b && a.len() < 32, "{a} {b}");
        Ok(())
    }
}
