//! Shadow rays: the fraction of a light that a point sees.

use super::path::SceneAccel;
use crate::geometry::{Ray, offset_origin};
use crate::scene::Light;
use glam::DVec3;
use rand::Rng;

/// Slots of [`ShadowHints`].
const HINT_SLOTS: usize = 8;

/// Per light (slot: its index modulo 8), the object that last
/// blocked a shadow ray towards it, tried first by the next one: shadow rays
/// from nearby points mostly meet the same blocker. A stale guess, or a slot
/// shared by two lights, costs one test; the answers never depend on it.
pub(crate) type ShadowHints = [Option<u32>; HINT_SLOTS];

/// Where shadow rays start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShadowFrom {
    /// A point on a surface.
    pub point: DVec3,
    /// The unit normal on the side the rays leave from (they start nudged along it).
    pub side: DVec3,
    /// The object whose surface it is, if any: its neighbours are tried first.
    pub object: Option<u32>,
}

/// The shade factor s in [0, 1]: the fraction of shadow rays from `from`
/// that reach light `index` (see [`Light::shade`]). Returns s and the
/// number of shadow rays traced; `hints` is read and updated.
#[inline(always)]
pub(crate) fn shade_factor(
    accel: &SceneAccel,
    light: &Light,
    index: u32,
    from: &ShadowFrom,
    samples: u32,
    rng: &mut impl Rng,
    hints: &mut ShadowHints,
) -> (f64, u64) {
    let origin = offset_origin(from.point, from.side);
    // Every shadow ray of this point starts here (same sliver); only its
    // direction changes.
    let start = Ray::off_surface(origin, DVec3::ZERO);
    let leaving = from.object;
    let blocker = &mut hints[index as usize % HINT_SLOTS];
    let bounds = light.bounds();
    // An area light's visible surface does not block its own rays.
    let own = bounds.map(|_| index);
    // An area light's rays all run from `origin` into its box: the parts of
    // the tree they may enter are found once.
    let reach = match bounds {
        Some((min, max)) if samples >= 2 => Some(accel.shadow_reach(origin, min, max, own)),
        _ => None,
    };
    light.shade(origin, samples, rng, |dir, t_max| {
        let ray = Ray { dir, ..start };
        !match &reach {
            Some(r) => accel.occluded_within(&ray, t_max, own, r, blocker),
            None => accel.occluded_hinted(&ray, t_max, own, leaving, blocker),
        }
    })
}
