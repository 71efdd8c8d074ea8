//! A rendered picture in memory: linear RGB floats, and the framework's
//! 8-bit quantisation of them. Writing it to a file is `output`'s.

use glam::DVec3;

/// A rendered picture: linear RGB floats, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<[f32; 3]>,
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

    /// Its pixels, rows from the top.
    pub(crate) fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }
}

/// A linear value in [0, 1] as a byte: the floor of 255·v, clamped (NaN
/// gives 0). The cast truncates, which is the floor on [0, 255], without a
/// call to `floorf`.
#[inline]
pub fn to_byte(v: f32) -> u8 {
    (255.0 * v.clamp(0.0, 1.0)) as u8
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
}
