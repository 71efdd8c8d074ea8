//! Photon-mapped renders (`photon-mapping.md`): PM's map is traced before
//! the frame; PPM and SPPM add iterations of photon passes to the
//! ray-traced direct light and compose the picture after each.

use super::buffers::Keep;
use super::film::Region;
use super::frame::Frame;
use super::progress::Watch;
use super::region::render_runs;
use crate::integrator::photons::{
    Brdf, FirstRadius, HitPoint, HitPointObserver, HitPointSeed, PhotonGrid, PhotonMap, PhotonMode,
    Plan, Term, gather, shoot, update_hit_point,
};
use crate::integrator::{Model, RayCounts, SceneAccel, ShadowHints};
use crate::sampling::strata;
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Why the progressive passes gave no picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Unfinished {
    /// Cancelled before the first iteration completed.
    Cancelled,
    /// More hit points than `max_hitpoints=`.
    HitPoints {
        /// The key's value.
        max: u64,
    },
}

/// What a photon pass left out, for the render's report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PhotonStats {
    /// Photons emitted per pass.
    pub emitted: u64,
    /// Photons stored in the last pass (PM: the map).
    pub stored: u64,
    /// Photons thinned out of the last pass by `max_photons=`.
    pub thinned: u64,
    /// Iterations completed (PPM and SPPM).
    pub iterations: u64,
    /// Iterations asked for (PPM and SPPM).
    pub planned: u64,
    /// Hit points (PPM).
    pub hit_points: u64,
    /// Rays cast tracing photons (one a path segment): PM's map, or every
    /// iteration's pass together.
    pub rays: u64,
    /// Wall time of PM's map (PPM and SPPM: of every photon pass together).
    pub elapsed: std::time::Duration,
}

/// Traces PM's photon map.
pub(crate) fn photon_map(
    scene: &Scene,
    accel: &SceneAccel,
    model: &Model,
    plan: &Plan,
    seed: u64,
) -> (PhotonMap, PhotonStats) {
    let start = std::time::Instant::now();
    let pass = shoot(scene, accel, model, plan, seed, 0);
    let stats = PhotonStats {
        emitted: pass.emitted,
        stored: pass.photons.len() as u64,
        thinned: pass.thinned,
        rays: pass.rays,
        ..PhotonStats::default()
    };
    let map = PhotonMap::new(pass.photons, plan.k, plan.radius, plan.filter);
    let stats = PhotonStats {
        elapsed: start.elapsed(),
        ..stats
    };
    (map, stats)
}

/// Everything the progressive passes read.
pub(crate) struct Progressive<'a> {
    /// The frame of the direct light (no photon map in it).
    pub frame: &'a Frame<'a>,
    pub scene: &'a Scene,
    pub accel: &'a SceneAccel,
    pub plan: &'a Plan,
    pub seed: u64,
    /// Call `each(i, pixels)` after iteration i when i is a multiple of this.
    pub checkpoint: u64,
}

/// What PPM's and SPPM's iterations give.
pub(crate) struct Progressed {
    /// The region's colours.
    pub pixels: Vec<[f32; 3]>,
    /// Each pixel's photon estimate (the `photons` pass), RGB.
    pub photons: Vec<f32>,
    /// Rays the eye passes traced.
    pub rays: RayCounts,
    /// The photon passes' figures.
    pub stats: PhotonStats,
    /// The hit points (PPM) or pixels' running estimates (SPPM) at the end.
    pub points: Vec<HitPoint>,
    /// Each pixel's ray-traced part: PPM's render of it, SPPM's mean of
    /// its iterations' samples.
    pub direct: Vec<DVec3>,
}

