//! A render's cost before it runs: the rays it will trace, roughly, and the
//! settings that drive that count (to warn about a render that will take long).

use super::key::CameraKey;
use super::{RenderError, RenderOptions, Renderer};
use crate::integrator::photons::{PhotonMode, Plan};
use crate::scene::LightKind;
use std::fmt;

/// Camera rays a pixel takes on average under the adaptive anti-aliasing
/// (one, and 49 more for the few pixels on edges), for [`WorkEstimate`].
const ADAPTIVE_RAYS_PER_PIXEL: u64 = 2;

/// Area lights named by their header's place, at most.
const AREA_LIGHTS_SHOWN: usize = 3;

/// What [`Renderer::estimate`] expects a render to cost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorkEstimate {
    /// Rays, roughly (within a few times either way).
    pub rays: u64,
    /// The settings that drive the count: image size, samples, qualities.
    pub drivers: Vec<Driver>,
}

/// A setting that drives a render's cost; shown as the estimate's warning says it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Driver {
    /// The image size, and the camera keys that set it (none when overridden).
    Size {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// `image_W=` and `image_H=`, where the file sets them.
        keys: Vec<CameraKey>,
    },
    /// `--spp N` samples a pixel.
    Samples(u32),
    /// Area lights, each taking `shadow_rays` a shading point.
    AreaLights {
        /// `shade_quality=`.
        quality: CameraKey,
        /// How many.
        count: u64,
        /// The first few headers' places, then how many more.
        at: Vec<String>,
        /// Shadow rays a point, for each.
        shadow_rays: u64,
    },
    /// Glossy reflections, each `rays` rays.
    Glossy {
        /// `drefl_quality=`.
        quality: CameraKey,
        /// Rays a glossy reflection.
        rays: u64,
    },
    /// Photon passes.
    Photons {
        /// The algorithm.
        mode: PhotonMode,
        /// Photons emitted a pass.
        emit: u64,
        /// Passes (PPM's and SPPM's iterations).
        passes: u64,
        /// The keys that set them, where the file does.
        keys: Vec<CameraKey>,
    },
}

/// ` (a, b, c)`, or nothing when `items` is empty.
fn listed(f: &mut fmt::Formatter<'_>, items: &[impl fmt::Display]) -> fmt::Result {
    for (i, item) in items.iter().enumerate() {
        let lead = if i == 0 { " (" } else { ", " };
        write!(f, "{lead}{item}")?;
    }
    if items.is_empty() {
        Ok(())
    } else {
        write!(f, ")")
    }
}

impl fmt::Display for Driver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Driver::Size {
                width,
                height,
                keys,
            } => {
                write!(f, "{width}x{height} pixels")?;
                listed(f, keys)
            }
            Driver::Samples(n) => write!(f, "--spp {n}"),
            Driver::AreaLights {
                quality,
                count,
                at,
                shadow_rays,
            } => {
                write!(f, "{quality} with {count} area light(s)")?;
                listed(f, at)?;
                write!(f, ": {shadow_rays} shadow rays each a point")
            }
            Driver::Glossy { quality, rays } => {
                write!(f, "{quality}: {rays} rays a glossy reflection")
            }
            Driver::Photons {
                mode,
                emit,
                passes,
                keys,
            } => {
                write!(
                    f,
                    "photons {}: {emit} a pass, {passes} pass(es)",
                    mode.name()
                )?;
                listed(f, keys)
            }
        }
    }
}

impl Renderer {
    /// The camera key `name` with `value`, and where the file sets it.
    pub(super) fn camera_key(&self, name: &'static str, value: &dyn fmt::Display) -> CameraKey {
        let at = self.scene.camera_key_line(name).map(|l| {
            let file = self.scene.path().map_or_else(
                || "<input>".to_string(),
                |p| crate::scene::escaped(&p.display().to_string()).into_owned(),
            );
            format!("{file}:{l}")
        });
        CameraKey {
            name,
            value: value.to_string(),
            at,
        }
    }

