//! Rendering: a [`Renderer`] keeps a prepared scene (its acceleration
//! structure built once) and renders it, or a region of it, to a [`Film`]
//! as [`RenderOptions`] say: on any number of threads, with a progress
//! callback and a flag another thread can set to stop it.

mod aov;
mod camera;
mod explain;
mod film;
mod frame;
mod memory;
mod passes;
mod photons;
mod report;
mod schedule;
mod shading_passes;
mod verdict;

pub use aov::Aov;
#[cfg(feature = "serve")]
pub(crate) use camera::basis;
pub use explain::{Explanation, HitPointTerm, ProgressiveTerm, Sampling};
pub use film::{Film, Plane, Region};
pub use photons::PhotonStats;
pub use schedule::MAX_THREADS;
pub use shading_passes::LIGHT_PASSES_MAX;
pub(crate) use verdict::{Cause, place};

use crate::integrator::photons::{PhotonMap, PhotonMode, PhotonOptions, Plan, Term};
use crate::integrator::{Integrator, Model, PhotonShading, RayCounts, SceneAccel};
use crate::output::Image;
use crate::scene::{Camera, LightKind, MAX_IMAGE_SIDE, Scene};
use frame::Frame;
use passes::{Keep, Watch, render_region};
use shading_passes::ShadingPasses;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// The most samples per pixel [`Renderer::explain`] takes (it keeps every
/// sample's ray tree).
pub const MAX_EXPLAINED_SPP: u32 = 4096;

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
    /// Image width, overriding the camera's `image_W=`; given alone, the
    /// height follows the camera's aspect. The lens is kept as the scene sets it.
    pub width: Option<u32>,
    /// Image height, overriding the camera's `image_H=` (see `width`).
    pub height: Option<u32>,
    /// The part of the frame to render (`None`: all of it). Its pixels are
    /// the same bytes as those pixels of the whole render.
    pub region: Option<Region>,
    /// Passes to store as planes of the film beside the colour, named as
    /// [`Aov::name`] says (the picture is the same with or without them).
    pub aovs: Vec<Aov>,
    /// Photon mapping as the command line overrides it.
    pub photons: PhotonOptions,
}

/// Figures about a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Wall time of the render (not counting parsing or the acceleration structure).
    pub elapsed: Duration,
    /// Wall time of the acceleration-structure build (when the renderer was made).
    pub build: Duration,
    /// Pixels re-rendered by the adaptive anti-aliasing.
    pub refined_pixels: u64,
    /// The photon passes' figures (all zero without photons).
    pub photons: PhotonStats,
}

impl RenderStats {
    /// Millions of rays per second, the acceleration structure's build counted in.
    pub fn mrays_per_sec(&self) -> f64 {
        let secs = (self.elapsed + self.build).as_secs_f64().max(1e-9);
        self.rays.total() as f64 / secs / 1e6
    }
}

/// Why a render did not produce a film.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    /// An image side outside 1 to [`MAX_IMAGE_SIDE`] pixels.
    #[error("{name} {value} is out of range: an image side must be 1 to {MAX_IMAGE_SIDE} pixels")]
    Side {
        /// `width` or `height`.
        name: &'static str,
        /// The value asked for.
        value: u32,
    },
    /// A region that is empty or not inside the frame.
    #[error(
        "the region {}x{} at ({}, {}) is not inside the {frame_w}x{frame_h} frame",
        region.width, region.height, region.x, region.y
    )]
    Region {
        /// The region asked for.
        region: Region,
        /// The frame's width.
        frame_w: u32,
        /// The frame's height.
        frame_h: u32,
    },
    /// A pixel outside the frame.
    #[error("the pixel ({x}, {y}) is not inside the {frame_w}x{frame_h} frame")]
    Pixel {
        /// Its column.
        x: u32,
        /// Its row (from the top).
        y: u32,
        /// The frame's width.
        frame_w: u32,
        /// The frame's height.
        frame_h: u32,
    },
    /// More samples per pixel than `explain` keeps trees of.
    #[error("spp {value} is too many to explain: every sample's tree is kept, at most {max}")]
    Samples {
        /// The samples asked for.
        value: u32,
        /// The most `explain` takes.
        max: u32,
    },
    /// More `light:N` passes than one render takes.
    #[error("{asked} light:N passes asked for: one render takes at most {max}")]
    LightPasses {
        /// The `light:N` passes asked for.
        asked: usize,
        /// The most one render takes.
        max: usize,
    },
    /// The cancel flag was set.
    #[error("the render was cancelled")]
    Cancelled,
    /// More PPM hit points than the camera's `max_hitpoints=` allows.
    #[error(
        "the eye pass found more than `max_hitpoints= {max}` hit points: raise it in the camera block, or render smaller"
    )]
    HitPoints {
        /// The key's value.
        max: u64,
    },
}

