//! Image textures, sampled bilinearly with wrapping as the framework does.

use glam::{DVec2, DVec3};
use std::path::Path;

/// A decoded image texture in linear floats (a byte b means b/255).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    /// Rows bottom-up: row 0 is the bottom of the picture (BMP order).
    texels: Vec<[f32; 3]>,
}

impl Texture {
    /// Decodes an image file (BMP 24/32-bit, PNG, JPEG).
    pub fn load(path: &Path) -> Result<Texture, String> {
        let img = image::open(path).map_err(|e| e.to_string())?.to_rgb8();
        let (w, h) = (img.width() as usize, img.height() as usize);
        if w == 0 || h == 0 {
            return Err("the image is empty".to_string());
        }
        let mut texels = Vec::with_capacity(w * h);
        // image stores rows top-down; the framework's row 0 is the bottom.
        for y in (0..h).rev() {
            for x in 0..w {
                let p = img.get_pixel(x as u32, y as u32).0;
                texels.push(p.map(|b| b as f32 / 255.0));
            }
        }
        Ok(Texture {
            width: w,
            height: h,
            texels,
        })
    }

    /// A texture from rows listed bottom-up (for tests and generated textures).
    pub fn from_rows(width: usize, height: usize, texels: Vec<[f32; 3]>) -> Texture {
        assert_eq!(texels.len(), width * height, "texel count"); // invariant: caller's contract
        Texture {
            width,
            height,
            texels,
        }
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The framework's `texture(u, v)`: u selects the row (from the bottom),
    /// v the column; texel k sits at coordinate k; both directions wrap.
    pub fn sample(&self, uv: DVec2) -> DVec3 {
        let (r0, r1, fr) = wrap(uv.x, self.height);
        let (c0, c1, fc) = wrap(uv.y, self.width);
        let at = |r: usize, c: usize| {
            let t = self.texels[r * self.width + c];
            DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
        };
        let bottom = at(r0, c0) * (1.0 - fc) + at(r0, c1) * fc;
        let top = at(r1, c0) * (1.0 - fc) + at(r1, c1) * fc;
        bottom * (1.0 - fr) + top * fr
    }
}

/// The two texel indices around coordinate `x · n` (wrapping) and the blend weight.
#[inline]
fn wrap(x: f64, n: usize) -> (usize, usize, f64) {
    let f = x - x.floor();
    let s = if f.is_finite() { f * n as f64 } else { 0.0 };
    let k = s.floor();
    let i0 = (k as usize).min(n - 1);
    let i1 = if i0 + 1 == n { 0 } else { i0 + 1 };
    (i0, i1, s - k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_two() -> Texture {
        // bottom row: black, red; top row: green, white
        Texture::from_rows(
            2,
            2,
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0; 3]],
        )
    }

    #[test]
    fn texel_k_sits_at_coordinate_k() {
        let t = two_by_two();
        assert_eq!(t.sample(DVec2::new(0.0, 0.0)), DVec3::ZERO);
        assert_eq!(t.sample(DVec2::new(0.0, 0.5)), DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(t.sample(DVec2::new(0.5, 0.0)), DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(t.sample(DVec2::new(0.5, 0.5)), DVec3::ONE);
    }

    #[test]
    fn blends_bilinearly_and_wraps() {
        let t = two_by_two();
        // Halfway between column 0 and 1 on the bottom row.
        assert_eq!(t.sample(DVec2::new(0.0, 0.25)), DVec3::new(0.5, 0.0, 0.0));
        // Column 1 blends with column 0 (wrap) at v = 0.75.
        assert_eq!(t.sample(DVec2::new(0.0, 0.75)), DVec3::new(0.5, 0.0, 0.0));
        // Negative and > 1 coordinates wrap.
        assert_eq!(
            t.sample(DVec2::new(-1.0, 2.5)),
            t.sample(DVec2::new(0.0, 0.5))
        );
        // Centre of all four.
        assert_eq!(t.sample(DVec2::new(0.25, 0.25)), DVec3::new(0.5, 0.5, 0.25));
    }

    #[test]
    fn bmp_rows_are_bottom_up() -> Result<(), Box<dyn std::error::Error>> {
        let dir = std::env::temp_dir().join(format!("glint-tex-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let path = dir.join("t.bmp");
        // Top row red, bottom row blue, as a person sees the picture.
        let img = image::RgbImage::from_fn(1, 2, |_, y| {
            if y == 0 {
                image::Rgb([255, 0, 0])
            } else {
                image::Rgb([0, 0, 255])
            }
        });
        img.save(&path)?;
        let t = Texture::load(&path)?;
        assert_eq!(t.sample(DVec2::new(0.0, 0.0)), DVec3::Z);
        assert_eq!(t.sample(DVec2::new(0.5, 0.0)), DVec3::X);
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }
}
