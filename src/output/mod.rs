//! Writing what a render made to files: the picture in the format its
//! extension names (`picture`), the AOVs beside it as EXR layers or images
//! of their own (`layers`), each written atomically (`atomic`).

mod atomic;
mod layers;
mod picture;

pub(crate) use atomic::write_atomically;
pub use layers::{
    PrimitiveTable, aov_path, primitive_colour, save_aov_images, save_exr_layers, save_film,
};
pub(crate) use layers::{aov_picture, hit_mask};
pub use picture::{Format, SaveError, encode_rgb8};
