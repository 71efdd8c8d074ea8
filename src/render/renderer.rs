//! The [`Renderer`]: a scene prepared once (its acceleration structure
//! built) and rendered again and again, whole or a region, as
//! [`RenderOptions`] say.

use super::aov::Aov;
use super::buffers::{Keep, Rendered};
use super::film::{Film, Region};
use super::frame::Frame;
use super::memory::{Load, MemoryNeed};
use super::progress::Watch;
use super::region::render_runs;
use super::shading_aovs::{LIGHT_AOVS_MAX, ShadingAovs};
use super::tile::Tile;
use super::{Control, PhotonStats, RenderError, RenderOptions, RenderStats, Stage};
use super::{photons, schedule};
use crate::image::Image;
use crate::integrator::photons::{PhotonMap, PhotonMode, Plan, Term, stored_per_emitted};
use crate::integrator::{Integrator, Model, PhotonShading, RayCounts, SceneAccel};
use crate::scene::{Camera, MAX_IMAGE_SIDE, Scene};
use std::time::{Duration, Instant};

/// A scene prepared for rendering: it owns the scene and the acceleration
/// structure built over its surfaces, so it renders again and again
/// (other options, other regions) without building anything twice.
pub struct Renderer {
    pub(super) scene: Scene,
    pub(super) accel: SceneAccel,
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

    /// Renders the frame (or the region) `options` ask for.
    pub fn render(&self, options: &RenderOptions) -> Result<Film, RenderError> {
        self.render_with(options, Control::default())
            .map(|(film, _)| film)
    }

    /// [`Renderer::render`], telling `control` its progress and stopping
    /// when its flag is set; with the figures of the render. A render of
    /// one part (`options.tile`) gives parts: see [`Renderer::render_parts`].
    pub fn render_with(
        &self,
        options: &RenderOptions,
        control: Control<'_>,
    ) -> Result<(Film, RenderStats), RenderError> {
        if let Some(tile) = options.tile {
            return Err(RenderError::Parts { tile });
        }
        let (w, h) = self.frame_size(options)?;
        let region = self.region(options, (w, h))?;
        let (mut films, stats) = self.render_runs(options, &[region], control, None)?;
        // One run, one film.
        let film = films.pop().ok_or(RenderError::Cancelled)?;
        Ok((film, stats))
    }

    /// The films of the part of the render `options.tile` names (all of
    /// it without one): one a run of adjacent bands it holds, top to
    /// bottom, each the same bytes as those rows of the whole render; none
    /// when the part holds no band. Merged by [`Film::assemble`].
    pub fn render_parts(
        &self,
        options: &RenderOptions,
        control: Control<'_>,
    ) -> Result<(Vec<Film>, RenderStats), RenderError> {
        let (w, h) = self.frame_size(options)?;
        let region = self.region(options, (w, h))?;
        let runs = match options.tile {
            Some(tile) => tile.runs(region),
            None => vec![region],
        };
        self.render_runs(options, &runs, control, None)
    }

    /// The render `options` ask for (all of it: no part), band by band
    /// ([`TILE_BAND`](super::TILE_BAND) rows, nearest the row `near` first; the region's
    /// middle without one), each band's film handed to `band` as soon as
    /// it is done, from whichever thread rendered it; then the whole film,
    /// the very values [`Renderer::render_with`] gives. PPM and SPPM,
    /// whose picture is whole after each iteration, hand over that one
    /// film at the end.
    pub fn render_bands(
        &self,
        options: &RenderOptions,
        near: Option<u32>,
        control: Control<'_>,
        band: &(dyn Fn(&Film) + Sync),
    ) -> Result<(Film, RenderStats), RenderError> {
        let whole = RenderOptions {
            tile: None,
            ..options.clone()
        };
        if Plan::of(&self.scene, &options.photons).0.mode.progressive() {
            let (film, stats) = self.render_with(&whole, control)?;
            band(&film);
            return Ok((film, stats));
        }
        let (w, h) = self.frame_size(options)?;
        let region = self.region(options, (w, h))?;
        let near = near.unwrap_or(region.y + region.height / 2);
        let mut order: Vec<Region> = (0..Tile::bands_of(region.height))
            .map(|b| Tile::band(region, b))
            .collect();
        order.sort_by_key(|b| (b.y + b.height / 2).abs_diff(near));
        let (films, stats) = self.render_runs(&whole, &order, control, Some(band))?;
        let film = Film::assemble((w, h), region, films).expect("a region's bands cover it once"); // invariant: the bands cover the region once, by construction (Tile::band of every band)
        Ok((film, stats))
    }

