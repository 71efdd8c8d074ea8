//! What a camera sample carries down its tree of rays, and the
//! acceleration structure it queries.

use crate::accel::{Accel, Primitive};
use crate::geometry::Shape;
use crate::sampling::RandomSource;
use crate::scene::Object;
use rand::SeedableRng;
use rand_pcg::Pcg32;

/// The acceleration structure over a scene's objects.
pub(crate) type SceneAccel = Accel<Object>;

impl Primitive for Object {
    #[inline(always)]
    fn shape(&self) -> &Shape {
        Object::shape(self)
    }

    #[inline(always)]
    fn light(&self) -> Option<u32> {
        Object::light(self)
    }
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Primary rays.
    pub camera: u64,
    /// Mirror and glossy reflection rays.
    pub reflected: u64,
    /// Refraction (and total-internal-reflection) rays.
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
}

impl RayCounts {
    /// All rays together.
    pub fn total(&self) -> u64 {
        self.camera + self.reflected + self.refracted + self.shadow
    }

    /// Adds another tally to this one.
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
    }
}

/// The state one camera sample carries down its tree of rays.
pub(crate) struct PathState {
    /// The sample's own random stream.
    pub rng: Stream,
    /// Rays traced so far.
    pub rays: RayCounts,
}

impl PathState {
    /// A sample drawing from `rng`, no ray traced yet.
    pub fn new(rng: Stream) -> Self {
        PathState {
            rng,
            rays: RayCounts::default(),
        }
    }
}

/// A sample's random stream, `Pcg32::seed_from_u64(seed)`, seeded when
/// first drawn from: a sample that draws nothing (a pixel's centre lit by
/// point lights) never pays for the seeding.
#[derive(Clone, Debug)]
pub(crate) struct Stream {
    seed: u64,
    rng: Option<Pcg32>,
}

impl Stream {
    /// The stream of `seed`, not seeded yet.
    pub fn new(seed: u64) -> Self {
        Stream { seed, rng: None }
    }
}

impl RandomSource for Stream {
    /// The generator, seeded now if it was never asked for before.
    #[inline(always)]
    fn generator(&mut self) -> &mut Pcg32 {
        let seed = self.seed;
        self.rng.get_or_insert_with(|| Pcg32::seed_from_u64(seed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn a_stream_draws_as_its_generator_seeded_up_front() {
        for seed in [0, 1, 0x9e37_79b9_7f4a_7c15, u64::MAX] {
            let mut eager = Pcg32::seed_from_u64(seed);
            let mut lazy = Stream::new(seed);
            // Asked again before every draw: seeded once, never again.
            let expected: Vec<u64> = (0..40).map(|_| eager.random()).collect();
            let drawn: Vec<u64> = (0..40).map(|_| lazy.generator().random()).collect();
            assert_eq!(drawn, expected, "seed {seed}");
        }
    }
}
