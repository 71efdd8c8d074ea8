//! Direct light at a lit surface point, light by light, in the two models
//! of the lineages: the framework's (L towards the light's centre times
//! the shade factor) and the 1/d² lineages' (weighted per shadow sample).

use super::surface::ShadingPoint;
use super::{PathContext, Whitted};
use crate::geometry::Ray;
use crate::integrator::model::Direct;
use crate::integrator::observer::{LightSeen, PathObserver};
use crate::integrator::optics::reflect;
use crate::integrator::photons::power;
use crate::integrator::visibility::{
    ShadowFrom, ShadowRays, grid_share, shade_factor, weighted_light,
};
use crate::scene::LightKind;
use glam::DVec3;

impl Whitted<'_> {
    /// Adds to `color` each light's direct term at `p` (hit by `ray`,
    /// albedo `k`), in the lights' order; none where photons carry it.
    #[inline(always)]
    pub(super) fn direct<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        k: DVec3,
        color: &mut DVec3,
        cx: &mut PathContext<O>,
    ) {
        if self.photons.no_direct {
            return;
        }
        let from = ShadowFrom {
            point: p.point,
            side: p.side,
            object: Some(p.object),
        };
        for (li, light) in self.scene.lights().iter().enumerate() {
            let l = (light.center() - p.point).normalize_or_zero();
            let seen = LightSeen {
                light: li as u32,
                l_dot_n: l.dot(p.n),
                s: 0.0,
                rays: 0,
                diffuse: 0.0,
                specular: 0.0,
                point: p.point,
                side: p.side,
            };
            let to = ShadowRays {
                accel: self.accel,
                light,
                index: li as u32,
                samples: self.shadow_samples,
            };
            let weight = match self.model.direct {
                Direct::Falloff { .. } => Some(self.falloff_light(ray, p, &to, &from, seen, cx)),
                Direct::Centre | Direct::Phong => self.centre_light(ray, p, &to, &from, seen, cx),
                Direct::Grid { half } => self.grid_light(ray, p, &to, &from, half, seen, cx),
            };
            if let Some(w) = weight {
                *color += k * light.color * w;
            }
        }
    }

    /// The 1/d² lineages' term of light `to` at `p`: the mean over its
    /// shadow samples that get through of diff·N·L + spec·(R·L)^50, over d².
    #[inline(always)]
    fn falloff_light<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        to: &ShadowRays,
        from: &ShadowFrom,
        mut seen: LightSeen,
        cx: &mut PathContext<O>,
    ) -> f64 {
        let (m, n) = (&p.material, p.n);
        let spec = match self.model.direct {
            Direct::Falloff { specular: true } => m.spec,
            _ => 0.0,
        };
        let mirror = reflect(ray.dir, n);
        let (mut diffuse, mut shiny, mut tried) = (0.0, 0.0, 0u32);
        let (e, rays) = weighted_light(
            to,
            from,
            &mut cx.st.rng,
            cx.hints,
            &mut cx.obs.queries(),
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
        cx.st.rays.shadow += rays;
        // The share of the samples' weight that got through (a weighted
        // shade factor), split into its two parts.
        let whole = diffuse + shiny;
        let share = if whole > 0.0 { e / whole } else { 0.0 };
        seen.rays = rays;
        seen.s = (share * f64::from(tried)).min(1.0);
        (seen.diffuse, seen.specular) = (diffuse * share, shiny * share);
        if e > 0.0
            && let LightKind::Point { .. } = to.light.kind
        {
            cx.obs.point_light(to.index);
        }
        cx.obs.light(&seen);
        e
    }

    /// The framework's term of light `to` at `p` (hit by `ray`):
    /// (diff·L·N + spec·(L·N)^20) times the shade factor, where L·N passes
    /// the model's threshold and some shadow ray gets through (`None`
    /// elsewhere); the colon family's highlight is spec·(R_I·L)^50.
    #[inline(always)]
    fn centre_light<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        to: &ShadowRays,
        from: &ShadowFrom,
        mut seen: LightSeen,
        cx: &mut PathContext<O>,
    ) -> Option<f64> {
        let d = seen.l_dot_n;
        if d <= self.model.min_dot {
            cx.obs.light(&seen);
            return None;
        }
        let (s, rays) = shade_factor(to, from, &mut cx.st.rng, cx.hints, &mut cx.obs.queries());
        cx.st.rays.shadow += rays;
        (seen.s, seen.rays) = (s, rays);
        if s <= 0.0 {
            cx.obs.light(&seen);
            return None;
        }
        if let LightKind::Point { .. } = to.light.kind {
            cx.obs.point_light(to.index);
        }
        let m = &p.material;
        let highlight = match self.model.direct {
            Direct::Phong => {
                let l = (to.light.center() - p.point).normalize_or_zero();
                reflect(ray.dir, p.n).dot(l).powi(50)
            }
            _ => d.powi(20),
        };
        (seen.diffuse, seen.specular) = (m.diff * d * s, m.spec * highlight * s);
        cx.obs.light(&seen);
        Some(seen.diffuse + seen.specular)
    }

    /// lazycal's term of light `to` at `p`: the share of its grid that `p`
    /// sees (see [`grid_share`]) over the mean of the light's colour, times
    /// diff·L·N + spec·(H·N)^50 with L towards its centre and H halfway
    /// between L and the eye (each part at least 0); `None` where no point
    /// of the grid is seen.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn grid_light<O: PathObserver>(
        &self,
        ray: &Ray,
        p: &ShadingPoint,
        to: &ShadowRays,
        from: &ShadowFrom,
        half: u32,
        mut seen: LightSeen,
        cx: &mut PathContext<O>,
    ) -> Option<f64> {
        let (s, rays) = grid_share(to, from, half, p.n, cx.hints, &mut cx.obs.queries());
        cx.st.rays.shadow += rays;
        (seen.s, seen.rays) = (s, rays);
        let mean = power(to.light.color);
        if s <= 0.0 || mean <= 0.0 {
            cx.obs.light(&seen);
            return None;
        }
        let m = &p.material;
        let l = (to.light.center() - p.point).normalize_or_zero();
        let h = (l - ray.dir).normalize_or_zero();
        let scale = s / mean;
        seen.diffuse = m.diff * seen.l_dot_n.max(0.0) * scale;
        seen.specular = m.spec * h.dot(p.n).max(0.0).powi(50) * scale;
        cx.obs.light(&seen);
        Some(seen.diffuse + seen.specular)
    }
}
