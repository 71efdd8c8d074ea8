//! One render's frame: the camera sample of every pixel and sub-pixel
//! (its ray and random stream), traced in packets, as the passes ask.

use super::camera::CameraRays;
use crate::accel::PACKET_MAX;
use crate::geometry::Ray;
use crate::integrator::{
    AntiAlias, Integrator, PathObserver, PathState, RayCounts, ShadowHints, Stream, mix,
};
use crate::sampling::{RandomSource, strata};
use crate::scene::Camera;
use glam::DVec3;
use rand_pcg::Pcg32;

/// Sub-pixel grid of the framework's anti-aliasing.
pub(crate) const AA_GRID: u32 = 7;
/// Sub-pixel grid of its 2015 ancestor's (abcbdf's, lazycal's): rays ⅓ px apart.
const AA_GRID3: u32 = 3;
/// Rows per rendering task, also the side of the tiles a task walks.
pub(crate) const BAND: usize = 8;
const _: () = assert!(
    BAND * BAND <= PACKET_MAX && (AA_GRID * AA_GRID) as usize <= PACKET_MAX,
    "a tile, and a pixel's grid, are one packet each"
);

/// PM3's pass-2 rays: (rows up, columns right) from the centre, in thirds
/// of a pixel, in the order PM3 traces them.
const CROSS: [(f64, f64); 4] = [(-1.0, 0.0), (0.0, -1.0), (0.0, 1.0), (1.0, 0.0)];

/// The colon family's anti-aliasing rays, as offsets (right, down) from a
/// pixel's centre: the 10×10 grid of step ⅕ over [−0.9, 0.9]², turned by
/// atan ½, the points strictly within the pixel (hta1996/Raytracing
/// `raytracer.cpp` `antiAliasing`, `const.h` `antiAliasingT` = 5).
pub(crate) fn rotated_grid() -> impl Iterator<Item = (f64, f64)> {
    const T: usize = 5;
    let (s, c) = 0.5f64.atan().sin_cos();
    (0..2 * T).flat_map(move |i| {
        (0..2 * T).filter_map(move |j| {
            let x = (i as f64 + 0.5) / T as f64 - 1.0;
            let y = (j as f64 + 0.5) / T as f64 - 1.0;
            let (dx, dy) = (x * c - y * s, x * s + y * c);
            (dx.abs() < 0.5 && dy.abs() < 0.5).then_some((dx, dy))
        })
    })
}

/// The columns and rows of a tile of pixels.
pub(crate) type Tile = (std::ops::Range<u32>, std::ops::Range<u32>);

/// The full frame of one render: its camera rays, integrator and random streams.
pub(crate) struct Frame<'a> {
    pub integrator: Integrator<'a>,
    camera: CameraRays,
    /// The full frame's size in pixels (a region is part of it).
    pub width: u32,
    pub height: u32,
    seed: u64,
    /// Whether lens samples all pass through the pixel's centre (the
    /// lineages' depth of field without `--spp`).
    centred: bool,
}

impl<'a> Frame<'a> {
    /// The frame of `camera` (its size already final), shading with
    /// `integrator`, with the random streams of `seed`.
    pub fn new(camera: &Camera, integrator: Integrator<'a>, seed: u64) -> Self {
        let (width, height) = (camera.width, camera.height);
        let lens = integrator.model().lens;
        Frame {
            integrator,
            camera: CameraRays::new(camera, width, height, lens),
            width,
            height,
            seed,
            centred: false,
        }
    }

    /// The frame with its lens samples through the pixels' centres.
    pub fn centred(self) -> Self {
        Frame {
            centred: true,
            ..self
        }
    }

    /// The random stream of one camera sample: a hash of (pixel, sample, seed).
    pub fn state(&self, x: u32, y: u32, sample: u32) -> PathState {
        PathState::new(stream(self.pixel_key(x, y), sample))
    }

    /// The part of [`Frame::state`]'s hash that is the pixel's (and the seed's).
    fn pixel_key(&self, x: u32, y: u32) -> u64 {
        let pixel = y as u64 * self.width as u64 + x as u64;
        mix(self.seed ^ mix(pixel))
    }

