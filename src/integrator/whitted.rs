//! The framework's shading model (spec: "Shading model"), computed
//! exactly: diffuse and the `L·N` specular per light with shadows, mirror
//! and glossy reflection, refraction with Beer absorption, the per-ray
//! clamp, depth 10.

use super::observer::{LightSeen, PathObserver, RayKind, SurfaceSeen};
use super::path::{PathState, SceneAccel};
use super::visibility::{ShadowFrom, ShadowHints, shade_factor};
use crate::accel::PACKET_MAX;
use crate::geometry::{Hit, Ray, offset_origin, perpendiculars};
use crate::scene::{Camera, LightKind, Scene};
use glam::DVec3;
use rand::Rng;
use rand_pcg::Pcg32;

/// A ray of this depth returns black (the camera ray has depth 1).
pub(crate) const MAX_DEPTH: u32 = 10;
/// Glossy reflections are averaged over many rays up to this depth, one ray
/// deeper; each glossy ray also counts this many levels (the framework's
/// `MAX_DREFL_DEP`), so a glossy surface seen in a glossy reflection takes one ray.
const GLOSSY_AVERAGE_DEPTH: u32 = 2;

/// The framework's ray tracer over one scene.
pub(crate) struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a SceneAccel,
    shadow_samples: u32,
    glossy_samples: u32,
}

impl<'a> Whitted<'a> {
    /// The tracer over `scene` (its camera's quality keys) using `accel`
    /// (built over the scene's objects) for ray queries.
    pub fn new(scene: &'a Scene, camera: &Camera, accel: &'a SceneAccel) -> Self {
        Whitted {
            scene,
            accel,
            shadow_samples: 16 * camera.shade_quality.max(1),
            glossy_samples: 16 * camera.drefl_quality.max(1),
        }
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
        let c = self.trace(ray, 1, st, obs, hints);
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
        self.accel.intersect_packet(rays, found);
        for (k, (ray, &hit)) in rays.iter().zip(found.iter()).enumerate() {
            states[k].rays.camera += 1;
            let obs = &mut observers[k];
            obs.ray(RayKind::Camera, 1, ray);
            out[k] = self.shade(ray, hit, 1, &mut states[k], obs, hints);
            obs.done(out[k], DVec3::ONE);
        }
    }

    /// The framework's `RayTracing`: the colour along `ray` at `depth`,
    /// clamped to at most 1 per channel.
    fn trace<O: PathObserver>(
        &self,
        ray: &Ray,
        depth: u32,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        let found = self.accel.intersect(ray, f64::INFINITY);
        self.shade(ray, found, depth, st, obs, hints)
    }

    /// [`Whitted::trace`] for a ray whose nearest hit is `found`.
    fn shade<O: PathObserver>(
        &self,
        ray: &Ray,
        found: Option<(u32, Hit)>,
        depth: u32,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        let scene = self.scene;
        let Some((index, hit)) = found else {
            return scene.background().color(ray.dir).min(DVec3::ONE);
        };
        let object = &self.accel.objects()[index as usize];
        obs.hit(object.origin());
        if let Some(light) = object.light() {
            obs.emitter(light, object.shape(), ray, &hit);
            return scene.lights()[light as usize].color.min(DVec3::ONE);
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

        if m.diff > 0.0 || m.spec > 0.0 {
            let k = match m.texture.and_then(|t| scene.textures().get(t as usize)) {
                Some(texture) => m.color * texture.sample(surface.uv),
                None => m.color,
            };
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
                if d <= 0.0 {
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

        // A ray deeper than MAX_DEPTH would return black: it is not traced.
        let glossy = m.drefl > 0.0;
        let reflected_depth = depth + if glossy { GLOSSY_AVERAGE_DEPTH } else { 1 };
        if m.refl > 0.0 && reflected_depth > MAX_DEPTH {
            obs.cut(RayKind::Reflection);
        }
        if m.refl > 0.0 && reflected_depth <= MAX_DEPTH {
            let mirror = reflect(ray.dir, n);
            let origin = offset_origin(point, side);
            let weight = m.color * m.refl;
            if !glossy {
                st.rays.reflected += 1;
                let ray = Ray::off_surface(origin, mirror);
                obs.ray(RayKind::Reflection, depth + 1, &ray);
                let c = self.trace(&ray, depth + 1, st, obs, hints);
                obs.done(c, weight);
                color += c * weight;
            } else {
                let samples = if depth <= GLOSSY_AVERAGE_DEPTH {
                    self.glossy_samples
                } else {
                    1
                };
                let (a1, a2) = perpendiculars(mirror);
                let mut fan = obs.fan();
                let mut sum = DVec3::ZERO;
                for k in 0..samples {
                    let dir = glossy_direction(mirror, side, a1, a2, m.drefl, &mut st.rng);
                    st.rays.reflected += 1;
                    let ray = Ray::off_surface(origin, dir);
                    let kind = RayKind::Glossy {
                        k: k + 1,
                        n: samples,
                    };
                    fan.ray(kind, reflected_depth, &ray);
                    let c = self.trace(&ray, reflected_depth, st, &mut fan, hints);
                    fan.done(c, weight / samples as f64);
                    sum += c;
                }
                color += sum / samples as f64 * weight;
            }
        }

        if depth >= MAX_DEPTH && m.refr > 0.0 {
            obs.cut(RayKind::Refraction);
        }
        if depth < MAX_DEPTH && m.refr > 0.0 {
            let eta = if front { 1.0 / m.rindex } else { m.rindex };
            let (dir, origin, kind) = match refract(ray.dir, n, eta) {
                Some(t) => (t, offset_origin(point, -side), RayKind::Refraction),
                None => (
                    reflect(ray.dir, n),
                    offset_origin(point, side),
                    RayKind::TotalInternalReflection,
                ),
            };
            st.rays.refracted += 1;
            let ray = Ray::off_surface(origin, dir);
            obs.ray(kind, depth + 1, &ray);
            let c = self.trace(&ray, depth + 1, st, obs, hints);
            let weight = if front {
                DVec3::splat(m.refr)
            } else {
                (-m.absor * hit.t).exp() * m.refr
            };
            obs.done(c, weight);
            color += c * weight;
        }
        obs.shaded(color);
        color.min(DVec3::ONE)
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
