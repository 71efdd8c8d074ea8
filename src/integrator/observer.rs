//! The path observer: what a renderer may watch along a camera sample's
//! tree of rays (the anti-aliasing's hash, a pixel's ray tree, the shading
//! passes' tally; two at once as a pair).
//! Shading is generic over it, so an observer that watches nothing costs
//! nothing.

use super::photons::Gathered;
use crate::accel::{QueryCost, QueryTally};
use crate::geometry::{Hit, Ray, Shape};
use crate::scene::{Material, Origin};
use glam::DVec3;

/// What a traced ray is, as its parent made it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    /// A ray from the camera through the image.
    Camera,
    /// A mirror reflection.
    Reflection,
    /// Ray `k` (from 1) of the `n` rays of a glossy reflection's fan.
    Glossy {
        /// Its place in the fan, from 1.
        k: u32,
        /// The rays of the fan.
        n: u32,
    },
    /// A refraction into or out of a transparent surface.
    Refraction,
    /// A refraction ray that Snell's law turned back (total internal reflection).
    TotalInternalReflection,
}

/// A surface a ray hit, as the shading code sees it.
pub(crate) struct SurfaceSeen<'a> {
    /// The block it came from.
    pub origin: Origin,
    /// Its shape.
    pub shape: &'a Shape,
    /// The ray that hit it.
    pub ray: &'a Ray,
    /// The hit.
    pub hit: &'a Hit,
    /// The material.
    pub material: &'a Material,
}

/// One light's term at a shaded point.
pub(crate) struct LightSeen {
    /// The light's index.
    pub light: u32,
    /// L·N (the term is zero unless it is positive).
    pub l_dot_n: f64,
    /// The shade factor (0 when not traced).
    pub s: f64,
    /// Shadow rays traced.
    pub rays: u64,
    /// The diffuse weight diff·(L·N)·s.
    pub diffuse: f64,
    /// The specular weight spec·(L·N)^20·s.
    pub specular: f64,
    /// The shaded point.
    pub point: DVec3,
    /// The unit normal on the side the shadow rays leave from.
    pub side: DVec3,
}

/// Watches the rays of one camera sample.
pub(crate) trait PathObserver {
    /// The observer of the rays of a glossy fan.
    type Fan<'s>: PathObserver
    where
        Self: 's;

    /// The observer for the rays of a glossy reflection's fan.
    fn fan(&mut self) -> Self::Fan<'_>;

    /// What counts the ray queries of the rays watched (`()`: nothing).
    type Queries<'q>: QueryTally
    where
        Self: 'q;

    /// Whether it counts the queries (then camera rays are queried one by
    /// one, not as packets, so that each is counted alone: the same answers).
    const COUNTS_QUERIES: bool = false;

    /// The tally of the query about to be made.
    fn queries(&mut self) -> Self::Queries<'_>;

    /// A ray hit the surface of `origin` (a primitive block or a light).
    fn hit(&mut self, origin: Origin);

    /// A point of the path is lit by point light `light` (s > 0).
    fn point_light(&mut self, light: u32);

    /// A ray of `kind` at `depth` is about to be traced.
    #[inline(always)]
    fn ray(&mut self, _kind: RayKind, _depth: u32, _ray: &Ray) {}

    /// The last ray begun hit a primitive's surface.
    #[inline(always)]
    fn surface(&mut self, _seen: &SurfaceSeen<'_>) {}

    /// The last ray begun hit area light `light`'s visible surface `shape`.
    #[inline(always)]
    fn emitter(&mut self, _light: u32, _shape: &Shape, _ray: &Ray, _hit: &Hit) {}

    /// A light's term at the last ray's hit.
    #[inline(always)]
    fn light(&mut self, _seen: &LightSeen) {}

    /// A child ray of `kind` was not traced: it would pass the depth limit.
    #[inline(always)]
    fn cut(&mut self, _kind: RayKind) {}

    /// The photon estimate at the last surface (PM): what it gathered and
    /// the term it adds.
    fn photons(&mut self, _gathered: &Gathered, _term: DVec3) {}

    /// The last ray's sum before the clamp to 1 per channel.
    #[inline(always)]
    fn shaded(&mut self, _sum: DVec3) {}

    /// The last ray begun ended with (clamped) `color`, weighted by `weight` in its parent.
    #[inline(always)]
    fn done(&mut self, _color: DVec3, _weight: DVec3) {}
}

/// A borrowed observer watches as its owner would.
impl<T: PathObserver> PathObserver for &mut T {
    type Fan<'s>
        = T::Fan<'s>
    where
        Self: 's;

    #[inline(always)]
    fn fan(&mut self) -> T::Fan<'_> {
        (**self).fan()
    }

    type Queries<'q>
        = T::Queries<'q>
    where
        Self: 'q;

    const COUNTS_QUERIES: bool = T::COUNTS_QUERIES;

    #[inline(always)]
    fn queries(&mut self) -> T::Queries<'_> {
        (**self).queries()
    }

    #[inline(always)]
    fn hit(&mut self, origin: Origin) {
        (**self).hit(origin)
    }

    #[inline(always)]
    fn point_light(&mut self, light: u32) {
        (**self).point_light(light)
    }

    #[inline(always)]
    fn ray(&mut self, kind: RayKind, depth: u32, ray: &Ray) {
        (**self).ray(kind, depth, ray)
    }

    #[inline(always)]
    fn surface(&mut self, seen: &SurfaceSeen<'_>) {
        (**self).surface(seen)
    }

    #[inline(always)]
    fn emitter(&mut self, light: u32, shape: &Shape, ray: &Ray, hit: &Hit) {
        (**self).emitter(light, shape, ray, hit)
    }

    #[inline(always)]
    fn light(&mut self, seen: &LightSeen) {
        (**self).light(seen)
    }

    #[inline(always)]
    fn cut(&mut self, kind: RayKind) {
        (**self).cut(kind)
    }

    #[inline(always)]
    fn photons(&mut self, gathered: &Gathered, term: DVec3) {
        (**self).photons(gathered, term)
    }

    #[inline(always)]
    fn shaded(&mut self, sum: DVec3) {
        (**self).shaded(sum)
    }

    #[inline(always)]
    fn done(&mut self, color: DVec3, weight: DVec3) {
        (**self).done(color, weight)
    }
}