    /// A rough count of the rays a render of `options` traces, before any
    /// is: camera samples × (1 + shadow rays a point) × glossy rays, with the
    /// settings that drive it, to warn about a render that will take long.
    pub fn estimate(&self, options: &RenderOptions) -> Result<WorkEstimate, RenderError> {
        let (w, h) = self.frame_size(options)?;
        let cam = self.scene.camera();
        let pixels = self.pixels(options)?;
        // Each driving key with its place when the scene was read from text.
        let file = self.scene.path().map_or_else(
            || "<input>".to_string(),
            |p| crate::scene::escaped(&p.display().to_string()).into_owned(),
        );
        let place = |line: Option<u32>| line.map(|l| format!("{file}:{l}"));
        let key = |name: &'static str, value: &dyn fmt::Display| self.camera_key(name, value);
        // The key, only where the file sets it.
        let file_key = |name: &'static str, value: &dyn fmt::Display| {
            Some(key(name, value)).filter(|k| k.at.is_some())
        };
        let keys = if options.width.is_none() && options.height.is_none() {
            [
                file_key("image_W", &cam.width),
                file_key("image_H", &cam.height),
            ]
            .into_iter()
            .flatten()
            .collect()
        } else {
            Vec::new()
        };
        let mut drivers = vec![Driver::Size {
            width: w,
            height: h,
            keys,
        }];
        let samples = match options.spp {
            Some(n) => {
                drivers.push(Driver::Samples(n));
                u64::from(n)
            }
            None => ADAPTIVE_RAYS_PER_PIXEL,
        };
        let lights = self.scene.lights();
        let area_lines: Vec<Option<u32>> = (0..lights.len() as u32)
            .filter(|&i| !matches!(lights[i as usize].kind, LightKind::Point { .. }))
            .map(|i| self.scene.light_line(i))
            .collect();
        let area = area_lines.len() as u64;
        let model = crate::integrator::Model::of(self.scene.dialect().dialect, cam);
        let per_area = u64::from(model.shadow_rays);
        let shadow = (lights.len() as u64 - area) + area * per_area;
        if area > 0 {
            // The area lights' headers too (the first few).
            let mut at: Vec<String> = area_lines
                .iter()
                .filter_map(|&l| place(l))
                .take(AREA_LIGHTS_SHOWN)
                .collect();
            if area_lines.len() > AREA_LIGHTS_SHOWN && !at.is_empty() {
                at.push(format!("and {} more", area_lines.len() - AREA_LIGHTS_SHOWN));
            }
            drivers.push(Driver::AreaLights {
                quality: key("shade_quality", &cam.shade_quality),
                count: area,
                at,
                shadow_rays: per_area,
            });
        }
        let glossy = model.glossy != crate::integrator::Glossy::Mirror
            && self.scene.materials().any(|m| m.drefl > 0.0);
        let spread = if glossy {
            let n = u64::from(model.glossy_samples);
            drivers.push(Driver::Glossy {
                quality: key("drefl_quality", &cam.drefl_quality),
                rays: n,
            });
            n
        } else {
            1
        };
        let mut rays = pixels
            .saturating_mul(samples)
            .saturating_mul(1 + shadow)
            .saturating_mul(spread);
        let (plan, _) = Plan::of(&self.scene, &options.photons);
        if plan.mode != PhotonMode::Off {
            // A photon meets a few surfaces; PPM and SPPM repeat the pass
            // (SPPM its eye pass too).
            let passes = if plan.mode.progressive() {
                plan.iterations
            } else {
                1
            };
            let p = &cam.photons;
            let mut keys = Vec::new();
            if options.photons.mode.is_none()
                && let Some(a) = cam.algorithm.as_deref()
            {
                keys.extend(file_key("algorithm", &a));
            }
            if options.photons.emit.is_none() {
                keys.extend(file_key("emit_photons", &p.emit_photons));
            }
            if plan.mode.progressive()
                && options.photons.iterations.is_none()
                && let Some(n) = p.iterations
            {
                keys.extend(file_key("iterations", &n));
            }
            drivers.push(Driver::Photons {
                mode: plan.mode,
                emit: plan.emit,
                passes,
                keys,
            });
            let eye = if plan.mode == PhotonMode::Sppm {
                pixels.saturating_mul(1 + shadow)
            } else {
                0
            };
            rays = rays.saturating_add(
                passes.saturating_mul(plan.emit.saturating_mul(4).saturating_add(eye)),
            );
        }
        Ok(WorkEstimate { rays, drivers })
    }
}
