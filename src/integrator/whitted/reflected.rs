//! The reflected ray of a surface point: a mirror's one ray, or a glossy
//! surface's fan averaged (each lineage's sampling).

use super::surface::ShadingPoint;
use super::{Bounce, PathContext, Whitted};
use crate::geometry::{Ray, offset_origin, perpendiculars};
use crate::integrator::model::Glossy;
use crate::integrator::observer::{PathObserver, RayKind};
use crate::integrator::optics::{disk_direction, glossy_direction, reflect};
use crate::sampling::RandomSource;
use glam::DVec3;

/// Glossy reflections are averaged over many rays up to this depth, one ray
/// deeper; each glossy ray also counts this many levels (the framework's
/// `MAX_DREFL_DEP`), so a glossy surface seen in a glossy reflection takes
/// one ray (a plain mirror in the lineages).
const GLOSSY_AVERAGE_DEPTH: u32 = 2;

impl Whitted<'_> {
    /// The reflected light at `p` (hit by `ray` at `at`) weighted by the
    /// material's colour × `refl=` (or `refl=` alone, as the model says); `None` where none is traced (no
    /// reflection, or past the depth limit: told to the observer as cut).
    #[inline(always)]
    pub(super) fn reflected<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        at: Bounce,
        cx: &mut PathContext<O>,
    ) -> Option<DVec3> {
        let (model, m, depth) = (&self.model, &p.material, at.depth);
        let glossy = m.drefl > 0.0
            && match model.glossy {
                Glossy::Exp => true,
                Glossy::Disk => depth <= GLOSSY_AVERAGE_DEPTH,
                Glossy::Mirror => false,
            };
        let reflected_depth = depth + if glossy { GLOSSY_AVERAGE_DEPTH } else { 1 };
        let refl = if model.secondary { m.refl } else { 0.0 };
        if refl <= 0.0 {
            return None;
        }
        // A ray deeper than the model's depth would return black: it is not traced.
        if reflected_depth > model.max_depth {
            cx.obs.cut(RayKind::Reflection);
            return None;
        }
        let mirror = reflect(ray.dir, p.n);
        let origin = offset_origin(p.point, p.side);
        let weight = if model.tinted_reflection {
            m.color * refl
        } else {
            DVec3::splat(refl)
        };
        let next = Bounce {
            depth: reflected_depth,
            ..at
        };
        if !glossy {
            cx.st.rays.reflected += 1;
            let ray = Ray::off_surface(origin, mirror);
            cx.obs.ray(RayKind::Reflection, depth + 1, &ray);
            let c = self.trace(&ray, next, cx);
            cx.obs.done(c, weight);
            return Some(c * weight);
        }
        let samples = match model.glossy {
            Glossy::Exp if depth > GLOSSY_AVERAGE_DEPTH => 1,
            _ => model.glossy_samples,
        };
        let (a1, a2) = perpendiculars(mirror);
        let mut fan = cx.obs.fan();
        let mut fan = PathContext {
            st: &mut *cx.st,
            obs: &mut fan,
            hints: &mut *cx.hints,
        };
        let mut sum = DVec3::ZERO;
        for k in 0..samples {
            let rng = fan.st.rng.generator();
            let dir = match model.glossy {
                Glossy::Exp => glossy_direction(mirror, p.side, a1, a2, m.drefl, rng),
                _ => disk_direction(mirror, a1, a2, m.drefl, rng),
            };
            fan.st.rays.reflected += 1;
            let ray = Ray::off_surface(origin, dir);
            let kind = RayKind::Glossy {
                k: k + 1,
                n: samples,
            };
            fan.obs.ray(kind, reflected_depth, &ray);
            let c = self.trace(&ray, next, &mut fan);
            fan.obs.done(c, weight / samples as f64);
            sum += c;
        }
        Some(sum / samples as f64 * weight)
    }
}
