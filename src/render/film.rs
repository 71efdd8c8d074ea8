//! The film: what a render produces for a region of the full frame, the
//! colour and any named planes of f32 channels beside it.

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

/// A named plane of a film: `channels` f32 values per pixel, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// Its name (`normal`, `depth`...).
    pub name: String,
    /// Values per pixel.
    pub channels: usize,
    /// `channels` × the region's pixels.
    pub data: Vec<f32>,
}

/// A rendered region of a frame: its colour and named planes.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    frame: (u32, u32),
    region: Region,
    color: Image,
    planes: Vec<Plane>,
}

impl Film {
    /// A film of `region` of a `frame` (width, height) whose colour is `color`
    /// (of the region's size).
    pub(crate) fn new(frame: (u32, u32), region: Region, color: Image) -> Film {
        Film {
            frame,
            region,
            color,
            planes: Vec::new(),
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

    /// The named planes beside the colour, in the order they were added.
    pub fn planes(&self) -> &[Plane] {
        &self.planes
    }

    /// The plane called `name`, if the film has one.
    pub fn plane(&self, name: &str) -> Option<&Plane> {
        self.planes.iter().find(|p| p.name == name)
    }

    /// Adds (or replaces) a plane; refused (false) unless its data holds
    /// `channels` (at least 1) values for each of the region's pixels.
    pub fn set_plane(&mut self, name: &str, channels: usize, data: Vec<f32>) -> bool {
        let want = (self.region.area() as usize).checked_mul(channels);
        if channels == 0 || want != Some(data.len()) {
            return false;
        }
        let plane = Plane {
            name: name.to_string(),
            channels,
            data,
        };
        match self.planes.iter_mut().find(|p| p.name == name) {
            Some(p) => *p = plane,
            None => self.planes.push(plane),
        }
        true
    }
}
