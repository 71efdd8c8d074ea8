//! `glint explain`: one pixel's ray trees, traced exactly as a render traces
//! that pixel, with the bytes the render writes there and a verdict on why
//! (`pixel`), and the report printed from them (`report`).

mod pixel;
mod report;

pub use pixel::{Explanation, HitPointTerm, ProgressiveTerm, Sampling};

use super::progress::Watch;
use super::{Region, RenderError, RenderOptions, Renderer, photons, schedule};
use crate::integrator::photons::PhotonMode;

/// The most samples per pixel [`Renderer::explain`] takes (it keeps every
/// sample's ray tree).
pub const MAX_EXPLAINED_SPP: u32 = 4096;

impl Renderer {
    /// Pixel (x, y) of the render `options` ask for (their region aside),
    /// explained: the same samples the render traces there, as ray trees,
    /// with the bytes it writes and a verdict.
    pub fn explain(
        &self,
        options: &RenderOptions,
        x: u32,
        y: u32,
    ) -> Result<Explanation, RenderError> {
        let (w, h) = self.frame_size(options)?;
        if let Some(value) = options.spp.filter(|&n| n > MAX_EXPLAINED_SPP) {
            return Err(RenderError::Samples {
                value,
                max: MAX_EXPLAINED_SPP,
            });
        }
        if x >= w || y >= h {
            return Err(RenderError::Pixel {
                x,
                y,
                frame_w: w,
                frame_h: h,
            });
        }
        // PM's map as the render traces it.
        let (plan, map, _) = self.photon_pass(options);
        let shading = self.photon_shading(&plan, map.as_ref());
        let (spp, frame) = self.sampled_frame(w, h, options, shading);
        if !plan.mode.progressive() {
            return Ok(pixel::explain_pixel(
                &frame,
                &self.scene,
                &self.accel,
                spp,
                (x, y),
            ));
        }
        // PPM and SPPM: the render's iterations over this one pixel's hit
        // points (the same photons; the photon passes on every core).
        let mut e = if plan.mode == PhotonMode::Sppm {
            let n = u32::try_from(plan.iterations).unwrap_or(u32::MAX);
            pixel::explain_fresh(&frame, &self.scene, &self.accel, n, (x, y))
        } else {
            pixel::explain_pixel(&frame, &self.scene, &self.accel, spp, (x, y))
        };
        let p = self.progressive(&frame, &plan, options.seed, plan.iterations.max(1));
        let watch = Watch {
            progress: &|_, _| {},
            cancel: None,
        };
        let pixel = Region {
            x,
            y,
            width: 1,
            height: 1,
        };
        let done = schedule::with_threads(None, || {
            photons::progressive(&p, &[pixel], spp, &watch, &mut |_, _| {})
        })
        .map_err(RenderError::from)?;
        let iterations = done.stats.iterations;
        let sppm = plan.mode == PhotonMode::Sppm;
        let term = pixel::ProgressiveTerm {
            algorithm: plan.mode,
            iterations,
            emitted: done.stats.emitted,
            direct: done
                .direct
                .first()
                .map_or([0.0; 3], |d| d.as_vec3().to_array()),
            points: done
                .points
                .iter()
                .map(|h| pixel::HitPointTerm {
                    point: (!sppm).then_some(h.point),
                    weight: h.weight,
                    radius: h.r2.sqrt(),
                    photons: h.n,
                    term: h.radiance(iterations),
                })
                .collect(),
        };
        let color = done.pixels.first().copied().unwrap_or(e.color);
        e.set_progressive(term, color);
        Ok(e)
    }
}