impl From<photons::Unfinished> for RenderError {
    fn from(e: photons::Unfinished) -> Self {
        match e {
            photons::Unfinished::Cancelled => RenderError::Cancelled,
            photons::Unfinished::HitPoints { max } => RenderError::HitPoints { max },
        }
    }
}

/// What PPM and SPPM hand the picture so far to: (iteration, film).
pub type Checkpoint<'c> = &'c (dyn Fn(u64, &Film) + Sync);

/// What a render tells as it goes, and how to stop it.
#[derive(Clone, Copy, Default)]
pub struct Control<'c> {
    /// Called with (done, total), in units of camera rays, as rows finish.
    pub progress: Option<&'c (dyn Fn(u64, u64) + Sync)>,
    /// Stops the render at once when another thread sets it (PPM and SPPM:
    /// after the last complete iteration, whose picture is the result).
    pub cancel: Option<&'c AtomicBool>,
    /// PPM and SPPM: given (iteration, film) every `checkpoint_every` iterations.
    pub checkpoint: Option<Checkpoint<'c>>,
    /// How many iterations apart checkpoints are (0: 10).
    pub checkpoint_every: u64,
}

/// Which image of a progressive render a callback is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// A quarter-size preview, one ray per pixel.
    Coarse,
    /// The render the options ask for.
    Final,
}

/// A scene prepared for rendering: it owns the scene and the acceleration
/// structure built over its surfaces, so it renders again and again
/// (other options, other regions) without building anything twice.
pub struct Renderer {
    scene: Scene,
    accel: SceneAccel,
    build: Duration,
}

impl Renderer {
    /// Prepares `scene`: builds its acceleration structure (which takes the
    /// scene's surfaces).
    pub fn new(mut scene: Scene) -> Renderer {
        let start = Instant::now();
        let accel = SceneAccel::build(scene.take_objects());
        Renderer {
            scene,
            accel,
            build: start.elapsed(),
        }
    }

    /// The acceleration structure over the scene's surfaces.
    pub(crate) fn accel(&self) -> &SceneAccel {
        &self.accel
    }

