//! PM's photon term at a diffuse hit: the map's K-nearest estimate.

use super::Whitted;
use super::surface::ShadingPoint;
use crate::geometry::Ray;
use crate::integrator::observer::PathObserver;
use crate::integrator::optics::reflect;
use crate::integrator::photons::{Brdf, PhotonMap};
use glam::DVec3;

impl Whitted<'_> {
    /// The photons of `map` gathered at `p` (hit by `ray`, albedo `k`),
    /// told to `obs`.
    #[inline(always)]
    pub(super) fn gather<O: PathObserver>(
        &self,
        map: &PhotonMap,
        ray: &Ray,
        p: &ShadingPoint,
        k: DVec3,
        obs: &mut O,
    ) -> DVec3 {
        let brdf = Brdf::of(
            self.photons.brdf,
            self.photons.specular,
            &p.material,
            reflect(ray.dir, p.n),
            p.side,
        );
        let gathered = map.estimate(p.point, p.side, &brdf);
        let term = k * gathered.value;
        obs.photons(&gathered, term);
        term
    }
}