    /// The camera ray at sub-pixel offset (fx, fy) in [0,1)² of pixel (x, y),
    /// fy measured downward from the pixel's top edge.
    pub fn ray(&self, x: u32, y: u32, fx: f64, fy: f64) -> Ray {
        let (i, j) = self.image_position(x, y, fx, fy);
        self.camera.ray(i, j)
    }

    /// Camera sample `s` of pixel (x, y) among `rows` × `cols` jittered
    /// strata: its ray, and its random stream after the jitter was drawn.
    /// With a lens, the ray leaves a point of the lens drawn after the
    /// jitter (all through the pixel's centre when the frame is `centred`).
    pub fn jittered(&self, x: u32, y: u32, s: u32, (rows, cols): (u32, u32)) -> (Ray, PathState) {
        let stratum = (s / cols, s % cols);
        self.sample_in(x, y, self.state(x, y, s), stratum, (rows, cols))
    }

    /// One sample jittered over the whole of pixel (x, y) with random
    /// stream `stream` (SPPM's sample of an iteration).
    pub fn fresh(&self, x: u32, y: u32, stream: u32) -> (Ray, PathState) {
        self.sample_in(x, y, self.state(x, y, stream), (0, 0), (1, 1))
    }

    /// The sample of stratum (r, c) of `rows` × `cols` in pixel (x, y),
    /// drawing from `st`.
    fn sample_in(
        &self,
        x: u32,
        y: u32,
        mut st: PathState,
        stratum: (u32, u32),
        strata: (u32, u32),
    ) -> (Ray, PathState) {
        let draws = self.draw(st.rng.generator(), stratum, strata);
        (self.ray_of(x, y, draws), st)
    }

    /// The draws of a sample of stratum (r, c) of `rows` × `cols`: its
    /// jitter, then with a lens a point of the lens (all through the
    /// pixel's centre when the frame is `centred`).
    fn draw(&self, rng: &mut Pcg32, (r, c): (u32, u32), (rows, cols): (u32, u32)) -> Draws {
        use rand::Rng;
        let (fx, fy) = if self.centred {
            (0.5, 0.5)
        } else {
            let fx = (c as f64 + rng.random::<f64>()) / cols as f64;
            let fy = (r as f64 + rng.random::<f64>()) / rows as f64;
            (fx, fy)
        };
        let disc = self.camera.has_lens().then(|| {
            loop {
                let u = 2.0 * rng.random::<f64>() - 1.0;
                let v = 2.0 * rng.random::<f64>() - 1.0;
                if u * u + v * v <= 1.0 {
                    break (u, v);
                }
            }
        });
        Draws { fx, fy, disc }
    }

    /// The camera ray of pixel (x, y) that `draws` says.
    fn ray_of(&self, x: u32, y: u32, Draws { fx, fy, disc }: Draws) -> Ray {
        self.ray_at(self.image_position(x, y, fx, fy), disc)
    }

    /// The camera ray through image position (i, j), from point `disc` of
    /// the lens if there is one (else the pinhole's).
    fn ray_at(&self, (i, j): (f64, f64), disc: Option<(f64, f64)>) -> Ray {
        match disc {
            None => self.camera.ray(i, j),
            Some(disc) => self.camera.lens_ray(i, j, disc),
        }
    }

    /// Frame position (rows from the bottom, columns) of sub-pixel (fx, fy)
    /// of pixel (x, y).
    fn image_position(&self, x: u32, y: u32, fx: f64, fy: f64) -> (f64, f64) {
        // Framework row i counts from the bottom: pixel y covers i ∈ [H−1−y, H−y).
        ((self.height - 1 - y) as f64 + (1.0 - fy), x as f64 + fx)
    }

    /// The camera sample of pass 1 at pixel (x, y): the ray through its
    /// centre and random stream 0.
    pub fn centre_sample(&self, x: u32, y: u32) -> (Ray, PathState) {
        (self.ray(x, y, 0.5, 0.5), self.state(x, y, 0))
    }

    /// The anti-aliasing of the lineage.
    pub fn anti_alias(&self) -> AntiAlias {
        self.integrator.model().anti_alias
    }

