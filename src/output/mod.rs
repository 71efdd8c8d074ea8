//! Writing what a render made to files: the picture in the format its
//! extension names (`picture`), the AOVs beside it as EXR layers or images
//! of their own (`layers`), each written atomically (`atomic`).

mod atomic;
mod layers;
mod picture;

pub use layers::{PrimitiveTable, pass_path, primitive_colour, save_exr_layers, save_pass_images};
pub(crate) use layers::{hit_mask, pass_image};
pub use picture::{Format, SaveError, encode_rgb8};
