//! Surface appearance: textures and light sampling.

mod light;
mod texture;

pub use light::{ShadowFrom, ShadowHints, shade_factor};
pub use light::{perpendiculars, strata};
pub use texture::Texture;
