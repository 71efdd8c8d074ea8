//! The passes over a region: pass 1 traces each pixel's centre (or its
//! stratified samples); with the adaptive anti-aliasing, pass 2 traces a
//! 7×7 grid (PM3 and V: four more rays) in each pixel whose hash differs
//! from a 4-neighbour's.
//! Pass 1 covers a one-pixel halo around the region, so a region's pixels
//! see the neighbours they see in a full render: the same bytes.

use super::aov::Aov;
use super::film::Region;
use super::frame::{BAND, Frame, Tile};
use super::shading_passes::{LightTally, ShadingPasses};
use crate::accel::QueryCost;
use crate::integrator::{AaHash, NoObserver, PathObserver, RayCounts, ShadowHints};
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
    /// Whether the render was asked to stop.
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// What the passes over a region produce.
pub(crate) struct Rendered {
    /// The region's colours, rows from the top.
    pub pixels: Vec<[f32; 3]>,
    /// Rays traced.
    pub rays: RayCounts,
    /// Pixels anti-aliased.
    pub refined: u64,
    /// Rays traced for each of the region's pixels, when asked for.
    pub rays_per_pixel: Option<Vec<f32>>,
    /// The shading passes' planes, in the order asked for, when asked for.
    pub shading: Option<Vec<(Aov, Vec<f32>)>>,
    /// The `cost` pass (nodes, tests per pixel), when asked for.
    pub costs: Option<Vec<f32>>,
}

/// What the passes keep besides the colours (by default: nothing).
#[derive(Clone, Copy, Default)]
pub(crate) struct Keep<'a> {
    /// The rays traced for each pixel.
    pub rays: bool,
    /// The shading passes' values.
    pub shading: Option<&'a ShadingPasses<'a>>,
    /// The queries each pixel's samples made.
    pub cost: bool,
}

/// What pass 1 keeps of a centre sample's observer: the anti-aliasing's
/// hash, the shading passes' tally and the queries' cost, where it watches them.
trait Kept: PathObserver + Clone {
    /// The folded hash.
    fn hash(&self) -> Option<u32> {
        None
    }

    /// The tally.
    fn tally(&self) -> Option<&LightTally> {
        None
    }

    /// The queries' cost.
    fn cost(&self) -> Option<QueryCost> {
        None
    }
}

impl Kept for NoObserver {}

impl Kept for AaHash {
    fn hash(&self) -> Option<u32> {
        Some(self.folded())
    }
}

impl Kept for LightTally {
    fn tally(&self) -> Option<&LightTally> {
        Some(self)
    }
}

impl Kept for QueryCost {
    fn cost(&self) -> Option<QueryCost> {
        Some(*self)
    }
}

impl<A: Kept, B: Kept> Kept for (A, B) {
    fn hash(&self) -> Option<u32> {
        self.0.hash().or(self.1.hash())
    }

    fn tally(&self) -> Option<&LightTally> {
        self.0.tally().or(self.1.tally())
    }

    fn cost(&self) -> Option<QueryCost> {
        self.0.cost().or(self.1.cost())
    }
}

/// Pass 1 over `tile`, each centre sample watched by a copy of `fresh`
/// (and the anti-aliasing's hash when `adaptive`): calls `put` for each
/// pixel with (x, y), its colour, what its observer kept (hash, tally,
/// cost) and the rays traced.
fn centre<O: Kept>(
    frame: &Frame,
    tile: Tile,
    (rays, hints): (&mut RayCounts, &mut ShadowHints),
    adaptive: bool,
    fresh: &O,
    put: &mut impl FnMut(u32, u32, DVec3, Option<u32>, Option<&LightTally>, Option<QueryCost>, u64),
) {
    fn watched<O: Kept>(
        frame: &Frame,
        tile: Tile,
        (rays, hints): (&mut RayCounts, &mut ShadowHints),
        fresh: &O,
        put: &mut impl FnMut(u32, u32, DVec3, Option<u32>, Option<&LightTally>, Option<QueryCost>, u64),
    ) {
        frame.centre_tile(tile, rays, hints, fresh, |x, y, c, o: &O, r| {
            put(x, y, c, o.hash(), o.tally(), o.cost(), r)
        });
    }
    if adaptive {
        let both = (AaHash::default(), fresh.clone());
        watched(frame, tile, (rays, hints), &both, put);
    } else {
        watched(frame, tile, (rays, hints), fresh, put);
    }
}

