//! The refracted ray of a surface point (or its total internal
//! reflection), with Beer absorption inside.

use super::surface::ShadingPoint;
use super::{Bounce, PathContext, Whitted};
use crate::geometry::{Ray, offset_origin};
use crate::integrator::model::{Absorb, Inside};
use crate::integrator::observer::{PathObserver, RayKind};
use crate::integrator::optics::{reflect, refract};
use glam::DVec3;

impl Whitted<'_> {
    /// The refracted light at `p` (hit by `ray` at `at`) weighted by
    /// `refr=` and, inside, the absorption along the ray; `None` where none
    /// is traced (no refraction, or at the depth limit: told as cut).
    #[inline(always)]
    pub(super) fn refracted<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        at: Bounce,
        cx: &mut PathContext<O>,
    ) -> Option<DVec3> {
        let (model, m, depth) = (&self.model, &p.material, at.depth);
        let refr = if model.secondary { m.refr } else { 0.0 };
        if refr <= 0.0 {
            return None;
        }
        if depth >= model.max_depth {
            cx.obs.cut(RayKind::Refraction);
            return None;
        }
        // Which side the ray is on: its face, or the lineages' flag.
        let within = match model.inside {
            Inside::FrontFace => !p.front,
            Inside::Parity => at.inside,
        };
        let rindex = if m.rindex <= 0.0 && model.unit_index_fallback {
            1.0
        } else {
            m.rindex
        };
        let eta = if within { rindex } else { 1.0 / rindex };
        let (dir, origin, kind, inside) = match refract(ray.dir, p.n, eta) {
            Some(t) => (
                t,
                offset_origin(p.point, -p.side),
                RayKind::Refraction,
                !at.inside,
            ),
            None => (
                reflect(ray.dir, p.n),
                offset_origin(p.point, p.side),
                RayKind::TotalInternalReflection,
                at.inside,
            ),
        };
        cx.st.rays.refracted += 1;
        let ray = Ray::off_surface(origin, dir);
        cx.obs.ray(kind, depth + 1, &ray);
        let next = Bounce {
            depth: depth + 1,
            inside,
            ..at
        };
        let c = self.trace(&ray, next, cx);
        let weight = if within && model.absorb == Absorb::Refracted {
            (-m.absor * p.t).exp() * refr
        } else {
            DVec3::splat(refr)
        };
        cx.obs.done(c, weight);
        Some(c * weight)
    }
}