    /// The camera rays pass 2 traces in a refined pixel: the 7×7 or 3×3
    /// grid, PM3's four rays ⅓ px away or the colon family's turned grid
    /// (none without anti-aliasing).
    pub fn refine_count(&self) -> usize {
        match self.anti_alias() {
            AntiAlias::Grid7 => (AA_GRID * AA_GRID) as usize,
            AntiAlias::Grid3 => (AA_GRID3 * AA_GRID3) as usize,
            AntiAlias::Cross5 => CROSS.len(),
            AntiAlias::Rotated => rotated_grid().count(),
            AntiAlias::None => 0,
        }
    }

    /// Sample `k` of pass 2 in pixel (x, y): of the 7×7 or 3×3 grid (row by row),
    /// of PM3's four rays ⅓ px above, left, right and below the centre, or
    /// of the colon family's turned grid.
    pub fn grid_sample(&self, x: u32, y: u32, k: usize) -> (Ray, PathState) {
        let (fx, fy) = self.grid_offset(k);
        (self.ray(x, y, fx, fy), self.state(x, y, 1 + k as u32))
    }

    /// The sub-pixel offset of [`Frame::grid_sample`] `k`.
    fn grid_offset(&self, k: usize) -> (f64, f64) {
        match self.anti_alias() {
            AntiAlias::Cross5 => {
                let (di, dj) = CROSS[k % CROSS.len()];
                // Rows from the top here, the lineage's i from the bottom.
                (0.5 + dj / 3.0, 0.5 - di / 3.0)
            }
            AntiAlias::Rotated => {
                let (dx, dy) = rotated_grid().nth(k).unwrap_or_default();
                (0.5 + dx, 0.5 + dy)
            }
            grid => {
                let g = if grid == AntiAlias::Grid3 {
                    AA_GRID3
                } else {
                    AA_GRID
                } as usize;
                let at = |k: usize| ((k % g) as f64 + 0.5) / g as f64;
                (at(k), at(k / g))
            }
        }
    }

    /// A refined pixel's colour from its pass-1 colour `first` (as stored)
    /// and the sum of its pass-2 samples.
    pub fn refined(&self, first: DVec3, sum: DVec3) -> DVec3 {
        match self.anti_alias() {
            AntiAlias::Cross5 => ((first + sum) / 5.0).min(DVec3::ONE),
            _ => sum / self.refine_count().max(1) as f64,
        }
    }

    /// Traces `n` (at most [`PACKET_MAX`]) camera rays as one packet: ray k
    /// and its random stream are `sample_of(k)`, watched by a copy of
    /// `fresh`. Calls `each(k, colour, observer, rays)` in order.
    pub fn packet<O: PathObserver + Clone>(
        &self,
        n: usize,
        sample_of: impl Fn(usize) -> (Ray, PathState),
        fresh: &O,
        each: impl FnMut(usize, DVec3, &mut O, &RayCounts),
        hints: &mut ShadowHints,
    ) {
        debug_assert!(n <= PACKET_MAX);
        // Slots past n hold placeholders; they are not traced.
        let mut camera = [Ray::new(DVec3::ZERO, DVec3::Z); PACKET_MAX];
        let mut states: [PathState; PACKET_MAX] =
            std::array::from_fn(|_| PathState::new(Stream::new(0)));
        for (k, (ray, st)) in camera.iter_mut().zip(&mut states).take(n).enumerate() {
            (*ray, *st) = sample_of(k);
        }
        self.trace(&camera[..n], &mut states[..n], fresh, each, hints);
    }

    /// [`Frame::packet`] of the camera samples `sample_of(k)`: a pixel, the
    /// sample's draws there and its random stream. Without a lens their
    /// rays are made together, lane by lane ([`CameraRays::rays`]).
    fn packet_of_draws<O: PathObserver + Clone>(
        &self,
        n: usize,
        sample_of: impl Fn(usize) -> ((u32, u32), Draws, PathState),
        fresh: &O,
        each: impl FnMut(usize, DVec3, &mut O, &RayCounts),
        hints: &mut ShadowHints,
    ) {
        debug_assert!(n <= PACKET_MAX);
        let mut at = [(0.0, 0.0); PACKET_MAX];
        let mut discs = [None; PACKET_MAX];
        let mut states: [PathState; PACKET_MAX] =
            std::array::from_fn(|_| PathState::new(Stream::new(0)));
        for k in 0..n {
            let ((x, y), Draws { fx, fy, disc }, st) = sample_of(k);
            (at[k], discs[k], states[k]) = (self.image_position(x, y, fx, fy), disc, st);
        }
        let mut camera = [Ray::new(DVec3::ZERO, DVec3::Z); PACKET_MAX];
        if discs[..n].iter().all(Option::is_none) {
            self.camera.rays(&at[..n], &mut camera[..n]);
        } else {
            for k in 0..n {
                camera[k] = self.ray_at(at[k], discs[k]);
            }
        }
        self.trace(&camera[..n], &mut states[..n], fresh, each, hints);
    }

