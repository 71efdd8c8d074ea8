//! Passes (AOVs): what the centre ray of each pixel first hits, stored as
//! named planes of the film beside the picture. One nearest-hit query per
//! pixel, no shading: a small cost beside the render.

use super::film::Region;
use super::frame::Frame;
use crate::integrator::SceneAccel;
use crate::scene::{Origin, Scene};
use rayon::prelude::*;

/// A pass a render can write beside its picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// The first hit's unit geometric normal, turned against the ray (x, y, z).
    Normal,
    /// The distance along the centre ray to the first hit (0 on a miss).
    Depth,
    /// The first hit's point (x, y, z).
    Position,
    /// The first hit's texture coordinates (u, v).
    Uv,
    /// The primitive block's index (−1 on a miss, −2 − n on light n's surface).
    Primitive,
    /// The material's colour × its texture at the first hit.
    Albedo,
    /// Rays traced for the pixel (camera, reflected, refracted, shadow;
    /// the 7×7 grid's too where the anti-aliasing refined it).
    Rays,
}

impl Aov {
    /// Every pass, in the order they are documented.
    pub const ALL: [Aov; 7] = [
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::Uv,
        Aov::Primitive,
        Aov::Albedo,
        Aov::Rays,
    ];

    /// Its name, as `--aov` takes it and as the film's plane is called.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Position => "position",
            Aov::Uv => "uv",
            Aov::Primitive => "primitive",
            Aov::Albedo => "albedo",
            Aov::Rays => "rays",
        }
    }

    /// Values per pixel.
    pub fn channels(self) -> usize {
        match self {
            Aov::Normal | Aov::Position | Aov::Albedo => 3,
            Aov::Uv => 2,
            Aov::Depth | Aov::Primitive | Aov::Rays => 1,
        }
    }

    /// A comma-separated list of pass names (repeats kept once).
    pub fn parse_list(list: &str) -> Result<Vec<Aov>, String> {
        let mut out = Vec::new();
        for word in list.split(',').map(str::trim) {
            let aov = Aov::ALL
                .into_iter()
                .find(|a| a.name() == word)
                .ok_or_else(|| {
                    let names: Vec<_> = Aov::ALL.iter().map(|a| a.name()).collect();
                    format!("unknown pass `{word}`; the passes are {}", names.join(", "))
                })?;
            if !out.contains(&aov) {
                out.push(aov);
            }
        }
        Ok(out)
    }
}

/// The planes of `aovs` over `region` of `frame`: each pixel's centre ray's first hit.
pub(crate) fn first_hit_planes(
    frame: &Frame,
    scene: &Scene,
    accel: &SceneAccel,
    region: Region,
    aovs: &[Aov],
) -> Vec<(Aov, Vec<f32>)> {
    let per_pixel: usize = aovs.iter().map(|a| a.channels()).sum();
    let rw = region.width as usize;
    let mut all = vec![0f32; region.area() as usize * per_pixel];
    all.par_chunks_mut(rw * per_pixel)
        .enumerate()
        .for_each(|(row, values)| {
            let y = region.y + row as u32;
            for (i, px) in values.chunks_mut(per_pixel).enumerate() {
                let ray = frame.ray(region.x + i as u32, y, 0.5, 0.5);
                let found = accel.intersect(&ray, f64::INFINITY);
                let mut at = 0;
                for &aov in aovs {
                    let out = &mut px[at..at + aov.channels()];
                    at += aov.channels();
                    let Some((index, hit)) = found else {
                        if aov == Aov::Primitive {
                            out[0] = -1.0;
                        }
                        continue;
                    };
                    let object = &accel.objects()[index as usize];
                    let s = object.shape().surface(&ray, &hit);
                    let front = s.normal.dot(ray.dir) < 0.0;
                    let put = |out: &mut [f32], v: &[f64]| {
                        out.iter_mut().zip(v).for_each(|(o, &v)| *o = v as f32);
                    };
                    match aov {
                        Aov::Normal => {
                            let n = if front { s.normal } else { -s.normal };
                            put(out, &n.to_array());
                        }
                        Aov::Depth => put(out, &[hit.t]),
                        Aov::Position => put(out, &s.point.to_array()),
                        Aov::Uv => put(out, &s.uv.to_array()),
                        Aov::Primitive => {
                            out[0] = match object.origin() {
                                Origin::Block(b) => b as f32,
                                Origin::Light(l) => -2.0 - l as f32,
                            }
                        }
                        // Counted by the render itself, not here.
                        Aov::Rays => {}
                        Aov::Albedo => {
                            let m = scene.material_of(object);
                            let texture = m.texture.and_then(|t| scene.textures().get(t as usize));
                            let k = match texture {
                                Some(t) => m.color * t.sample(s.uv),
                                None => m.color,
                            };
                            put(out, &k.to_array());
                        }
                    }
                }
            }
        });
    let mut planes: Vec<(Aov, Vec<f32>)> = aovs
        .iter()
        .map(|&a| (a, Vec::with_capacity(region.area() as usize * a.channels())))
        .collect();
    for px in all.chunks(per_pixel) {
        let mut at = 0;
        for (aov, data) in &mut planes {
            data.extend_from_slice(&px[at..at + aov.channels()]);
            at += aov.channels();
        }
    }
    planes
}
