//! Rendering: cameras, the shading model, anti-aliasing, tiles and threads.

mod camera;
mod integrator;

pub use camera::CameraRays;
pub use integrator::{MAX_DEPTH, RayCounts};

use crate::accel::{Accel, PACKET_MAX};
use crate::geometry::Ray;
use crate::output::Image;
use crate::scene::Scene;
use crate::shading::ShadowHints;
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
    /// Worker threads, at most [`MAX_THREADS`] (`None`, or a pool the
    /// system refuses to start: one per core). The image is the same either way.
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
const _: () = assert!(
    BAND * BAND <= PACKET_MAX && (AA_GRID * AA_GRID) as usize <= PACKET_MAX,
    "a tile, and a pixel's grid, are one packet each"
);

/// The most worker threads a render starts: far more than any machine's
/// cores, and each idle one costs time (10 000 took minutes on 2 cores).
pub const MAX_THREADS: usize = 1024;

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
            .num_threads(n.clamp(1, MAX_THREADS))
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

/// The columns and rows of a tile of pixels.
type Tile = (std::ops::Range<u32>, std::ops::Range<u32>);

struct Frame<'a> {
    tracer: Tracer<'a>,
    camera: CameraRays,
    width: u32,
    height: u32,
    seed: u64,
}

impl<'a> Frame<'a> {
    /// The frame of `scene`'s camera, tracing through `accel`, with the
    /// random streams of `seed`.
    fn new(scene: &'a Scene, accel: &'a Accel<'a>, seed: u64) -> Self {
        let (width, height) = (scene.camera.width, scene.camera.height);
        Frame {
            tracer: Tracer::new(scene, accel),
            camera: CameraRays::new(&scene.camera, width, height),
            width,
            height,
            seed,
        }
    }

    /// The random stream of one camera sample: a hash of (pixel, sample, seed).
    fn state(&self, x: u32, y: u32, sample: u32) -> PathState {
        let pixel = y as u64 * self.width as u64 + x as u64;
        let key = mix(mix(self.seed ^ mix(pixel)) ^ sample as u64);
        PathState {
            rng: Pcg32::seed_from_u64(key),
            rays: RayCounts::default(),
        }
    }

    /// The camera ray at sub-pixel offset (fx, fy) in [0,1)² of pixel (x, y),
    /// fy measured downward from the pixel's top edge.
    fn ray(&self, x: u32, y: u32, fx: f64, fy: f64) -> Ray {
        // Framework row i counts from the bottom: pixel y covers i ∈ [H−1−y, H−y).
        let i = (self.height - 1 - y) as f64 + (1.0 - fy);
        let j = x as f64 + fx;
        self.camera.ray(i, j)
    }

    /// Camera sample `s` of pixel (x, y) among `rows` × `cols` jittered
    /// strata: its ray, and its random stream after the jitter was drawn.
    fn jittered(&self, x: u32, y: u32, s: u32, (rows, cols): (u32, u32)) -> (Ray, PathState) {
        use rand::Rng;
        let (r, c) = (s / cols, s % cols);
        let mut st = self.state(x, y, s);
        let fx = (c as f64 + st.rng.random::<f64>()) / cols as f64;
        let fy = (r as f64 + st.rng.random::<f64>()) / rows as f64;
        (self.ray(x, y, fx, fy), st)
    }

    /// Traces `n` (at most [`PACKET_MAX`]) camera rays as one packet: ray k
    /// and its random stream are `sample_of(k)`. Calls `each(k, colour,
    /// hash, rays)` in order.
    fn packet(
        &self,
        n: usize,
        sample_of: impl Fn(usize) -> (Ray, PathState),
        mut each: impl FnMut(usize, DVec3, u64, &RayCounts),
        hints: &mut ShadowHints,
    ) {
        debug_assert!(n <= PACKET_MAX);
        // Slots past n hold placeholders; they are not traced.
        let mut camera = [Ray::new(DVec3::ZERO, DVec3::Z); PACKET_MAX];
        let mut states: [PathState; PACKET_MAX] = std::array::from_fn(|_| PathState {
            rng: Pcg32::new(0, 0),
            rays: RayCounts::default(),
        });
        for (k, (ray, st)) in camera.iter_mut().zip(&mut states).take(n).enumerate() {
            (*ray, *st) = sample_of(k);
        }
        let mut hashes = [0u64; PACKET_MAX];
        let mut colors = [DVec3::ZERO; PACKET_MAX];
        self.tracer.trace_camera_packet(
            &camera[..n],
            &mut states[..n],
            &mut hashes[..n],
            &mut colors[..n],
            hints,
        );
        for k in 0..n {
            each(k, colors[k], hashes[k], &states[k].rays);
        }
    }