    /// Traces `camera` (at most [`PACKET_MAX`] rays) with the random
    /// streams `states` as one packet, each ray watched by a copy of
    /// `fresh`. Calls `each(k, colour, observer, rays)` in order.
    fn trace<O: PathObserver + Clone>(
        &self,
        camera: &[Ray],
        states: &mut [PathState],
        fresh: &O,
        mut each: impl FnMut(usize, DVec3, &mut O, &RayCounts),
        hints: &mut ShadowHints,
    ) {
        let n = camera.len();
        let mut observers: [O; PACKET_MAX] = std::array::from_fn(|_| fresh.clone());
        let mut colors = [DVec3::ZERO; PACKET_MAX];
        self.integrator.trace_camera_packet(
            camera,
            states,
            &mut observers[..n],
            &mut colors[..n],
            hints,
        );
        for (k, observer) in observers.iter_mut().take(n).enumerate() {
            each(k, colors[k], observer, &states[k].rays);
        }
    }

    /// Pass 2 for pixel (x, y), whose pass-1 colour was `first`: the mean
    /// of the framework's 7×7 grid of camera rays (or PM3's five rays),
    /// traced as one packet, each watched by a copy of `fresh` that is
    /// handed to `seen` once traced.
    pub fn refine<O: PathObserver + Clone>(
        &self,
        (x, y): (u32, u32),
        first: DVec3,
        rays: &mut RayCounts,
        hints: &mut ShadowHints,
        fresh: &O,
        mut seen: impl FnMut(&O),
    ) -> DVec3 {
        // Summed in grid order, as one ray after another would be.
        let mut sum = DVec3::ZERO;
        let n = self.refine_count();
        let key = self.pixel_key(x, y);
        self.packet_of_draws(
            n,
            |k| {
                let (fx, fy) = self.grid_offset(k);
                let st = PathState::new(stream(key, 1 + k as u32));
                ((x, y), Draws { fx, fy, disc: None }, st)
            },
            fresh,
            |_, c, o, r| {
                sum += c;
                rays.add(r);
                seen(o);
            },
            hints,
        );
        self.refined(first, sum)
    }

    /// Pass 1 over the tile of columns `xs` and rows `ys` when a pixel takes
    /// one ray through its centre, traced as one packet, each watched by a
    /// copy of `fresh`. Calls `put(x, y, colour, observer, rays traced)` for
    /// each pixel.
    pub fn centre_tile<O: PathObserver + Clone>(
        &self,
        (xs, ys): Tile,
        rays: &mut RayCounts,
        hints: &mut ShadowHints,
        fresh: &O,
        mut put: impl FnMut(u32, u32, DVec3, &O, u64),
    ) {
        let w = xs.len();
        let pixel = |k: usize| (xs.start + (k % w) as u32, ys.start + (k / w) as u32);
        let n = w * ys.len();
        self.packet_of_draws(
            n,
            |k| {
                let (x, y) = pixel(k);
                let st = PathState::new(stream(self.pixel_key(x, y), 0));
                let centre = Draws {
                    fx: 0.5,
                    fy: 0.5,
                    disc: None,
                };
                ((x, y), centre, st)
            },
            fresh,
            |k, c, o, r| {
                let (x, y) = pixel(k);
                rays.add(r);
                put(x, y, c, o, r.total());
            },
            hints,
        );
    }

