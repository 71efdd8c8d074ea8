//! The film: what a render produces for a region of the full frame, the
//! colour and any AOVs (f32 channels a pixel) beside it.

use super::aov::Aov;
use crate::image::Image;

/// A rectangle of pixels of the full frame: columns `x..x + width`, rows
/// `y..y + height`, rows counted from the top.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    /// First column.
    pub x: u32,
    /// First row (from the top).
    pub y: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl Region {
    /// The whole of a `width` × `height` frame.
    pub fn full(width: u32, height: u32) -> Region {
        Region {
            x: 0,
            y: 0,
            width,
            height,
        }
    }

    /// Whether it holds at least one pixel and lies inside a `width` × `height` frame.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.width > 0
            && self.height > 0
            && self.x.checked_add(self.width).is_some_and(|e| e <= width)
            && self.y.checked_add(self.height).is_some_and(|e| e <= height)
    }

    /// This region grown by `margin` pixels on every side, cut to a
    /// `width` × `height` frame.
    pub(crate) fn grown(&self, margin: u32, width: u32, height: u32) -> Region {
        let x = self.x.saturating_sub(margin);
        let y = self.y.saturating_sub(margin);
        let x1 = (self.x + self.width).saturating_add(margin).min(width);
        let y1 = (self.y + self.height).saturating_add(margin).min(height);
        Region {
            x,
            y,
            width: x1 - x,
            height: y1 - y,
        }
    }

    /// Pixels it holds.
    pub fn area(&self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

impl std::str::FromStr for Region {
    type Err = String;

    /// `X0,Y0,X1,Y1`: columns X0..X1 and rows Y0..Y1, ends excluded (`--region`).
    fn from_str(s: &str) -> Result<Region, String> {
        let n: Vec<u32> = s
            .split(',')
            .map(|v| {
                v.trim()
                    .parse::<u32>()
                    .map_err(|e| format!("`{}` is not a pixel coordinate: {e}", v.trim()))
            })
            .collect::<Result<_, _>>()?;
        let [x0, y0, x1, y1] = n[..] else {
            return Err("expected `X0,Y0,X1,Y1`, e.g. `--region 0,0,64,48`".to_string());
        };
        if x1 <= x0 || y1 <= y0 {
            return Err(format!(
                "the region is empty: X1 must exceed X0 and Y1 exceed Y0 (got {s})"
            ));
        }
        Ok(Region {
            x: x0,
            y: y0,
            width: x1 - x0,
            height: y1 - y0,
        })
    }
}

/// One AOV of a film: `aov.channels()` f32 values a pixel, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct AovImage {
    /// Which AOV.
    pub aov: Aov,
    /// `aov.channels()` × the region's pixels.
    pub data: Vec<f32>,
}

impl AovImage {
    /// Values a pixel.
    pub fn channels(&self) -> usize {
        self.aov.channels()
    }
}

/// A rendered region of a frame: its colour and AOVs.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    frame: (u32, u32),
    region: Region,
    color: Image,
    aovs: Vec<AovImage>,
}

impl Film {
    /// A film of `region` of a `frame` (width, height) whose colour is `color`
    /// (of the region's size).
    pub(crate) fn new(frame: (u32, u32), region: Region, color: Image) -> Film {
        Film {
            frame,
            region,
            color,
            aovs: Vec::new(),
        }
    }

    /// The full frame's size (width, height) in pixels.
    pub fn frame_size(&self) -> (u32, u32) {
        self.frame
    }

    /// The part of the frame this film holds.
    pub fn region(&self) -> Region {
        self.region
    }

    /// The colour, the region's size.
    pub fn image(&self) -> &Image {
        &self.color
    }

    /// The colour, taken out of the film.
    pub fn into_image(self) -> Image {
        self.color
    }

    /// The AOVs beside the colour, in the order they were added.
    pub fn aovs(&self) -> &[AovImage] {
        &self.aovs
    }

    /// Its image of `aov`, if the film has one.
    pub fn aov(&self, aov: Aov) -> Option<&AovImage> {
        self.aovs.iter().find(|p| p.aov == aov)
    }

