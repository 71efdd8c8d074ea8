//! The Whitted-style ray tracer of every lineage, computed exactly: the
//! framework's shading model (spec: "Shading model": diffuse and the `L·N`
//! specular per light with shadows, mirror and glossy reflection,
//! refraction with Beer absorption, the per-ray clamp, depth 10) and the
//! relatives' variations of it, read from a [`Model`].

use super::model::{Direct, Emitter, Glossy, Inside, Model};
use super::observer::{LightSeen, PathObserver, RayKind, SurfaceSeen};
use super::path::{PathState, SceneAccel};
use super::visibility::{ShadowFrom, ShadowHints, shade_factor, weighted_light};
use crate::accel::PACKET_MAX;
use crate::geometry::{Hit, Ray, offset_origin, perpendiculars};
use crate::scene::{Camera, LightKind, Scene};
use glam::DVec3;
use rand::Rng;
use rand_pcg::Pcg32;

/// Glossy reflections are averaged over many rays up to this depth, one ray
/// deeper; each glossy ray also counts this many levels (the framework's
/// `MAX_DREFL_DEP`), so a glossy surface seen in a glossy reflection takes
/// one ray (a plain mirror in the lineages).
const GLOSSY_AVERAGE_DEPTH: u32 = 2;

/// The ray tracer over one scene, in its dialect's model.
pub(crate) struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a SceneAccel,
    shadow_samples: u32,
    model: Model,
}

impl<'a> Whitted<'a> {
    /// The tracer over `scene` (its dialect, its camera's quality keys)
    /// using `accel` (built over the scene's objects) for ray queries.
    pub fn new(scene: &'a Scene, camera: &Camera, accel: &'a SceneAccel) -> Self {
        Whitted {
            scene,
            accel,
            shadow_samples: 16 * camera.shade_quality.max(1),
            model: Model::of(scene.dialect().dialect, camera),
        }
    }

    /// The model it shades with.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The colour seen along one camera ray, told to `obs`: the reference
    /// the packet tests compare with.
    #[cfg(test)]
    pub fn trace_camera<O: PathObserver>(
        &self,
        ray: &Ray,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        st.rays.camera += 1;
        obs.ray(RayKind::Camera, 1, ray);
        let c = self.trace(ray, 1, false, st, obs, hints);
        obs.done(c, DVec3::ONE);
        c
    }

    /// The colours seen along up to [`PACKET_MAX`] camera rays into `out`,
    /// ray k told to `observers[k]`.
    pub fn trace_camera_packet<O: PathObserver>(
        &self,
        rays: &[Ray],
        states: &mut [PathState],
        observers: &mut [O],
        out: &mut [DVec3],
        hints: &mut ShadowHints,
    ) {
        let mut found = [None; PACKET_MAX];
        let found = &mut found[..rays.len()];
        if O::COUNTS_QUERIES {
            // Ray by ray, each query counted alone: the packet's answers.
            for (k, ray) in rays.iter().enumerate() {
                let tally = &mut observers[k].queries();
                found[k] = self.accel.intersect_tallied(ray, f64::INFINITY, tally);
            }
        } else {
            self.accel.intersect_packet(rays, found);
        }
        for (k, (ray, &hit)) in rays.iter().zip(found.iter()).enumerate() {
            if O::COUNTS_QUERIES {
                // Each sample's cost its own: no blocker remembered from another.
                *hints = ShadowHints::default();
            }
            states[k].rays.camera += 1;
            let obs = &mut observers[k];
            obs.ray(RayKind::Camera, 1, ray);
            out[k] = self.shade(ray, hit, 1, false, &mut states[k], obs, hints);
            obs.done(out[k], DVec3::ONE);
        }
    }

