//! Rendering: cameras, the shading model, anti-aliasing, tiles and threads.

mod camera;
mod integrator;

pub use camera::CameraRays;
pub use integrator::{MAX_DEPTH, RayCounts};

use crate::accel::Accel;
use crate::output::Image;
use crate::scene::Scene;
use glam::DVec3;
use integrator::{PathState, Tracer, mix};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How to render.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RenderOptions {
    /// Worker threads (`None`: one per core).
    pub threads: Option<usize>,
    /// Seed of every random stream.
    pub seed: u64,
    /// Stratified samples per pixel; `None` for the framework's adaptive
    /// anti-aliasing (one ray, 7×7 where neighbours differ).
    pub spp: Option<u32>,
}

/// Figures about a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Wall time of the render (not counting parsing), the BVH build included.
    pub elapsed: Duration,
    /// Wall time of the acceleration-structure build.
    pub build: Duration,
    /// Pixels re-rendered by the adaptive anti-aliasing.
    pub refined_pixels: u64,
}

impl RenderStats {
    /// Millions of rays per second.
    pub fn mrays_per_sec(&self) -> f64 {
        self.rays.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

/// Renders a scene at its camera's size.
pub fn render(scene: &Scene, options: &RenderOptions) -> Image {
    render_with_progress(scene, options, &|_, _| {}).0
}

/// Sub-pixel grid of the framework's anti-aliasing.
const AA_GRID: u32 = 7;
/// Rows per rendering task, also the side of the tiles a task walks.
const BAND: usize = 8;

/// Renders a scene, calling `progress(done, total)` (in units of camera
/// rays) as rows finish; returns the image and the figures.
pub fn render_with_progress(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> (Image, RenderStats) {
    let start = Instant::now();
    let run = || render_inner(scene, options, progress);
    let (image, rays, refined, build) = match options.threads {
        Some(n) => match rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
        {
            Ok(pool) => pool.install(run),
            Err(_) => run(),
        },
        None => run(),
    };
    let stats = RenderStats {
        rays,
        elapsed: start.elapsed(),
        build,
        refined_pixels: refined,
    };
    (image, stats)
}

/// Bytes of memory a render of `width` × `height` pixels holds at its peak
/// (pixel buffer, hashes, 8-bit copy for encoding), for refusing absurd sizes.
pub fn memory_needed(width: u32, height: u32) -> u64 {
    width as u64 * height as u64 * (12 + 4 + 3 + 3)
}

struct Frame<'a> {
    tracer: Tracer<'a>,
    camera: CameraRays,
    width: u32,
    height: u32,
    seed: u64,
}

impl Frame<'_> {
    /// The random stream of one camera sample: a hash of (pixel, sample, seed).
    fn state(&self, x: u32, y: u32, sample: u32) -> PathState {
        let pixel = y as u64 * self.width as u64 + x as u64;
        let key = mix(mix(self.seed ^ mix(pixel)) ^ sample as u64);
        PathState {
            rng: Pcg32::seed_from_u64(key),
            rays: RayCounts::default(),
        }
    }

    /// One camera ray at sub-pixel offset (fx, fy) in [0,1)² of pixel (x, y),
    /// fy measured downward from the pixel's top edge.
    fn sample(
        &self,
        x: u32,
        y: u32,
        fx: f64,
        fy: f64,
        st: &mut PathState,
        hash: &mut u64,
    ) -> DVec3 {
        // Framework row i counts from the bottom: pixel y covers i ∈ [H−1−y, H−y).
        let i = (self.height - 1 - y) as f64 + (1.0 - fy);
        let j = x as f64 + fx;
        self.tracer.trace_camera(&self.camera.ray(i, j), st, hash)
    }
}

fn render_inner(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> (Image, RayCounts, u64, Duration) {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let build_start = Instant::now();
    let accel = Accel::build(&scene.objects);
    let build = build_start.elapsed();
    let frame = Frame {
        tracer: Tracer::new(scene, &accel),
        camera: CameraRays::new(&scene.camera, w, h),
        width: w,
        height: h,
        seed: options.seed,
    };
    let spp = options.spp.map(|n| n.max(1));
    let per_pixel = spp.unwrap_or(1) as u64;
    let total = AtomicU64::new(w as u64 * h as u64 * per_pixel);
    let done = AtomicU64::new(0);
    let report = |n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        progress(d, total.load(Ordering::Relaxed));
    };

    // Pass 1: stratified samples, or the framework's single ray and its hash.
    // A task is a band of rows (rayon steals work, so both cores stay busy
    // to the end), walked in small square tiles so neighbouring rays reuse
    // the same nodes and primitives in the cache.
    let shade = |x: u32, y: u32, rays: &mut RayCounts| -> ([f32; 3], u32) {
        match spp {
            Some(n) => (to_f32(stratified(&frame, x, y, n, rays)), 0),
            None => {
                let mut st = frame.state(x, y, 0);
                let mut hash = 0u64;
                let c = frame.sample(x, y, 0.5, 0.5, &mut st, &mut hash);
                rays.add(&st.rays);
                (to_f32(c), (hash ^ (hash >> 32)) as u32)
            }
        }
    };
    let wu = w as usize;
    let mut pixels = vec![[0f32; 3]; wu * h as usize];
    let mut hashes = vec![0u32; pixels.len()];
    let row_rays: Vec<RayCounts> = pixels
        .par_chunks_mut(wu * BAND)
        .zip(hashes.par_chunks_mut(wu * BAND))
        .enumerate()
        .map(|(band, (band_pixels, band_hashes))| {
            let y0 = band * BAND;
            let rows = band_pixels.len() / wu;
            let mut rays = RayCounts::default();
            for x0 in (0..wu).step_by(BAND) {
                for dy in 0..rows {
                    for x in x0..(x0 + BAND).min(wu) {
                        let i = dy * wu + x;
                        (band_pixels[i], band_hashes[i]) =
                            shade(x as u32, (y0 + dy) as u32, &mut rays);
                    }
                }
            }
            report(band_pixels.len() as u64 * per_pixel);
            rays
        })
        .collect();
    let mut rays = RayCounts::default();
    row_rays.iter().for_each(|r| rays.add(r));

    // Pass 2 (adaptive only): pixels whose hash differs from a 4-neighbour get a 7×7 grid.
    let mut refined = 0u64;
    if spp.is_none() {
        let differs = |p: usize| {
            let (x, y) = ((p % w as usize) as u32, (p / w as usize) as u32);
            let hh = hashes[p];
            let wu = w as usize;
            (x > 0 && hashes[p - 1] != hh)
                || (x + 1 < w && hashes[p + 1] != hh)
                || (y > 0 && hashes[p - wu] != hh)
                || (y + 1 < h && hashes[p + wu] != hh)
        };
        let edge: Vec<u32> = (0..pixels.len())
            .filter(|&p| differs(p))
            .map(|p| p as u32)
            .collect();
        refined = edge.len() as u64;
        let n = (AA_GRID * AA_GRID) as u64;
        total.fetch_add(refined * n, Ordering::Relaxed);
        let refined_colors: Vec<(DVec3, RayCounts)> = edge
            .par_chunks(16)
            .flat_map_iter(|chunk| {
                let out: Vec<(DVec3, RayCounts)> = chunk
                    .iter()
                    .map(|&p| {
                        let (x, y) = (p % w, p / w);
                        let mut sum = DVec3::ZERO;
                        let mut rays = RayCounts::default();
                        for a in 0..AA_GRID {
                            for b in 0..AA_GRID {
                                let mut st = frame.state(x, y, 1 + a * AA_GRID + b);
                                let fx = (b as f64 + 0.5) / AA_GRID as f64;
                                let fy = (a as f64 + 0.5) / AA_GRID as f64;
                                sum += frame.sample(x, y, fx, fy, &mut st, &mut 0);
                                rays.add(&st.rays);
                            }
                        }
                        (sum / n as f64, rays)
                    })
                    .collect();
                report(out.len() as u64 * n);
                out
            })
            .collect();
        for (&p, (c, r)) in edge.iter().zip(&refined_colors) {
            pixels[p as usize] = to_f32(*c);
            rays.add(r);
        }
    }
    (Image::from_pixels(w, h, pixels), rays, refined, build)
}

#[inline]
fn to_f32(c: DVec3) -> [f32; 3] {
    c.as_vec3().to_array()
}

/// `n` stratified samples in a pixel: exactly its centre for n = 1, else a
/// jittered grid of n strata.
fn stratified(frame: &Frame, x: u32, y: u32, n: u32, rays: &mut RayCounts) -> DVec3 {
    use rand::Rng;
    if n == 1 {
        let mut st = frame.state(x, y, 0);
        let c = frame.sample(x, y, 0.5, 0.5, &mut st, &mut 0);
        rays.add(&st.rays);
        return c;
    }
    let (rows, cols) = crate::shading::strata(n);
    let mut sum = DVec3::ZERO;
    for r in 0..rows {
        for c in 0..cols {
            let mut st = frame.state(x, y, r * cols + c);
            let fx = (c as f64 + st.rng.random::<f64>()) / cols as f64;
            let fy = (r as f64 + st.rng.random::<f64>()) / rows as f64;
            sum += frame.sample(x, y, fx, fy, &mut st, &mut 0);
            rays.add(&st.rays);
        }
    }
    sum / n as f64
}
