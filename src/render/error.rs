//! Why a render did not produce a film.

use super::film::Region;
use super::photons;
use super::tile::Tile;
use crate::scene::MAX_IMAGE_SIDE;

/// Why a render did not produce a film.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    /// An image side outside 1 to [`MAX_IMAGE_SIDE`] pixels.
    #[error("{name} {value} is out of range: an image side must be 1 to {MAX_IMAGE_SIDE} pixels")]
    Side {
        /// `width` or `height`.
        name: &'static str,
        /// The value asked for.
        value: u32,
    },
    /// A region that is empty or not inside the frame.
    #[error(
        "the region {}x{} at ({}, {}) is not inside the {frame_w}x{frame_h} frame",
        region.width, region.height, region.x, region.y
    )]
    Region {
        /// The region asked for.
        region: Region,
        /// The frame's width.
        frame_w: u32,
        /// The frame's height.
        frame_h: u32,
    },
    /// A pixel outside the frame.
    #[error("the pixel ({x}, {y}) is not inside the {frame_w}x{frame_h} frame")]
    Pixel {
        /// Its column.
        x: u32,
        /// Its row (from the top).
        y: u32,
        /// The frame's width.
        frame_w: u32,
        /// The frame's height.
        frame_h: u32,
    },
    /// More samples per pixel than `explain` keeps trees of.
    #[error("spp {value} is too many to explain: every sample's tree is kept, at most {max}")]
    Samples {
        /// The samples asked for.
        value: u32,
        /// The most `explain` takes.
        max: u32,
    },
    /// More `light:N` AOVs than one render takes.
    #[error("{asked} light:N AOVs asked for: one render takes at most {max}")]
    LightAovs {
        /// The `light:N` AOVs asked for.
        asked: usize,
        /// The most one render takes.
        max: usize,
    },
    /// A render of one part asked for as a whole film.
    #[error("part {tile} of a render is rendered to its bands (render_parts), not a film")]
    Parts {
        /// The part.
        tile: Tile,
    },
    /// The cancel flag was set.
    #[error("the render was cancelled")]
    Cancelled,
    /// More PPM hit points than the camera's `max_hitpoints=` allows.
    #[error(
        "the eye pass found more than `max_hitpoints= {max}` hit points: raise it in the camera block, or render smaller"
    )]
    HitPoints {
        /// The key's value.
        max: u64,
    },
}

impl From<photons::Unfinished> for RenderError {
    fn from(e: photons::Unfinished) -> Self {
        match e {
            photons::Unfinished::Cancelled => RenderError::Cancelled,
            photons::Unfinished::HitPoints { max } => RenderError::HitPoints { max },
        }
    }
}
