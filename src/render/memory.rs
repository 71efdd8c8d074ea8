//! The memory a render takes on top of what the process holds when it
//! starts (the scene, its BVH, the program): an estimate a little above
//! the peak, for refusing a render that cannot fit before any of it is
//! spent, and the settings that would make it fit.

use super::key::CameraKey;
use crate::integrator::photons::{
    HitPoint, HitPointSeed, Photon, PhotonMode, Plan, Term, batch_emitted,
};
use std::fmt;
use std::mem::size_of;

/// Bytes every render takes whatever its size: the program's code as it
/// runs (paged in as it is first run), the allocator's and the encoders'
/// first pages (measured: 1.7 MiB over what a 64×48 render held before it
/// started, on two threads).
const BASE: u64 = 2 << 20;

/// Bytes each worker thread takes: its stack and allocator arena as far
/// as a render touches them.
const THREAD: u64 = 1 << 20;

/// Bytes a pixel takes in every render before it is written: the film and
/// the adaptive anti-aliasing's hashes.
const FILM_PIXEL: u64 = 16;

/// Bytes a pixel takes for each channel of an AOV: its plane (f32).
const PASS_CHANNEL: u64 = 4;

/// Bytes a pixel takes while the picture and its AOVs are written, beside
/// the film: the output's copies and the encoder's buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Encoding {
    /// A pixel of the picture.
    pub pixel: u64,
    /// A pixel of one AOV channel.
    pub channel: u64,
}

impl Encoding {
    /// The costliest output (OpenEXR), for a render whose output is not known.
    pub const LARGEST: Encoding = Encoding {
        pixel: 28,
        channel: 10,
    };
}

/// Bytes a pixel takes in PPM and SPPM besides its hit points: the direct
/// light, its running sum, the eye pass's colours, the composed pictures
/// and the `photons` AOV (five colours of 24 bytes), with room.
const PROGRESSIVE_PIXEL: u64 = 128;

/// Bytes a photon of PM's map takes beside the photon itself: the k-d
/// tree's positions, directions and indices (52) and its splits.
const MAP_PHOTON: u64 = 56;

/// Bytes a photon takes while PM's map is built, beside the photons and
/// the map: the build's entries and splits.
const MAP_BUILD: u64 = 48;

/// Bytes a photon of a PPM or SPPM pass takes in its grid: its bucket key,
/// its place in the order, and up to four buckets' starts (twice: the
/// counting sort's copy).
const GRID_PHOTON: u64 = 40;

/// Bytes a photon takes while it is kept: its hash, and the copy of the
/// hashes a cut selects from.
const KEPT_HASH: u64 = 16;

/// What drives a render's memory: its settings and what was measured of
/// the scene (photons stored per photon emitted, hit points per pixel).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Load {
    /// Pixels rendered.
    pub pixels: u64,
    /// Worker threads.
    pub threads: u64,
    /// Channels of the AOVs, all together.
    pub channels: u64,
    /// What writing the output takes.
    pub encoding: Encoding,
    /// The photon algorithm.
    pub mode: PhotonMode,
    /// Whether PPM builds a preliminary map for its hit points' radii
    /// (not lazycal's, which starts at R).
    pub preliminary_map: bool,
    /// Photons emitted a pass.
    pub emit: u64,
    /// `max_photons=`.
    pub max_photons: u64,
    /// `max_hitpoints=`.
    pub max_hitpoints: u64,
    /// Photons a pass stores per photon emitted.
    pub stored_per_emitted: f64,
    /// Hit points a pixel holds (PPM: all of the picture's; SPPM: one
    /// iteration's).
    pub hit_points_per_pixel: f64,
}

impl Load {
    /// The load of `pixels` pixels on `threads` threads with `channels`
    /// AOV channels under `plan`, before anything is measured.
    pub fn new(pixels: u64, threads: u64, channels: u64, plan: &Plan) -> Self {
        Load {
            pixels,
            threads,
            channels,
            encoding: Encoding::LARGEST,
            mode: plan.mode,
            preliminary_map: plan.term != Term::Only,
            emit: plan.emit,
            max_photons: plan.max_photons,
            max_hitpoints: plan.max_hitpoints,
            stored_per_emitted: 0.0,
            hit_points_per_pixel: 0.0,
        }
    }