    /// The framework's `RayTracing`: the colour along `ray` at `depth`
    /// (`inside`: the lineages' refraction flag), clamped to at most 1 per
    /// channel (in the lineages that clamp only the camera ray, at depth 1).
    #[allow(clippy::too_many_arguments)] // the ray's state, its random stream and observer
    fn trace<O: PathObserver>(
        &self,
        ray: &Ray,
        depth: u32,
        inside: bool,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        let found = self
            .accel
            .intersect_tallied(ray, f64::INFINITY, &mut obs.queries());
        self.shade(ray, found, depth, inside, st, obs, hints)
    }

    /// The colour `c` seen at `depth`, clamped as the model says.
    #[inline(always)]
    fn clamp(&self, c: DVec3, depth: u32) -> DVec3 {
        if self.model.clamp_every_ray || depth == 1 {
            c.min(DVec3::ONE)
        } else {
            c
        }
    }

    /// [`Whitted::trace`] for a ray whose nearest hit is `found`.
    #[allow(clippy::too_many_arguments)] // the ray's state, its random stream and observer
    fn shade<O: PathObserver>(
        &self,
        ray: &Ray,
        found: Option<(u32, Hit)>,
        depth: u32,
        inside: bool,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        let scene = self.scene;
        let model = &self.model;
        let Some((index, hit)) = found else {
            return self.clamp(scene.background().color(ray.dir), depth);
        };
        let object = &self.accel.objects()[index as usize];
        obs.hit(object.origin());
        if let Some(light) = object.light() {
            obs.emitter(light, object.shape(), ray, &hit);
            let c = scene.lights()[light as usize].color;
            return match model.emitter {
                Emitter::Clamped => c.min(DVec3::ONE),
                Emitter::Normalised if c.max_element() > 0.0 => c / c.max_element(),
                Emitter::Normalised => c,
            };
        }
        let m = scene.material_of(object);
        let shape = object.shape();
        let mut surface = if m.texture.is_some() || m.normal_map.is_some() {
            shape.surface(ray, &hit)
        } else {
            shape.surface_untextured(ray, &hit)
        };
        if let Some(map) = m.normal_map.and_then(|t| scene.textures().get(t as usize)) {
            surface.shading_normal = shape.mapped_normal(&surface, map.sample(surface.uv));
        }
        let point = surface.point;
        let front = surface.normal.dot(ray.dir) < 0.0;
        // Normals facing the ray: geometric (for nudging new rays) and shading.
        let (side, n) = if front {
            (surface.normal, surface.shading_normal)
        } else {
            (-surface.normal, -surface.shading_normal)
        };
        obs.surface(&SurfaceSeen {
            origin: object.origin(),
            shape,
            ray,
            hit: &hit,
            material: &m,
        });
        let mut color = DVec3::ZERO;

        if m.diff > 0.0 || (m.spec > 0.0 && model.lit_by_specular) {
            let k = match m.texture.and_then(|t| scene.textures().get(t as usize)) {
                Some(texture) if model.texture_replaces => texture.sample(surface.uv),
                Some(texture) => m.color * texture.sample(surface.uv),
                None => m.color,
            };
            if model.ambient {
                color += k * m.diff * scene.background().ambient();
            }
            let from = ShadowFrom {
                point,
                side,
                object: Some(index),
            };
            for (li, light) in scene.lights().iter().enumerate() {
                let l = (light.center() - point).normalize_or_zero();
                let d = l.dot(n);
                let mut seen = LightSeen {
                    light: li as u32,
                    l_dot_n: d,
                    s: 0.0,
                    rays: 0,
                    diffuse: 0.0,
                    specular: 0.0,
                    point,
                    side,
                };
                if let Direct::Falloff { specular } = model.direct {
                    let spec = if specular { m.spec } else { 0.0 };
                    let mirror = reflect(ray.dir, n);
                    let (mut diffuse, mut shiny, mut tried) = (0.0, 0.0, 0u32);
                    let (e, rays) = weighted_light(
                        self.accel,
                        light,
                        li as u32,
                        &from,
                        self.shadow_samples,
                        &mut st.rng,
                        hints,
                        &mut obs.queries(),
                        |l, dist| {
                            let inv = 1.0 / (dist * dist);
                            let (nl, rl) = (n.dot(l), mirror.dot(l));
                            let a = if nl > 0.0 { m.diff * nl * inv } else { 0.0 };
                            let b = if spec > 0.0 && rl > 0.0 {
                                spec * rl.powi(50) * inv
                            } else {
                                0.0
                            };
                            diffuse += a;
                            shiny += b;
                            tried += 1;
                            a + b
                        },
                    );
                    st.rays.shadow += rays;
                    // The share of the samples' weight that got through (a
                    // weighted shade factor), split into its two parts.
                    let whole = diffuse + shiny;
                    let share = if whole > 0.0 { e / whole } else { 0.0 };
                    seen.rays = rays;
                    seen.s = (share * f64::from(tried)).min(1.0);
                    (seen.diffuse, seen.specular) = (diffuse * share, shiny * share);
                    if e > 0.0
                        && let LightKind::Point { .. } = light.kind
                    {
                        obs.point_light(li as u32);
                    }
                    obs.light(&seen);
                    color += k * light.color * e;
                    continue;
                }
                if d <= model.min_dot {
                    obs.light(&seen);
                    continue;
                }
                let (s, rays) = shade_factor(
                    self.accel,
                    light,
                    li as u32,
                    &from,
                    self.shadow_samples,
                    &mut st.rng,
                    hints,
                    &mut obs.queries(),
                );
                st.rays.shadow += rays;
                (seen.s, seen.rays) = (s, rays);
                if s <= 0.0 {
                    obs.light(&seen);
                    continue;
                }
                if let LightKind::Point { .. } = light.kind {
                    obs.point_light(li as u32);
                }
                (seen.diffuse, seen.specular) = (m.diff * d * s, m.spec * d.powi(20) * s);
                obs.light(&seen);
                let weight = seen.diffuse + seen.specular;
                color += k * light.color * weight;
            }
        }

        // A ray deeper than the model's depth would return black: it is not traced.
        let max_depth = model.max_depth;
        let glossy = m.drefl > 0.0
            && match model.glossy {
                Glossy::Exp => true,
                Glossy::Disk => depth <= GLOSSY_AVERAGE_DEPTH,
                Glossy::Mirror => false,
            };
        let reflected_depth = depth + if glossy { GLOSSY_AVERAGE_DEPTH } else { 1 };
        let (refl, refr) = if model.secondary {
            (m.refl, m.refr)
        } else {
            (0.0, 0.0)
        };
        if refl > 0.0 && reflected_depth > max_depth {
            obs.cut(RayKind::Reflection);
        }
        if refl > 0.0 && reflected_depth <= max_depth {
            let mirror = reflect(ray.dir, n);
            let origin = offset_origin(point, side);
            let weight = m.color * refl;
            if !glossy {
                st.rays.reflected += 1;
                let ray = Ray::off_surface(origin, mirror);
                obs.ray(RayKind::Reflection, depth + 1, &ray);
                let c = self.trace(&ray, depth + 1, inside, st, obs, hints);
                obs.done(c, weight);
                color += c * weight;
            } else {
                let samples = match model.glossy {
                    Glossy::Exp if depth > GLOSSY_AVERAGE_DEPTH => 1,
                    Glossy::Exp => 16 * self.scene.camera().drefl_quality.max(1),
                    _ => model.glossy_samples,
                };
                let (a1, a2) = perpendiculars(mirror);
                let mut fan = obs.fan();
                let mut sum = DVec3::ZERO;
                for k in 0..samples {
                    let dir = match model.glossy {
                        Glossy::Exp => glossy_direction(mirror, side, a1, a2, m.drefl, &mut st.rng),
                        _ => disk_direction(mirror, a1, a2, m.drefl, &mut st.rng),
                    };
                    st.rays.reflected += 1;
                    let ray = Ray::off_surface(origin, dir);
                    let kind = RayKind::Glossy {
                        k: k + 1,
                        n: samples,
                    };
                    fan.ray(kind, reflected_depth, &ray);
                    let c = self.trace(&ray, reflected_depth, inside, st, &mut fan, hints);
                    fan.done(c, weight / samples as f64);
                    sum += c;
                }
                color += sum / samples as f64 * weight;
            }
        }

        if depth >= max_depth && refr > 0.0 {
            obs.cut(RayKind::Refraction);
        }
        if depth < max_depth && refr > 0.0 {
            // Which side the ray is on: its face, or the lineages' flag.
            let within = match model.inside {
                Inside::FrontFace => !front,
                Inside::Parity => inside,
            };
            let rindex = if m.rindex <= 0.0 && model.unit_index_fallback {
                1.0
            } else {
                m.rindex
            };
            let eta = if within { rindex } else { 1.0 / rindex };
            let (dir, origin, kind, next) = match refract(ray.dir, n, eta) {
                Some(t) => (t, offset_origin(point, -side), RayKind::Refraction, !inside),
                None => (
                    reflect(ray.dir, n),
                    offset_origin(point, side),
                    RayKind::TotalInternalReflection,
                    inside,
                ),
            };
            st.rays.refracted += 1;
            let ray = Ray::off_surface(origin, dir);
            obs.ray(kind, depth + 1, &ray);
            let c = self.trace(&ray, depth + 1, next, st, obs, hints);
            let weight = if within {
                (-m.absor * hit.t).exp() * refr
            } else {
                DVec3::splat(refr)
            };
            obs.done(c, weight);
            color += c * weight;
        }
        obs.shaded(color);
        self.clamp(color, depth)
    }
}

