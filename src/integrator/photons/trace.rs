//! Photon tracing (`photon-mapping.md`, Units, Emission, Tracing): each
//! light's share of the photons leaves it with power 4π·c/n (lazycal's:
//! c/n, [`Term::photon_power`]), bounces by
//! Russian roulette and is stored at diffuse hits. Photon j of pass i draws
//! from its own stream keyed by (seed, i, j), so a pass is the same
//! whatever the threads.

use super::plan::{PhotonBrdf, Plan, Term};
use super::thin::Kept;
use super::units::{MAX_PHOTON_HITS, power, share};
use crate::geometry::perpendiculars;
use crate::geometry::{Ray, offset_origin};
use crate::integrator::model::{Glossy, Inside, Model};
use crate::integrator::observer::mix;
use crate::integrator::optics::{
    cosine_direction, disk_direction, glossy_direction, reflect, refract, sphere_direction,
};
use crate::integrator::{PhotonBounce, SceneAccel};
use crate::scene::{Light, LightKind, Scene};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use rayon::prelude::*;

/// Photons traced per task: fixed, so the tasks (and the order their
/// photons are joined in) do not depend on the threads.
const CHUNK: u64 = 4096;

/// Chunks a batch holds for each worker thread: enough to keep them busy,
/// few enough that a batch's photons are small beside the cap.
const BATCH_PER_THREAD: u64 = 8;

/// A photon stored on a diffuse surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Photon {
    /// Where it landed.
    pub pos: DVec3,
    /// The unit direction it travelled in.
    pub dir: DVec3,
    /// Its power (flux), RGB.
    pub power: DVec3,
    /// Mirror and glass bounces before it landed.
    pub bounces: u32,
}

/// The photons of one pass.
#[derive(Clone, Debug, Default)]
pub(crate) struct PhotonPass {
    /// Stored photons, in photon order.
    pub photons: Vec<Photon>,
    /// Photons emitted.
    pub emitted: u64,
    /// Photons that would have been stored beyond `max_photons=` (the kept
    /// ones were thinned evenly and their power scaled to make up for them).
    pub thinned: u64,
    /// Rays cast: one nearest-hit query per path segment.
    pub rays: u64,
}

/// Each emitting light's index and photon count (the counts add up to
/// about `n`; lights with P(c) ≤ 0 or no power get none).
pub(crate) fn shares(lights: &[Light], n: u64) -> Vec<(usize, u64)> {
    let emits = |l: &Light| power(l.color) > 0.0 && share(l) > 0.0;
    let total: f64 = lights.iter().filter(|l| emits(l)).map(share).sum();
    if total <= 0.0 {
        return Vec::new();
    }
    lights
        .iter()
        .enumerate()
        .filter(|(_, l)| emits(l))
        .map(|(i, l)| (i, (n as f64 * share(l) / total).round() as u64))
        .filter(|&(_, k)| k > 0)
        .collect()
}

/// Photons emitted in a batch on `threads` workers: chunks traced at once
/// before their photons join the kept ones.
pub(crate) fn batch_emitted(threads: u64) -> u64 {
    BATCH_PER_THREAD * threads.max(1) * CHUNK
}

/// One pass's photons and their streams: photon j is light l's when j is
/// in l's range, and draws from a stream keyed by (seed, pass, j).
struct Emission<'a> {
    tracer: Tracer<'a>,
    /// Each emitting light's first index, the light and its count.
    starts: Vec<(u64, usize, u64)>,
    emitted: u64,
    key: u64,
}

impl<'a> Emission<'a> {
    fn new(tracer: Tracer<'a>, seed: u64, pass: u64) -> Self {
        let shares = shares(tracer.scene.lights(), tracer.plan.emit);
        let mut starts = Vec::with_capacity(shares.len());
        let mut emitted = 0u64;
        for &(l, n) in &shares {
            starts.push((emitted, l, n));
            emitted += n;
        }
        Emission {
            tracer,
            starts,
            emitted,
            key: mix(mix(seed ^ 0x5048_4f54_4f4e_5321) ^ mix(pass)),
        }
    }

    /// Traces photon `j` into `out`; returns the rays it cast.
    fn trace(&self, j: u64, out: &mut Vec<Photon>) -> u64 {
        let (_, l, n) = self.starts[self.starts.partition_point(|s| s.0 <= j) - 1];
        let mut rng = Pcg32::seed_from_u64(mix(self.key ^ j));
        self.tracer.trace(l, n, &mut rng, out)
    }
}

