//! A region's passes: pass 1 over its bands (`band`), each pixel's centre
//! or its stratified samples; with the adaptive anti-aliasing, pass 2 over
//! the pixels whose hash differs from a 4-neighbour's (`refine`).
//! Pass 1 covers a one-pixel halo around the region, so a region's pixels
//! see the neighbours they see in a full render: the same bytes. Several
//! regions (a part's runs of bands) render side by side as one job.

use super::band::{Pass1, trace_band};
use super::buffers::{Buffers, Keep, Rendered};
use super::film::Region;
use super::frame::Frame;
use super::progress::{Progress, Watch};
use super::refine::refine_edges;
use crate::integrator::RayCounts;
use rayon::prelude::*;

/// For each of `runs` (regions of the frame apart from each other), the
/// colours of its pixels, the rays traced, the pixels anti-aliased and
/// what `keep` asks for; the runs side by side on the threads, taken in
/// their order, told to `watch` as one job, each handed to `done` with its
/// index as it is finished; `None` when cancelled.
pub(crate) fn render_runs(
    frame: &Frame,
    runs: &[Region],
    spp: Option<u32>,
    keep: Keep,
    watch: &Watch,
    done: &(dyn Fn(usize, &Rendered) + Sync),
) -> Option<Vec<Rendered>> {
    let adaptive = spp.is_none() && frame.refine_count() > 0;
    let spp = spp.map(|n| n.max(1));
    // Pass 1 covers a halo around each run when pass 2 compares neighbours.
    let area = |region: &Region| {
        if adaptive {
            region.grown(1, frame.width, frame.height)
        } else {
            *region
        }
    };
    let total = runs.iter().map(|r| area(r).area()).sum::<u64>() * u64::from(spp.unwrap_or(1));
    let progress = Progress::new(watch, total);
    // Bridged: the workers take the runs in their order (nearest first, for
    // a page that shows them as they come), each run's bands in parallel.
    let mut finished: Vec<(usize, Option<Rendered>)> = runs
        .iter()
        .enumerate()
        .par_bridge()
        .map(|(i, &region)| {
            let pass = Pass1 {
                frame,
                area: area(&region),
                spp,
                adaptive,
                keep,
                progress: &progress,
            };
            let rendered = passes(&pass, region);
            if let Some(r) = &rendered {
                done(i, r);
            }
            (i, rendered)
        })
        .collect();
    finished.sort_unstable_by_key(|(i, _)| *i);
    finished.into_iter().map(|(_, r)| r).collect()
}

/// Pass 1 over `pass.area` and, with the adaptive anti-aliasing, pass 2
/// over `region` (inside it); `None` when cancelled.
fn passes(pass: &Pass1, region: Region) -> Option<Rendered> {
    let mut buffers = Buffers::new(pass.area, pass.adaptive, pass.keep);

    // Pass 1: stratified samples, or one ray through each pixel's centre
    // (with the framework's hash when the anti-aliasing follows). A task is
    // a band of rows (rayon steals work, so both cores stay busy to the
    // end), walked in 8×8 tiles, each one packet of camera rays when a
    // pixel takes one ray, so neighbouring rays share nodes in the cache.
    let band_rays: Vec<RayCounts> = buffers
        .bands()
        .into_par_iter()
        .map(|band| trace_band(pass, band))
        .collect();
    let mut rays = RayCounts::default();
    band_rays.iter().for_each(|r| rays.add(r));
    if pass.progress.cancelled() {
        return None;
    }

    // Pass 2 (adaptive only).
    let mut refined = 0u64;
    if pass.adaptive {
        let (n, r) = refine_edges(
            pass.frame,
            region,
            &mut buffers,
            pass.keep.cost,
            pass.progress,
        )?;
        refined = n;
        rays.add(&r);
    }
    Some(buffers.finish(region, rays, refined))
}
