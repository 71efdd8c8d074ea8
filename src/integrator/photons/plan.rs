//! Which photon algorithm a render runs and with which settings: the
//! file's dialect and `algorithm=`, the camera's photon keys and the
//! command line's overrides (`photon-mapping.md`, "When photons are traced").

use crate::scene::{Dialect, Scene};

/// A photon algorithm, or none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhotonMode {
    /// Whitted only.
    Off,
    /// One photon map, gathered with the K nearest photons.
    Pm,
    /// Progressive photon mapping: fixed hit points, shrinking radii.
    Ppm,
    /// Stochastic progressive photon mapping: fresh jittered hit points
    /// every iteration.
    Sppm,
}

impl PhotonMode {
    /// The mode named `s` (`pm`, `ppm`, `sppm`, `off`; any case).
    pub fn from_name(s: &str) -> Option<PhotonMode> {
        match s.to_ascii_lowercase().as_str() {
            "off" | "none" | "rt" => Some(PhotonMode::Off),
            "pm" => Some(PhotonMode::Pm),
            "ppm" => Some(PhotonMode::Ppm),
            "sppm" => Some(PhotonMode::Sppm),
            _ => None,
        }
    }

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PhotonMode::Off => "off",
            PhotonMode::Pm => "pm",
            PhotonMode::Ppm => "ppm",
            PhotonMode::Sppm => "sppm",
        }
    }

    /// Whether it runs in iterations.
    pub fn progressive(self) -> bool {
        matches!(self, PhotonMode::Ppm | PhotonMode::Sppm)
    }
}

impl std::str::FromStr for PhotonMode {
    type Err = String;

    /// As [`PhotonMode::from_name`], with the command line's message.
    fn from_str(s: &str) -> Result<PhotonMode, String> {
        PhotonMode::from_name(s)
            .ok_or_else(|| format!("unknown photon mode `{s}`: expected pm, ppm, sppm or off"))
    }
}

/// How gathered photons are weighted by their distance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PhotonFilter {
    /// Every photon counts fully.
    #[default]
    Box,
    /// Jensen's cone filter: 1 − dist/(1.1·r), normalised.
    Cone,
}

impl PhotonFilter {
    /// The filter named `s` (`box`, `cone`).
    pub fn from_name(s: &str) -> Option<PhotonFilter> {
        match s {
            "box" => Some(PhotonFilter::Box),
            "cone" => Some(PhotonFilter::Cone),
            _ => None,
        }
    }

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PhotonFilter::Box => "box",
            PhotonFilter::Cone => "cone",
        }
    }
}

impl std::str::FromStr for PhotonFilter {
    type Err = String;

    /// As [`PhotonFilter::from_name`], with the command line's message.
    fn from_str(s: &str) -> Result<PhotonFilter, String> {
        PhotonFilter::from_name(s)
            .ok_or_else(|| format!("unknown photon filter `{s}`: expected box or cone"))
    }
}

impl std::fmt::Display for PhotonFilter {
    /// Its name (the command line's default value is shown by it).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What the command line says about photons; `None` fields: as the file says.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct PhotonOptions {
    /// `--photons`: the algorithm, forced on or off.
    pub mode: Option<PhotonMode>,
    /// `--iterations`: PPM and SPPM passes.
    pub iterations: Option<u64>,
    /// `--emit`: photons emitted per pass.
    pub emit: Option<u64>,
    /// `--photon-filter`.
    pub filter: PhotonFilter,
}

/// How the photon term joins a diffuse hit's colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Term {
    /// Z14: all diffuse light comes from photons (the lights' direct term is
    /// not traced); photons are stored at every diffuse hit.
    Replace,
    /// Added to the ray-traced direct light; photons are stored from their
    /// second hit on (the variants), or only after a mirror or glass bounce
    /// (`caustics`: the framework's and W's model, forced on).
    Add {
        /// Only photons that passed a mirror or glass are stored.
        caustics: bool,
    },
    /// lazycal: the picture is the photon estimate alone (no ray-traced
    /// light, not even the background); photons are stored at every
    /// diffuse hit, each carries c/n of its light's colour c (not 4π·c/n),
    /// a hit point weighs k (not diff·k) and starts at radius R.
    Only,
}

impl Term {
    /// The power of one of `n` photons of a light of colour `c`: 4π·c/n,
    /// or c/n for lazycal's photons.
    pub fn photon_power(self, c: glam::DVec3, n: u64) -> glam::DVec3 {
        let scale = match self {
            Term::Only => 1.0,
            _ => 4.0 * std::f64::consts::PI,
        };
        c * (scale / n.max(1) as f64)
    }
}

/// How a gathered photon is weighted at a hit point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum PhotonBrdf {
    /// diff (+ the specular lobe where the plan has `specular`): the
    /// photon spec's estimate.
    #[default]
    Lobe,
    /// The colon family's `Material::BRDF`: diff·cos θ + spec·(R_I·L)^50,
    /// times diff again (its hit point's colour carries diff: `ppm.cpp`
    /// `calcIllumination`); a photon bounces diffusely with chance
    /// (diff + spec)·P(k).
    Phong,
}

/// Where a PPM hit point's radius starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FirstRadius {
    /// The K-th nearest photon's distance in a preliminary map, at most R.
    Nearest,
    /// R for every hit point (the colon family's `initr2`).
    Fixed,
}

