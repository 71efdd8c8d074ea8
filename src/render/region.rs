//! A region's passes: pass 1 over its bands (`band`), each pixel's centre
//! or its stratified samples; with the adaptive anti-aliasing, pass 2 over
//! the pixels whose hash differs from a 4-neighbour's (`refine`).
//! Pass 1 covers a one-pixel halo around the region, so a region's pixels
//! see the neighbours they see in a full render: the same bytes.

use super::band::{Pass1, trace_band};
use super::buffers::{Buffers, Keep, Rendered};
use super::film::Region;
use super::frame::Frame;
use super::progress::{Progress, Watch};
use super::refine::refine_edges;
use crate::integrator::RayCounts;
use rayon::prelude::*;

/// The colours of `region`'s pixels, the rays traced, the pixels
/// anti-aliased and what `keep` asks for; `None` when cancelled.
pub(crate) fn render_region(
    frame: &Frame,
    region: Region,
    spp: Option<u32>,
    keep: Keep,
    watch: &Watch,
) -> Option<Rendered> {
    let (w, h) = (frame.width, frame.height);
    let adaptive = spp.is_none() && frame.refine_count() > 0;
    let spp = spp.map(|n| n.max(1));
    // Pass 1 covers a halo around the region when pass 2 compares neighbours.
    let area = if adaptive {
        region.grown(1, w, h)
    } else {
        region
    };
    let progress = Progress::new(watch, area.area() * spp.unwrap_or(1) as u64);
    let mut buffers = Buffers::new(area, adaptive, keep);

    // Pass 1: stratified samples, or one ray through each pixel's centre
    // (with the framework's hash when the anti-aliasing follows). A task is
    // a band of rows (rayon steals work, so both cores stay busy to the
    // end), walked in 8×8 tiles, each one packet of camera rays when a
    // pixel takes one ray, so neighbouring rays share nodes in the cache.
    let pass = Pass1 {
        frame,
        area,
        spp,
        adaptive,
        keep,
        progress: &progress,
    };
    let band_rays: Vec<RayCounts> = buffers
        .bands()
        .into_par_iter()
        .map(|band| trace_band(&pass, band))
        .collect();
    let mut rays = RayCounts::default();
    band_rays.iter().for_each(|r| rays.add(r));
    if watch.cancelled() {
        return None;
    }

    // Pass 2 (adaptive only).
    let mut refined = 0u64;
    if adaptive {
        let (n, r) = refine_edges(frame, region, &mut buffers, keep.cost, &progress)?;
        refined = n;
        rays.add(&r);
    }
    Some(buffers.finish(region, rays, refined))
}
