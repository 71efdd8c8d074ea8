//! What a ray that hits nothing sees.

use glam::DVec3;

/// What a ray that hits nothing sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// A uniform colour (`color=`).
    Color(DVec3),
    /// A vertical gradient (`top=` / `bottom=`) on the ray direction's z.
    Gradient {
        /// Colour looking straight up.
        top: DVec3,
        /// Colour looking straight down.
        bottom: DVec3,
    },
}

impl Background {
    /// The colour seen along the unit direction `d`.
    #[inline]
    pub fn color(&self, d: DVec3) -> DVec3 {
        match *self {
            Background::Color(c) => c,
            Background::Gradient { top, bottom } => {
                let t = (d.z + 1.0) * 0.5;
                bottom * (1.0 - t) + top * t
            }
        }
    }

    /// The colour of the lineages' ambient term (`color=`; the mean of a gradient's ends).
    pub fn ambient(&self) -> DVec3 {
        match *self {
            Background::Color(c) => c,
            Background::Gradient { top, bottom } => (top + bottom) * 0.5,
        }
    }
}