/// `d` mirrored about the unit normal `n`.
#[inline]
fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

/// Snell's law for unit `d` arriving against unit `n` with index ratio
/// `eta`; `None` on total internal reflection.
#[inline]
fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| (d * eta + n * (eta * cos_i - k.sqrt())).normalize())
}

/// The mirror direction perturbed by the `exp` blur: offset by
/// drefl·(x·a1 + y·a2) with radius 2^u − 1 and a uniform angle. A direction
/// pushed below the surface is folded back above it.
#[inline(always)]
fn glossy_direction(
    mirror: DVec3,
    side: DVec3,
    a1: DVec3,
    a2: DVec3,
    drefl: f64,
    rng: &mut Pcg32,
) -> DVec3 {
    let radius = (rng.random::<f64>()).exp2() - 1.0;
    // A uniform angle as a point of the unit circle, without sin and cos: a
    // point (x, y) uniform in the unit disc has a uniform angle θ, and so has
    // 2θ, whose cosine and sine are (x² − y², 2xy) / r² (no square root).
    let (c, s) = loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        let r2 = x * x + y * y;
        if r2 <= 1.0 && r2 > 1e-12 {
            let inv = 1.0 / r2;
            break ((x * x - y * y) * inv, 2.0 * x * y * inv);
        }
    };
    let mut dir = (mirror + (a1 * c + a2 * s) * (radius * drefl)).normalize();
    let below = dir.dot(side);
    if below < 0.0 {
        dir -= side * (2.0 * below);
    }
    dir
}

