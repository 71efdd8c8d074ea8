//! The colon family's reflected and refracted light (hta1996/Raytracing
//! `raytracer.cpp` `rayTracing`): a mirror, glass split by Fresnel's
//! reflectance, and no ray whose weight falls below the model's least.

use super::surface::ShadingPoint;
use super::{Bounce, PathContext, Whitted};
use crate::geometry::{Ray, offset_origin};
use crate::integrator::observer::{PathObserver, RayKind};
use crate::integrator::optics::{reflect, refract};
use glam::DVec3;

/// Below this a coefficient counts as 0 (its `Const::eps`).
const EPS: f64 = 1e-6;

/// The unpolarised Fresnel reflectance for a ray meeting a surface at
/// cosine `cos_i` (> 0) from a medium into one `index` times denser; 1 on
/// total internal reflection.
pub(crate) fn reflectance(cos_i: f64, index: f64) -> f64 {
    let sin2_t = (1.0 - cos_i * cos_i) / (index * index);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_p = (cos_i * index - cos_t) / (cos_i * index + cos_t);
    let r_s = (cos_i - cos_t * index) / (cos_i + cos_t * index);
    (r_p * r_p + r_s * r_s) / 2.0
}

impl Whitted<'_> {
    /// The light reflected and refracted at `p` (hit by `ray` at `at`):
    /// with refl= alone a mirror of weight colour × refl; with refr= alone
    /// the refracted ray of weight refr; with both, Fresnel's R and 1 − R
    /// (the reflection tinted by the colour); total internal reflection
    /// reflects with colour × (refl + refr). The index is the material's
    /// entering the front face, its inverse leaving.
    #[inline(always)]
    pub(super) fn fresnel<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        at: Bounce,
        cx: &mut PathContext<O>,
    ) -> DVec3 {
        let (m, model) = (&p.material, &self.model);
        if !model.secondary || (m.refl <= EPS && m.refr <= EPS) {
            return DVec3::ZERO;
        }
        let index = if p.front { m.rindex } else { 1.0 / m.rindex };
        let mirror = reflect(ray.dir, p.n);
        let through = refract(ray.dir, p.n, 1.0 / index);
        let mut color = DVec3::ZERO;
        let reflected = |share: f64, tint: DVec3, cx: &mut PathContext<O>| {
            let origin = offset_origin(p.point, p.side);
            let ray = Ray::off_surface(origin, mirror);
            self.follow(&ray, RayKind::Reflection, at, share, tint * share, cx)
        };
        match through {
            _ if m.refr <= EPS => color += reflected(m.refl, m.color, cx),
            None => color += reflected(m.refl + m.refr, m.color, cx),
            Some(t) => {
                let (kl, kr) = if m.refl <= EPS {
                    (0.0, m.refr)
                } else {
                    let r = reflectance(-ray.dir.dot(p.n), index);
                    (r, 1.0 - r)
                };
                if kl > EPS {
                    color += reflected(kl, m.color, cx);
                }
                if kr > EPS {
                    let ray = Ray::off_surface(offset_origin(p.point, -p.side), t);
                    let next = Bounce {
                        inside: !at.inside,
                        ..at
                    };
                    color += self.follow(&ray, RayKind::Refraction, next, kr, DVec3::splat(kr), cx);
                }
            }
        }
        color
    }

    /// The light along `ray` (of `kind`, leaving a hit at `at`) times
    /// `weight`, its share of the path `share`; nothing where the ray would
    /// be too deep or too faint to trace (told to the observer as cut).
    fn follow<O: PathObserver>(
        &self,
        ray: &Ray,
        kind: RayKind,
        at: Bounce,
        share: f64,
        weight: DVec3,
        cx: &mut PathContext<O>,
    ) -> DVec3 {
        let next = Bounce {
            depth: at.depth + 1,
            weight: at.weight * share,
            ..at
        };
        if next.depth > self.model.max_depth || next.weight < self.model.min_weight {
            cx.obs.cut(kind);
            return DVec3::ZERO;
        }
        match kind {
            RayKind::Refraction => cx.st.rays.refracted += 1,
            _ => cx.st.rays.reflected += 1,
        }
        cx.obs.ray(kind, next.depth, ray);
        let c = self.trace(ray, next, cx);
        cx.obs.done(c, weight);
        c * weight
    }
}