    /// Pass 2 for pixel (x, y): the mean of the framework's 7×7 grid of
    /// camera rays, traced as one packet.
    fn refine(&self, x: u32, y: u32, rays: &mut RayCounts, hints: &mut ShadowHints) -> DVec3 {
        let g = AA_GRID as usize;
        let at = |k: usize| ((k % g) as f64 + 0.5) / g as f64;
        // Summed in grid order, as one ray after another would be.
        let mut sum = DVec3::ZERO;
        self.packet(
            g * g,
            |k| {
                (
                    self.ray(x, y, at(k), at(k / g)),
                    self.state(x, y, 1 + k as u32),
                )
            },
            |_, c, _, r| {
                sum += c;
                rays.add(r);
            },
            hints,
        );
        sum / (g * g) as f64
    }

    /// Pass 1 over the tile of columns `xs` and rows `ys` when a pixel takes
    /// one ray through its centre, traced as one packet. Calls
    /// `put(x, y, colour, hash)` for each pixel (the hash folded to 32 bits).
    fn centre_tile(
        &self,
        (xs, ys): Tile,
        rays: &mut RayCounts,
        hints: &mut ShadowHints,
        mut put: impl FnMut(u32, u32, DVec3, u32),
    ) {
        let w = xs.len();
        let pixel = |k: usize| (xs.start + (k % w) as u32, ys.start + (k / w) as u32);
        self.packet(
            w * ys.len(),
            |k| {
                let (x, y) = pixel(k);
                (self.ray(x, y, 0.5, 0.5), self.state(x, y, 0))
            },
            |k, c, h, r| {
                let (x, y) = pixel(k);
                rays.add(r);
                put(x, y, c, (h ^ (h >> 32)) as u32);
            },
            hints,
        );
    }

    /// Pass 1 over a tile when a pixel takes `n` (2 or more) stratified
    /// samples: calls `put(x, y, mean)` for each pixel, the tile's samples
    /// traced in packets.
    fn stratified_tile(
        &self,
        (xs, ys): Tile,
        n: u32,
        rays: &mut RayCounts,
        hints: &mut ShadowHints,
        mut put: impl FnMut(u32, u32, DVec3),
    ) {
        let strata = crate::shading::strata(n);
        let (w, n) = (xs.len() as u64, u64::from(n));
        // Up to 64 pixels of up to 2^32 samples: u64 on any target.
        let total = w * ys.len() as u64 * n;
        // Sample i of the tile: pixel i / n (row by row), sample i % n. A
        // packet may end inside a pixel; the pixel's sum runs on into the next.
        let at = |i: u64| {
            let p = i / n;
            let (x, y) = (xs.start + (p % w) as u32, ys.start + (p / w) as u32);
            (x, y, (i % n) as u32)
        };
        let mut sum = DVec3::ZERO;
        let mut start = 0;
        while start < total {
            let len = (total - start).min(PACKET_MAX as u64);
            self.packet(
                len as usize,
                |k| {
                    let (x, y, s) = at(start + k as u64);
                    self.jittered(x, y, s, strata)
                },
                |k, c, _, r| {
                    let (x, y, s) = at(start + k as u64);
                    // Summed in sample order, as ray after ray would be.
                    sum += c;
                    rays.add(r);
                    if u64::from(s) + 1 == n {
                        put(x, y, sum / n as f64);
                        sum = DVec3::ZERO;
                    }
                },
                hints,
            );
            start += len;
        }
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
    let frame = Frame::new(scene, &accel, options.seed);
    let spp = options.spp.map(|n| n.max(1));
    let per_pixel = spp.unwrap_or(1) as u64;
    let total = AtomicU64::new(w as u64 * h as u64 * per_pixel);
    let done = AtomicU64::new(0);
    let report = |n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        progress(d, total.load(Ordering::Relaxed));
    };

