//! Shadow rays: the fraction of a light that a point sees.

use super::path::SceneAccel;
use crate::accel::{QueryTally, ShadowReach};
use crate::geometry::{Ray, offset_origin};
use crate::sampling::RandomSource;
use crate::scene::Light;
use glam::DVec3;

/// Slots of [`ShadowHints`].
const HINT_SLOTS: usize = 8;

/// Per light (slot: its index modulo 8), the object that blocked the last
/// shadow ray towards it (none if that ray got through), tried first by the
/// next one: shadow rays from nearby points mostly meet the same blocker, or
/// none. A stale guess, or a slot shared by two lights, costs one test; the
/// answers never depend on it.
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

/// The shadow rays of a shading point towards one light: the light,
/// its index, how many rays, and the structure they query.
pub(crate) struct ShadowRays<'a> {
    /// The structure the rays query.
    pub accel: &'a SceneAccel,
    /// The light they go to.
    pub light: &'a Light,
    /// Its index in the scene.
    pub index: u32,
    /// How many an area light takes.
    pub samples: u32,
}

/// The shade factor s in [0, 1]: the fraction of the shadow rays `to`
/// from `from` that reach their light (see [`Light::shade`]). Returns s
/// and the number of shadow rays traced; `hints` is read and updated, and
/// the queries are counted into `tally`.
#[inline(always)]
pub(crate) fn shade_factor(
    to: &ShadowRays,
    from: &ShadowFrom,
    rng: &mut impl RandomSource,
    hints: &mut ShadowHints,
    tally: &mut impl QueryTally,
) -> (f64, u64) {
    let mut shadow = Shadow::new(to, from, hints, tally);
    to.light.shade(shadow.origin, to.samples, rng, |dir, t| {
        shadow.reaches(dir, t)
    })
}

/// The mean of `weight(unit direction, distance)` over the shadow rays `to`
/// from `from` that reach their light (see [`Light::shade_weighted`]),
/// and the number of shadow rays traced.
#[inline(always)]
pub(crate) fn weighted_light(
    to: &ShadowRays,
    from: &ShadowFrom,
    rng: &mut impl RandomSource,
    hints: &mut ShadowHints,
    tally: &mut impl QueryTally,
    weight: impl FnMut(DVec3, f64) -> f64,
) -> (f64, u64) {
    let mut shadow = Shadow::new(to, from, hints, tally);
    to.light.shade_weighted(
        shadow.origin,
        to.samples,
        rng,
        |dir, t| shadow.reaches(dir, t),
        weight,
    )
}

/// lazycal's share of light `to` that `from` sees: the points of its fixed
/// grid of (2·`half` + 1)² (see [`Light::for_each_grid_point`]) in front
/// of the surface (their offset from the point has a dot product with
/// `normal` above 10⁻⁵, as lazycal tests it) that a shadow ray reaches,
/// over all the points. Returns the share and the number of shadow rays.
#[inline(always)]
pub(crate) fn grid_share(
    to: &ShadowRays,
    from: &ShadowFrom,
    half: u32,
    normal: DVec3,
    hints: &mut ShadowHints,
    tally: &mut impl QueryTally,
) -> (f64, u64) {
    let mut shadow = Shadow::new(to, from, hints, tally);
    let (mut seen, mut rays) = (0u32, 0u64);
    let n = to.light.for_each_grid_point(from.point, half, |dir, dist| {
        if dist * dir.dot(normal) > 1e-5 {
            rays += 1;
            if shadow.reaches(dir, dist) {
                seen += 1;
            }
        }
    });
    (f64::from(seen) / f64::from(n.max(1)), rays)
}

/// The shadow rays of one shading point towards one light, their queries
/// counted into a `T`.
struct Shadow<'a, T> {
    accel: &'a SceneAccel,
    /// Where they start (nudged off the surface).
    origin: DVec3,
    start: Ray,
    /// The surface they leave (its neighbours are tried first).
    leaving: Option<u32>,
    /// The light's own surface, which does not block its rays.
    own: Option<u32>,
    /// The parts of the tree rays into an area light's box may enter.
    reach: Option<ShadowReach>,
    blocker: &'a mut Option<u32>,
    tally: &'a mut T,
}

impl<'a, T: QueryTally> Shadow<'a, T> {
    #[inline(always)]
    fn new(
        to: &ShadowRays<'a>,
        from: &ShadowFrom,
        hints: &'a mut ShadowHints,
        tally: &'a mut T,
    ) -> Self {
        let ShadowRays {
            accel,
            light,
            index,
            samples,
        } = *to;
        let origin = offset_origin(from.point, from.side);
        let bounds = light.bounds();
        let own = bounds.map(|_| index);
        // An area light's rays all run from `origin` into its box: the parts of
        // the tree they may enter are found once.
        let reach = match bounds {
            Some((min, max)) if samples >= 2 => Some(accel.shadow_reach(origin, min, max, own)),
            _ => None,
        };
        Shadow {
            accel,
            origin,
            // Every shadow ray of this point starts here (same sliver); only
            // its direction changes.
            start: Ray::off_surface(origin, DVec3::ZERO),
            leaving: from.object,
            own,
            reach,
            blocker: &mut hints[index as usize % HINT_SLOTS],
            tally,
        }
    }

    /// Whether the ray in direction `dir` reaches the light `t_max` away.
    #[inline(always)]
    fn reaches(&mut self, dir: DVec3, t_max: f64) -> bool {
        let ray = Ray { dir, ..self.start };
        let (own, tally) = (self.own, &mut *self.tally);
        !match &self.reach {
            Some(r) => self
                .accel
                .occluded_within(&ray, t_max, own, r, self.blocker, tally),
            None => self
                .accel
                .occluded_hinted(&ray, t_max, own, self.leaving, self.blocker, tally),
        }
    }
}
