//! What a render is asked for ([`RenderOptions`]) and how it reports and
//! stops as it goes ([`Control`]).

use super::aov::Aov;
use super::film::{Film, Region};
use super::tile::Tile;
use crate::integrator::photons::PhotonOptions;
use std::sync::atomic::AtomicBool;

/// How to render.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RenderOptions {
    /// Worker threads, at most [`MAX_THREADS`](super::MAX_THREADS) (`None`, or a pool the
    /// system refuses to start: one per core). The image is the same either way.
    pub threads: Option<usize>,
    /// Seed of every random stream.
    pub seed: u64,
    /// Stratified samples per pixel; `None` for the framework's adaptive
    /// anti-aliasing (one ray, 7×7 where neighbours differ).
    pub spp: Option<u32>,
    /// Image width, overriding the camera's `image_W=`; given alone, the
    /// height follows the camera's aspect. The lens is kept as the scene sets it.
    pub width: Option<u32>,
    /// Image height, overriding the camera's `image_H=` (see `width`).
    pub height: Option<u32>,
    /// The part of the frame to render (`None`: all of it). Its pixels are
    /// the same bytes as those pixels of the whole render.
    pub region: Option<Region>,
    /// Passes to store as planes of the film beside the colour, named as
    /// [`Aov::name`] says (the picture is the same with or without them).
    pub aovs: Vec<Aov>,
    /// Photon mapping as the command line overrides it.
    pub photons: PhotonOptions,
    /// One part of the render, for [`Renderer::render_parts`](super::Renderer::render_parts)
    /// (`None`: all of it).
    pub tile: Option<Tile>,
}

/// What PPM and SPPM hand the picture so far to: (iteration, film).
pub type Checkpoint<'c> = &'c (dyn Fn(u64, &Film) + Sync);

/// What a render tells as it goes, and how to stop it.
#[derive(Clone, Copy, Default)]
pub struct Control<'c> {
    /// Called with (done, total), in units of camera rays, as rows finish.
    pub progress: Option<&'c (dyn Fn(u64, u64) + Sync)>,
    /// Stops the render at once when another thread sets it (PPM and SPPM:
    /// after the last complete iteration, whose picture is the result).
    pub cancel: Option<&'c AtomicBool>,
    /// PPM and SPPM: given (iteration, film) every `checkpoint_every` iterations.
    pub checkpoint: Option<Checkpoint<'c>>,
    /// How many iterations apart checkpoints are (0: 10).
    pub checkpoint_every: u64,
}

/// Which image of a progressive render a callback is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The preview: a cheaper render shown first.
    Coarse,
    /// The render the options ask for.
    Final,
}
