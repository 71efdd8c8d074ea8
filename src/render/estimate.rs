//! A render's cost before it runs: the rays it will trace, roughly, and the
//! settings that drive that count (to warn about a render that will take long).

use super::{RenderError, RenderOptions, Renderer};
use crate::integrator::photons::{PhotonMode, Plan};
use crate::scene::LightKind;

/// Camera rays a pixel takes on average under the adaptive anti-aliasing
/// (one, and 49 more for the few pixels on edges), for [`WorkEstimate`].
const ADAPTIVE_RAYS_PER_PIXEL: u64 = 2;

/// What [`Renderer::estimate`] expects a render to cost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorkEstimate {
    /// Rays, roughly (within a few times either way).
    pub rays: u64,
    /// The settings that drive the count: image size, samples, qualities.
    pub drivers: Vec<String>,
}

impl Renderer {
    /// A rough count of the rays a render of `options` traces, before any
    /// is: camera samples × (1 + shadow rays a point) × glossy rays, with the
    /// settings that drive it, to warn about a render that will take long.
    pub fn estimate(&self, options: &RenderOptions) -> Result<WorkEstimate, RenderError> {
        let (w, h) = self.frame_size(options)?;
        let cam = self.scene.camera();
        let pixels = self.pixels(options)?;
        // Each driving key with its place, `scene.txt:12 `shade_quality=64``,
        // when the scene was read from text.
        let file = self.scene.path().map_or_else(
            || "<input>".to_string(),
            |p| crate::scene::escaped(&p.display().to_string()).into_owned(),
        );
        let place = |line: Option<u32>| line.map(|l| format!("{file}:{l}"));
        let key = |name: &str, value: &dyn std::fmt::Display| match place(
            self.scene.camera_key_line(name),
        ) {
            Some(at) => format!("{at} `{name}={value}`"),
            None => format!("`{name}={value}`"),
        };
        let file_key = |name: &str, value: &dyn std::fmt::Display| {
            self.scene
                .camera_key_line(name)
                .is_some()
                .then(|| key(name, value))
        };
        let mut size = format!("{w}x{h} pixels");
        if options.width.is_none() && options.height.is_none() {
            let keys: Vec<String> = [
                file_key("image_W", &cam.width),
                file_key("image_H", &cam.height),
            ]
            .into_iter()
            .flatten()
            .collect();
            if !keys.is_empty() {
                size = format!("{size} ({})", keys.join(", "));
            }
        }
        let mut drivers = vec![size];
        let samples = match options.spp {
            Some(n) => {
                drivers.push(format!("--spp {n}"));
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
        let per_area = 16 * u64::from(cam.shade_quality.max(1));
        let shadow = (lights.len() as u64 - area) + area * per_area;
        if area > 0 {
            // The area lights' headers too (the first few).
            const SHOWN: usize = 3;
            let mut at: Vec<String> = area_lines
                .iter()
                .filter_map(|&l| place(l))
                .take(SHOWN)
                .collect();
            if area_lines.len() > SHOWN && !at.is_empty() {
                at.push(format!("and {} more", area_lines.len() - SHOWN));
            }
            let at = if at.is_empty() {
                String::new()
            } else {
                format!(" ({})", at.join(", "))
            };
            drivers.push(format!(
                "{} with {area} area light(s){at}: {per_area} shadow rays each a point",
                key("shade_quality", &cam.shade_quality)
            ));
        }
        let model = crate::integrator::Model::of(self.scene.dialect().dialect, cam);
        let glossy = model.glossy != crate::integrator::Glossy::Mirror
            && self.scene.materials().any(|m| m.drefl > 0.0);
        let spread = if glossy {
            let n = u64::from(model.glossy_samples);
            drivers.push(format!(
                "{}: {n} rays a glossy reflection",
                key("drefl_quality", &cam.drefl_quality)
            ));
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
            let mut keys: Vec<String> = Vec::new();
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
            let keys = if keys.is_empty() {
                String::new()
            } else {
                format!(" ({})", keys.join(", "))
            };
            drivers.push(format!(
                "photons {}: {} a pass, {passes} pass(es){keys}",
                plan.mode.name(),
                plan.emit
            ));
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