    /// Bytes at the peak: what every render holds, and the largest of the
    /// photon algorithm's stages (each holding what the next needs).
    pub fn bytes(&self) -> u64 {
        let pixels = self.pixels as f64;
        let frame = BASE as f64
            + (self.threads * THREAD) as f64
            + pixels
                * (FILM_PIXEL
                    + self.encoding.pixel
                    + self.channels * (PASS_CHANNEL + self.encoding.channel))
                    as f64;
        let photon = size_of::<Photon>() as f64;
        let point = size_of::<HitPoint>() as f64;
        // The eye pass's rows and their concatenation (each row freed as it
        // is copied: measured, 1.1 to 1.5 times the seeds at the peak), then
        // the hit points made of them.
        let seed = size_of::<(u32, HitPointSeed)>() as f64;
        let eye = |points: f64| points * (1.5 * seed + point);
        let stages = match self.mode {
            PhotonMode::Off => 0.0,
            PhotonMode::Pm => {
                let (trace, kept) = self.pass();
                // The map is built from the kept photons, then holds them.
                let build = kept * (2.0 * photon + (MAP_BUILD + MAP_PHOTON) as f64);
                trace.max(build)
            }
            PhotonMode::Ppm => {
                let points = (self.hit_points_per_pixel * pixels).min(self.max_hitpoints as f64);
                let (trace, kept) = self.pass();
                let build = if self.preliminary_map {
                    kept * (2.0 * photon + (MAP_BUILD + MAP_PHOTON) as f64)
                } else {
                    0.0
                };
                let grid = kept * (photon + GRID_PHOTON as f64);
                // The eye pass; the preliminary map, then every pass and
                // its grid, beside the hit points.
                pixels * PROGRESSIVE_PIXEL as f64
                    + eye(points).max(points * point + trace.max(build).max(grid))
            }
            PhotonMode::Sppm => {
                let visible = (self.hit_points_per_pixel * pixels).min(self.max_hitpoints as f64);
                let (trace, kept) = self.pass();
                let grid = kept * (photon + GRID_PHOTON as f64);
                // A running estimate a pixel; every iteration's eye pass,
                // then its visible points beside the pass and its grid.
                pixels * (PROGRESSIVE_PIXEL as f64 + point + 4.0)
                    + eye(visible).max(visible * point + trace.max(grid))
            }
        };
        (frame + stages).min(u64::MAX as f64) as u64
    }

    /// A photon pass's bytes while it is traced (the photons kept, their
    /// hashes, a batch's chunks grown by doubling) and the photons it keeps.
    fn pass(&self) -> (f64, f64) {
        let photon = size_of::<Photon>() as f64;
        let ratio = self.stored_per_emitted;
        let stored = self.emit as f64 * ratio;
        let batch = (batch_emitted(self.threads) as f64 * ratio).min(stored);
        let max = self.max_photons as f64;
        let held = stored.min(max + max / 8.0 + batch);
        let trace = held * (photon + KEPT_HASH as f64) + 2.0 * batch * photon;
        (trace, stored.min(max))
    }
}

/// The largest value in `lo..=hi` for which `fits` holds (it holds for
/// all values below one it holds for), if any.
fn largest(lo: u64, hi: u64, fits: impl Fn(u64) -> bool) -> Option<u64> {
    if hi < lo || !fits(lo) {
        return None;
    }
    let (mut good, mut bad) = (lo, hi.saturating_add(1));
    while bad - good > 1 {
        let mid = good + (bad - good) / 2;
        if fits(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(good)
}

/// A setting that, changed alone, brings a render within the memory
/// available; shown as the refusal says it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Fit {
    /// A smaller frame of the same shape.
    Size {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// No AOVs (`--aov`).
    NoAovs,
    /// Fewer photons emitted a pass: `--emit` (or `emit_photons=`).
    Emit {
        /// The most that fit.
        value: u64,
        /// The file's `emit_photons=`, where it sets it (and no `--emit` overrides it).
        key: Option<CameraKey>,
    },
    /// A lower cap on the photons a pass keeps: `max_photons=` (the
    /// command line has no option for it).
    MaxPhotons {
        /// The most that fit.
        value: u64,
        /// The file's `max_photons=`, where it sets it.
        key: Option<CameraKey>,
    },
}

impl fmt::Display for Fit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let set = |f: &mut fmt::Formatter<'_>, key: &Option<CameraKey>| match key {
            Some(k) => write!(f, " (the file has {k})"),
            None => Ok(()),
        };
        match self {
            Fit::Size { width, height } => write!(f, "--width {width} --height {height}"),
            Fit::NoAovs => write!(f, "no --aov"),
            Fit::Emit { value, key } => {
                write!(f, "--emit {value}")?;
                set(f, key)
            }
            Fit::MaxPhotons { value, key } => {
                write!(f, "`max_photons= {value}` in the camera block")?;
                set(f, key)
            }
        }
    }
}

/// What a render takes in memory beyond what the process holds before
/// it, as [`Renderer::memory_needed`](super::Renderer::memory_needed)
/// estimates it, and what it is made of.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryNeed {
    /// Bytes at the peak: an estimate a little above the truth (the
    /// photons a pass stores and the hit points a pixel holds are
    /// measured on a sample first).
    pub bytes: u64,
    pub(super) load: Load,
    /// The frame's size.
    pub(super) frame: (u32, u32),
    /// `emit_photons=` where the file sets it and no `--emit` overrides it.
    pub(super) emit_key: Option<CameraKey>,
    /// `max_photons=` where the file sets it.
    pub(super) max_key: Option<CameraKey>,
}

