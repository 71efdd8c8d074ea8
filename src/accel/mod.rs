//! Ray queries over all of a scene's objects: nearest hit and any hit.
//!
//! Bounded objects sit in a bounding volume hierarchy (binned SAH, collapsed
//! to four children a node, f32 boxes rounded outward so no hit is lost,
//! a node's four tested together); unbounded ones
//! (planes), and any whose bounds are not finite or beyond 1e30, are tested
//! one by one. Queries come one ray at a time, as packets of coherent rays
//! (a tile's camera rays), or, for a ray leaving a surface, as a walk up
//! the tree from that surface's leaf; the shadow rays of one point towards
//! an area light walk only the subtrees within their reach, found once.
//! Answers are exactly those of testing every object in index order: same
//! object, same hit.

mod build;
mod bvh;
mod collapse;
mod hull;
mod isa;
mod node;
mod packet;
mod ray_box;
mod tally;
#[cfg(test)]
mod tests;
mod walk;

use crate::geometry::{Hit, Ray, Shape};
use build::PARALLEL_MIN;
use bvh::Bvh;
use glam::DVec3;
use hull::Hull;
pub use isa::Isa;
use node::Item;
use rayon::prelude::*;
pub use tally::{QueryCost, QueryTally};

/// Rays in one packet at most (longer slices are split).
pub const PACKET_MAX: usize = 64;

/// Subtrees [`Accel::shadow_reach`] keeps at most.
const REACH: usize = 16;

/// The parts of the tree a point's shadow rays towards one area light may
/// enter.
#[derive(Clone, Copy, Debug)]
pub struct ShadowReach {
    roots: [u32; REACH],
    len: usize,
}

/// Which part of the tree an any-hit query walks.
enum Walk<'r> {
    /// All of it, up from the leaf of this object when it is known.
    Up(Option<u32>),
    /// These subtrees alone.
    Within(&'r [u32]),
}

/// What the structure holds: a shape, and whether it is the visible
/// surface of a light (shadow rays towards that light ignore it).
pub trait Primitive {
    /// The geometry.
    fn shape(&self) -> &Shape;
    /// The light whose visible surface this is, if any.
    fn light(&self) -> Option<u32>;
}

/// A bare shape, for the micro-benchmarks: never a light's surface.
#[cfg(feature = "bench")]
impl Primitive for Shape {
    fn shape(&self) -> &Shape {
        self
    }

    fn light(&self) -> Option<u32> {
        None
    }
}

/// Answers ray queries over the objects it owns.
pub struct Accel<P> {
    objects: Vec<P>,
    bvh: Bvh,
    /// Objects kept out of the tree (planes), tested against every ray.
    unbounded: Vec<u32>,
    /// The instruction set the queries run in.
    isa: Isa,
}

impl<P: Primitive> Accel<P> {
    /// Builds the structure over `objects` (indices into it are returned by queries).
    pub fn build(objects: Vec<P>) -> Self
    where
        P: Sync,
    {
        // In parallel into one exact allocation (an indexed collect writes
        // in place: no temporary pieces to stay resident and raise the
        // peak), the objects left out marked, then dropped in place.
        let mut items = Vec::new();
        objects
            .par_iter()
            .with_min_len(PARALLEL_MIN)
            .enumerate()
            .map(|(i, o)| {
                let item = o.shape().bounds().and_then(|b| Item::new(i as u32, &b));
                item.unwrap_or(Item::LEFT_OUT)
            })
            .collect_into_vec(&mut items);
        items.retain(|it| !it.left_out());
        // The objects left out, in order: the gaps between the items' indices.
        let mut unbounded = Vec::new();
        let mut next = 0;
        for index in items.iter().map(Item::index).chain([objects.len() as u32]) {
            unbounded.extend(next..index);
            next = index + 1;
        }
        let bvh = Bvh::build(items, objects.len());
        Accel {
            objects,
            bvh,
            unbounded,
            isa: Isa::chosen(),
        }
    }

    /// The same structure, its queries run in `isa` (the same answers).
    #[cfg(test)]
    pub fn with_isa(self, isa: Isa) -> Self {
        Accel { isa, ..self }
    }

    /// The objects the queries run over.
    pub fn objects(&self) -> &[P] {
        &self.objects
    }

