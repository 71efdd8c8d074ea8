//! The hashed grid of one pass's photons that PPM and SPPM gather from
//! (pbrt-v4's SPPM hashes its visible points the same way): every photon
//! within a radius of a point, in a fixed order.

use super::trace::Photon;
use crate::integrator::observer::mix;
use glam::DVec3;

/// A pass's photons bucketed by the cell of a grid that holds them.
pub(crate) struct PhotonGrid<'a> {
    photons: &'a [Photon],
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
        let mut grid = PhotonGrid {
            photons,
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