impl MemoryNeed {
    /// The need of the same render written with `encoding` (the costliest
    /// output is assumed until then).
    pub fn with_encoding(mut self, encoding: Encoding) -> Self {
        self.load.encoding = encoding;
        self.bytes = self.load.bytes();
        self
    }

    /// The settings that, changed alone, would bring the render within
    /// `available` bytes, each at the largest value that fits (none when
    /// nothing alone does).
    pub fn fits(&self, available: u64) -> Vec<Fit> {
        let load = &self.load;
        let within = |l: Load| l.bytes() <= available;
        let mut fits = Vec::new();
        let (w, h) = self.frame;
        // The frame scaled by s/1024 on each side, its pixels by (s/1024)².
        let scaled = |s: u64, side: u32| (u64::from(side) * s / 1024).max(1) as u32;
        if let Some(s) = largest(1, 1023, |s| {
            let pixels = (load.pixels as f64 * (s * s) as f64 / (1u64 << 20) as f64) as u64;
            within(Load {
                pixels,
                ..load.clone()
            })
        }) {
            fits.push(Fit::Size {
                width: scaled(s, w),
                height: scaled(s, h),
            });
        }
        if load.channels > 0
            && within(Load {
                channels: 0,
                ..load.clone()
            })
        {
            fits.push(Fit::NoAovs);
        }
        if load.mode != PhotonMode::Off {
            if let Some(value) = largest(1, load.emit.saturating_sub(1), |emit| {
                within(Load {
                    emit,
                    ..load.clone()
                })
            }) {
                fits.push(Fit::Emit {
                    value,
                    key: self.emit_key.clone(),
                });
            }
            let kept = (load.emit as f64 * load.stored_per_emitted) as u64;
            if let Some(value) = largest(1, load.max_photons.min(kept), |max_photons| {
                within(Load {
                    max_photons,
                    ..load.clone()
                })
            })
            .filter(|&v| v < load.max_photons.min(kept))
            {
                fits.push(Fit::MaxPhotons {
                    value,
                    key: self.max_key.clone(),
                });
            }
        }
        fits
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(mode: PhotonMode) -> Load {
        Load {
            pixels: 420 * 420,
            threads: 2,
            channels: 0,
            encoding: Encoding::LARGEST,
            mode,
            preliminary_map: true,
            emit: 10_000_000,
            max_photons: 1_000_000,
            max_hitpoints: 4_000_000,
            stored_per_emitted: 2.5,
            hit_points_per_pixel: 1.2,
        }
    }

    /// The photons a pass keeps bound its memory, not those it emits:
    /// ten times the photons, the same bytes once the cap is reached.
    #[test]
    fn the_cap_bounds_a_pass_not_the_photons_emitted() {
        for mode in [PhotonMode::Pm, PhotonMode::Ppm, PhotonMode::Sppm] {
            let ten = load(mode);
            let hundred = Load {
                emit: 100_000_000,
                ..ten.clone()
            };
            assert_eq!(ten.bytes(), hundred.bytes(), "{mode:?}");
            let capped_lower = Load {
                max_photons: 100_000,
                ..ten.clone()
            };
            assert!(capped_lower.bytes() < ten.bytes(), "{mode:?}");
        }
    }

    /// Each suggestion, applied, fits; and is the largest that does.
    #[test]
    fn each_fit_fits_and_is_the_largest() {
        let need = MemoryNeed {
            bytes: 0,
            load: Load {
                channels: 12,
                ..load(PhotonMode::Pm)
            },
            frame: (420, 420),
            emit_key: None,
            max_key: None,
        };
        let available = need.load.bytes() * 2 / 3;
        let fits = need.fits(available);
        assert!(!fits.is_empty());
        for fit in fits {
            let (at, above) = match fit {
                Fit::Size { width, height } => {
                    let pixels = |w: u32, h: u32| u64::from(w) * u64::from(h);
                    let at = Load {
                        pixels: pixels(width, height),
                        ..need.load.clone()
                    };
                    let above = Load {
                        pixels: pixels(width + 2, height + 2),
                        ..need.load.clone()
                    };
                    (at, above)
                }
                Fit::NoAovs => {
                    let at = Load {
                        channels: 0,
                        ..need.load.clone()
                    };
                    (at, need.load.clone())
                }
                Fit::Emit { value, .. } => (
                    Load {
                        emit: value,
                        ..need.load.clone()
                    },
                    Load {
                        emit: value + 1,
                        ..need.load.clone()
                    },
                ),
                Fit::MaxPhotons { value, .. } => (
                    Load {
                        max_photons: value,
                        ..need.load.clone()
                    },
                    Load {
                        max_photons: value + 1,
                        ..need.load.clone()
                    },
                ),
            };
            assert!(at.bytes() <= available, "{fit}");
            assert!(above.bytes() > available, "{fit}");
        }
    }
}