    /// The region `options` render in a `frame`: theirs, if inside it, or all of it.
    fn region(&self, options: &RenderOptions, (w, h): (u32, u32)) -> Result<Region, RenderError> {
        let region = options.region.unwrap_or(Region::full(w, h));
        if !region.fits(w, h) {
            return Err(RenderError::Region {
                region,
                frame_w: w,
                frame_h: h,
            });
        }
        Ok(region)
    }

    /// The films of `runs` (regions of the frame apart from each other),
    /// one each, rendered in their order, each handed to `each` (if any) as
    /// it is done (PPM and SPPM: none is).
    fn render_runs(
        &self,
        options: &RenderOptions,
        runs: &[Region],
        control: Control<'_>,
        each: Option<&(dyn Fn(&Film) + Sync)>,
    ) -> Result<(Vec<Film>, RenderStats), RenderError> {
        let start = Instant::now();
        let (w, h) = self.frame_size(options)?;
        let (plan, map, photon_stats) = self.photon_pass(options);
        let tracing = self.photon_shading(&plan, map.as_ref());
        let (spp, frame) = self.sampled_frame(w, h, options, tracing);
        let watch = Watch {
            progress: control.progress.unwrap_or(&|_, _| {}),
            cancel: control.cancel,
        };
        let shading = ShadingAovs::of(&options.aovs, &self.scene).map_err(|asked| {
            RenderError::LightAovs {
                asked,
                max: LIGHT_AOVS_MAX,
            }
        })?;
        let aovs = &options.aovs;
        let done = |i: usize, r: &Rendered| {
            if let (Some(each), Some(&run)) = (each, runs.get(i)) {
                each(&film_of(r.clone(), (w, h), run, aovs));
            }
        };
        let job = RegionJob {
            frame: &frame,
            runs,
            done: &done,
            spp,
            keep: Keep {
                rays: options.aovs.contains(&Aov::Rays),
                shading: shading.as_ref(),
                cost: options.aovs.contains(&Aov::Cost),
            },
            watch: &watch,
            threads: options.threads,
        };
        let (done, photon_stats) = if plan.mode.progressive() {
            self.iterated(&job, &plan, options.seed, control)?
        } else {
            (job.trace()?, photon_stats)
        };
        let mut stats = RenderStats {
            rays: RayCounts::default(),
            elapsed: Duration::ZERO,
            build: self.build,
            refined_pixels: 0,
            photons: photon_stats,
        };
        let films = done
            .into_iter()
            .zip(runs)
            .map(|(done, &run)| {
                stats.rays.add(&done.rays);
                stats.refined_pixels += done.refined;
                film_of(done, (w, h), run, &options.aovs)
            })
            .collect();
        stats.elapsed = start.elapsed();
        Ok((films, stats))
    }

