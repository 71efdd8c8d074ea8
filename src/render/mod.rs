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
    /// Wall time of the render (not counting parsing).
    pub elapsed: Duration,
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

/// Side of the square tiles the image is cut into for the threads.
const TILE: u32 = 16;
/// Sub-pixel grid of the framework's anti-aliasing.
const AA_GRID: u32 = 7;

/// Renders a scene, calling `progress(done, total)` (in units of camera
/// rays) as tiles finish; returns the image and the figures.
pub fn render_with_progress(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> (Image, RenderStats) {
    let start = Instant::now();
    let run = || render_inner(scene, options, progress);
    let (image, rays, refined) = match options.threads {
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
        refined_pixels: refined,
    };
    (image, stats)
}

/// One tile's rectangle, in pixels (y from the top).
#[derive(Clone, Copy)]
struct Tile {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

fn tiles(w: u32, h: u32) -> Vec<Tile> {
    let mut v = Vec::new();
    for y0 in (0..h).step_by(TILE as usize) {
        for x0 in (0..w).step_by(TILE as usize) {
            v.push(Tile {
                x0,
                y0,
                x1: (x0 + TILE).min(w),
                y1: (y0 + TILE).min(h),
            });
        }
    }
    v
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
) -> (Image, RayCounts, u64) {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let accel = Accel::build(&scene.objects);
    let frame = Frame {
        tracer: Tracer::new(scene, &accel),
        camera: CameraRays::new(&scene.camera, w, h),
        width: w,
        height: h,
        seed: options.seed,
    };
    let tiles = tiles(w, h);
    let spp = options.spp.map(|n| n.max(1));
    let per_pixel = spp.unwrap_or(1) as u64;
    let total = AtomicU64::new(w as u64 * h as u64 * per_pixel);
    let done = AtomicU64::new(0);
    let report = |n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        progress(d, total.load(Ordering::Relaxed));
    };

    // Pass 1: every pixel (stratified samples, or the framework's single ray with its hash).
    let results: Vec<(Vec<DVec3>, Vec<u64>, RayCounts)> = tiles
        .par_iter()
        .map(|t| {
            let mut colors = Vec::with_capacity(((t.x1 - t.x0) * (t.y1 - t.y0)) as usize);
            let mut hashes = Vec::with_capacity(colors.capacity());
            let mut rays = RayCounts::default();
            for y in t.y0..t.y1 {
                for x in t.x0..t.x1 {
                    let (c, hash) = match spp {
                        Some(n) => (stratified(&frame, x, y, n, &mut rays), 0),
                        None => {
                            let mut st = frame.state(x, y, 0);
                            let mut hash = 0;
                            let c = frame.sample(x, y, 0.5, 0.5, &mut st, &mut hash);
                            rays.add(&st.rays);
                            (c, hash)
                        }
                    };
                    colors.push(c);
                    hashes.push(hash);
                }
            }
            report(colors.len() as u64 * per_pixel);
            (colors, hashes, rays)
        })
        .collect();

    let mut pixels = vec![DVec3::ZERO; (w * h) as usize];
    let mut hashes = vec![0u64; (w * h) as usize];
    let mut rays = RayCounts::default();
    for (t, (c, hs, r)) in tiles.iter().zip(&results) {
        let tw = (t.x1 - t.x0) as usize;
        for (k, (col, hash)) in c.iter().zip(hs).enumerate() {
            let idx = (t.y0 as usize + k / tw) * w as usize + t.x0 as usize + k % tw;
            pixels[idx] = *col;
            hashes[idx] = *hash;
        }
        rays.add(r);
    }
    drop(results);

    // Pass 2 (adaptive only): pixels whose hash differs from a 4-neighbour get a 7×7 grid.
    let mut refined = 0u64;
    if spp.is_none() {
        let edge: Vec<u32> = (0..w * h)
            .filter(|&p| {
                let (x, y) = (p % w, p / w);
                let hh = hashes[p as usize];
                (x > 0 && hashes[(p - 1) as usize] != hh)
                    || (x + 1 < w && hashes[(p + 1) as usize] != hh)
                    || (y > 0 && hashes[(p - w) as usize] != hh)
                    || (y + 1 < h && hashes[(p + w) as usize] != hh)
            })
            .collect();
        refined = edge.len() as u64;
        let n = (AA_GRID * AA_GRID) as u64;
        total.fetch_add(refined * n, Ordering::Relaxed);
        let refined_colors: Vec<(DVec3, RayCounts)> = edge
            .par_chunks(64)
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
                                let (fx, fy) = (
                                    (b as f64 + 0.5) / AA_GRID as f64,
                                    (a as f64 + 0.5) / AA_GRID as f64,
                                );
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
            pixels[p as usize] = *c;
            rays.add(r);
        }
    }
    let image = Image::from_fn(w, h, |x, y| pixels[(y * w + x) as usize]);
    (image, rays, refined)
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