/// Two observers watch the same rays, the first told first.
impl<A: PathObserver, B: PathObserver> PathObserver for (A, B) {
    type Fan<'s>
        = (A::Fan<'s>, B::Fan<'s>)
    where
        Self: 's;

    #[inline(always)]
    fn fan(&mut self) -> Self::Fan<'_> {
        (self.0.fan(), self.1.fan())
    }

    type Queries<'q>
        = (A::Queries<'q>, B::Queries<'q>)
    where
        Self: 'q;

    const COUNTS_QUERIES: bool = A::COUNTS_QUERIES || B::COUNTS_QUERIES;

    #[inline(always)]
    fn queries(&mut self) -> Self::Queries<'_> {
        (self.0.queries(), self.1.queries())
    }

    #[inline(always)]
    fn hit(&mut self, origin: Origin) {
        self.0.hit(origin);
        self.1.hit(origin);
    }

    #[inline(always)]
    fn point_light(&mut self, light: u32) {
        self.0.point_light(light);
        self.1.point_light(light);
    }

    #[inline(always)]
    fn ray(&mut self, kind: RayKind, depth: u32, ray: &Ray) {
        self.0.ray(kind, depth, ray);
        self.1.ray(kind, depth, ray);
    }

    #[inline(always)]
    fn surface(&mut self, seen: &SurfaceSeen<'_>) {
        self.0.surface(seen);
        self.1.surface(seen);
    }

    #[inline(always)]
    fn emitter(&mut self, light: u32, shape: &Shape, ray: &Ray, hit: &Hit) {
        self.0.emitter(light, shape, ray, hit);
        self.1.emitter(light, shape, ray, hit);
    }

    #[inline(always)]
    fn light(&mut self, seen: &LightSeen) {
        self.0.light(seen);
        self.1.light(seen);
    }

    #[inline(always)]
    fn cut(&mut self, kind: RayKind) {
        self.0.cut(kind);
        self.1.cut(kind);
    }

    #[inline(always)]
    fn photons(&mut self, gathered: &Gathered, term: DVec3) {
        self.0.photons(gathered, term);
        self.1.photons(gathered, term);
    }

    #[inline(always)]
    fn shaded(&mut self, sum: DVec3) {
        self.0.shaded(sum);
        self.1.shaded(sum);
    }

    #[inline(always)]
    fn done(&mut self, color: DVec3, weight: DVec3) {
        self.0.done(color, weight);
        self.1.done(color, weight);
    }
}

/// Watches nothing.
#[derive(Clone, Copy, Default)]
pub(crate) struct NoObserver;

impl PathObserver for NoObserver {
    type Fan<'s> = NoObserver;

    #[inline(always)]
    fn fan(&mut self) -> NoObserver {
        NoObserver
    }

    type Queries<'q> = ();

    #[inline(always)]
    fn queries(&mut self) {}

    #[inline(always)]
    fn hit(&mut self, _: Origin) {}

    #[inline(always)]
    fn point_light(&mut self, _: u32) {}
}

/// The framework's anti-aliasing hash: a sum over what the sample's
/// mirror and refraction chain hits and the point lights that light it
/// (glossy fans are not counted). Neighbouring pixels with different
/// hashes are anti-aliased.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct AaHash(pub u64);

impl PathObserver for AaHash {
    type Fan<'s> = NoObserver;

    #[inline(always)]
    fn fan(&mut self) -> NoObserver {
        NoObserver
    }

    type Queries<'q> = ();

    #[inline(always)]
    fn queries(&mut self) {}

    #[inline(always)]
    fn hit(&mut self, origin: Origin) {
        self.0 = self.0.wrapping_add(object_id(origin));
    }

    #[inline(always)]
    fn point_light(&mut self, light: u32) {
        self.0 = self
            .0
            .wrapping_add(mix(light as u64 + 1) ^ 0x9e37_79b9_7f4a_7c15);
    }
}

/// The `cost` pass's observer: counts every query of every ray of the
/// sample, glossy fans included.
impl PathObserver for QueryCost {
    type Fan<'s> = &'s mut QueryCost;

    #[inline(always)]
    fn fan(&mut self) -> &mut QueryCost {
        self
    }

    type Queries<'q> = &'q mut QueryCost;

    const COUNTS_QUERIES: bool = true;

    #[inline(always)]
    fn queries(&mut self) -> &mut QueryCost {
        self
    }

    #[inline(always)]
    fn hit(&mut self, _: Origin) {}

    #[inline(always)]
    fn point_light(&mut self, _: u32) {}
}

impl AaHash {
    /// The hash folded to the 32 bits a pixel keeps.
    #[inline]
    pub fn folded(self) -> u32 {
        (self.0 ^ (self.0 >> 32)) as u32
    }
}

/// What an object adds to a pixel's hash: a value per block and per area
/// light (computed on the spot: a table of them would cost a cache miss per
/// hit in a large scene).
#[inline]
fn object_id(origin: Origin) -> u64 {
    match origin {
        Origin::Block(b) => mix(b as u64 + 1),
        Origin::Light(l) => mix((l as u64 + 1) << 32),
    }
}

/// A 64-bit mix (splitmix64's finaliser).
#[inline]
pub(crate) fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