    /// PPM's or SPPM's iterations over `job`'s runs under `plan`, the
    /// picture handed to `control`'s checkpoint as they go (a render of
    /// one run); then, when asked for, the ray-traced part's AOVs from one
    /// render of it. Returns what the passes produce for each run (the
    /// photon term among it) and the photon figures.
    fn iterated(
        &self,
        job: &RegionJob,
        plan: &Plan,
        seed: u64,
        control: Control<'_>,
    ) -> Result<(Vec<Rendered>, PhotonStats), RenderError> {
        let (w, h) = (job.frame.width, job.frame.height);
        let checkpoint = match control.checkpoint_every {
            0 => 10,
            n => n,
        };
        let p = self.progressive(job.frame, plan, seed, checkpoint);
        let mut each = |i: u64, pixels: &[[f32; 3]]| {
            if let (Some(checkpoint), [region]) = (control.checkpoint, job.runs) {
                let image = Image::from_pixels(region.width, region.height, pixels.to_vec());
                checkpoint(i, &Film::new((w, h), *region, image));
            }
        };
        let done = schedule::with_threads(job.threads, || {
            photons::progressive(&p, job.runs, job.spp, job.watch, &mut each)
        })
        .map_err(RenderError::from)?;
        let keep = job.keep;
        let traced = if keep.rays || keep.cost || keep.shading.is_some() {
            Some(job.trace()?)
        } else {
            None
        };
        // The iterations' pixels and photon term cut at the runs.
        let (mut pixels, mut term) = (done.pixels.into_iter(), done.photons.into_iter());
        let mut traced = traced.map(Vec::into_iter);
        let mut rendered = Vec::with_capacity(job.runs.len());
        for (i, run) in job.runs.iter().enumerate() {
            let n = run.area() as usize;
            let (rays_per_pixel, shading, costs) = match traced.as_mut().and_then(Iterator::next) {
                Some(t) => (t.rays_per_pixel, t.shading, t.costs),
                None => (None, None, None),
            };
            rendered.push(Rendered {
                pixels: pixels.by_ref().take(n).collect(),
                // The eye passes' rays, counted once.
                rays: if i == 0 {
                    done.rays
                } else {
                    RayCounts::default()
                },
                refined: 0,
                rays_per_pixel,
                shading,
                costs,
                photon_term: Some(term.by_ref().take(n * 3).collect()),
            });
        }
        Ok((rendered, done.stats))
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
    pub(super) fn frame<'s>(
        &'s self,
        w: u32,
        h: u32,
        seed: u64,
        photons: PhotonShading<'s>,
    ) -> Frame<'s> {
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
    pub(super) fn sampled_frame<'s>(
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
    pub(super) fn photon_pass(
        &self,
        options: &RenderOptions,
    ) -> (Plan, Option<PhotonMap>, PhotonStats) {
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
    pub(super) fn progressive<'s>(
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
    pub(super) fn photon_shading<'s>(
        &self,
        plan: &Plan,
        map: Option<&'s PhotonMap>,
    ) -> PhotonShading<'s> {
        PhotonShading {
            map,
            no_direct: plan.mode != PhotonMode::Off
                && matches!(plan.term, Term::Replace | Term::Only),
            specular: plan.specular,
            brdf: plan.brdf,
            no_ambient: plan.mode != PhotonMode::Off && !plan.ambient,
        }
    }

    /// The bytes a render of `options` takes on top of what the process
    /// holds before it, an estimate a little above the peak for every
    /// output format, sampling mode, pass and photon algorithm, and what
    /// drives it. With photons it first traces a sample of them (and PPM's
    /// and SPPM's eye pass over a sample of pixels) to measure how many a
    /// pass stores (and how many hit points a pixel holds).
    pub fn memory_needed(&self, options: &RenderOptions) -> Result<MemoryNeed, RenderError> {
        let (w, h) = self.frame_size(options)?;
        let pixels = self.pixels(options)?;
        let threads = schedule::workers(options.threads) as u64;
        let channels = options.aovs.iter().map(|a| a.channels() as u64).sum();
        let plan = Plan::of(&self.scene, &options.photons).0;
        let mut load = Load::new(pixels, threads, channels, &plan);
        if plan.mode != PhotonMode::Off {
            let model = Model::of(self.scene.dialect().dialect, self.scene.camera());
            load.stored_per_emitted = schedule::with_threads(options.threads, || {
                stored_per_emitted(&self.scene, &self.accel, &model, &plan, options.seed)
            });
        }
        if plan.mode.progressive() {
            let (spp, frame) = self.sampled_frame(w, h, options, PhotonShading::default());
            let region = self.region(options, (w, h))?;
            let runs = match options.tile {
                Some(tile) => tile.runs(region),
                None => vec![region],
            };
            load.hit_points_per_pixel = schedule::with_threads(options.threads, || {
                photons::hit_points_per_pixel(&frame, &runs, spp, plan.mode)
            });
        }
        let p = &self.scene.camera().photons;
        let file_key = |name: &'static str, value: &dyn std::fmt::Display| {
            Some(self.camera_key(name, value)).filter(|k| k.at.is_some())
        };
        Ok(MemoryNeed {
            bytes: load.bytes(),
            load,
            frame: (w, h),
            emit_key: file_key("emit_photons", &p.emit_photons)
                .filter(|_| options.photons.emit.is_none()),
            max_key: file_key("max_photons", &p.max_photons),
        })
    }

    /// The pixels a render of `options` fills: its part's of its region's, or the frame's.
    pub(super) fn pixels(&self, options: &RenderOptions) -> Result<u64, RenderError> {
        let (w, h) = self.frame_size(options)?;
        let region = options.region.unwrap_or(Region::full(w, h));
        Ok(match options.tile {
            Some(tile) => tile.runs(region).iter().map(Region::area).sum(),
            None => region.area(),
        })
    }

    /// The notes and warnings about photons a render of `options` makes:
    /// which algorithm runs, keys without effect, settings that switch it off.
    pub fn photon_notes(&self, options: &RenderOptions) -> Vec<String> {
        Plan::of(&self.scene, &options.photons).1
    }

    /// The warning a render whose photon passes reached `max_photons=`
    /// makes, from its figures `stats`: what was kept and how it was made up for.
    pub fn photon_cap_warning(&self, stats: &PhotonStats) -> Option<String> {
        if stats.thinned == 0 {
            return None;
        }
        let cap = self.camera_key("max_photons", &stats.stored);
        let which = if cap.at.is_some() {
            ""
        } else {
            " (the default)"
        };
        let stored = stats.stored + stats.thinned;
        Some(format!(
            "warning: {cap}{which} reached: {} photon pass stored {stored} photons and kept {} of them, \
             chosen evenly, their power scaled by {:.3}; raise `max_photons=` to keep them all",
            if stats.planned > 0 { "the last" } else { "the" },
            stats.stored,
            stored as f64 / stats.stored as f64
        ))
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

/// The passes over runs of a frame (regions apart from each other), as a
/// render runs them.
struct RegionJob<'j> {
    frame: &'j Frame<'j>,
    runs: &'j [Region],
    /// Told each run's passes as they finish.
    done: &'j (dyn Fn(usize, &Rendered) + Sync),
    spp: Option<u32>,
    keep: Keep<'j>,
    watch: &'j Watch<'j>,
    threads: Option<usize>,
}