/// The colours of `region`'s pixels, the rays traced (per pixel too when
/// `count`), the pixels anti-aliased and the values of the `shading`
/// passes; `None` when cancelled.
pub(crate) fn render_region(
    frame: &Frame,
    region: Region,
    spp: Option<u32>,
    keep: Keep,
    watch: &Watch,
) -> Option<Rendered> {
    let Keep {
        rays: count,
        shading,
        cost,
    } = keep;
    let (w, h) = (frame.width, frame.height);
    let adaptive = spp.is_none() && frame.refine_count() > 0;
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
    let mut counts = vec![0u32; if count { pixels.len() } else { 0 }];
    // The shading passes' planes, written straight by each band.
    let mut planes: Vec<(Aov, Vec<f32>)> = shading.map_or_else(Vec::new, |s| {
        let n = pixels.len();
        s.aovs()
            .iter()
            .map(|&a| (a, vec![0f32; n * a.channels()]))
            .collect()
    });
    let mut costs = vec![QueryCost::default(); if cost { pixels.len() } else { 0 }];
    let band_rays = |band: usize,
                     band_pixels: &mut [[f32; 3]],
                     (band_hashes, band_counts): (&mut [u32], &mut [u32]),
                     mut band_planes: Vec<&mut [f32]>,
                     band_costs: &mut [QueryCost]| {
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
            let mut tally = |i: usize, r: u64| {
                if let Some(n) = band_counts.get_mut(i) {
                    *n = r.min(u32::MAX as u64) as u32;
                }
            };
            let mut fill = |i: usize, t: &LightTally| {
                if let Some(s) = shading {
                    s.fill(&mut band_planes, i, t);
                }
            };
            match spp {
                Some(n) if n > 1 => {
                    let put = |x, y, c, r| {
                        let i = index(x, y);
                        band_pixels[i] = to_f32(c);
                        tally(i, r);
                    };
                    let (rs, hs) = (&mut rays, &mut hints);
                    if cost {
                        let spent = |x, y, q: &QueryCost| band_costs[index(x, y)].add(q);
                        let fresh = QueryCost::default();
                        frame.stratified_tile(tile.clone(), n, rs, hs, &fresh, put, spent);
                    } else {
                        let none = |_, _, _: &NoObserver| {};
                        frame.stratified_tile(tile.clone(), n, rs, hs, &NoObserver, put, none);
                    }
                    // No centre sample was traced: the tally traces it apart.
                    if let Some(s) = shading {
                        let put = |x, y, _, t: &LightTally, _| fill(index(x, y), t);
                        let mut apart = RayCounts::default();
                        frame.centre_tile(tile, &mut apart, &mut hints, s.tally(), put);
                    }
                }
                _ => {
                    let mut put = |x, y, c, hash, t: Option<&LightTally>, q, r| {
                        let i = index(x, y);
                        band_pixels[i] = to_f32(c);
                        if let (Some(h), Some(hash)) = (band_hashes.get_mut(i), hash) {
                            *h = hash;
                        }
                        tally(i, r);
                        if let Some(t) = t {
                            fill(i, t);
                        }
                        if let (Some(c), Some(q)) = (band_costs.get_mut(i), q) {
                            *c = q;
                        }
                    };
                    let state = (&mut rays, &mut hints);
                    let a = adaptive;
                    match (shading, cost) {
                        (None, false) => centre(frame, tile, state, a, &NoObserver, &mut put),
                        (Some(s), false) => centre(frame, tile, state, a, s.tally(), &mut put),
                        (None, true) => {
                            centre(frame, tile, state, a, &QueryCost::default(), &mut put)
                        }
                        (Some(s), true) => {
                            let both = (*s.tally(), QueryCost::default());
                            centre(frame, tile, state, a, &both, &mut put)
                        }
                    }
                }
            }
        }
        report(band_pixels.len() as u64 * per_pixel);
        rays
    };
    // Each band's slice of the hashes, counts, costs and of every shading
    // plane (empty when not kept).
    let bands = pixels.len().div_ceil(aw * BAND);
    let (hash_bands, count_bands, cost_bands) = (
        band_slices(&mut hashes, aw * BAND, bands),
        band_slices(&mut counts, aw * BAND, bands),
        band_slices(&mut costs, aw * BAND, bands),
    );
    let mut shaded_bands: Vec<Vec<&mut [f32]>> = (0..bands).map(|_| Vec::new()).collect();
    for (aov, plane) in &mut planes {
        let len = aw * BAND * aov.channels();
        for (band, slice) in shaded_bands.iter_mut().zip(plane.chunks_mut(len)) {
            band.push(slice);
        }
    }
    let band_rays: Vec<RayCounts> = pixels
        .par_chunks_mut(aw * BAND)
        .zip(hash_bands.into_par_iter().zip(count_bands))
        .zip(shaded_bands.into_par_iter().zip(cost_bands))
        .enumerate()
        .map(|(band, ((p, hc), (ss, qs)))| band_rays(band, p, hc, ss, qs))
        .collect();
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
        let hash = |x: u32, y: u32| hashes[at(x, y)];
        let edge: Vec<(u32, u32)> = (region.y..region.y + region.height)
            .flat_map(|y| (region.x..region.x + region.width).map(move |x| (x, y)))
            .filter(|&(x, y)| differs(hash, x, y, w, h))
            .collect();
        refined = edge.len() as u64;
        let n = frame.refine_count() as u64;
        total.fetch_add(refined * n, Ordering::Relaxed);
        let refined_colors: Vec<(DVec3, RayCounts, QueryCost)> = edge
            .par_chunks(16)
            .flat_map_iter(|chunk| {
                if watch.cancelled() {
                    return Vec::new();
                }
                let mut hints = ShadowHints::default();
                let out: Vec<(DVec3, RayCounts, QueryCost)> = chunk
                    .iter()
                    .map(|&(x, y)| {
                        let (mut rays, mut spent) = (RayCounts::default(), QueryCost::default());
                        let first = DVec3::from(glam::Vec3::from(pixels[at(x, y)]));
                        let (rs, hs) = (&mut rays, &mut hints);
                        let c = if cost {
                            let add = |q: &QueryCost| spent.add(q);
                            frame.refine(x, y, first, rs, hs, &QueryCost::default(), add)
                        } else {
                            frame.refine(x, y, first, rs, hs, &NoObserver, |_| {})
                        };
                        (c, rays, spent)
                    })
                    .collect();
                report(out.len() as u64 * n);
                out
            })
            .collect();
        if watch.cancelled() || refined_colors.len() != edge.len() {
            return None;
        }
        for (&(x, y), (c, r, q)) in edge.iter().zip(&refined_colors) {
            pixels[at(x, y)] = to_f32(*c);
            rays.add(r);
            if let Some(spent) = costs.get_mut(at(x, y)) {
                spent.add(q);
            }
            if let Some(n) = counts.get_mut(at(x, y)) {
                *n = n.saturating_add(r.total().min(u32::MAX as u64) as u32);
            }
        }
    }
    // The counts as f32 planes, on every core.
    let rays_per_pixel = count.then(|| {
        let all: Vec<f32> = counts.par_iter().map(|&n| n as f32).collect();
        crop(all, 1, area, region)
    });
    let shading = shading.map(|_| {
        let cropped = |(a, p): (Aov, Vec<f32>)| (a, crop(p, a.channels(), area, region));
        planes.into_iter().map(cropped).collect()
    });
    let costs = cost.then(|| {
        let mut all = vec![0f32; costs.len() * 2];
        all.par_chunks_mut(2).zip(&costs).for_each(|(o, q)| {
            o.copy_from_slice(&[q.nodes as f32, q.tests as f32]);
        });
        crop(all, 2, area, region)
    });
    Some(Rendered {
        pixels: crop(pixels, 1, area, region),
        rays,
        refined,
        rays_per_pixel,
        shading,
        costs,
    })
}

/// `v` cut into `bands` chunks of `len`, or `bands` empty slices when `v` is empty.
fn band_slices<T>(v: &mut [T], len: usize, bands: usize) -> Vec<&mut [T]> {
    if v.is_empty() {
        (0..bands).map(|_| &mut [][..]).collect()
    } else {
        v.chunks_mut(len).collect()
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

#[inline]
fn to_f32(c: DVec3) -> [f32; 3] {
    c.as_vec3().to_array()
}