/// The pixels of `runs` (regions of the frame apart from each other, one
/// after the other) after PPM's or SPPM's iterations, the rays the eye
/// passes traced and the figures; after a cancel, those of the last
/// complete iteration (an error if none completed). `each(i, pixels)` is
/// given every checkpoint's picture.
pub(crate) fn progressive(
    p: &Progressive<'_>,
    runs: &[Region],
    spp: Option<u32>,
    watch: &Watch,
    each: &mut dyn FnMut(u64, &[[f32; 3]]),
) -> Result<Progressed, Unfinished> {
    let plan = p.plan;
    let total = plan.iterations;
    let pixels = runs.iter().map(Region::area).sum::<u64>() as usize;
    let mut stats = PhotonStats {
        planned: total,
        ..PhotonStats::default()
    };
    let mut rays = RayCounts::default();
    let (direct, mut points) = if plan.mode == PhotonMode::Ppm {
        ppm_hit_points(p, runs, spp, watch, &mut rays)?
    } else {
        (vec![DVec3::ZERO; pixels], sppm_estimates(plan, pixels))
    };
    stats.hit_points = points.len() as u64;
    let mut direct_sum = vec![DVec3::ZERO; pixels];
    let mut last: Option<Vec<[f32; 3]>> = None;
    for i in 1..=total {
        if watch.cancelled() {
            break;
        }
        let at = Iteration { p, runs, i, watch };
        if !at.run(&mut points, &mut direct_sum, &mut rays, &mut stats)? {
            break;
        }
        (watch.progress)(i, total);
        if i % p.checkpoint.max(1) == 0 || i == total {
            let picture = compose(&direct, &direct_sum, &points, i, plan.mode);
            each(i, &picture);
            last = Some(picture);
        } else {
            last = None;
        }
    }
    let picture = match last {
        Some(picture) => picture,
        None if stats.iterations > 0 => {
            compose(&direct, &direct_sum, &points, stats.iterations, plan.mode)
        }
        None => return Err(Unfinished::Cancelled),
    };
    let direct = direct_part(&direct, &direct_sum, stats.iterations, plan.mode);
    Ok(Progressed {
        pixels: picture,
        photons: photon_term(&points, stats.iterations, pixels),
        rays,
        stats,
        points,
        direct,
    })
}

/// PPM's start: the direct light rendered once, and the hit points of the
/// samples the picture takes (with `--spp` or an open lens, each of its n
/// samples, weighing 1/n), their R₀² the K-nearest distance² in a
/// preliminary map, at most R² (lazycal's: no direct light, R₀ = R).
fn ppm_hit_points(
    p: &Progressive<'_>,
    runs: &[Region],
    spp: Option<u32>,
    watch: &Watch,
    rays: &mut RayCounts,
) -> Result<(Vec<DVec3>, Vec<HitPoint>), Unfinished> {
    let model = *p.frame.integrator.model();
    let plan = p.plan;
    let quiet = Watch {
        progress: &|_, _| {},
        cancel: watch.cancel,
    };
    // lazycal's picture is the photon estimate alone: no ray-traced part.
    let only = plan.term == Term::Only;
    let done = if only {
        Vec::new()
    } else {
        render_runs(p.frame, runs, spp, Keep::default(), &quiet, &|_, _| {})
            .ok_or(Unfinished::Cancelled)?
    };
    done.iter().for_each(|d| rays.add(&d.rays));
    let (seeds, r) = match spp {
        Some(n) => {
            let strata = strata(n);
            eye_pass(p.frame, runs, n, plan.max_hitpoints, |x, y, s| {
                p.frame.jittered(x, y, s, strata)
            })
        }
        None => eye_pass(p.frame, runs, 1, plan.max_hitpoints, |x, y, _| {
            p.frame.centre_sample(x, y)
        }),
    }?;
    rays.add(&r);
    let mut points = hit_points(p.scene, &model, plan, seeds.hits);
    if only {
        let pixels = runs.iter().map(Region::area).sum::<u64>() as usize;
        return Ok((vec![DVec3::ZERO; pixels], points));
    }
    let direct: Vec<DVec3> = done
        .iter()
        .flat_map(|d| &d.pixels)
        .map(|c| DVec3::from(glam::Vec3::from(*c)))
        .collect();
    if plan.first_radius == FirstRadius::Nearest {
        let (map, _) = photon_map(p.scene, p.accel, &model, plan, p.seed ^ 0x7072_656c);
        points.par_iter_mut().for_each(|h| {
            h.r2 = map.radius2(h.point, h.side).min(plan.radius * plan.radius);
        });
    }
    Ok((direct, points))
}

