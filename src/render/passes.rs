//! The passes over a region: pass 1 traces each pixel's centre (or its
//! stratified samples); with the framework's adaptive anti-aliasing, pass 2
//! traces a 7×7 grid in each pixel whose hash differs from a 4-neighbour's.
//! Pass 1 covers a one-pixel halo around the region, so a region's pixels
//! see the neighbours they see in a full render: the same bytes.

use super::film::Region;
use super::frame::{AA_GRID, BAND, Frame};
use crate::integrator::{AaHash, NoObserver, RayCounts, ShadowHints};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// What the passes report as they go and whether they should stop.
pub(crate) struct Watch<'w> {
    /// Called with (done, total) in units of camera rays.
    pub progress: &'w (dyn Fn(u64, u64) + Sync),
    /// Set by another thread to stop the render.
    pub cancel: Option<&'w AtomicBool>,
}

impl Watch<'_> {
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// The colours of `region`'s pixels (rows from the top), the rays traced
/// and the pixels anti-aliased; `None` when cancelled.
pub(crate) fn render_region(
    frame: &Frame,
    region: Region,
    spp: Option<u32>,
    watch: &Watch,
) -> Option<(Vec<[f32; 3]>, RayCounts, u64)> {
    let (w, h) = (frame.width, frame.height);
    let adaptive = spp.is_none();
    let spp = spp.map(|n| n.max(1));
    let per_pixel = spp.unwrap_or(1) as u64;
    // Pass 1 covers a halo around the region when pass 2 compares neighbours.
    let area = if adaptive {
        region.grown(1, w, h)
    } else {
        region
    };
    let total = AtomicU64::new(area.area() * per_pixel);
    let done = AtomicU64::new(0);
    let report = |n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        (watch.progress)(d, total.load(Ordering::Relaxed));
    };

    // Pass 1: stratified samples, or one ray through each pixel's centre
    // (with the framework's hash when the anti-aliasing follows). A task is
    // a band of rows (rayon steals work, so both cores stay busy to the
    // end), walked in 8×8 tiles, each one packet of camera rays when a
    // pixel takes one ray, so neighbouring rays share nodes in the cache.
    let aw = area.width as usize;
    let mut pixels = vec![[0f32; 3]; aw * area.height as usize];
    let mut hashes = vec![0u32; if adaptive { pixels.len() } else { 0 }];
    let band_rays = |band: usize, band_pixels: &mut [[f32; 3]], band_hashes: &mut [u32]| {
        let mut rays = RayCounts::default();
        if watch.cancelled() {
            return rays;
        }
        let y0 = area.y as usize + band * BAND;
        let rows = band_pixels.len() / aw;
        // The band's worker keeps its blockers from tile to tile.
        let mut hints = ShadowHints::default();
        for x0 in (area.x as usize..(area.x + area.width) as usize).step_by(BAND) {
            // Per tile, so that a cancel is prompt even with many samples.
            if watch.cancelled() {
                return rays;
            }
            let x1 = (x0 + BAND).min((area.x + area.width) as usize);
            let tile = (x0 as u32..x1 as u32, y0 as u32..(y0 + rows) as u32);
            let index = |x: u32, y: u32| (y as usize - y0) * aw + (x - area.x) as usize;
            match spp {
                Some(n) if n > 1 => {
                    let put = |x, y, c| band_pixels[index(x, y)] = to_f32(c);
                    frame.stratified_tile(tile, n, &mut rays, &mut hints, put);
                }
                Some(_) => {
                    let put = |x, y, c, _: &NoObserver| band_pixels[index(x, y)] = to_f32(c);
                    frame.centre_tile(tile, &mut rays, &mut hints, put);
                }
                None => {
                    let put = |x, y, c, hash: &AaHash| {
                        let i = index(x, y);
                        (band_pixels[i], band_hashes[i]) = (to_f32(c), hash.folded());
                    };
                    frame.centre_tile(tile, &mut rays, &mut hints, put);
                }
            }
        }
        report(band_pixels.len() as u64 * per_pixel);
        rays
    };
    let band_rays: Vec<RayCounts> = if adaptive {
        pixels
            .par_chunks_mut(aw * BAND)
            .zip(hashes.par_chunks_mut(aw * BAND))
            .enumerate()
            .map(|(band, (p, hs))| band_rays(band, p, hs))
            .collect()
    } else {
        pixels
            .par_chunks_mut(aw * BAND)
            .enumerate()
            .map(|(band, p)| band_rays(band, p, &mut []))
            .collect()
    };
    let mut rays = RayCounts::default();
    band_rays.iter().for_each(|r| rays.add(r));
    if watch.cancelled() {
        return None;
    }

    // Pass 2 (adaptive only): the region's pixels whose hash differs from a
    // 4-neighbour's get a 7×7 grid.
    let mut refined = 0u64;
    if adaptive {
        let at = |x: u32, y: u32| (y - area.y) as usize * aw + (x - area.x) as usize;
        let differs = |x: u32, y: u32| {
            let hh = hashes[at(x, y)];
            (x > 0 && hashes[at(x - 1, y)] != hh)
                || (x + 1 < w && hashes[at(x + 1, y)] != hh)
                || (y > 0 && hashes[at(x, y - 1)] != hh)
                || (y + 1 < h && hashes[at(x, y + 1)] != hh)
        };
        let edge: Vec<(u32, u32)> = (region.y..region.y + region.height)
            .flat_map(|y| (region.x..region.x + region.width).map(move |x| (x, y)))
            .filter(|&(x, y)| differs(x, y))
            .collect();
        refined = edge.len() as u64;
        let n = (AA_GRID * AA_GRID) as u64;
        total.fetch_add(refined * n, Ordering::Relaxed);
        let refined_colors: Vec<(DVec3, RayCounts)> = edge
            .par_chunks(16)
            .flat_map_iter(|chunk| {
                if watch.cancelled() {
                    return Vec::new();
                }
                let mut hints = ShadowHints::default();
                let out: Vec<(DVec3, RayCounts)> = chunk
                    .iter()
                    .map(|&(x, y)| {
                        let mut rays = RayCounts::default();
                        (frame.refine(x, y, &mut rays, &mut hints), rays)
                    })
                    .collect();
                report(out.len() as u64 * n);
                out
            })
            .collect();
        if watch.cancelled() || refined_colors.len() != edge.len() {
            return None;
        }
        for (&(x, y), (c, r)) in edge.iter().zip(&refined_colors) {
            pixels[at(x, y)] = to_f32(*c);
            rays.add(r);
        }
    }
    let pixels = if area == region {
        pixels
    } else {
        crop(&pixels, area, region)
    };
    Some((pixels, rays, refined))
}

/// The pixels of `region` out of those of `area` (which holds it).
fn crop(pixels: &[[f32; 3]], area: Region, region: Region) -> Vec<[f32; 3]> {
    let aw = area.width as usize;
    let (dx, dy) = ((region.x - area.x) as usize, (region.y - area.y) as usize);
    (0..region.height as usize)
        .flat_map(|r| {
            let start = (dy + r) * aw + dx;
            pixels[start..start + region.width as usize].iter().copied()
        })
        .collect()
}

#[inline]
fn to_f32(c: DVec3) -> [f32; 3] {
    c.as_vec3().to_array()
}
