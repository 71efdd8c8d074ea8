//! The hashed grid of one pass's photons that PPM and SPPM gather from
//! (pbrt-v4's SPPM hashes its visible points the same way): every photon
//! within a radius of a point, in a fixed order; and [`FluxSum`], a sum of
//! their flux whose bytes do not depend on that order.

use super::trace::Photon;
use crate::integrator::observer::mix;
use glam::DVec3;

/// A pass's photons bucketed by the cell of a grid that holds them.
pub(crate) struct PhotonGrid<'a> {
    photons: &'a [Photon],
    /// The largest |component| of a photon's power.
    peak: f64,
    cell: f64,
    mask: u64,
    /// Bucket b's photons are `order[starts[b]..starts[b + 1]]`, in photon order.
    starts: Vec<u32>,
    order: Vec<u32>,
}

impl<'a> PhotonGrid<'a> {
    /// The grid over `photons` with cells of side `cell` (at least the
    /// largest radius it will be asked about).
    pub fn new(photons: &'a [Photon], cell: f64) -> Self {
        let cell = if cell > 0.0 && cell.is_finite() {
            cell
        } else {
            1.0
        };
        let buckets = (photons.len().max(1) * 2).next_power_of_two() as u64;
        let mask = buckets - 1;
        let peak = photons
            .iter()
            .map(|p| p.power.abs().max_element())
            .fold(0.0, f64::max);
        let mut grid = PhotonGrid {
            photons,
            peak,
            cell,
            mask,
            starts: vec![0; buckets as usize + 1],
            order: vec![0; photons.len()],
        };
        // Counting sort by bucket: stable, so each bucket is in photon order.
        let keys: Vec<u32> = photons.iter().map(|p| grid.bucket_of(p.pos)).collect();
        for &k in &keys {
            grid.starts[k as usize + 1] += 1;
        }
        for b in 0..buckets as usize {
            grid.starts[b + 1] += grid.starts[b];
        }
        let mut next = grid.starts.clone();
        for (i, &k) in keys.iter().enumerate() {
            grid.order[next[k as usize] as usize] = i as u32;
            next[k as usize] += 1;
        }
        grid
    }

    /// The largest |component| of a photon's power.
    pub fn peak(&self) -> f64 {
        self.peak
    }

    fn cell_of(&self, x: f64) -> i64 {
        (x / self.cell).floor() as i64
    }

    fn bucket(&self, c: [i64; 3]) -> u32 {
        let h = mix(mix(mix(c[0] as u64) ^ c[1] as u64) ^ c[2] as u64);
        (h & self.mask) as u32
    }

    fn bucket_of(&self, p: DVec3) -> u32 {
        self.bucket([self.cell_of(p.x), self.cell_of(p.y), self.cell_of(p.z)])
    }

    /// Calls `f(photon)` for every photon within √`r2` (≤ the cell side) of
    /// `x`, bucket by bucket in bucket order, each in photon order.
    pub fn for_each_within(&self, x: DVec3, r2: f64, mut f: impl FnMut(&Photon)) {
        let r = r2.sqrt().min(self.cell);
        let lo = [
            self.cell_of(x.x - r),
            self.cell_of(x.y - r),
            self.cell_of(x.z - r),
        ];
        let hi = [
            self.cell_of(x.x + r),
            self.cell_of(x.y + r),
            self.cell_of(x.z + r),
        ];
        // 2r ≤ 2 cells, so 3 cells an axis hold the ball (rounding aside).
        let hi = [0, 1, 2].map(|k| hi[k].min(lo[k] + 2));
        // At most 3 cells an axis (2r ≤ 2 cells): 27 buckets, some maybe equal.
        let mut buckets = [0u32; 27];
        let mut n = 0;
        for cx in lo[0]..=hi[0] {
            for cy in lo[1]..=hi[1] {
                for cz in lo[2]..=hi[2] {
                    buckets[n] = self.bucket([cx, cy, cz]);
                    n += 1;
                }
            }
        }
        let buckets = &mut buckets[..n];
        buckets.sort_unstable();
        let mut last = None;
        for &b in buckets.iter() {
            if last == Some(b) {
                continue;
            }
            last = Some(b);
            let (s, e) = (self.starts[b as usize], self.starts[b as usize + 1]);
            for &i in &self.order[s as usize..e as usize] {
                let p = &self.photons[i as usize];
                if (p.pos - x).length_squared() <= r2 {
                    f(p);
                }
            }
        }
    }
}

/// A sum of flux, each term at most `bound` a component, kept as integers
/// (fixed point, 2⁻⁶¹·`bound` apart): the same bytes in any order, so a
/// pixel's estimate does not depend on the grid's cells, which follow the
/// radii of the pixels rendered with it (a region's, a part's).
pub(crate) struct FluxSum {
    scale: f64,
    sum: [i128; 3],
}

impl FluxSum {
    /// An empty sum of terms of at most `bound` a component.
    pub fn new(bound: f64) -> Self {
        // 2^(60 − e) for bound < 2^(e + 1): every term × scale < 2^61.
        let e = ((bound.to_bits() >> 52) & 0x7ff) as i64 - 1023;
        let exponent = (60 - e).clamp(-1022, 1023);
        let scale = f64::from_bits(((exponent + 1023) as u64) << 52);
        FluxSum { scale, sum: [0; 3] }
    }

    /// Adds `term` (each component at most the bound in size).
    #[inline]
    pub fn add(&mut self, term: DVec3) {
        let t = term * self.scale;
        // `as` saturates: a term past the bound cannot wrap.
        self.sum[0] += t.x as i64 as i128;
        self.sum[1] += t.y as i64 as i128;
        self.sum[2] += t.z as i64 as i128;
    }

    /// The sum.
    pub fn total(&self) -> DVec3 {
        DVec3::new(self.sum[0] as f64, self.sum[1] as f64, self.sum[2] as f64) / self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flux_sum_is_the_same_in_any_order_and_near_the_float_sum() {
        // Terms over twelve orders of magnitude, summed forwards and backwards.
        let terms: Vec<DVec3> = (0..1000)
            .map(|i| {
                let x = (i as f64 * 0.618_034).fract();
                DVec3::new(x, x * x * 1e-6, (1.0 - x) * 1e-12)
            })
            .collect();
        let (mut forward, mut backward) = (FluxSum::new(1.0), FluxSum::new(1.0));
        terms.iter().for_each(|&t| forward.add(t));
        terms.iter().rev().for_each(|&t| backward.add(t));
        assert_eq!(forward.total().to_array(), backward.total().to_array());
        let float: DVec3 = terms.iter().sum();
        let got = forward.total();
        for k in 0..3 {
            assert!(
                (got[k] - float[k]).abs() <= 1e-15 * float[k] + 1000.0 * 2f64.powi(-60),
                "{got} vs {float}"
            );
        }
        // A bound of 0 (no power) sums to 0; negative terms count too.
        let mut zero = FluxSum::new(0.0);
        zero.add(DVec3::ZERO);
        assert_eq!(zero.total(), DVec3::ZERO);
        let mut signed = FluxSum::new(2.0);
        signed.add(DVec3::new(1.5, -0.25, 0.0));
        signed.add(DVec3::new(-0.5, -0.25, 2.0));
        assert_eq!(signed.total(), DVec3::new(1.0, -0.5, 2.0));
    }
}
