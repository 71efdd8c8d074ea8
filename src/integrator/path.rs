//! What a camera sample carries down its tree of rays, and the
//! acceleration structure it queries.

use crate::accel::{Accel, Primitive};
use crate::geometry::Shape;
use crate::scene::Object;
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
    pub rng: Pcg32,
    /// Rays traced so far.
    pub rays: RayCounts,
}

impl PathState {
    /// A sample drawing from `rng`, no ray traced yet.
    pub fn new(rng: Pcg32) -> Self {
        PathState {
            rng,
            rays: RayCounts::default(),
        }
    }
}
