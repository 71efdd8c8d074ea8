//! Pass 1 over one band: each pixel's centre ray (with the observers the
//! render keeps), or its stratified samples, walked in tiles of one packet.

use super::buffers::{Band, Keep};
use super::film::Region;
use super::frame::{BAND, Frame, Tile};
use super::observe::{Kept, ObservedJob, Watched, with_observer};
use super::progress::Progress;
use super::shading_aovs::LightTally;
use crate::accel::QueryCost;
use crate::integrator::{RayCounts, ShadowHints};
use glam::DVec3;

/// What pass 1 over a region's bands shares.
pub(super) struct Pass1<'p> {
    /// The frame's samples.
    pub frame: &'p Frame<'p>,
    /// The pixels pass 1 covers (the region and its halo).
    pub area: Region,
    /// Stratified samples per pixel; `None`: one ray through the centre.
    pub spp: Option<u32>,
    /// Whether the anti-aliasing's hash is kept (pass 2 follows).
    pub adaptive: bool,
    /// What is kept besides the colours.
    pub keep: Keep<'p>,
    /// Where the camera rays done are counted.
    pub progress: &'p Progress<'p>,
}

/// Traces pass 1 over `band`, writing its buffers; returns the rays traced
/// (what was traced before a cancel).
pub(super) fn trace_band(pass: &Pass1, band: Band) -> RayCounts {
    let mut rays = RayCounts::default();
    if pass.progress.cancelled() {
        return rays;
    }
    let (frame, area) = (pass.frame, pass.area);
    let aw = area.width as usize;
    let Band {
        y0,
        pixels,
        hashes,
        counts,
        mut shaded,
        costs,
    } = band;
    let rows = pixels.len() / aw;
    let per_pixel = pass.spp.unwrap_or(1) as u64;
    // The band's worker keeps its blockers from tile to tile.
    let mut hints = ShadowHints::default();
    for x0 in (area.x as usize..(area.x + area.width) as usize).step_by(BAND) {
        // Per tile, so that a cancel is prompt even with many samples.
        if pass.progress.cancelled() {
            return rays;
        }
        let x1 = (x0 + BAND).min((area.x + area.width) as usize);
        let tile = (x0 as u32..x1 as u32, y0 as u32..(y0 + rows) as u32);
        let index = |x: u32, y: u32| (y as usize - y0) * aw + (x - area.x) as usize;
        let mut tally = |i: usize, r: u64| {
            if let Some(n) = counts.get_mut(i) {
                *n = r.min(u32::MAX as u64) as u32;
            }
        };
        let shading = pass.keep.shading;
        let mut fill = |i: usize, t: &LightTally| {
            if let Some(s) = shading {
                s.fill(&mut shaded, i, t);
            }
        };
        let state = (&mut rays, &mut hints);
        match pass.spp {
            Some(n) if n > 1 => {
                let put = |x, y, c, r| {
                    let i = index(x, y);
                    pixels[i] = to_f32(c);
                    tally(i, r);
                };
                let spent = |x, y, q: QueryCost| costs[index(x, y)].add(&q);
                let cost_only = Watched {
                    hash: false,
                    tally: None,
                    cost: pass.keep.cost,
                };
                let job = Stratified {
                    frame,
                    tile: tile.clone(),
                    n,
                    state,
                    put,
                    spent,
                };
                with_observer(cost_only, job);
                // No centre sample was traced: the tally traces it apart.
                if let Some(s) = shading {
                    let put = |x, y, _, t: &LightTally, _| fill(index(x, y), t);
                    let mut apart = RayCounts::default();
                    frame.centre_tile(tile, &mut apart, &mut hints, s.tally(), put);
                }
            }
            _ => {
                let put = |x, y, c, hash, t: Option<&LightTally>, q, r| {
                    let i = index(x, y);
                    pixels[i] = to_f32(c);
                    if let (Some(h), Some(hash)) = (hashes.get_mut(i), hash) {
                        *h = hash;
                    }
                    tally(i, r);
                    if let Some(t) = t {
                        fill(i, t);
                    }
                    if let (Some(c), Some(q)) = (costs.get_mut(i), q) {
                        *c = q;
                    }
                };
                let watched = Watched {
                    hash: pass.adaptive,
                    tally: shading.map(|s| s.tally()),
                    cost: pass.keep.cost,
                };
                with_observer(
                    watched,
                    Centres {
                        frame,
                        tile,
                        state,
                        put,
                    },
                );
            }
        }
    }
    pass.progress.report(pixels.len() as u64 * per_pixel);
    rays
}

/// A tile's centre rays, each pixel handed to `put` with (x, y), its
/// colour, what its observer kept (hash, tally, cost) and the rays traced.
struct Centres<'j, P> {
    frame: &'j Frame<'j>,
    tile: Tile,
    state: (&'j mut RayCounts, &'j mut ShadowHints),
    put: P,
}

impl<P> ObservedJob for Centres<'_, P>
where
    P: FnMut(u32, u32, DVec3, Option<u32>, Option<&LightTally>, Option<QueryCost>, u64),
{
    type Out = ();

    fn run<O: Kept>(self, fresh: &O) {
        let Centres {
            frame,
            tile,
            state: (rays, hints),
            mut put,
        } = self;
        frame.centre_tile(tile, rays, hints, fresh, |x, y, c, o: &O, r| {
            put(x, y, c, o.hash(), o.tally(), o.cost(), r)
        });
    }
}

/// A tile's `n` stratified samples a pixel: each pixel's mean and rays to
/// `put`, each sample's query cost (when watched) to `spent`.
struct Stratified<'j, P, S> {
    frame: &'j Frame<'j>,
    tile: Tile,
    n: u32,
    state: (&'j mut RayCounts, &'j mut ShadowHints),
    put: P,
    spent: S,
}

impl<P, S> ObservedJob for Stratified<'_, P, S>
where
    P: FnMut(u32, u32, DVec3, u64),
    S: FnMut(u32, u32, QueryCost),
{
    type Out = ();

    fn run<O: Kept>(self, fresh: &O) {
        let Stratified {
            frame,
            tile,
            n,
            state: (rays, hints),
            mut put,
            mut spent,
        } = self;
        let seen = |x, y, o: &O| {
            if let Some(q) = o.cost() {
                spent(x, y, q)
            }
        };
        let put = |x, y, c, r: &RayCounts| {
            rays.add(r);
            put(x, y, c, r.total())
        };
        frame.stratified_tile(tile, n, hints, fresh, put, seen);
    }
}

/// A colour as the buffers store it.
#[inline]
pub(super) fn to_f32(c: DVec3) -> [f32; 3] {
    c.as_vec3().to_array()
}
