//! The photons' measure of power and the limits of their paths and gathers.

use crate::scene::Light;

/// The most hits a photon makes (`photon-mapping.md`, Tracing).
pub(crate) const MAX_PHOTON_HITS: u32 = 10;

/// Fewer photons than this in a gather give no estimate.
pub(crate) const MIN_GATHERED: usize = 8;

/// P(c): the mean of a colour's channels, the photons' measure of power.
#[inline]
pub(crate) fn power(c: glam::DVec3) -> f64 {
    (c.x + c.y + c.z) / 3.0
}

/// A light's weight in the share of the photons: its `power:` where the
/// file gives one (the colon family's), else P(c).
pub(crate) fn share(l: &Light) -> f64 {
    l.emission.power.unwrap_or_else(|| power(l.color))
}
