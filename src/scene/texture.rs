//! Image textures, sampled bilinearly with wrapping as the framework does.

use glam::{DVec2, DVec3};

/// A decoded image texture: a byte per channel, read as byte/255 (or as
/// the lineage divides its bytes).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    /// Rows bottom-up: row 0 is the bottom of the picture (BMP order).
    texels: Vec<[u8; 3]>,
    /// What each byte reads as: byte / divisor, rounded once to f32.
    value: [f64; 256],
    /// Whether coordinates wrap at the seam (else they clamp at the edges).
    wraps: bool,
}

impl Texture {
    /// A texture from rows of bytes listed bottom-up, each read as byte/255.
    pub fn from_rows(width: usize, height: usize, texels: Vec<[u8; 3]>) -> Texture {
        assert_eq!(texels.len(), width * height, "texel count"); // invariant: caller's contract
        Texture {
            width,
            height,
            texels,
            value: byte_values(255.0),
            wraps: true,
        }
    }

    /// Reads each byte as byte/`divisor` (the framework divides its bytes
    /// by 256).
    pub(crate) fn set_byte_divisor(&mut self, divisor: f32) {
        self.value = byte_values(divisor);
    }

    /// Turns the rows upside down and clamps coordinates at the edges
    /// instead of wrapping (a lineage that loads images top row first).
    pub(crate) fn flip_clamped(&mut self) {
        let w = self.width;
        let rows: Vec<&[[u8; 3]]> = self.texels.chunks(w.max(1)).rev().collect();
        self.texels = rows.concat();
        self.wraps = false;
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
        let (r0, r1, fr) = wrap(uv.x, self.height, self.wraps);
        let (c0, c1, fc) = wrap(uv.y, self.width, self.wraps);
        let at = |r: usize, c: usize| {
            DVec3::from_array(self.texels[r * self.width + c].map(|b| self.value[usize::from(b)]))
        };
        let bottom = at(r0, c0) * (1.0 - fc) + at(r0, c1) * fc;
        let top = at(r1, c0) * (1.0 - fc) + at(r1, c1) * fc;
        bottom * (1.0 - fr) + top * fr
    }
}

/// Each byte's reading: byte / `divisor` rounded to f32, the precision
/// texels have been held in since the first textures (the same pictures).
fn byte_values(divisor: f32) -> [f64; 256] {
    std::array::from_fn(|b| f64::from(b as f32 / divisor))
}

/// The two texel indices around coordinate `x · n` (its fraction: the
/// texture repeats) and the blend weight; past the last texel the next is
/// the first when `wraps`, else the last again.
#[inline]
fn wrap(x: f64, n: usize, wraps: bool) -> (usize, usize, f64) {
    let f = x - x.floor();
    let s = if f.is_finite() { f * n as f64 } else { 0.0 };
    // s is finite and at least 0 (x − ⌊x⌋ cannot round below it): its
    // floor is its truncation, exact through i64, with no library call.
    let whole = s as i64;
    let k = whole as f64;
    let i0 = (whole as usize).min(n - 1);
    let i1 = match (i0 + 1 == n, wraps) {
        (false, _) => i0 + 1,
        (true, true) => 0,
        (true, false) => i0,
    };
    (i0, i1, s - k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values around every case of [`wrap`]: whole numbers
    /// and halves, their neighbours, the ends of the exact ranges, zeros of
    /// both signs, infinities, NaN, and random values of every size.
    fn edge_values() -> Vec<f64> {
        let mut v = vec![0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
        for base in [
            0.5,
            1.0,
            1.5,
            2.0,
            254.5,
            255.0,
            2f64.powi(23),
            2f64.powi(52),
            2f64.powi(63),
        ] {
            for x in [base, base.next_up(), base.next_down()] {
                v.extend([x, -x]);
            }
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..20_000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            let bits = state >> 1;
            v.push(f64::from_bits(bits));
            v.push((bits >> 11) as f64 / (1u64 << 53) as f64 * 600.0 - 300.0);
        }
        v
    }

    #[test]
    fn texel_indices_are_those_of_the_library_floor() {
        // The lookup's indices and weight as written with `floor` calls.
        let reference = |x: f64, n: usize, wraps: bool| {
            let f = x - x.floor();
            let s = if f.is_finite() { f * n as f64 } else { 0.0 };
            let k = s.floor();
            let i0 = (k as usize).min(n - 1);
            let i1 = match (i0 + 1 == n, wraps) {
                (false, _) => i0 + 1,
                (true, true) => 0,
                (true, false) => i0,
            };
            (i0, i1, (s - k).to_bits())
        };
        for x in edge_values() {
            for n in [1, 2, 3, 600, 1024, 1 << 20] {
                for wraps in [true, false] {
                    let (i0, i1, w) = wrap(x, n, wraps);
                    assert_eq!((i0, i1, w.to_bits()), reference(x, n, wraps), "{x:e}, {n}");
                }
            }
        }
    }

    fn two_by_two() -> Texture {
        // bottom row: black, red; top row: green, white
        Texture::from_rows(2, 2, vec![[0; 3], [255, 0, 0], [0, 255, 0], [255; 3]])
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
    fn every_byte_reads_as_its_share_of_the_divisor() {
        // b/255 in binary is the byte b repeated, never a tie between two
        // f32: rounding the f64 quotient to f32 rounds the exact one.
        for b in 0..=255u8 {
            let mut t = Texture::from_rows(1, 1, vec![[b, 255 - b, b / 2]]);
            let near = |c: u8, d: f64| f64::from((f64::from(c) / d) as f32);
            let at = |t: &Texture| t.sample(DVec2::ZERO);
            let expect = |d| DVec3::new(near(b, d), near(255 - b, d), near(b / 2, d));
            assert_eq!(at(&t), expect(255.0), "byte {b}");
            t.set_byte_divisor(256.0);
            assert_eq!(at(&t), expect(256.0), "byte {b}");
        }
    }

    #[test]
    fn lineages_read_bytes_their_way() {
        // Bytes 255 and 128 read as b/256 (the framework).
        let mut t = Texture::from_rows(2, 1, vec![[255, 128, 0], [0; 3]]);
        t.set_byte_divisor(256.0);
        assert_eq!(
            t.sample(DVec2::ZERO),
            DVec3::new(255.0 / 256.0, 0.5, 0.0).as_vec3().as_dvec3()
        );
        // W's: the top row first, and no wrapping past the last texel.
        let mut t = two_by_two();
        t.flip_clamped();
        assert_eq!(t.sample(DVec2::new(0.0, 0.0)), DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(t.sample(DVec2::new(0.5, 0.5)), DVec3::new(1.0, 0.0, 0.0));
        // Between the last column and the seam: the last column, not a blend with the first.
        assert_eq!(t.sample(DVec2::new(0.0, 0.75)), DVec3::ONE);
    }
}