    /// The scene it renders (its surfaces are in [`Renderer::accel`]).
    pub(crate) fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The ray through the centre of pixel (x, y) of a `w` × `h` render,
    /// as the render traces it.
    pub(crate) fn centre_rays(
        &self,
        w: u32,
        h: u32,
    ) -> impl Fn(u32, u32) -> crate::geometry::Ray + '_ {
        let frame = self.frame(w, h, 0, PhotonShading::default());
        move |x, y| frame.ray(x, y, 0.5, 0.5)
    }

    /// How long building the acceleration structure took.
    pub fn build_time(&self) -> Duration {
        self.build
    }

    /// The frame size `options` give: the camera's, or the overrides
    /// (one alone keeps the camera's aspect).
    pub fn frame_size(&self, options: &RenderOptions) -> Result<(u32, u32), RenderError> {
        for (name, v) in [("width", options.width), ("height", options.height)] {
            if let Some(value) = v
                && (value == 0 || value > MAX_IMAGE_SIDE)
            {
                return Err(RenderError::Side { name, value });
            }
        }
        let cam = self.scene.camera();
        let (w0, h0) = (cam.width as f64, cam.height as f64);
        let scaled = |v: f64| (v.round() as u32).clamp(1, MAX_IMAGE_SIDE);
        Ok(match (options.width, options.height) {
            (Some(w), Some(h)) => (w, h),
            (Some(w), None) => (w, scaled(w as f64 * h0 / w0)),
            (None, Some(h)) => (scaled(h as f64 * w0 / h0), h),
            (None, None) => (cam.width, cam.height),
        })
    }

    /// A rough count of the rays a render of `options` traces, before any
    /// is: camera samples × (1 + shadow rays a point) × glossy rays, with the
    /// settings that drive it, to warn about a render that will take long.
    pub fn estimate(&self, options: &RenderOptions) -> Result<WorkEstimate, RenderError> {
        let (w, h) = self.frame_size(options)?;
        let cam = self.scene.camera();
        let pixels = self.pixels(options)?;
        // Each driving key with its place, `scene.txt:12 `shade_quality=64``,
        // when the scene was read from text.
        let file = self.scene.path().map_or_else(
            || "<input>".to_string(),
            |p| crate::scene::escaped(&p.display().to_string()).into_owned(),
        );
        let place = |line: Option<u32>| line.map(|l| format!("{file}:{l}"));
        let key = |name: &str, value: &dyn std::fmt::Display| match place(
            self.scene.camera_key_line(name),
        ) {
            Some(at) => format!("{at} `{name}={value}`"),
            None => format!("`{name}={value}`"),
        };
        let file_key = |name: &str, value: &dyn std::fmt::Display| {
            self.scene
                .camera_key_line(name)
                .is_some()
                .then(|| key(name, value))
        };
        let mut size = format!("{w}x{h} pixels");
        if options.width.is_none() && options.height.is_none() {
            let keys: Vec<String> = [
                file_key("image_W", &cam.width),
                file_key("image_H", &cam.height),
            ]
            .into_iter()
            .flatten()
            .collect();
            if !keys.is_empty() {
                size = format!("{size} ({})", keys.join(", "));
            }
        }
        let mut drivers = vec![size];
        let samples = match options.spp {
            Some(n) => {
                drivers.push(format!("--spp {n}"));
                u64::from(n)
            }
            None => ADAPTIVE_RAYS_PER_PIXEL,
        };
        let lights = self.scene.lights();
        let area_lines: Vec<Option<u32>> = (0..lights.len() as u32)
            .filter(|&i| !matches!(lights[i as usize].kind, LightKind::Point { .. }))
            .map(|i| self.scene.light_line(i))
            .collect();
        let area = area_lines.len() as u64;
        let per_area = 16 * u64::from(cam.shade_quality.max(1));
        let shadow = (lights.len() as u64 - area) + area * per_area;
        if area > 0 {
            // The area lights' headers too (the first few).
            const SHOWN: usize = 3;
            let mut at: Vec<String> = area_lines
                .iter()
                .filter_map(|&l| place(l))
                .take(SHOWN)
                .collect();
            if area_lines.len() > SHOWN && !at.is_empty() {
                at.push(format!("and {} more", area_lines.len() - SHOWN));
            }
            let at = if at.is_empty() {
                String::new()
            } else {
                format!(" ({})", at.join(", "))
            };
            drivers.push(format!(
                "{} with {area} area light(s){at}: {per_area} shadow rays each a point",
                key("shade_quality", &cam.shade_quality)
            ));
        }
        let model = crate::integrator::Model::of(self.scene.dialect().dialect, cam);
        let glossy = model.glossy != crate::integrator::Glossy::Mirror
            && self.scene.materials().any(|m| m.drefl > 0.0);
        let spread = if glossy {
            let n = u64::from(model.glossy_samples);
            drivers.push(format!(
                "{}: {n} rays a glossy reflection",
                key("drefl_quality", &cam.drefl_quality)
            ));
            n
        } else {
            1
        };
        let mut rays = pixels
            .saturating_mul(samples)
            .saturating_mul(1 + shadow)
            .saturating_mul(spread);
        let (plan, _) = Plan::of(&self.scene, &options.photons);
        if plan.mode != PhotonMode::Off {
            // A photon meets a few surfaces; PPM and SPPM repeat the pass
            // (SPPM its eye pass too).
            let passes = if plan.mode.progressive() {
                plan.iterations
            } else {
                1
            };
            let p = &cam.photons;
            let mut keys: Vec<String> = Vec::new();
            if options.photons.mode.is_none()
                && let Some(a) = cam.algorithm.as_deref()
            {
                keys.extend(file_key("algorithm", &a));
            }
            if options.photons.emit.is_none() {
                keys.extend(file_key("emit_photons", &p.emit_photons));
            }
            if plan.mode.progressive()
                && options.photons.iterations.is_none()
                && let Some(n) = p.iterations
            {
                keys.extend(file_key("iterations", &n));
            }
            let keys = if keys.is_empty() {
                String::new()
            } else {
                format!(" ({})", keys.join(", "))
            };
            drivers.push(format!(
                "photons {}: {} a pass, {passes} pass(es){keys}",
                plan.mode.name(),
                plan.emit
            ));
            let eye = if plan.mode == PhotonMode::Sppm {
                pixels.saturating_mul(1 + shadow)
            } else {
                0
            };
            rays = rays.saturating_add(
                passes.saturating_mul(plan.emit.saturating_mul(4).saturating_add(eye)),
            );
        }
        Ok(WorkEstimate { rays, drivers })
    }

    /// Renders the frame (or the region) `options` ask for.
    pub fn render(&self, options: &RenderOptions) -> Result<Film, RenderError> {
        self.render_with(options, Control::default())
            .map(|(film, _)| film)
    }

    /// [`Renderer::render`], telling `control` its progress and stopping
    /// when its flag is set; with the figures of the render.
    pub fn render_with(
        &self,
        options: &RenderOptions,
        control: Control<'_>,
    ) -> Result<(Film, RenderStats), RenderError> {
        let start = Instant::now();
        let (w, h) = self.frame_size(options)?;
        let region = options.region.unwrap_or(Region::full(w, h));
        if !region.fits(w, h) {
            return Err(RenderError::Region {
                region,
                frame_w: w,
                frame_h: h,
            });
        }
        let (plan, map, mut photon_stats) = self.photon_pass(options);
        let tracing = self.photon_shading(&plan, map.as_ref());
        let (spp, frame) = self.sampled_frame(w, h, options, tracing);
        let watch = Watch {
            progress: control.progress.unwrap_or(&|_, _| {}),
            cancel: control.cancel,
        };
        let count = options.aovs.contains(&Aov::Rays);
        let shading = ShadingPasses::of(&options.aovs, &self.scene).map_err(|asked| {
            RenderError::LightPasses {
                asked,
                max: LIGHT_PASSES_MAX,
            }
        })?;
        let mut photon_term = None;
        let done = if plan.mode.progressive() {
            let checkpoint = match control.checkpoint_every {
                0 => 10,
                n => n,
            };
            let p = self.progressive(&frame, &plan, options.seed, checkpoint);
            let mut each = |i: u64, pixels: &[[f32; 3]]| {
                if let Some(checkpoint) = control.checkpoint {
                    let image = Image::from_pixels(region.width, region.height, pixels.to_vec());
                    checkpoint(i, &Film::new((w, h), region, image));
                }
            };
            let done = schedule::with_threads(options.threads, || {
                photons::progressive(&p, region, spp, &watch, &mut each)
            })
            .map_err(RenderError::from)?;
            let (pixels, rays) = (done.pixels, done.rays);
            photon_stats = done.stats;
            photon_term = Some(done.photons);
            // The passes of the ray-traced part, from one render of it.
            let keep = Keep {
                rays: count,
                shading: shading.as_ref(),
                cost: options.aovs.contains(&Aov::Cost),
            };
            let traced = if count || keep.cost || shading.is_some() {
                let done = schedule::with_threads(options.threads, || {
                    render_region(&frame, region, spp, keep, &watch)
                });
                Some(done.ok_or(RenderError::Cancelled)?)
            } else {
                None
            };
            let (rays_per_pixel, shading, costs) = match traced {
                Some(t) => (t.rays_per_pixel, t.shading, t.costs),
                None => (None, None, None),
            };
            passes::Rendered {
                pixels,
                rays,
                refined: 0,
                rays_per_pixel,
                shading,
                costs,
            }
        } else {
            let done = schedule::with_threads(options.threads, || {
                let keep = Keep {
                    rays: count,
                    shading: shading.as_ref(),
                    cost: options.aovs.contains(&Aov::Cost),
                };
                render_region(&frame, region, spp, keep, &watch)
            });
            done.ok_or(RenderError::Cancelled)?
        };
        let (rays, refined) = (done.rays, done.refined);
        let image = Image::from_pixels(region.width, region.height, done.pixels);
        let mut film = Film::new((w, h), region, image);
        let mut planes = Vec::new();
        if let Some(shaded) = done.shading {
            planes.extend(shaded);
        }
        if let Some(term) = photon_term {
            // PPM's and SPPM's estimate, not the ray tracer's (zero) term.
            planes.retain(|(a, _)| *a != Aov::Photons);
            planes.push((Aov::Photons, term));
        }
        if let Some(counts) = done.rays_per_pixel {
            planes.push((Aov::Rays, counts));
        }
        if let Some(costs) = done.costs {
            planes.push((Aov::Cost, costs));
        }
        // In the order asked for.
        for &aov in &options.aovs {
            if let Some((_, data)) = planes.iter_mut().find(|(a, _)| *a == aov) {
                film.set_plane(&aov.name(), aov.channels(), std::mem::take(data));
            }
        }
        let stats = RenderStats {
            rays,
            elapsed: start.elapsed(),
            build: self.build,
            refined_pixels: refined,
            photons: photon_stats,
        };
        Ok((film, stats))
    }

    /// Pixel (x, y) of the render `options` ask for (their region aside),
    /// explained: the same samples the render traces there, as ray trees,
    /// with the bytes it writes and a verdict.
    pub fn explain(
        &self,
        options: &RenderOptions,
        x: u32,
        y: u32,
    ) -> Result<Explanation, RenderError> {
        let (w, h) = self.frame_size(options)?;
        if let Some(value) = options.spp.filter(|&n| n > MAX_EXPLAINED_SPP) {
            return Err(RenderError::Samples {
                value,
                max: MAX_EXPLAINED_SPP,
            });
        }
        if x >= w || y >= h {
            return Err(RenderError::Pixel {
                x,
                y,
                frame_w: w,
                frame_h: h,
            });
        }
        // PM's map as the render traces it.
        let (plan, map, _) = self.photon_pass(options);
        let shading = self.photon_shading(&plan, map.as_ref());
        let (spp, frame) = self.sampled_frame(w, h, options, shading);
        if !plan.mode.progressive() {
            return Ok(explain::explain_pixel(
                &frame,
                &self.scene,
                &self.accel,
                spp,
                (x, y),
            ));
        }
        // PPM and SPPM: the render's iterations over this one pixel's hit
        // points (the same photons; the photon passes on every core).
        let mut e = if plan.mode == PhotonMode::Sppm {
            let n = u32::try_from(plan.iterations).unwrap_or(u32::MAX);
            explain::explain_fresh(&frame, &self.scene, &self.accel, n, (x, y))
        } else {
            explain::explain_pixel(&frame, &self.scene, &self.accel, spp, (x, y))
        };
        let p = self.progressive(&frame, &plan, options.seed, plan.iterations.max(1));
        let watch = Watch {
            progress: &|_, _| {},
            cancel: None,
        };
        let pixel = Region {
            x,
            y,
            width: 1,
            height: 1,
        };
        let done = schedule::with_threads(None, || {
            photons::progressive(&p, pixel, spp, &watch, &mut |_, _| {})
        })
        .map_err(RenderError::from)?;
        let iterations = done.stats.iterations;
        let sppm = plan.mode == PhotonMode::Sppm;
        let term = explain::ProgressiveTerm {
            algorithm: if sppm { "sppm" } else { "ppm" },
            iterations,
            emitted: done.stats.emitted,
            direct: done
                .direct
                .first()
                .map_or([0.0; 3], |d| d.as_vec3().to_array()),
            points: done
                .points
                .iter()
                .map(|h| explain::HitPointTerm {
                    point: (!sppm).then_some(h.point),
                    weight: h.weight,
                    radius: h.r2.sqrt(),
                    photons: h.n,
                    term: h.radiance(iterations),
                })
                .collect(),
        };
        let color = done.pixels.first().copied().unwrap_or(e.color);
        e.set_progressive(term, color);
        Ok(e)
    }

    /// For each primitive block that made a surface (0-based index): its
    /// shape's kind and the 1-based line of its header.
    pub fn primitive_table(&self) -> std::collections::BTreeMap<u32, (&'static str, Option<u32>)> {
        let mut table = std::collections::BTreeMap::new();
        for o in self.accel.objects() {
            if let Some(b) = o.block() {
                table
                    .entry(b)
                    .or_insert_with(|| (o.shape().kind_name(), self.scene.block_line(b)));
            }
        }
        table
    }

    /// The scene file's name, as given (`None`: parsed from text).
    pub fn scene_file(&self) -> Option<String> {
        self.scene.path().map(|p| p.display().to_string())
    }

    /// The frame of a `w` × `h` render with the random streams of `seed`,
    /// shading with `photons`.
    fn frame<'s>(&'s self, w: u32, h: u32, seed: u64, photons: PhotonShading<'s>) -> Frame<'s> {
        let camera = Camera {
            width: w,
            height: h,
            ..self.scene.camera().clone()
        };
        let integrator = Integrator::whitted(&self.scene, &camera, &self.accel, photons);
        Frame::new(&camera, integrator, seed)
    }

    /// The frame `options` render and the samples a pixel takes: `--spp`,
    /// or with an open lens `dofSample=` rays through the pixel's centre.
    fn sampled_frame<'s>(
        &'s self,
        w: u32,
        h: u32,
        options: &RenderOptions,
        photons: PhotonShading<'s>,
    ) -> (Option<u32>, Frame<'s>) {
        let frame = self.frame(w, h, options.seed, photons);
        let dof = &self.scene.camera().dof;
        match options.spp {
            None if dof.aperture > 0.0 => (Some(dof.samples.max(1)), frame.centred()),
            spp => (spp, frame),
        }
    }

    /// The photon plan `options` give and, under PM, its photon map
    /// (traced as the render traces it) with the pass's figures.
    fn photon_pass(&self, options: &RenderOptions) -> (Plan, Option<PhotonMap>, PhotonStats) {
        let (plan, _) = Plan::of(&self.scene, &options.photons);
        if plan.mode != PhotonMode::Pm {
            return (plan, None, PhotonStats::default());
        }
        let model = Model::of(self.scene.dialect().dialect, self.scene.camera());
        let (map, stats) = schedule::with_threads(options.threads, || {
            photons::photon_map(&self.scene, &self.accel, &model, &plan, options.seed)
        });
        (plan, Some(map), stats)
    }

    /// PPM's or SPPM's iterations under `plan` on `frame`, its picture
    /// composed every `checkpoint` iterations.
    fn progressive<'s>(
        &'s self,
        frame: &'s Frame<'s>,
        plan: &'s Plan,
        seed: u64,
        checkpoint: u64,
    ) -> photons::Progressive<'s> {
        photons::Progressive {
            frame,
            scene: &self.scene,
            accel: &self.accel,
            plan,
            seed,
            checkpoint,
        }
    }

    /// How the ray tracer shades under `plan`, gathering from `map` (PM).
    fn photon_shading<'s>(&self, plan: &Plan, map: Option<&'s PhotonMap>) -> PhotonShading<'s> {
        PhotonShading {
            map,
            no_direct: plan.mode != PhotonMode::Off && plan.term == Term::Replace,
            specular: plan.specular,
        }
    }

    /// An upper bound of the bytes a render of `options` takes on top of
    /// what the process holds before it, for every output format, sampling
    /// mode, pass and photon algorithm (photons and hit points bounded by
    /// their keys).
    pub fn memory_needed(&self, options: &RenderOptions) -> Result<u64, RenderError> {
        let pixels = self.pixels(options)?;
        let threads = schedule::workers(options.threads) as u64;
        let channels = options.aovs.iter().map(|a| a.channels() as u64).sum();
        let plan = Plan::of(&self.scene, &options.photons).0;
        Ok(memory::memory_needed(pixels, threads, channels, &plan))
    }

    /// The pixels a render of `options` fills: its region's, or the frame's.
    fn pixels(&self, options: &RenderOptions) -> Result<u64, RenderError> {
        let (w, h) = self.frame_size(options)?;
        Ok(match options.region {
            Some(r) => r.area(),
            None => u64::from(w) * u64::from(h),
        })
    }

    /// The notes and warnings about photons a render of `options` makes:
    /// which algorithm runs, keys without effect, settings that switch it off.
    pub fn photon_notes(&self, options: &RenderOptions) -> Vec<String> {
        Plan::of(&self.scene, &options.photons).1
    }

    /// Renders `preview` (a cheaper render of the same picture, such as a
    /// smaller one at one ray per pixel; none when `None`) without progress
    /// reports and hands it to `show` as [`Stage::Coarse`], then renders what
    /// `options` ask for and hands that over as [`Stage::Final`]. Stops at
    /// once when the flag of `control` is set.
    pub fn render_progressive(
        &self,
        options: &RenderOptions,
        preview: Option<&RenderOptions>,
        control: Control<'_>,
        show: &mut dyn FnMut(Stage, &Film),
    ) -> Result<(Film, RenderStats), RenderError> {
        if let Some(preview) = preview {
            let quiet = Control {
                progress: None,
                ..control
            };
            let (film, _) = self.render_with(preview, quiet)?;
            show(Stage::Coarse, &film);
        }
        let (film, stats) = self.render_with(options, control)?;
        show(Stage::Final, &film);
        Ok((film, stats))
    }
}