impl RegionJob<'_> {
    /// The runs' passes, keeping what the job asks for, on its threads.
    fn trace(&self) -> Result<Vec<Rendered>, RenderError> {
        let done = schedule::with_threads(self.threads, || {
            render_runs(
                self.frame, self.runs, self.spp, self.keep, self.watch, self.done,
            )
        });
        done.ok_or(RenderError::Cancelled)
    }
}

/// The film of `region` of a `frame` from what its passes produced, its
/// AOVs in the order `aovs` asks for.
fn film_of(done: Rendered, frame: (u32, u32), region: Region, aovs: &[Aov]) -> Film {
    let image = Image::from_pixels(region.width, region.height, done.pixels);
    let mut film = Film::new(frame, region, image);
    let mut planes = Vec::new();
    if let Some(shaded) = done.shading {
        planes.extend(shaded);
    }
    if let Some(term) = done.photon_term {
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
    for &aov in aovs {
        if let Some((_, data)) = planes.iter_mut().find(|(a, _)| *a == aov) {
            film.set_aov(aov, std::mem::take(data));
        }
    }
    film
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::sync::atomic::AtomicBool;

    /// A small scene of every kind of event the anti-aliasing sees: edges,
    /// a mirror, glass, shadows of a point and an area light, a texture-free
    /// gradient sky.
    fn scene() -> Renderer {
        let text = include_str!("../../tests/data/events.txt");
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
