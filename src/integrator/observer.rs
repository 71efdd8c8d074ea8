//! The path observer: what a renderer may watch along a camera sample's
//! tree of rays (the anti-aliasing's hash now, a pixel's ray tree next).
//! Shading is generic over it, so an observer that watches nothing costs
//! nothing.

use crate::scene::Origin;

/// Watches the rays of one camera sample.
pub(crate) trait PathObserver {
    /// The observer of the rays of a glossy fan.
    type Fan<'s>: PathObserver
    where
        Self: 's;

    /// The observer for the rays of a glossy reflection's fan.
    fn fan(&mut self) -> Self::Fan<'_>;

    /// A ray hit the surface of `origin` (a primitive block or a light).
    fn hit(&mut self, origin: Origin);

    /// A point of the path is lit by point light `light` (s > 0).
    fn point_light(&mut self, light: u32);
}

/// Watches nothing.
#[derive(Default)]
pub(crate) struct NoObserver;

impl PathObserver for NoObserver {
    type Fan<'s> = NoObserver;

    #[inline(always)]
    fn fan(&mut self) -> NoObserver {
        NoObserver
    }

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