    /// Adds (or replaces) an AOV; refused (false) unless its data holds
    /// `aov.channels()` values for each of the region's pixels.
    pub fn set_aov(&mut self, aov: Aov, data: Vec<f32>) -> bool {
        let want = (self.region.area() as usize).checked_mul(aov.channels());
        if want != Some(data.len()) {
            return false;
        }
        let image = AovImage { aov, data };
        match self.aovs.iter_mut().find(|p| p.aov == aov) {
            Some(p) => *p = image,
            None => self.aovs.push(image),
        }
        true
    }
}

/// Why films of parts of a render do not make one film.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AssembleError {
    /// A part of another frame size.
    #[error("a part is of a {got_w}x{got_h} frame, not {want_w}x{want_h}")]
    Frame {
        /// The part's frame width.
        got_w: u32,
        /// The part's frame height.
        got_h: u32,
        /// The film's frame width.
        want_w: u32,
        /// The film's frame height.
        want_h: u32,
    },
    /// A part outside the region.
    #[error("a part ({}x{} at ({}, {})) is not inside the region", part.width, part.height, part.x, part.y)]
    Outside {
        /// The part's region.
        part: Region,
    },
    /// A part whose AOVs are not those of the others.
    #[error("a part ({}x{} at ({}, {})) has other AOVs than the first", part.width, part.height, part.x, part.y)]
    Aovs {
        /// The part's region.
        part: Region,
    },
    /// A pixel two parts hold.
    #[error("the pixel ({x}, {y}) is in two parts")]
    Twice {
        /// Its column.
        x: u32,
        /// Its row.
        y: u32,
    },
    /// A pixel no part holds.
    #[error("the pixel ({x}, {y}) is in no part")]
    Missing {
        /// Its column.
        x: u32,
        /// Its row.
        y: u32,
    },
}

impl Film {
    /// The film of `region` of a `frame` (width, height) pasted together
    /// from `parts`, films of regions of that frame that hold each of its
    /// pixels once, all with the same AOVs in the same order (the first's).
    pub fn assemble(
        frame: (u32, u32),
        region: Region,
        parts: impl IntoIterator<Item = Film>,
    ) -> Result<Film, AssembleError> {
        let n = region.area() as usize;
        let mut color = vec![[0f32; 3]; n];
        let mut seen = vec![false; n];
        let mut aovs: Option<Vec<AovImage>> = None;
        for part in parts {
            if part.frame != frame {
                return Err(AssembleError::Frame {
                    got_w: part.frame.0,
                    got_h: part.frame.1,
                    want_w: frame.0,
                    want_h: frame.1,
                });
            }
            let r = part.region;
            let inside = r.x >= region.x
                && r.y >= region.y
                && r.x + r.width <= region.x + region.width
                && r.y + r.height <= region.y + region.height;
            if !inside {
                return Err(AssembleError::Outside { part: r });
            }
            let kinds = |a: &[AovImage]| a.iter().map(|p| p.aov).collect::<Vec<_>>();
            let planes = aovs.get_or_insert_with(|| {
                part.aovs
                    .iter()
                    .map(|p| AovImage {
                        aov: p.aov,
                        data: vec![0f32; n * p.channels()],
                    })
                    .collect()
            });
            if kinds(planes) != kinds(&part.aovs) {
                return Err(AssembleError::Aovs { part: r });
            }
            let pixels = part.color.pixels();
            for row in 0..r.height {
                let to = ((r.y - region.y + row) * region.width + (r.x - region.x)) as usize;
                let from = (row * r.width) as usize;
                let w = r.width as usize;
                if let Some(i) = seen[to..to + w].iter().position(|&s| s) {
                    return Err(AssembleError::Twice {
                        x: r.x + i as u32,
                        y: r.y + row,
                    });
                }
                seen[to..to + w].fill(true);
                color[to..to + w].copy_from_slice(&pixels[from..from + w]);
                for (plane, src) in planes.iter_mut().zip(&part.aovs) {
                    let c = plane.channels();
                    plane.data[to * c..(to + w) * c]
                        .copy_from_slice(&src.data[from * c..(from + w) * c]);
                }
            }
        }
        if let Some(i) = seen.iter().position(|&s| !s) {
            let i = i as u32;
            return Err(AssembleError::Missing {
                x: region.x + i % region.width,
                y: region.y + i / region.width,
            });
        }
        let mut film = Film::new(
            frame,
            region,
            Image::from_pixels(region.width, region.height, color),
        );
        film.aovs = aovs.unwrap_or_default();
        Ok(film)
    }
}