/// Pixels whose eye pass measures how many hit points a pixel holds.
const PILOT_PIXELS: u64 = 4096;

/// Hit points a pixel of `runs` holds under `mode` (PPM: its `spp`
/// samples' or its centre's, SPPM: one iteration's), from the eye pass
/// over up to [`PILOT_PIXELS`] pixels spread evenly over them: the
/// sample's mean and four standard errors (an estimate rarely below the truth).
pub(crate) fn hit_points_per_pixel(
    frame: &Frame<'_>,
    runs: &[Region],
    spp: Option<u32>,
    mode: PhotonMode,
) -> f64 {
    let pixels: u64 = runs.iter().map(Region::area).sum();
    let n = PILOT_PIXELS.min(pixels);
    if n == 0 {
        return 0.0;
    }
    // Pixel k·pixels/n of the runs, counted through them, as a region of its own.
    let pilot: Vec<Region> = (0..n)
        .filter_map(|k| {
            let mut at = k * pixels / n;
            runs.iter().find_map(|r| {
                if at < r.area() {
                    let (w, i) = (u64::from(r.width), at);
                    Some(Region {
                        x: r.x + (i % w) as u32,
                        y: r.y + (i / w) as u32,
                        width: 1,
                        height: 1,
                    })
                } else {
                    at -= r.area();
                    None
                }
            })
        })
        .collect();
    let pass = match (mode, spp) {
        (PhotonMode::Sppm, _) => {
            eye_pass(frame, &pilot, 1, u64::MAX, |x, y, _| frame.fresh(x, y, 1))
        }
        (_, Some(n)) => {
            let strata = strata(n);
            eye_pass(frame, &pilot, n, u64::MAX, |x, y, s| {
                frame.jittered(x, y, s, strata)
            })
        }
        (_, None) => eye_pass(frame, &pilot, 1, u64::MAX, |x, y, _| {
            frame.centre_sample(x, y)
        }),
    };
    let Ok((pass, _)) = pass else {
        return 0.0;
    };
    let mut counts = vec![0f64; pilot.len()];
    for (pixel, _) in &pass.hits {
        counts[*pixel as usize] += 1.0;
    }
    let m = counts.len() as f64;
    let mean = counts.iter().sum::<f64>() / m;
    let var = counts.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / m;
    mean + 4.0 * (var / m).sqrt()
}

/// SPPM's start: one running estimate a pixel, its point fresh each iteration.
fn sppm_estimates(plan: &Plan, pixels: usize) -> Vec<HitPoint> {
    (0..pixels as u32)
        .map(|pixel| HitPoint {
            pixel,
            point: DVec3::ZERO,
            side: DVec3::Z,
            brdf: Brdf {
                diff: 0.0,
                spec: 0.0,
                mirror: DVec3::Z,
                cosine: None,
            },
            weight: DVec3::ONE,
            r2: plan.radius * plan.radius,
            n: 0.0,
            m: 0,
            tau: DVec3::ZERO,
        })
        .collect()
}

/// Iteration `i` of PPM or SPPM over `runs`.
struct Iteration<'a, 'p> {
    p: &'a Progressive<'p>,
    runs: &'a [Region],
    i: u64,
    watch: &'a Watch<'a>,
}

