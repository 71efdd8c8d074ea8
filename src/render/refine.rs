//! Pass 2 of the adaptive anti-aliasing: each pixel of the region whose
//! hash differs from a 4-neighbour's gets the lineage's grid of rays (the
//! framework's 7×7, PM3's and V's four more).

use super::band::to_f32;
use super::buffers::Buffers;
use super::film::Region;
use super::frame::Frame;
use super::observe::{Kept, ObservedJob, Watched, with_observer};
use super::progress::Progress;
use crate::accel::QueryCost;
use crate::integrator::{RayCounts, ShadowHints};
use glam::DVec3;
use rayon::prelude::*;

/// Refines `region`'s edge pixels in `buffers` (pass 1 done over their
/// area); returns the pixels refined and the rays traced, `None` when cancelled.
pub(super) fn refine_edges(
    frame: &Frame,
    region: Region,
    buffers: &mut Buffers,
    cost: bool,
    progress: &Progress,
) -> Option<(u64, RayCounts)> {
    let (w, h) = (frame.width, frame.height);
    let hash = |x: u32, y: u32| buffers.hashes[buffers.at(x, y)];
    let edge: Vec<(u32, u32)> = (region.y..region.y + region.height)
        .flat_map(|y| (region.x..region.x + region.width).map(move |x| (x, y)))
        .filter(|&(x, y)| differs(hash, x, y, w, h))
        .collect();
    let n = frame.refine_count() as u64;
    progress.add_total(edge.len() as u64 * n);
    let watched = Watched {
        hash: false,
        tally: None,
        cost,
    };
    let buffers_read = &*buffers;
    let refined: Vec<(DVec3, RayCounts, QueryCost)> = edge
        .par_chunks(16)
        .flat_map_iter(|chunk| {
            if progress.cancelled() {
                return Vec::new();
            }
            let mut hints = ShadowHints::default();
            let out: Vec<(DVec3, RayCounts, QueryCost)> = chunk
                .iter()
                .map(|&(x, y)| {
                    let first = buffers_read.pixels[buffers_read.at(x, y)];
                    let first = DVec3::from(glam::Vec3::from(first));
                    let job = Grid {
                        frame,
                        pixel: (x, y),
                        first,
                        hints: &mut hints,
                    };
                    with_observer(watched, job)
                })
                .collect();
            progress.report(out.len() as u64 * n);
            out
        })
        .collect();
    if progress.cancelled() || refined.len() != edge.len() {
        return None;
    }
    let mut rays = RayCounts::default();
    for (&(x, y), (c, r, q)) in edge.iter().zip(&refined) {
        let i = buffers.at(x, y);
        buffers.pixels[i] = to_f32(*c);
        rays.add(r);
        if let Some(spent) = buffers.costs.get_mut(i) {
            spent.add(q);
        }
        if let Some(n) = buffers.counts.get_mut(i) {
            *n = n.saturating_add(r.total().min(u32::MAX as u64) as u32);
        }
    }
    Some((edge.len() as u64, rays))
}

/// One pixel's grid: its colour, rays and (when watched) query cost.
struct Grid<'j> {
    frame: &'j Frame<'j>,
    pixel: (u32, u32),
    /// The pixel's pass-1 colour.
    first: DVec3,
    hints: &'j mut ShadowHints,
}

impl ObservedJob for Grid<'_> {
    type Out = (DVec3, RayCounts, QueryCost);

    fn run<O: Kept>(self, fresh: &O) -> Self::Out {
        let (mut rays, mut spent) = (RayCounts::default(), QueryCost::default());
        let (x, y) = self.pixel;
        let add = |o: &O| {
            if let Some(q) = o.cost() {
                spent.add(&q)
            }
        };
        let c = self
            .frame
            .refine((x, y), self.first, &mut rays, self.hints, fresh, add);
        (c, rays, spent)
    }
}

/// Whether pixel (x, y) of a `w` × `h` frame is anti-aliased: its hash
/// (`hash(x, y)`, asked only inside the frame) differs from a 4-neighbour's.
pub(crate) fn differs(hash: impl Fn(u32, u32) -> u32, x: u32, y: u32, w: u32, h: u32) -> bool {
    let hh = hash(x, y);
    (x > 0 && hash(x - 1, y) != hh)
        || (x + 1 < w && hash(x + 1, y) != hh)
        || (y > 0 && hash(x, y - 1) != hh)
        || (y + 1 < h && hash(x, y + 1) != hh)
}