/// The lineages' glossy direction: the mirror direction offset by
/// drefl²·(x·a1 + y·a2), (x, y) uniform in the unit disk (the disk is
/// symmetric, so any perpendicular pair serves).
#[inline(always)]
fn disk_direction(mirror: DVec3, a1: DVec3, a2: DVec3, drefl: f64, rng: &mut Pcg32) -> DVec3 {
    let (x, y) = loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        if x * x + y * y <= 1.0 {
            break (x, y);
        }
    };
    (mirror + (a1 * x + a2 * y) * (drefl * drefl)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snell_and_total_internal_reflection() {
        // 45° into glass of index 1.5: sin t = sin 45° / 1.5.
        let d = DVec3::new(1.0, 0.0, -1.0).normalize();
        let t = refract(d, DVec3::Z, 1.0 / 1.5);
        let sin_t = (0.5f64.sqrt()) / 1.5;
        assert!(
            t.is_some_and(|t| (t.x - sin_t).abs() < 1e-14
                && (t.z + (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-14)
        );
        // Leaving glass at 45° with index 1.5: sin t would be 1.06 > 1.
        assert!(refract(d, DVec3::Z, 1.5).is_none());
        assert_eq!(reflect(d, DVec3::Z), DVec3::new(d.x, 0.0, -d.z));
    }

    #[test]
    fn glossy_directions_stay_above_the_surface_and_near_the_mirror() {
        use rand::SeedableRng;
        let mut rng = Pcg32::seed_from_u64(7);
        // Steep mirror direction: no folding, so the angle to it is at most atan(drefl).
        let mirror = DVec3::new(1.0, 0.0, 1.0).normalize();
        let (a1, a2) = perpendiculars(mirror);
        let mut max_angle: f64 = 0.0;
        for _ in 0..2000 {
            let d = glossy_direction(mirror, DVec3::Z, a1, a2, 0.25, &mut rng);
            assert!((d.length() - 1.0).abs() < 1e-12);
            max_angle = max_angle.max(d.dot(mirror).clamp(-1.0, 1.0).acos());
        }
        assert!(max_angle <= 0.25f64.atan() + 1e-12);
        assert!(
            max_angle > 0.2,
            "the blur reaches close to its radius: {max_angle}"
        );
        // Grazing mirror direction: every sample is folded above the surface.
        let mirror = DVec3::new(1.0, 0.0, 0.01).normalize();
        let (a1, a2) = perpendiculars(mirror);
        for _ in 0..2000 {
            assert!(glossy_direction(mirror, DVec3::Z, a1, a2, 0.25, &mut rng).z >= 0.0);
        }
    }

    #[test]
    fn glossy_blur_angle_is_uniform_and_radius_follows_exp() {
        use rand::SeedableRng;
        let mut rng = Pcg32::seed_from_u64(11);
        let mirror = DVec3::Z;
        let (a1, a2) = perpendiculars(mirror);
        let drefl = 0.5;
        let n = 64_000;
        let mut angle_bins = [0u32; 16];
        let mut below_half = 0u32;
        for _ in 0..n {
            let d = glossy_direction(mirror, DVec3::Z, a1, a2, drefl, &mut rng);
            // Back to the offset in the (a1, a2) plane: d ∝ mirror + offset.
            let off = d / d.dot(mirror) - mirror;
            let (x, y) = (off.dot(a1), off.dot(a2));
            let phi = y.atan2(x).rem_euclid(std::f64::consts::TAU);
            angle_bins[((phi / std::f64::consts::TAU) * 16.0) as usize % 16] += 1;
            // radius = drefl·(2^u − 1): below drefl·(√2 − 1) exactly when u < ½.
            if (x * x + y * y).sqrt() < drefl * (2f64.sqrt() - 1.0) {
                below_half += 1;
            }
        }
        // Chi-square with 15 degrees of freedom: 37.7 is its 0.999 quantile.
        let expected = n as f64 / 16.0;
        let chi2: f64 = angle_bins
            .iter()
            .map(|&k| (k as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 37.7, "angle not uniform: {angle_bins:?} chi2={chi2}");
        // Half the radii below the median of 2^u − 1, within 4 standard deviations.
        let sd = (n as f64 * 0.25).sqrt();
        assert!(
            (below_half as f64 - n as f64 / 2.0).abs() < 4.0 * sd,
            "{below_half} of {n} radii below the median"
        );
    }
}