    // Pass 1: stratified samples, or one ray through each pixel's centre
    // (with the framework's hash when the anti-aliasing follows). A task is
    // a band of rows (rayon steals work, so both cores stay busy to the
    // end), walked in 8×8 tiles, each one packet of camera rays when a
    // pixel takes one ray, so neighbouring rays share nodes in the cache.
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
            // The band's worker keeps its blockers from tile to tile.
            let mut hints = ShadowHints::default();
            for x0 in (0..wu).step_by(BAND) {
                let x1 = (x0 + BAND).min(wu);
                let tile = (x0 as u32..x1 as u32, y0 as u32..(y0 + rows) as u32);
                let index = |x: u32, y: u32| (y as usize - y0) * wu + x as usize;
                match spp {
                    Some(n) if n > 1 => {
                        let put = |x, y, c| band_pixels[index(x, y)] = to_f32(c);
                        frame.stratified_tile(tile, n, &mut rays, &mut hints, put);
                    }
                    _ => {
                        let put = |x, y, c, hash| {
                            let i = index(x, y);
                            (band_pixels[i], band_hashes[i]) = (to_f32(c), hash);
                        };
                        frame.centre_tile(tile, &mut rays, &mut hints, put);
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
                let mut hints = ShadowHints::default();
                let out: Vec<(DVec3, RayCounts)> = chunk
                    .iter()
                    .map(|&p| {
                        let mut rays = RayCounts::default();
                        (frame.refine(p % w, p / w, &mut rays, &mut hints), rays)
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write;

    /// A cloud of spheres (a deep tree), a plane, a cube and a glass ball.
    fn scene() -> Result<Scene, crate::scene::SceneError> {
        let mut text = String::from(
            "camera\n O= 0 -14 6\n N= 0 1 -0.3\n image_W= 61\n image_H= 37\nend\n\
             light point\n O= 6 -10 16\n color= 1 1 1\nend\n\
             primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.8\nend\n\
             primitive cube\n O= 3 -3 1\n Dx= 1 0 0\n Dy= 0 1 0\n x= 1\n y= 1\n z= 1\n \
             color= 1 0 0\n diff= 0.5\n refl= 0.5\nend\n\
             primitive sphere\n O= -2 -4 2\n R= 1\n color= 1 1 1\n refr= 0.9\n rindex= 1.5\nend\n",
        );
        let mut x = 0.37f64;
        for _ in 0..3000 {
            let mut next = || {
                x = (x * 7919.0 + 0.123).fract();
                x
            };
            let (a, b, c) = (next(), next(), next());
            // Writing to a String cannot fail.
            let _ = write!(
                text,
                "primitive sphere\n O= {} {} {}\n R= 0.12\n color= {a} {b} {c}\n diff= 0.9\nend\n",
                10.0 * a - 5.0,
                10.0 * b - 5.0,
                10.0 * c + 0.5
            );
        }
        Scene::parse(&text, ".")
    }

    #[test]
    fn packets_equal_single_rays() -> Result<(), crate::scene::SceneError> {
        let scene = scene()?;
        let accel = Accel::build(&scene.objects);
        let frame = Frame::new(&scene, &accel, 7);
        let mut hints = ShadowHints::default();
        let mut compared = 0;
        let mut distinct = std::collections::HashSet::new();
        // Tiles of every shape: full, cut at the right and bottom edges.
        for (xs, ys) in [
            (0..8, 0..8),
            (56..61, 8..16),
            (8..16, 32..37),
            (0..61, 20..21),
        ] {
            let mut rays = RayCounts::default();
            frame.centre_tile((xs, ys), &mut rays, &mut hints, |x, y, c, hash| {
                let mut st = frame.state(x, y, 0);
                let mut want_hash = 0u64;
                let mut alone = ShadowHints::default();
                let want = frame.tracer.trace_camera(
                    &frame.ray(x, y, 0.5, 0.5),
                    &mut st,
                    &mut want_hash,
                    &mut alone,
                );
                assert_eq!(c, want, "pixel {x} {y}");
                assert_eq!(
                    hash,
                    (want_hash ^ (want_hash >> 32)) as u32,
                    "pixel {x} {y}"
                );
                distinct.insert(hash);
                compared += 1;
            });
            assert!(rays.camera > 0 && rays.shadow > 0);
        }
        assert_eq!(compared, 64 + 40 + 40 + 61);
        // Pass 2: a pixel's 7×7 grid as one packet, against ray after ray.
        for (x, y) in [(0, 0), (30, 18), (60, 36), (12, 25)] {
            let mut rays = RayCounts::default();
            let got = frame.refine(x, y, &mut rays, &mut hints);
            let mut want = DVec3::ZERO;
            let mut want_rays = RayCounts::default();
            for a in 0..AA_GRID {
                for b in 0..AA_GRID {
                    let mut st = frame.state(x, y, 1 + a * AA_GRID + b);
                    let fx = (b as f64 + 0.5) / AA_GRID as f64;
                    let fy = (a as f64 + 0.5) / AA_GRID as f64;
                    want += frame.tracer.trace_camera(
                        &frame.ray(x, y, fx, fy),
                        &mut st,
                        &mut 0,
                        &mut hints,
                    );
                    want_rays.add(&st.rays);
                }
            }
            assert_eq!(got, want / (AA_GRID * AA_GRID) as f64, "pixel {x} {y}");
            assert_eq!(rays, want_rays);
        }
        // Not a blank picture: many different objects were seen.
        assert!(distinct.len() > 20, "{} distinct hashes", distinct.len());
        Ok(())
    }

    /// Pixel (x, y)'s mean of `n` stratified samples traced ray after ray
    /// (the samples [`Frame::jittered`] gives), and the rays that took.
    fn stratified_alone(frame: &Frame, x: u32, y: u32, n: u32) -> (DVec3, RayCounts) {
        let strata = crate::shading::strata(n);
        let mut rays = RayCounts::default();
        let mut sum = DVec3::ZERO;
        for s in 0..n {
            let (ray, mut st) = frame.jittered(x, y, s, strata);
            let mut alone = ShadowHints::default();
            sum += frame.tracer.trace_camera(&ray, &mut st, &mut 0, &mut alone);
            rays.add(&st.rays);
        }
        (sum / n as f64, rays)
    }

    #[test]
    fn stratified_packets_equal_single_rays() -> Result<(), crate::scene::SceneError> {
        let scene = scene()?;
        let accel = Accel::build(&scene.objects);
        let frame = Frame::new(&scene, &accel, 11);
        let mut hints = ShadowHints::default();
        // Sample counts whose packets hold many pixels, end inside a pixel
        // (6, 9, 43) or cover part of one (70); tiles whole, and cut at the
        // right and bottom edges.
        for (n, (xs, ys)) in [
            (2, (0..8, 0..8)),
            (6, (56..61, 8..16)),
            (9, (24..32, 16..24)),
            (43, (8..16, 32..37)),
            (70, (30..32, 18..19)),
        ] {
            let mut want_rays = RayCounts::default();
            let mut want = std::collections::HashMap::new();
            for y in ys.clone() {
                for x in xs.clone() {
                    let (c, r) = stratified_alone(&frame, x, y, n);
                    want.insert((x, y), c);
                    want_rays.add(&r);
                }
            }
            let mut rays = RayCounts::default();
            let mut got = std::collections::HashMap::new();
            frame.stratified_tile((xs, ys), n, &mut rays, &mut hints, |x, y, c| {
                assert!(got.insert((x, y), c).is_none(), "pixel {x} {y} twice");
            });
            assert_eq!(got, want, "{n} samples");
            assert_eq!(rays, want_rays, "{n} samples");
            assert!(rays.shadow > 0);
        }
        Ok(())
    }

    #[test]
    fn a_stratified_render_puts_each_pixel_where_it_belongs() -> Result<(), crate::scene::SceneError>
    {
        let scene = scene()?;
        let options = RenderOptions {
            threads: Some(2),
            seed: 3,
            spp: Some(2),
        };
        let (image, rays, _, _) = render_inner(&scene, &options, &|_, _| {});
        let accel = Accel::build(&scene.objects);
        let frame = Frame::new(&scene, &accel, 3);
        let mut want_rays = RayCounts::default();
        for y in 0..image.height() {
            for x in 0..image.width() {
                let (c, r) = stratified_alone(&frame, x, y, 2);
                assert_eq!(image.pixel(x, y), to_f32(c), "pixel {x} {y}");
                want_rays.add(&r);
            }
        }
        assert_eq!(rays, want_rays);
        Ok(())
    }
}