impl Iteration<'_, '_> {
    /// SPPM's eye pass (its colours summed into `direct_sum`), the photon
    /// pass and every hit point's gather and update; false when cancelled
    /// before the gather.
    fn run(
        &self,
        points: &mut [HitPoint],
        direct_sum: &mut [DVec3],
        rays: &mut RayCounts,
        stats: &mut PhotonStats,
    ) -> Result<bool, Unfinished> {
        let (p, i) = (self.p, self.i);
        let model = *p.frame.integrator.model();
        let plan = p.plan;
        let visible = if plan.mode == PhotonMode::Sppm {
            let max = plan.max_hitpoints;
            let (seeds, r) = eye_pass(p.frame, self.runs, 1, max, |x, y, _| {
                p.frame.fresh(x, y, i as u32)
            })?;
            rays.add(&r);
            direct_sum
                .iter_mut()
                .zip(&seeds.colors)
                .for_each(|(s, c)| *s += *c);
            let hits = hit_points(p.scene, &model, plan, seeds.hits);
            Some(Visible::new(hits, direct_sum.len()))
        } else {
            None
        };
        let start = std::time::Instant::now();
        let pass = shoot(p.scene, p.accel, &model, plan, p.seed, i);
        stats.elapsed += start.elapsed();
        if self.watch.cancelled() {
            return Ok(false);
        }
        (stats.emitted, stats.stored, stats.thinned) =
            (pass.emitted, pass.photons.len() as u64, pass.thinned);
        stats.rays += pass.rays;
        let cell = points.iter().map(|h| h.r2).fold(0.0, f64::max).sqrt();
        let grid = PhotonGrid::new(&pass.photons, cell);
        let alpha = plan.reduction;
        match &visible {
            None => points.par_iter_mut().for_each(|h| {
                h.gather(&grid);
                update_hit_point(h, alpha);
            }),
            Some(visible) => points.par_iter_mut().for_each(|h| {
                for v in visible.of(h.pixel) {
                    let (m, tau) = gather(&grid, v.point, v.side, &v.brdf, h.r2);
                    h.m += m;
                    h.tau += v.weight * tau;
                }
                update_hit_point(h, alpha);
            }),
        }
        stats.iterations = i;
        Ok(true)
    }
}

/// The `photons` AOV: each pixel's photon estimate alone, after `iterations`.
fn photon_term(points: &[HitPoint], iterations: u64, pixels: usize) -> Vec<f32> {
    let mut term = vec![0f32; pixels * 3];
    for h in points {
        let v = h.radiance(iterations).as_vec3();
        let at = h.pixel as usize * 3;
        term[at..at + 3]
            .iter_mut()
            .zip(v.to_array())
            .for_each(|(t, v)| *t += v);
    }
    term
}

/// Each pixel's ray-traced part after `passes` passes: PPM's render of
/// it, SPPM's mean of its iterations' samples.
fn direct_part(
    direct: &[DVec3],
    direct_sum: &[DVec3],
    passes: u64,
    mode: PhotonMode,
) -> Vec<DVec3> {
    if mode == PhotonMode::Sppm {
        let passes = passes.max(1) as f64;
        direct_sum.iter().map(|s| *s / passes).collect()
    } else {
        direct.to_vec()
    }
}

/// The picture after `passes` passes: clamp(direct + Σ the pixel's hit
/// points' estimates); SPPM's direct light is the mean of its iterations'.
fn compose(
    direct: &[DVec3],
    direct_sum: &[DVec3],
    points: &[HitPoint],
    passes: u64,
    mode: PhotonMode,
) -> Vec<[f32; 3]> {
    let mut sum = direct_part(direct, direct_sum, passes, mode);
    for h in points {
        sum[h.pixel as usize] += h.radiance(passes);
    }
    sum.iter()
        .map(|c| c.min(DVec3::ONE).as_vec3().to_array())
        .collect()
}

/// The diffuse hits of the camera samples of each pixel of the runs,
/// tagged with the pixel (counted through the runs), and each pixel's mean colour.
struct EyePass {
    hits: Vec<(u32, HitPointSeed)>,
    colors: Vec<DVec3>,
}

/// SPPM's hit points of one iteration, grouped by pixel (one flat list:
/// the eye pass meets the pixels in order).
struct Visible {
    points: Vec<HitPoint>,
    /// Pixel p's points are `points[starts[p]..starts[p + 1]]`.
    starts: Vec<u32>,
}

