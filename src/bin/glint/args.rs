//! The argument groups and value parsers several subcommands share.

use clap::Args;
use glint::{Dialect, MAX_THREADS, PhotonFilter, PhotonMode, PhotonOptions, RenderOptions};

/// What decides a picture's pixels beside the scene: its size, samples and seed.
#[derive(Args)]
pub struct PixelArgs {
    /// Image width in pixels, overriding the scene's image_W= (the lens stays as the scene sets it).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels, overriding the scene's image_H=.
    #[arg(long)]
    height: Option<u32>,
    /// Seed of the random streams (same scene and seed: same bytes, whatever the threads).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Stratified samples per pixel instead of the framework's adaptive anti-aliasing
    /// (at least 1; 1: exactly one ray through each pixel's centre).
    #[arg(long, value_parser = at_least_one::<u32>)]
    spp: Option<u32>,
}

impl PixelArgs {
    /// The render options they set, the rest as `base` has them.
    pub fn apply(&self, base: RenderOptions) -> RenderOptions {
        RenderOptions {
            width: self.width,
            height: self.height,
            seed: self.seed,
            spp: self.spp,
            ..base
        }
    }
}

/// The photon options of `render` and `explain`.
#[derive(Args)]
pub struct PhotonArgs {
    /// Photon mapping: pm, ppm, sppm or off [default: as the file's dialect and `algorithm=` say]
    #[arg(long)]
    photons: Option<PhotonMode>,
    /// PPM and SPPM iterations, overriding the camera's `iterations=` (at least 1).
    #[arg(long, value_parser = at_least_one::<u64>)]
    iterations: Option<u64>,
    /// Photons emitted per pass, overriding the camera's `emit_photons=` (at least 1).
    #[arg(long, value_parser = at_least_one::<u64>)]
    emit: Option<u64>,
    /// How gathered photons are weighted by distance: box or cone (Jensen's).
    #[arg(long, default_value_t)]
    photon_filter: PhotonFilter,
}

impl PhotonArgs {
    /// The library's photon options they set.
    pub fn options(&self) -> PhotonOptions {
        PhotonOptions {
            mode: self.photons,
            iterations: self.iterations,
            emit: self.emit,
            filter: self.photon_filter,
        }
    }
}

/// `--dialect`, shared by every command that reads a scene.
#[derive(Args)]
pub struct DialectArg {
    /// The lineage whose renderer's model draws the file: f, z14, pm3, v or w
    /// (or a repository's name) [default: chosen by the file's markers]
    #[arg(long)]
    pub dialect: Option<Dialect>,
}

/// Parses a whole number that must be at least 1 (`--spp`, `--threads`);
/// clap reports a refusal as an argument error with exit code 2.
pub fn at_least_one<T>(s: &str) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + From<u8>,
    T::Err: std::fmt::Display,
{
    let n: T = s.trim().parse().map_err(|e| format!("{e}"))?;
    if n < T::from(1) {
        return Err("must be at least 1".to_string());
    }
    Ok(n)
}

/// Parses `--threads`: 1 to [`MAX_THREADS`].
pub fn thread_count(s: &str) -> Result<usize, String> {
    let n = at_least_one::<usize>(s)?;
    if n > MAX_THREADS {
        return Err(format!("must be at most {MAX_THREADS}"));
    }
    Ok(n)
}
