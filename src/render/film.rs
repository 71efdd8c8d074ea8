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