impl Visible {
    /// `points` in pixel order, as the eye pass gives them.
    fn new(points: Vec<HitPoint>, pixels: usize) -> Self {
        debug_assert!(points.is_sorted_by_key(|h| h.pixel));
        let mut starts = vec![0u32; pixels + 1];
        for h in &points {
            starts[h.pixel as usize + 1] += 1;
        }
        for p in 0..pixels {
            starts[p + 1] += starts[p];
        }
        Visible { points, starts }
    }

    fn of(&self, pixel: u32) -> &[HitPoint] {
        let p = pixel as usize;
        &self.points[self.starts[p] as usize..self.starts[p + 1] as usize]
    }
}

/// Traces samples `sample(x, y, s)`, s < `n`, of each pixel of `runs`,
/// keeping their hits, each weighing 1/n; more than `max` hits stop it
/// (an error naming `max_hitpoints=`), so it never holds more than `max`.
fn eye_pass(
    frame: &Frame<'_>,
    runs: &[Region],
    n: u32,
    max: u64,
    sample: impl Fn(u32, u32, u32) -> (crate::geometry::Ray, crate::integrator::PathState) + Sync,
) -> Result<(EyePass, RayCounts), Unfinished> {
    let share = 1.0 / f64::from(n.max(1));
    let found = AtomicU64::new(0);
    // Each row of the runs: its run, its row in the frame and its first pixel.
    let mut first = 0u32;
    let mut lines = Vec::new();
    for run in runs {
        for y in run.y..run.y + run.height {
            lines.push((*run, y, first));
            first += run.width;
        }
    }
    let rows: Option<Vec<(EyePass, RayCounts)>> = lines
        .into_par_iter()
        .map(|(region, y, first)| {
            let mut hints = ShadowHints::default();
            let mut row = EyePass {
                hits: Vec::new(),
                colors: Vec::with_capacity(region.width as usize),
            };
            let mut rays = RayCounts::default();
            let fresh = HitPointObserver::default();
            for x in region.x..region.x + region.width {
                let pixel = first + (x - region.x);
                let before = row.hits.len();
                let mut color = DVec3::ZERO;
                for s in 0..n.max(1) {
                    frame.packet(
                        1,
                        |_| sample(x, y, s),
                        &fresh,
                        |_, c, obs, r| {
                            row.hits.extend(obs.seeds.drain(..).map(|mut h| {
                                h.throughput *= share;
                                (pixel, h)
                            }));
                            color += c;
                            rays.add(r);
                        },
                        &mut hints,
                    );
                }
                let new = (row.hits.len() - before) as u64;
                if found.fetch_add(new, Ordering::Relaxed) + new > max {
                    return None;
                }
                row.colors.push(color * share);
            }
            Some((row, rays))
        })
        .collect();
    let Some(rows) = rows else {
        return Err(Unfinished::HitPoints { max });
    };
    let mut pass = EyePass {
        hits: Vec::with_capacity(rows.iter().map(|r| r.0.hits.len()).sum()),
        colors: Vec::with_capacity(first as usize),
    };
    let mut rays = RayCounts::default();
    for (row, r) in rows {
        pass.hits.extend(row.hits);
        pass.colors.extend(row.colors);
        rays.add(&r);
    }
    Ok((pass, rays))
}

/// The hit points of the eye pass's diffuse hits.
fn hit_points(
    scene: &Scene,
    model: &Model,
    plan: &Plan,
    seeds: Vec<(u32, HitPointSeed)>,
) -> Vec<HitPoint> {
    seeds
        .into_iter()
        .map(|(pixel, s)| HitPoint {
            pixel,
            point: s.point,
            side: s.side,
            brdf: {
                let mut brdf = Brdf::of(plan.brdf, plan.specular, &s.material, s.mirror, s.side);
                // lazycal's hit point weighs k/π, whatever its `diff=`.
                if plan.term == Term::Only {
                    brdf.diff = 1.0;
                }
                brdf
            },
            weight: s.throughput * model.albedo(&s.material, scene.textures(), s.uv),
            r2: plan.radius * plan.radius,
            n: 0.0,
            m: 0,
            tau: DVec3::ZERO,
        })
        .collect()
}
