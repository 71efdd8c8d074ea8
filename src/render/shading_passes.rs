//! The passes of the camera hit's shading: `light:N`, `shade`, `why` and
//! `clamp`. Each pixel's centre sample (ray and random stream of pass 1)
//! is traced again with the ray-tree observer, so every value is the one
//! the render computed at that hit; refined pixels are described by their
//! centre sample too. This costs about a `--spp 1` render on top.

use super::aov::{Aov, albedo};
use super::film::Region;
use super::frame::Frame;
use super::verdict::{Cause, cause};
use crate::accel::PACKET_MAX;
use crate::integrator::{RayNode, RayTree, ShadowHints};
use crate::output::Image;
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;

/// The planes of the shading passes of `aovs` over `region` of `frame`.
pub(crate) fn shading_planes(
    frame: &Frame,
    scene: &Scene,
    region: Region,
    aovs: &[Aov],
) -> Vec<(Aov, Vec<f32>)> {
    let aovs: Vec<Aov> = aovs.iter().copied().filter(|a| a.shaded()).collect();
    let per_pixel: usize = aovs.iter().map(|a| a.channels()).sum();
    let rw = region.width as usize;
    let mut all = vec![0f32; region.area() as usize * per_pixel];
    all.par_chunks_mut(rw * per_pixel)
        .enumerate()
        .for_each(|(row, values)| {
            let y = region.y + row as u32;
            let mut hints = ShadowHints::default();
            for start in (0..rw).step_by(PACKET_MAX) {
                let len = (rw - start).min(PACKET_MAX);
                let x0 = region.x + start as u32;
                frame.packet::<RayTree>(
                    len,
                    |k| frame.centre_sample(x0 + k as u32, y),
                    |k, c, tree, _| {
                        let roots = std::mem::take(tree).into_roots();
                        let px = &mut values[(start + k) * per_pixel..][..per_pixel];
                        if let Some(root) = roots.first() {
                            fill(px, &aovs, root, c, scene);
                        }
                    },
                    &mut hints,
                );
            }
        });
    let mut planes: Vec<(Aov, Vec<f32>)> = aovs
        .iter()
        .map(|&a| (a, Vec::with_capacity(region.area() as usize * a.channels())))
        .collect();
    for px in all.chunks(per_pixel.max(1)) {
        let mut at = 0;
        for (aov, data) in &mut planes {
            data.extend_from_slice(&px[at..at + aov.channels()]);
            at += aov.channels();
        }
    }
    planes
}

/// One pixel's values of `aovs`, from its centre sample's tree `root`
/// whose colour is `color`.
fn fill(px: &mut [f32], aovs: &[Aov], root: &RayNode, color: DVec3, scene: &Scene) {
    let mut at = 0;
    for &aov in aovs {
        let out = &mut px[at..at + aov.channels()];
        at += aov.channels();
        let put = |out: &mut [f32], v: DVec3| {
            out.copy_from_slice(&v.as_vec3().to_array()[..out.len()]);
        };
        match aov {
            Aov::Light(n) => put(out, light_term(root, n, scene)),
            Aov::Shade => {
                let s: Vec<f64> = root
                    .lights
                    .iter()
                    .filter(|l| l.l_dot_n > 0.0)
                    .map(|l| l.s)
                    .collect();
                if !s.is_empty() {
                    out[0] = (s.iter().sum::<f64>() / s.len() as f64) as f32;
                    out[1] = s.iter().copied().fold(f64::INFINITY, f64::min) as f32;
                }
            }
            Aov::Why => {
                let rgb = Image::from_pixels(1, 1, vec![color.as_vec3().to_array()]).to_rgb8();
                let kind = cause(root, [rgb[0], rgb[1], rgb[2]], None).0;
                out[0] = Cause::ALL.iter().position(|&c| c == kind).unwrap_or(0) as f32;
            }
            Aov::Clamp => {
                let over = root
                    .unclamped
                    .map_or(DVec3::ZERO, |u| (u - DVec3::ONE).max(DVec3::ZERO));
                put(out, over);
            }
            _ => {}
        }
    }
}

/// Light `n`'s diffuse and specular at the camera ray's hit: colour ×
/// texture × the light's colour × (diffuse + specular weight), as the
/// shading sums it (zero where it faces away or is blocked).
fn light_term(root: &RayNode, n: u32, scene: &Scene) -> DVec3 {
    let (Some(hit), Some(m)) = (&root.hit, &root.material) else {
        return DVec3::ZERO;
    };
    let Some(light) = scene.lights().get(n as usize) else {
        return DVec3::ZERO;
    };
    root.lights
        .iter()
        .find(|l| l.light == n)
        .map_or(DVec3::ZERO, |l| {
            albedo(scene, m, hit.uv) * light.color * (l.diffuse + l.specular)
        })
}
