//! The Whitted-style ray tracer of every lineage, computed exactly: the
//! framework's shading model (spec: "Shading model": diffuse and the `L·N`
//! specular per light with shadows, mirror and glossy reflection,
//! refraction with Beer absorption, the per-ray clamp, depth 10) and the
//! relatives' variations of it, read from a [`Model`].

use super::model::{Direct, Emitter, Glossy, Inside, Model};
use super::observer::{LightSeen, PathObserver, RayKind, SurfaceSeen};
use super::optics::{disk_direction, glossy_direction, reflect, refract};
use super::path::{PathState, SceneAccel};
use super::photons::{Brdf, PhotonMap};
use super::visibility::{ShadowFrom, ShadowHints, shade_factor, weighted_light};
use crate::accel::PACKET_MAX;
use crate::geometry::{Hit, Ray, offset_origin, perpendiculars};
use crate::scene::{Camera, LightKind, Scene};
use glam::DVec3;

/// Glossy reflections are averaged over many rays up to this depth, one ray
/// deeper; each glossy ray also counts this many levels (the framework's
/// `MAX_DREFL_DEP`), so a glossy surface seen in a glossy reflection takes
/// one ray (a plain mirror in the lineages).
const GLOSSY_AVERAGE_DEPTH: u32 = 2;

/// What the ray tracer does about photons.
#[derive(Clone, Copy, Default)]
pub(crate) struct PhotonShading<'a> {
    /// The map gathered at diffuse hits (PM).
    pub map: Option<&'a PhotonMap>,
    /// Whether the lights' direct term is left out (Z14's model with
    /// photons: they carry all diffuse light).
    pub no_direct: bool,
    /// Whether gathered photons carry the lineage's specular lobe.
    pub specular: bool,
}

/// The ray tracer over one scene, in its dialect's model.
pub(crate) struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a SceneAccel,
    shadow_samples: u32,
    model: Model,
    photons: PhotonShading<'a>,
}

impl<'a> Whitted<'a> {
    /// The tracer over `scene` (its dialect, its camera's quality keys)
    /// using `accel` (built over the scene's objects) for ray queries, with
    /// `photons`.
    pub fn new(
        scene: &'a Scene,
        camera: &Camera,
        accel: &'a SceneAccel,
        photons: PhotonShading<'a>,
    ) -> Self {
        Whitted {
            scene,
            accel,
            shadow_samples: 16 * camera.shade_quality.max(1),
            model: Model::of(scene.dialect().dialect, camera),
            photons,
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
            let k = model.albedo(&m, scene.textures(), surface.uv);
            if model.ambient {
                color += k * m.diff * scene.background().ambient();
            }
            let from = ShadowFrom {
                point,
                side,
                object: Some(index),
            };
            let lights = if self.photons.no_direct {
                &[][..]
            } else {
                scene.lights()
            };
            for (li, light) in lights.iter().enumerate() {
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
            if let Some(map) = self.photons.map
                && m.diff > 0.0
            {
                let brdf = Brdf {
                    diff: m.diff,
                    spec: if self.photons.specular { m.spec } else { 0.0 },
                    mirror: reflect(ray.dir, n),
                };
                let gathered = map.estimate(point, side, &brdf);
                let term = k * gathered.value;
                obs.photons(&gathered, term);
                color += term;
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
