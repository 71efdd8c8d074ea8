//! The argument groups and value parsers several subcommands share.

use clap::Args;
use glint::{
    Aov, Dialect, MAX_THREADS, PhotonFilter, PhotonMode, PhotonOptions, Region, RenderOptions,
};

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

    /// The arguments that set them again, those left at their defaults left out.
    pub fn to_args(&self) -> Vec<String> {
        let mut args = Vec::new();
        push(&mut args, "--width", self.width);
        push(&mut args, "--height", self.height);
        push(&mut args, "--seed", Some(self.seed).filter(|&s| s != 0));
        push(&mut args, "--spp", self.spp);
        args
    }
}

/// What of the picture a render makes beside its colour: a region of it, and AOVs.
#[derive(Args)]
pub struct PictureArgs {
    /// AOVs (arbitrary output values) to write beside the picture,
    /// comma-separated: normal, depth, position, uv, primitive, albedo, rays,
    /// light:N, shade, why, clamp, cost, photons (layers of an .exr; else
    /// OUT.AOV.EXT files).
    #[arg(long)]
    aov: Option<String>,
    /// Render only columns X0..X1 and rows Y0..Y1 (ends excluded, rows from
    /// the top): `X0,Y0,X1,Y1`; its pixels are those of the whole render.
    #[arg(long)]
    region: Option<Region>,
}

impl PictureArgs {
    /// The AOVs asked for (none without `--aov`), or why the list is wrong.
    pub fn aovs(&self) -> Result<Vec<Aov>, String> {
        match &self.aov {
            Some(list) => Aov::parse_list(list).map_err(|e| format!("--aov: {e}")),
            None => Ok(Vec::new()),
        }
    }

    /// The region asked for, if any.
    pub fn region(&self) -> Option<Region> {
        self.region
    }

    /// The arguments that set them again (`--aov` as it was given).
    pub fn to_args(&self) -> Vec<String> {
        let mut args = Vec::new();
        push(&mut args, "--aov", self.aov.as_deref());
        let region = self
            .region
            .map(|r| format!("{},{},{},{}", r.x, r.y, r.x + r.width, r.y + r.height));
        push(&mut args, "--region", region);
        args
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

    /// The arguments that set them again, those left at their defaults left out.
    pub fn to_args(&self) -> Vec<String> {
        let mut args = Vec::new();
        push(&mut args, "--photons", self.photons.map(PhotonMode::name));
        push(&mut args, "--iterations", self.iterations);
        push(&mut args, "--emit", self.emit);
        let filter = Some(self.photon_filter).filter(|&f| f != PhotonFilter::default());
        push(&mut args, "--photon-filter", filter.map(PhotonFilter::name));
        args
    }
}

/// `--dialect`, shared by every command that reads a scene.
#[derive(Args)]
pub struct DialectArg {
    /// The lineage whose renderer's model draws the file: f, z14, pm3, v, w, a18, l17 or colon
    /// (or a repository's name) [default: chosen by the file's markers]
    #[arg(long)]
    pub dialect: Option<Dialect>,
}

impl DialectArg {
    /// The arguments that set it again (none when the markers choose).
    pub fn to_args(&self) -> Vec<String> {
        let mut args = Vec::new();
        push(&mut args, "--dialect", self.dialect.map(Dialect::name));
        args
    }
}

/// Appends `option VALUE` to `args` when there is a value.
fn push(args: &mut Vec<String>, option: &str, value: Option<impl ToString>) {
    if let Some(value) = value {
        args.extend([option.to_string(), value.to_string()]);
    }
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