    /// The nearest hit with `ray.t_min` < t < `t_max`: the object's index and the hit.
    /// Of hits at the same distance, the lowest index wins.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<(u32, Hit)> {
        self.intersect_tallied(ray, t_max, &mut ())
    }

    /// [`Accel::intersect`], its nodes and tests counted into `tally`.
    #[inline]
    pub fn intersect_tallied(
        &self,
        ray: &Ray,
        t_max: f64,
        tally: &mut impl QueryTally,
    ) -> Option<(u32, Hit)> {
        let mut best: Option<(u32, Hit)> = None;
        let mut t_best = t_max;
        tally.tests(self.unbounded.len());
        for &i in &self.unbounded {
            self.test::<true>(i, ray, &mut best, &mut t_best);
        }
        self.bvh.traverse::<true>(
            None,
            ray,
            &mut t_best,
            self.isa,
            tally,
            #[inline(always)]
            |prims, t_best| {
                for &i in prims {
                    self.test::<false>(i, ray, &mut best, t_best);
                }
                (false, prims.len())
            },
        );
        best
    }

    /// Tests object `i` against `ray`, keeping in `best` (at `t_best`) the
    /// nearer hit; of two at the same distance the lower index wins, so the
    /// answer does not depend on the order objects are tested in.
    /// `UNBOUNDED`: as for [`Accel::hit`].
    #[inline(always)]
    fn test<const UNBOUNDED: bool>(
        &self,
        i: u32,
        ray: &Ray,
        best: &mut Option<(u32, Hit)>,
        t_best: &mut f64,
    ) {
        let limit = match *best {
            // A hit's t lies in (t_min, t_max) with t_min ≥ 0: positive
            // and finite, so its next float up is the next bit pattern
            // (what `next_up` gives, without its branches for the rest).
            Some((b, _)) if i < b => {
                debug_assert!(*t_best > 0.0 && t_best.is_finite());
                f64::from_bits(t_best.to_bits() + 1)
            }
            _ => *t_best,
        };
        if let Some(h) = self.hit::<UNBOUNDED>(i, ray, limit) {
            *t_best = h.t;
            *best = Some((i, h));
        }
    }

    /// Whether anything lies on the ray with `ray.t_min` < t < `t_max`, not counting
    /// the visible surface of light `ignore_light`.
    #[cfg(any(test, feature = "bench"))]
    pub fn occluded(&self, ray: &Ray, t_max: f64, ignore_light: Option<u32>) -> bool {
        self.occluded_hinted(ray, t_max, ignore_light, None, &mut None, &mut ())
    }

    /// [`Accel::occluded`] for a ray leaving the surface of object `from`
    /// (if known), whose neighbours are tried first, and trying the object
    /// in `hint` before all, leaving in it the blocker found, or none if the
    /// ray gets through. Its nodes and tests are counted into `tally`.
    pub fn occluded_hinted(
        &self,
        ray: &Ray,
        t_max: f64,
        ignore_light: Option<u32>,
        from: Option<u32>,
        hint: &mut Option<u32>,
        tally: &mut impl QueryTally,
    ) -> bool {
        self.any_hit(ray, t_max, ignore_light, Walk::Up(from), hint, tally)
    }

    /// The subtrees that the shadow rays from `origin` to points of the box
    /// [`min`, `max`] (an area light's) may enter, found once for all of
    /// them: those that meet the hull of the two, as small as
    /// [`ShadowReach`] has room for (leaves holding only light
    /// `ignore_light`'s own surface left out).
    pub fn shadow_reach(
        &self,
        origin: DVec3,
        min: DVec3,
        max: DVec3,
        ignore_light: Option<u32>,
    ) -> ShadowReach {
        let mut roots = [0; REACH];
        let own = |prims: &[u32]| prims.iter().all(|&i| self.lights_own(i, ignore_light));
        let len = self
            .bvh
            .reach(&Hull::new(origin, min, max), &mut roots, own);
        ShadowReach { roots, len }
    }

    /// [`Accel::occluded_hinted`] for a ray from the origin given to
    /// [`Accel::shadow_reach`] that ends (at `t_max`) in its box, walking
    /// only the subtrees of `reach`: the same answer, the rest of the tree
    /// being out of the ray's reach. Its nodes and tests are counted into `tally`.
    pub fn occluded_within(
        &self,
        ray: &Ray,
        t_max: f64,
        ignore_light: Option<u32>,
        reach: &ShadowReach,
        hint: &mut Option<u32>,
        tally: &mut impl QueryTally,
    ) -> bool {
        let roots = &reach.roots[..reach.len];
        self.any_hit(ray, t_max, ignore_light, Walk::Within(roots), hint, tally)
    }

    /// The any-hit query of [`Accel::occluded_hinted`] and
    /// [`Accel::occluded_within`]: the hint, the unbounded objects, then
    /// the tree as `walk` says.
    #[inline(always)]
    fn any_hit(
        &self,
        ray: &Ray,
        t_max: f64,
        ignore_light: Option<u32>,
        walk: Walk,
        hint: &mut Option<u32>,
        tally: &mut impl QueryTally,
    ) -> bool {
        if let Some(i) = *hint {
            tally.tests(1);
            if self.blocks::<false>(i, ray, t_max, ignore_light) {
                return true;
            }
        }
        // The unbounded ones in order, up to the first that blocks.
        let found = self.first_blocker::<true>(&self.unbounded, ray, t_max, ignore_light);
        tally.tests(found.map_or(self.unbounded.len(), |k| k + 1));
        if let Some(k) = found {
            *hint = Some(self.unbounded[k]);
            return true;
        }
        let mut blocker = None;
        let mut t_best = t_max;
        // A block only so the closure may carry `#[inline(always)]`.
        let leaf = {
            #[inline(always)]
            |prims: &[u32], _: &mut f64| {
                let k = self.first_blocker::<false>(prims, ray, t_max, ignore_light);
                blocker = k.map(|k| prims[k]);
                (blocker.is_some(), k.map_or(prims.len(), |k| k + 1))
            }
        };
        match walk {
            Walk::Up(from) => {
                self.bvh
                    .traverse::<false>(from, ray, &mut t_best, self.isa, tally, leaf)
            }
            Walk::Within(roots) => {
                self.bvh
                    .traverse_within::<false>(roots, ray, &mut t_best, self.isa, tally, leaf)
            }
        }
        // A ray that gets through forgets the guess: the rays after it
        // (mostly its neighbours) get through too, and would each pay a test.
        *hint = blocker;
        blocker.is_some()
    }

    /// The place in `objects` of the first that [`Accel::blocks`] the ray.
    /// (A loop, not `position`: its closure was left out of line.)
    #[inline(always)]
    fn first_blocker<const UNBOUNDED: bool>(
        &self,
        objects: &[u32],
        ray: &Ray,
        t_max: f64,
        ignore_light: Option<u32>,
    ) -> Option<usize> {
        for (k, &i) in objects.iter().enumerate() {
            if self.blocks::<UNBOUNDED>(i, ray, t_max, ignore_light) {
                return Some(k);
            }
        }
        None
    }

    /// Whether object `i` lies on the ray with `ray.t_min` < t < `t_max`
    /// and is not the visible surface of light `ignore_light` (`UNBOUNDED`:
    /// as for [`Accel::hit`]).
    #[inline(always)]
    fn blocks<const UNBOUNDED: bool>(
        &self,
        i: u32,
        ray: &Ray,
        t_max: f64,
        ignore_light: Option<u32>,
    ) -> bool {
        if self.lights_own(i, ignore_light) {
            return false;
        }
        if UNBOUNDED {
            self.hit::<true>(i, ray, t_max).is_some()
        } else {
            let shape = self.objects[i as usize].shape();
            shape.blocks_bounded(ray, ray.t_min, t_max)
        }
    }

    /// Object `i`'s hit by `ray` with `ray.t_min` < t < `t_max`. The
    /// commonest kinds' tests are inlined here, where a call would cost as
    /// much as the test: a plane's for `UNBOUNDED` (the loops over the
    /// unbounded objects, which every query tests), else a sphere's (any
    /// object: the others' tests are called).
    #[inline(always)]
    fn hit<const UNBOUNDED: bool>(&self, i: u32, ray: &Ray, t_max: f64) -> Option<Hit> {
        let shape = self.objects[i as usize].shape();
        if UNBOUNDED {
            shape.intersect_unbounded(ray, ray.t_min, t_max)
        } else {
            shape.intersect_bounded(ray, ray.t_min, t_max)
        }
    }

    /// Whether object `i` is the visible surface of light `light` (never,
    /// for `None`).
    #[inline(always)]
    fn lights_own(&self, i: u32, light: Option<u32>) -> bool {
        light.is_some() && self.objects[i as usize].light() == light
    }

    /// Nodes in the hierarchy (for statistics).
    #[cfg(feature = "bench")]
    pub fn node_count(&self) -> usize {
        self.bvh.node_count()
    }

    /// Bytes the structure holds beyond the objects themselves.
    #[cfg(feature = "bench")]
    pub fn memory_bytes(&self) -> usize {
        size_of::<Self>() + self.bvh.heap_bytes() + self.unbounded.capacity() * size_of::<u32>()
    }
}
