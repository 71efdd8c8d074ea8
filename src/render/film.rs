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