/// Traces pass `pass` of `plan.emit` photons through `scene`, in `model`.
pub(crate) fn shoot(
    scene: &Scene,
    accel: &SceneAccel,
    model: &Model,
    plan: &Plan,
    seed: u64,
    pass: u64,
) -> PhotonPass {
    let tracer = Tracer {
        scene,
        accel,
        model,
        plan,
    };
    let e = Emission::new(tracer, seed, pass);
    // Batches of chunks, in order, each joining the kept photons as soon
    // as it is traced: a pass holds at most `max_photons=` (and an eighth)
    // and one batch, however many it emits.
    let chunks = e.emitted.div_ceil(CHUNK);
    let batch = batch_emitted(rayon::current_num_threads() as u64) / CHUNK;
    let mut kept = Kept::new(plan.max_photons, e.key);
    let mut rays = 0;
    for first in (0..chunks).step_by(batch as usize) {
        let traced: Vec<(Vec<Photon>, u64)> = (first..(first + batch).min(chunks))
            .into_par_iter()
            .map(|c| {
                let (mut out, mut rays) = (Vec::new(), 0);
                for j in c * CHUNK..((c + 1) * CHUNK).min(e.emitted) {
                    rays += e.trace(j, &mut out);
                }
                (out, rays)
            })
            .collect();
        for (chunk, r) in &traced {
            kept.extend(chunk);
            rays += r;
        }
    }
    let (photons, thinned) = kept.finish(|p, by| p.power *= by);
    PhotonPass {
        photons,
        emitted: e.emitted,
        thinned,
        rays,
    }
}

/// Photons traced to measure how many a pass stores: at least this many...
const PILOT_MIN: u64 = 4096;
/// ...and a 256th of those emitted, up to this many (a few percent of the
/// pass's time at most; where few photons are stored, a small sample's
/// standard error is a large part of the mean).
const PILOT_MAX: u64 = 65_536;

/// Photons a pass of `plan` stores per photon emitted, from a sample of
/// pass 0's photons spread evenly over its lights (a 256th of them, from
/// [`PILOT_MIN`] to [`PILOT_MAX`]): the sample's mean and four standard
/// errors (an estimate that is rarely below the truth).
pub(crate) fn stored_per_emitted(
    scene: &Scene,
    accel: &SceneAccel,
    model: &Model,
    plan: &Plan,
    seed: u64,
) -> f64 {
    let tracer = Tracer {
        scene,
        accel,
        model,
        plan,
    };
    let e = Emission::new(tracer, seed, 0);
    let n = (e.emitted / 256).clamp(PILOT_MIN, PILOT_MAX).min(e.emitted);
    if n == 0 {
        return 0.0;
    }
    let counts: Vec<f64> = (0..n)
        .into_par_iter()
        .map_init(Vec::new, |out, k| {
            out.clear();
            e.trace(k * e.emitted / n, out);
            out.len() as f64
        })
        .collect();
    let mean = counts.iter().sum::<f64>() / n as f64;
    let var = counts.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / n as f64;
    (mean + 4.0 * (var / n as f64).sqrt()).min(f64::from(MAX_PHOTON_HITS))
}

/// What one photon's path reads.
struct Tracer<'a> {
    scene: &'a Scene,
    accel: &'a SceneAccel,
    model: &'a Model,
    plan: &'a Plan,
}