    /// Pass 1 over a tile when a pixel takes `n` (2 or more) stratified
    /// samples: calls `put(x, y, mean, rays traced)` for each pixel, the
    /// tile's samples traced in packets, each watched by a copy of `fresh`
    /// that is handed to `seen(x, y, observer)` once traced.
    pub fn stratified_tile<O: PathObserver + Clone>(
        &self,
        (xs, ys): Tile,
        n: u32,
        hints: &mut ShadowHints,
        fresh: &O,
        mut put: impl FnMut(u32, u32, DVec3, &RayCounts),
        mut seen: impl FnMut(u32, u32, &O),
    ) {
        let strata = strata(n);
        // Up to 64 pixels of up to 2^32 samples: u64 on any target.
        let total = xs.len() as u64 * ys.len() as u64 * u64::from(n);
        // The tile's samples pixel by pixel (row by row), each pixel's in
        // order. A packet may end inside a pixel; the pixel's sum runs on
        // into the next.
        let mut next = Cursor::new(self, xs.start, ys.start);
        let mut at = [next; PACKET_MAX];
        // A packet's streams are seeded for all its samples first, then
        // their draws made, then their rays: short loops whose samples
        // overlap in the CPU (each sample's steps form a chain).
        let mut rngs: [Stream; PACKET_MAX] = std::array::from_fn(|_| Stream::new(0));
        let mut draws = [Draws::default(); PACKET_MAX];
        let mut sum = DVec3::ZERO;
        let mut pixel_rays = RayCounts::default();
        let mut start = 0;
        while start < total {
            let len = (total - start).min(PACKET_MAX as u64);
            let len = len as usize;
            for (a, rng) in at.iter_mut().zip(&mut rngs).take(len) {
                *a = next;
                *rng = stream(next.key, next.s);
                // Seeded here, as `draw` below would seed it anyway.
                rng.generator();
                next.advance(self, &xs, n, strata.1);
            }
            for ((a, rng), d) in at.iter().zip(&mut rngs).zip(&mut draws).take(len) {
                *d = self.draw(rng.generator(), a.stratum, strata);
            }
            self.packet_of_draws(
                len,
                |k| {
                    let st = PathState::new(rngs[k].clone());
                    ((at[k].x, at[k].y), draws[k], st)
                },
                fresh,
                |k, c, o, r| {
                    let Cursor { x, y, s, .. } = at[k];
                    seen(x, y, o);
                    // Summed in sample order, as ray after ray would be.
                    sum += c;
                    pixel_rays.add(r);
                    if s + 1 == n {
                        put(x, y, sum / n as f64, &pixel_rays);
                        (sum, pixel_rays) = (DVec3::ZERO, RayCounts::default());
                    }
                },
                hints,
            );
            start += len as u64;
        }
    }
}

/// The random stream of sample `sample` of the pixel whose key is `key`.
fn stream(key: u64, sample: u32) -> Stream {
    Stream::new(mix(key ^ sample as u64))
}

/// A camera sample's draws: its sub-pixel offset (in [0,1)², y down) and,
/// with a lens, its point of the unit disc.
#[derive(Clone, Copy, Default)]
struct Draws {
    fx: f64,
    fy: f64,
    disc: Option<(f64, f64)>,
}

/// One stratified sample of a tile, counted on from the last (no division
/// a sample): its pixel and that pixel's key, its index and stratum.
#[derive(Clone, Copy)]
struct Cursor {
    x: u32,
    y: u32,
    key: u64,
    s: u32,
    stratum: (u32, u32),
}

impl Cursor {
    /// Sample 0 of pixel (x, y) of `frame`.
    fn new(frame: &Frame<'_>, x: u32, y: u32) -> Self {
        Cursor {
            x,
            y,
            key: frame.pixel_key(x, y),
            s: 0,
            stratum: (0, 0),
        }
    }