/// Camera rays a pixel takes on average under the adaptive anti-aliasing
/// (one, and 49 more for the few pixels on edges), for [`WorkEstimate`].
const ADAPTIVE_RAYS_PER_PIXEL: u64 = 2;

/// What [`Renderer::estimate`] expects a render to cost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorkEstimate {
    /// Rays, roughly (within a few times either way).
    pub rays: u64,
    /// The settings that drive the count: image size, samples, qualities.
    pub drivers: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A small scene of every kind of event the anti-aliasing sees: edges,
    /// a mirror, glass, shadows of a point and an area light, a texture-free
    /// gradient sky.
    fn scene() -> Renderer {
        let text = "background\n top= 0.6 0.7 0.9\n bottom= 0.1 0.1 0.1\nend\n\
             camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 40\n image_H= 30\n shade_quality= 1\n drefl_quality= 1\nend\n\
             light point\n O= 4 -6 8\n color= 0.8 0.8 0.8\nend\n\
             light square\n O= -3 0 6\n Dx= 0.5 0 0\n Dy= 0 0.5 0\n color= 0.4 0.4 0.4\nend\n\
             primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.7\n refl= 0.2\n drefl= 0.1\nend\n\
             primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\n refl= 0.3\nend\n\
             primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 1 1 1\n refr= 0.9\n rindex= 1.5\n absor= 0.2 0.1 0\nend\n\
             primitive cylinder\n O1= 0 2 0\n O2= 0 2 2.5\n R= 0.4\n color= 0.2 0.9 0.3\n diff= 0.8\n spec= 0.3\nend\n";
        match Scene::parse(text, ".") {
            Ok(s) => Renderer::new(s),
            Err(e) => panic!("{e}"), // invariant: the test's own fixed input (a failure fails the test)
        }
    }

    fn render(r: &Renderer, options: &RenderOptions) -> Image {
        match r.render(options) {
            Ok(film) => film.into_image(),
            Err(e) => panic!("{e}"), // invariant: the test's own fixed input (a failure fails the test)
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 48,
            failure_persistence: None,
            rng_seed: proptest::test_runner::RngSeed::Fixed(5),
            ..ProptestConfig::default()
        })]

        /// A region's pixels are the same values as those pixels of the whole
        /// frame, at any size, with adaptive anti-aliasing and with --spp.
        #[test]
        fn a_region_is_the_whole_render_cut(
            w in 1u32..48, h in 1u32..40,
            fx in 0.0..1.0f64, fy in 0.0..1.0f64, fw in 0.0..1.0f64, fh in 0.0..1.0f64,
            spp in prop::sample::select(vec![None, Some(1), Some(3)]),
            seed in 0u64..4,
        ) {
            let r = scene();
            let full = RenderOptions { width: Some(w), height: Some(h), spp, seed, threads: Some(2), ..RenderOptions::default() };
            let whole = render(&r, &full);
            let x = ((w as f64 * fx) as u32).min(w - 1);
            let y = ((h as f64 * fy) as u32).min(h - 1);
            let rw = 1 + ((w - x - 1) as f64 * fw) as u32;
            let rh = 1 + ((h - y - 1) as f64 * fh) as u32;
            let region = Region { x, y, width: rw, height: rh };
            let part = render(&r, &RenderOptions { region: Some(region), ..full.clone() });
            prop_assert_eq!((part.width(), part.height()), (rw, rh));
            for j in 0..rh {
                for i in 0..rw {
                    prop_assert_eq!(part.pixel(i, j), whole.pixel(x + i, y + j), "pixel {} {}", x + i, y + j);
                }
            }
        }
    }

    #[test]
    fn regions_outside_the_frame_and_bad_sizes_are_errors() {
        let r = scene();
        let at = |x, y, width, height| RenderOptions {
            region: Some(Region {
                x,
                y,
                width,
                height,
            }),
            ..RenderOptions::default()
        };
        for bad in [
            at(0, 0, 0, 1),
            at(0, 0, 41, 1),
            at(39, 29, 2, 1),
            at(u32::MAX, 0, 2, 1),
        ] {
            assert!(
                matches!(r.render(&bad), Err(RenderError::Region { .. })),
                "{bad:?}"
            );
        }
        assert!(r.render(&at(39, 29, 1, 1)).is_ok());
        let wide = RenderOptions {
            width: Some(MAX_IMAGE_SIDE + 1),
            ..RenderOptions::default()
        };
        assert_eq!(
            r.render(&wide),
            Err(RenderError::Side {
                name: "width",
                value: MAX_IMAGE_SIDE + 1
            })
        );
        // One side alone keeps the camera's 4:3.
        let one = RenderOptions {
            width: Some(80),
            ..RenderOptions::default()
        };
        assert_eq!(r.frame_size(&one), Ok((80, 60)));
    }

    #[test]
    fn a_set_flag_cancels_the_render() {
        let r = scene();
        let flag = AtomicBool::new(true);
        let control = Control {
            cancel: Some(&flag),
            ..Control::default()
        };
        for spp in [None, Some(2)] {
            let options = RenderOptions {
                spp,
                ..RenderOptions::default()
            };
            assert_eq!(
                r.render_with(&options, control).map(|_| ()),
                Err(RenderError::Cancelled)
            );
        }
        flag.store(false, std::sync::atomic::Ordering::Relaxed);
        assert!(r.render_with(&RenderOptions::default(), control).is_ok());
    }

    #[test]
    fn a_progressive_render_shows_a_coarse_then_the_final_image() {
        let r = scene();
        let options = RenderOptions::default();
        let quarter = RenderOptions {
            width: Some(10),
            height: Some(8),
            spp: Some(1),
            ..options.clone()
        };
        let mut shown = Vec::new();
        let (film, _) = match r.render_progressive(
            &options,
            Some(&quarter),
            Control::default(),
            &mut |stage, f| shown.push((stage, f.image().width(), f.image().height())),
        ) {
            Ok(done) => done,
            Err(e) => panic!("{e}"), // invariant: the test's own fixed input (a failure fails the test)
        };
        assert_eq!(shown, vec![(Stage::Coarse, 10, 8), (Stage::Final, 40, 30)]);
        assert_eq!(film.image(), &render(&r, &options));
        // A flag set once the preview is shown stops the final render.
        let flag = AtomicBool::new(false);
        let control = Control {
            cancel: Some(&flag),
            ..Control::default()
        };
        let mut stages = Vec::new();
        let run = r.render_progressive(&options, Some(&quarter), control, &mut |stage, _| {
            stages.push(stage);
            flag.store(true, std::sync::atomic::Ordering::Relaxed);
        });
        assert_eq!(run.map(|_| ()), Err(RenderError::Cancelled));
        assert_eq!(stages, vec![Stage::Coarse]);
        // Without a preview, only the final image is shown.
        let mut stages = Vec::new();
        let run = r.render_progressive(&options, None, Control::default(), &mut |stage, _| {
            stages.push(stage)
        });
        assert!(run.is_ok());
        assert_eq!(stages, vec![Stage::Final]);
    }
}