/// A render's photon settings, resolved.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Plan {
    /// The algorithm.
    pub mode: PhotonMode,
    /// Photons emitted per pass.
    pub emit: u64,
    /// Most photons stored per pass.
    pub max_photons: u64,
    /// K of the K-nearest estimate.
    pub k: usize,
    /// Largest gather radius R.
    pub radius: f64,
    /// PPM/SPPM passes.
    pub iterations: u64,
    /// α of the radius update.
    pub reduction: f64,
    /// Most PPM hit points.
    pub max_hitpoints: u64,
    /// How the term joins the direct light, and which photons are stored.
    pub term: Term,
    /// Whether gathered photons carry the lineage's specular lobe
    /// spec·max(0, R_I·(−d))^50 (PM3 and V).
    pub specular: bool,
    /// The distance filter.
    pub filter: PhotonFilter,
    /// Whether the ambient term stays when photons carry all diffuse light
    /// ([`Term::Replace`]: Z14 keeps it, the colon family's PPM does not).
    pub ambient: bool,
    /// How gathered photons are weighted.
    pub brdf: PhotonBrdf,
    /// Where a PPM hit point's radius starts.
    pub first_radius: FirstRadius,
}

impl Plan {
    /// The plan for `scene` with the command line's `options`, and the
    /// notes it makes (keys without effect, settings that switch photons off).
    pub fn of(scene: &Scene, options: &PhotonOptions) -> (Plan, Vec<String>) {
        let dialect = scene.dialect().dialect;
        let cam = scene.camera();
        let p = &cam.photons;
        let mut notes = Vec::new();
        let file_mode = match dialect {
            Dialect::Z14 | Dialect::Pm3 => PhotonMode::Pm,
            Dialect::V => match cam.algorithm.as_deref() {
                Some("PM") => PhotonMode::Pm,
                Some("PPM") => PhotonMode::Ppm,
                Some("RC" | "RT") => PhotonMode::Off,
                // V's default `algorithm=` is SPPM (lineages.md §3.3).
                _ => PhotonMode::Sppm,
            },
            // Its program draws the ray-traced picture first, PPM's rounds
            // after it (`ppm.cpp` `ppm::Run`): glint draws the first, and
            // PPM with `--photons ppm`.
            Dialect::F | Dialect::W | Dialect::A18 | Dialect::Colon => PhotonMode::Off,
            Dialect::L17 => PhotonMode::Ppm,
        };
        let mut mode = options.mode.unwrap_or(file_mode);
        let term = match dialect {
            Dialect::Z14 | Dialect::Colon => Term::Replace,
            Dialect::Pm3 | Dialect::V => Term::Add { caustics: false },
            Dialect::F | Dialect::W | Dialect::A18 => Term::Add { caustics: true },
            Dialect::L17 => Term::Only,
        };
        let emit = options.emit.unwrap_or(p.emit_photons);
        let radius = p.sample_dist;
        if mode != PhotonMode::Off && emit == 0 {
            notes.push("warning: `emit_photons=` is 0: no photon pass".to_string());
            mode = PhotonMode::Off;
        }
        if mode != PhotonMode::Off && radius <= 0.0 {
            notes.push("warning: `sample_dist=` is 0: no photon term".to_string());
            mode = PhotonMode::Off;
        }
        if mode != PhotonMode::Off
            && !scene
                .lights()
                .iter()
                .any(|l| super::units::power(l.color) > 0.0 && super::units::share(l) > 0.0)
        {
            notes.push(
                "warning: no light has any power (colour sum or `power:` ≤ 0): no photon pass"
                    .to_string(),
            );
            mode = PhotonMode::Off;
        }
        let plan = Plan {
            mode,
            emit,
            max_photons: p.max_photons.max(1),
            k: p.sample_photons.clamp(1, 1 << 20) as usize,
            radius,
            iterations: options.iterations.or(p.iterations).unwrap_or(5000).max(1),
            reduction: p.reduction.unwrap_or(0.7),
            max_hitpoints: p.max_hitpoints.unwrap_or(4_000_000),
            term,
            specular: matches!(dialect, Dialect::Pm3 | Dialect::V | Dialect::Colon),
            filter: options.filter,
            ambient: dialect != Dialect::Colon,
            brdf: if dialect == Dialect::Colon {
                PhotonBrdf::Phong
            } else {
                PhotonBrdf::Lobe
            },
            first_radius: if dialect == Dialect::Colon {
                FirstRadius::Fixed
            } else {
                FirstRadius::Nearest
            },
        };
        plan.note_unused(scene, file_mode, &mut notes);
        (plan, notes)
    }

    /// Notes for the photon keys the file sets that have no effect here.
    fn note_unused(&self, scene: &Scene, file_mode: PhotonMode, notes: &mut Vec<String>) {
        let set = |k: &str| scene.camera().photons.keys.contains(&k);
        let progressive_keys = ["max_hitpoints", "iterations", "reduction"];
        let map_keys = [
            "emit_photons",
            "max_photons",
            "sample_photons",
            "sample_dist",
        ];
        let unused: Vec<&str> = match self.mode {
            PhotonMode::Off => map_keys.iter().chain(&progressive_keys).copied().collect(),
            PhotonMode::Pm => progressive_keys.to_vec(),
            PhotonMode::Ppm | PhotonMode::Sppm => Vec::new(),
        };
        let unused: Vec<String> = unused
            .into_iter()
            .filter(|k| set(k))
            .map(|k| format!("`{k}=`"))
            .collect();
        if !unused.is_empty() {
            let why = match self.mode {
                PhotonMode::Off if file_mode == PhotonMode::Off => {
                    "this file's dialect traces no photons (try --photons pm)".to_string()
                }
                mode => format!("photons: {}", mode.name()),
            };
            notes.push(format!("note: {} have no effect: {why}", unused.join(" ")));
        }
        if self.mode == PhotonMode::Off && file_mode != PhotonMode::Off {
            notes.push(format!(
                "note: photons off: the file's dialect renders {} (indirect light and caustics not rendered)",
                file_mode.name()
            ));
        }
    }
}