    /// On to the next sample of `n` a pixel in strata of `cols` columns,
    /// and after a pixel's last to the next pixel of columns `xs` (row by row).
    fn advance(&mut self, frame: &Frame<'_>, xs: &std::ops::Range<u32>, n: u32, cols: u32) {
        self.s += 1;
        self.stratum.1 += 1;
        if self.stratum.1 == cols {
            self.stratum = (self.stratum.0 + 1, 0);
        }
        if self.s == n {
            let (x, y) = if self.x + 1 == xs.end {
                (xs.start, self.y + 1)
            } else {
                (self.x + 1, self.y)
            };
            *self = Cursor::new(frame, x, y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{AaHash, NoObserver, SceneAccel};
    use crate::scene::Scene;
    use std::fmt::Write;

    /// `scene`'s accelerator and camera, for building frames.
    fn prepared(scene: &Scene) -> (SceneAccel, Camera) {
        (
            SceneAccel::build(scene.objects().to_vec()),
            scene.camera().clone(),
        )
    }

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
        // Enough materials that the packets read them ahead.
        assert!(scene.material_count() > crate::integrator::READ_AHEAD_MATERIALS);
        let (accel, camera) = prepared(&scene);
        let frame = Frame::new(
            &camera,
            Integrator::whitted(&scene, &camera, &accel, Default::default()),
            7,
        );
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
            frame.centre_tile(
                (xs, ys),
                &mut rays,
                &mut hints,
                &AaHash::default(),
                |x, y, c, hash: &AaHash, _| {
                    let mut st = frame.state(x, y, 0);
                    let mut want_hash = AaHash::default();
                    let mut alone = ShadowHints::default();
                    let want = frame.integrator.trace_camera(
                        &frame.ray(x, y, 0.5, 0.5),
                        &mut st,
                        &mut want_hash,
                        &mut alone,
                    );
                    assert_eq!(c, want, "pixel {x} {y}");
                    assert_eq!(*hash, want_hash, "pixel {x} {y}");
                    distinct.insert(hash.folded());
                    compared += 1;
                },
            );
            assert!(rays.camera > 0 && rays.shadow > 0);
        }
        assert_eq!(compared, 64 + 40 + 40 + 61);
        // Pass 2: a pixel's 7×7 grid as one packet, against ray after ray.
        for (x, y) in [(0, 0), (30, 18), (60, 36), (12, 25)] {
            let mut rays = RayCounts::default();
            let got = frame.refine(
                (x, y),
                DVec3::ZERO,
                &mut rays,
                &mut hints,
                &NoObserver,
                |_| {},
            );
            let mut want = DVec3::ZERO;
            let mut want_rays = RayCounts::default();
            for a in 0..AA_GRID {
                for b in 0..AA_GRID {
                    let mut st = frame.state(x, y, 1 + a * AA_GRID + b);
                    let fx = (b as f64 + 0.5) / AA_GRID as f64;
                    let fy = (a as f64 + 0.5) / AA_GRID as f64;
                    want += frame.integrator.trace_camera(
                        &frame.ray(x, y, fx, fy),
                        &mut st,
                        &mut NoObserver,
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
        let strata = strata(n);
        let mut rays = RayCounts::default();
        let mut sum = DVec3::ZERO;
        for s in 0..n {
            let (ray, mut st) = frame.jittered(x, y, s, strata);
            let mut alone = ShadowHints::default();
            sum += frame
                .integrator
                .trace_camera(&ray, &mut st, &mut NoObserver, &mut alone);
            rays.add(&st.rays);
        }
        (sum / n as f64, rays)
    }

    #[test]
    fn stratified_packets_equal_single_rays() -> Result<(), crate::scene::SceneError> {
        let scene = scene()?;
        let (accel, camera) = prepared(&scene);
        let frame = Frame::new(
            &camera,
            Integrator::whitted(&scene, &camera, &accel, Default::default()),
            11,
        );
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
            let put = |x, y, c, r: &RayCounts| {
                assert!(got.insert((x, y), c).is_none(), "pixel {x} {y} twice");
                rays.add(r);
            };
            frame.stratified_tile((xs, ys), n, &mut hints, &NoObserver, put, |_, _, _| {});
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
        let (accel, camera) = prepared(&scene);
        let frame = Frame::new(
            &camera,
            Integrator::whitted(&scene, &camera, &accel, Default::default()),
            3,
        );
        let options = crate::render::RenderOptions {
            threads: Some(2),
            seed: 3,
            spp: Some(2),
            ..Default::default()
        };
        let renderer = crate::render::Renderer::new(scene.clone());
        let (film, stats) = match renderer.render_with(&options, Default::default()) {
            Ok(done) => done,
            Err(e) => panic!("{e}"), // invariant: the test's own fixed input (a failure fails the test)
        };
        let image = film.image();
        let mut want_rays = RayCounts::default();
        for y in 0..image.height() {
            for x in 0..image.width() {
                let (c, r) = stratified_alone(&frame, x, y, 2);
                assert_eq!(image.pixel(x, y), c.as_vec3().to_array(), "pixel {x} {y}");
                want_rays.add(&r);
            }
        }
        assert_eq!(stats.rays, want_rays);
        Ok(())
    }
}