impl Tracer<'_> {
    /// Traces one photon of light `l` (which emits `n` this pass), storing
    /// it into `out` at each diffuse hit the plan keeps; returns the rays
    /// it cast.
    fn trace(&self, l: usize, n: u64, rng: &mut Pcg32, out: &mut Vec<Photon>) -> u64 {
        let light = &self.scene.lights()[l];
        let (origin, dir) = emit(light, rng);
        // The colon family's photons carry c·power/n (`ppm.cpp`
        // `Photontracer::emit`).
        let mut flux = match light.emission.power {
            Some(p) => light.color * (p / n.max(1) as f64),
            None => self.plan.term.photon_power(light.color, n),
        };
        let mut ray = Ray::new(origin, dir);
        let (mut bounces, mut inside, mut hits) = (0u32, false, 0u32);
        // A light's own surface is passed through: a few times at most.
        let (mut passes, mut rays) = (0, 0);
        while hits < MAX_PHOTON_HITS {
            rays += 1;
            let Some((index, hit)) = self.accel.intersect(&ray, f64::INFINITY) else {
                return rays;
            };
            let object = &self.accel.objects()[index as usize];
            match object.light() {
                Some(own) if own as usize == l && passes < 4 => {
                    passes += 1;
                    ray = Ray::off_surface(ray.at(hit.t), ray.dir);
                    continue;
                }
                Some(_) => return rays,
                None => {}
            }
            hits += 1;
            let m = self.scene.material_of(object);
            let shape = object.shape();
            let mut surface = if m.texture.is_some() || m.normal_map.is_some() {
                shape.surface(&ray, &hit)
            } else {
                shape.surface_untextured(&ray, &hit)
            };
            if let Some(map) = m
                .normal_map
                .and_then(|t| self.scene.textures().get(t as usize))
            {
                surface.shading_normal = shape.mapped_normal(&surface, map.sample(surface.uv));
            }
            let point = surface.point;
            let front = surface.normal.dot(ray.dir) < 0.0;
            let (side, nrm) = if front {
                (surface.normal, surface.shading_normal)
            } else {
                (-surface.normal, -surface.shading_normal)
            };
            let (k, diffuse) = match self.model.photon_bounce {
                PhotonBounce::Textured => (
                    self.model.albedo(&m, self.scene.textures(), surface.uv),
                    m.diff,
                ),
                PhotonBounce::Untextured => (m.color, m.diff + m.spec),
            };
            let within = match self.model.inside {
                Inside::FrontFace => !front,
                Inside::Parity => inside,
            };
            if m.diff > 0.0 && self.stores(hits, bounces) {
                out.push(Photon {
                    pos: point,
                    dir: ray.dir,
                    power: flux,
                    bounces,
                });
            }
            // Russian roulette over diffuse, reflect, refract (absorb the rest).
            let transmit = if within {
                (-m.absor * hit.t).exp()
            } else {
                DVec3::ONE
            };
            let (refl, refr) = if self.model.secondary {
                (m.refl, m.refr)
            } else {
                (0.0, 0.0)
            };
            let diffuse = match self.plan.brdf {
                PhotonBrdf::Lobe => diffuse,
                PhotonBrdf::Phong => m.diff + m.spec,
            };
            let mut p = [
                diffuse * power(k),
                refl * power(m.color),
                refr * power(transmit),
            ];
            let sum: f64 = p.iter().sum();
            if sum > 1.0 {
                p.iter_mut().for_each(|x| *x /= sum);
                flux *= sum;
            }
            let u = rng.random::<f64>();
            let next = if u < p[0] {
                flux *= k / power(k);
                (offset_origin(point, side), cosine_direction(nrm, rng))
            } else if u < p[0] + p[1] {
                flux *= m.color / power(m.color);
                bounces += 1;
                (
                    offset_origin(point, side),
                    self.mirror(ray.dir, nrm, side, m.drefl, rng),
                )
            } else if u < p[0] + p[1] + p[2] {
                flux *= transmit / power(transmit);
                bounces += 1;
                let rindex = if m.rindex <= 0.0 && self.model.unit_index_fallback {
                    1.0
                } else {
                    m.rindex
                };
                let eta = if within { rindex } else { 1.0 / rindex };
                match refract(ray.dir, nrm, eta) {
                    Some(t) => {
                        inside = !inside;
                        (offset_origin(point, -side), t)
                    }
                    None => (offset_origin(point, side), reflect(ray.dir, nrm)),
                }
            } else {
                return rays;
            };
            ray = Ray::off_surface(next.0, next.1);
        }
        rays
    }

    /// Whether a photon at its `hits`-th hit after `bounces` mirror or glass
    /// bounces is stored.
    fn stores(&self, hits: u32, bounces: u32) -> bool {
        match self.plan.term {
            Term::Replace | Term::Only => true,
            Term::Add { caustics: true } => bounces > 0,
            Term::Add { caustics: false } => hits > 1,
        }
    }

    /// The mirror direction of `dir` about `n`, blurred as the model's glossy
    /// reflection is (`drefl=`).
    fn mirror(&self, dir: DVec3, n: DVec3, side: DVec3, drefl: f64, rng: &mut Pcg32) -> DVec3 {
        let mirror = reflect(dir, n);
        if drefl <= 0.0 {
            return mirror;
        }
        let (a1, a2) = perpendiculars(mirror);
        match self.model.glossy {
            Glossy::Exp => glossy_direction(mirror, side, a1, a2, drefl, rng),
            Glossy::Disk => disk_direction(mirror, a1, a2, drefl, rng),
            Glossy::Mirror => mirror,
        }
    }
}

/// Where a photon of `light` starts and its unit direction.
fn emit(light: &Light, rng: &mut Pcg32) -> (DVec3, DVec3) {
    match light.kind {
        LightKind::Point { pos } => (pos, sphere_direction(rng)),
        LightKind::Square { center, dx, dy } => {
            let (a, b) = (
                2.0 * rng.random::<f64>() - 1.0,
                2.0 * rng.random::<f64>() - 1.0,
            );
            let dir = match light.emission.normal {
                Some(n) => cosine_direction(n, rng),
                None => sphere_direction(rng),
            };
            (center + dx * a + dy * b, dir)
        }
        LightKind::Sphere { center, radius } => {
            let n = sphere_direction(rng);
            (center + n * radius, cosine_direction(n, rng))
        }
    }
}
