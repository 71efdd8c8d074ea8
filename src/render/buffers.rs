//! The per-pixel buffers of a region's passes (colours, the anti-aliasing's
//! hashes, rays, shading AOVs, costs), cut into the bands the threads take,
//! and what is left of them once the passes are done.

use super::aov::Aov;
use super::film::Region;
use super::frame::BAND;
use super::shading_aovs::ShadingAovs;
use crate::accel::QueryCost;
use crate::integrator::RayCounts;
use rayon::prelude::*;

/// What the passes keep besides the colours (by default: nothing).
#[derive(Clone, Copy, Default)]
pub(crate) struct Keep<'a> {
    /// The rays traced for each pixel.
    pub rays: bool,
    /// The shading AOVs' values.
    pub shading: Option<&'a ShadingAovs<'a>>,
    /// The queries each pixel's samples made.
    pub cost: bool,
}

/// What the passes over a region produce.
#[derive(Clone)]
pub(crate) struct Rendered {
    /// The region's colours, rows from the top.
    pub pixels: Vec<[f32; 3]>,
    /// Rays traced.
    pub rays: RayCounts,
    /// Pixels anti-aliased.
    pub refined: u64,
    /// Rays traced for each of the region's pixels, when asked for.
    pub rays_per_pixel: Option<Vec<f32>>,
    /// The shading AOVs, in the order asked for, when asked for.
    pub shading: Option<Vec<(Aov, Vec<f32>)>>,
    /// The `cost` AOV (nodes, tests per pixel), when asked for.
    pub costs: Option<Vec<f32>>,
    /// PPM's or SPPM's photon estimate (RGB a pixel), not the ray tracer's (zero) term.
    pub photon_term: Option<Vec<f32>>,
}

/// Every per-pixel buffer of the passes over `area` (a region and, with
/// the adaptive anti-aliasing, its halo); those not kept are empty.
pub(super) struct Buffers {
    /// The pixels they hold: the region, and its halo when anti-aliased.
    pub area: Region,
    /// The colours.
    pub pixels: Vec<[f32; 3]>,
    /// The anti-aliasing's hashes of pass 1's centre samples.
    pub hashes: Vec<u32>,
    /// Rays traced a pixel.
    pub counts: Vec<u32>,
    /// The shading AOVs' values, `channels` a pixel each.
    pub shaded: Vec<(Aov, Vec<f32>)>,
    /// The queries each pixel's samples made.
    pub costs: Vec<QueryCost>,
    keep_rays: bool,
    keep_shading: bool,
    keep_cost: bool,
}

/// One band: the unit of work a thread takes, `BAND` full rows of the
/// area, with its slice of every buffer.
pub(super) struct Band<'b> {
    /// Its first row in the frame.
    pub y0: usize,
    /// Its rows of each buffer, as in [`Buffers`].
    pub pixels: &'b mut [[f32; 3]],
    pub hashes: &'b mut [u32],
    pub counts: &'b mut [u32],
    /// A slice of each shading AOV, in the buffers' order.
    pub shaded: Vec<&'b mut [f32]>,
    pub costs: &'b mut [QueryCost],
}

impl Buffers {
    /// The buffers of `area`'s passes: the hashes when `adaptive`, and what `keep` asks for.
    pub fn new(area: Region, adaptive: bool, keep: Keep) -> Buffers {
        let n = area.area() as usize;
        let sized = |on: bool| if on { n } else { 0 };
        let shaded = keep.shading.map_or_else(Vec::new, |s| {
            s.aovs()
                .iter()
                .map(|&a| (a, vec![0f32; n * a.channels()]))
                .collect()
        });
        Buffers {
            area,
            pixels: vec![[0f32; 3]; n],
            hashes: vec![0u32; sized(adaptive)],
            counts: vec![0u32; sized(keep.rays)],
            shaded,
            costs: vec![QueryCost::default(); sized(keep.cost)],
            keep_rays: keep.rays,
            keep_shading: keep.shading.is_some(),
            keep_cost: keep.cost,
        }
    }

    /// The index of pixel (x, y) of the frame in the buffers.
    pub fn at(&self, x: u32, y: u32) -> usize {
        (y - self.area.y) as usize * self.area.width as usize + (x - self.area.x) as usize
    }

    /// The buffers cut into bands, top to bottom.
    pub fn bands(&mut self) -> Vec<Band<'_>> {
        let aw = self.area.width as usize;
        let len = aw * BAND;
        let bands = self.pixels.len().div_ceil(len);
        let hashes = band_slices(&mut self.hashes, len, bands);
        let counts = band_slices(&mut self.counts, len, bands);
        let costs = band_slices(&mut self.costs, len, bands);
        let mut shaded: Vec<Vec<&mut [f32]>> = (0..bands).map(|_| Vec::new()).collect();
        for (aov, values) in &mut self.shaded {
            for (band, slice) in shaded
                .iter_mut()
                .zip(values.chunks_mut(len * aov.channels()))
            {
                band.push(slice);
            }
        }
        let y0 = self.area.y as usize;
        // Every buffer has `bands` slices: the zip takes them all.
        self.pixels
            .chunks_mut(len)
            .zip(shaded)
            .zip(hashes)
            .zip(counts)
            .zip(costs)
            .enumerate()
            .map(|(b, ((((pixels, shaded), hashes), counts), costs))| Band {
                y0: y0 + b * BAND,
                pixels,
                hashes,
                counts,
                shaded,
                costs,
            })
            .collect()
    }

    /// What is kept of the buffers for `region` (inside the area), with
    /// the passes' rays and refined pixels.
    pub fn finish(self, region: Region, rays: RayCounts, refined: u64) -> Rendered {
        let area = self.area;
        // The counts as f32 values, on every core.
        let rays_per_pixel = self.keep_rays.then(|| {
            let all: Vec<f32> = self.counts.par_iter().map(|&n| n as f32).collect();
            crop(all, 1, area, region)
        });
        let shading = self.keep_shading.then(|| {
            let cropped = |(a, p): (Aov, Vec<f32>)| (a, crop(p, a.channels(), area, region));
            self.shaded.into_iter().map(cropped).collect()
        });
        let costs = self.keep_cost.then(|| {
            let mut all = vec![0f32; self.costs.len() * 2];
            all.par_chunks_mut(2).zip(&self.costs).for_each(|(o, q)| {
                o.copy_from_slice(&[q.nodes as f32, q.tests as f32]);
            });
            crop(all, 2, area, region)
        });
        Rendered {
            pixels: crop(self.pixels, 1, area, region),
            rays,
            refined,
            rays_per_pixel,
            shading,
            costs,
            photon_term: None,
        }
    }
}

/// `v` cut into `bands` chunks of `len`, or `bands` empty slices when `v` is empty.
fn band_slices<T>(v: &mut [T], len: usize, bands: usize) -> Vec<&mut [T]> {
    if v.is_empty() {
        (0..bands).map(|_| &mut [][..]).collect()
    } else {
        v.chunks_mut(len).collect()
    }
}

/// The pixels of `region` out of those of `area` (which holds it), `per`
/// values a pixel.
fn crop<T: Copy>(pixels: Vec<T>, per: usize, area: Region, region: Region) -> Vec<T> {
    if area == region {
        return pixels;
    }
    let aw = area.width as usize;
    let (dx, dy) = ((region.x - area.x) as usize, (region.y - area.y) as usize);
    (0..region.height as usize)
        .flat_map(|r| {
            let start = ((dy + r) * aw + dx) * per;
            pixels[start..start + region.width as usize * per]
                .iter()
                .copied()
        })
        .collect()
}
