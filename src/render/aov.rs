//! Passes (AOVs): what the centre ray of each pixel first hits, stored as
//! named planes of the film beside the picture. One nearest-hit query per
//! pixel, no shading: a small cost beside the render. (The passes of the
//! camera hit's shading, `light:N`, `shade`, `why`, `clamp`, are tallied
//! by pass 1 itself: `shading_passes`.)

use super::film::Region;
use super::frame::Frame;
use crate::integrator::SceneAccel;
use crate::scene::{Material, Origin, Scene};
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
    /// Light N's diffuse and specular at the centre ray's hit: colour ×
    /// texture × the light's colour × (diffuse + specular weight), RGB.
    Light(u32),
    /// The shade factors at the centre ray's hit over the lights it faces
    /// (L·N > 0): their mean and their smallest (0 where it faces none).
    Shade,
    /// The verdict's kind at the centre ray (its index in the legend).
    Why,
    /// What the clamp cut at the centre ray's hit: the sum above 1 per channel.
    Clamp,
    /// The work of every ray query the pixel's samples made (camera,
    /// reflected, refracted and shadow rays, glossy fans and the 7×7 grid
    /// included; nearest-hit and any-hit queries alike): BVH nodes visited
    /// (inner nodes, whose children's boxes are tested, and leaves) and
    /// primitives tested (the leaves', the unbounded ones, planes, tested
    /// against every ray, and an any-hit query's hinted blocker).
    Cost,
    /// The photon term at the centre ray's hit, RGB: what PM's estimate
    /// adds there (PPM and SPPM: each pixel's photon estimate).
    Photons,
}

impl Aov {
    /// Every pass, in the order they are documented (`light:N` as light 0).
    pub const ALL: [Aov; 13] = [
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::Uv,
        Aov::Primitive,
        Aov::Albedo,
        Aov::Rays,
        Aov::Light(0),
        Aov::Shade,
        Aov::Why,
        Aov::Clamp,
        Aov::Cost,
        Aov::Photons,
    ];

    /// Its name, as `--aov` takes it and as the film's plane is called.
    pub fn name(self) -> std::borrow::Cow<'static, str> {
        match self {
            Aov::Normal => "normal".into(),
            Aov::Depth => "depth".into(),
            Aov::Position => "position".into(),
            Aov::Uv => "uv".into(),
            Aov::Primitive => "primitive".into(),
            Aov::Albedo => "albedo".into(),
            Aov::Rays => "rays".into(),
            Aov::Light(n) => format!("light:{n}").into(),
            Aov::Shade => "shade".into(),
            Aov::Why => "why".into(),
            Aov::Clamp => "clamp".into(),
            Aov::Cost => "cost".into(),
            Aov::Photons => "photons".into(),
        }
    }

    /// Values per pixel.
    pub fn channels(self) -> usize {
        match self {
            Aov::Normal
            | Aov::Position
            | Aov::Albedo
            | Aov::Light(_)
            | Aov::Clamp
            | Aov::Photons => 3,
            Aov::Uv | Aov::Shade | Aov::Cost => 2,
            Aov::Depth | Aov::Primitive | Aov::Rays | Aov::Why => 1,
        }
    }

    /// Whether it comes from the camera hit's shading (tallied by pass 1).
    pub(crate) fn shaded(self) -> bool {
        matches!(
            self,
            Aov::Light(_) | Aov::Shade | Aov::Why | Aov::Clamp | Aov::Photons
        )
    }

    /// Whether the render counts it as it traces (rays, queries).
    pub(crate) fn rendered(self) -> bool {
        matches!(self, Aov::Rays | Aov::Cost)
    }

    /// A comma-separated list of pass names (repeats kept once).
    pub fn parse_list(list: &str) -> Result<Vec<Aov>, String> {
        let mut out = Vec::new();
        for word in list.split(',').map(str::trim) {
            let light = word.strip_prefix("light:").map(|n| {
                n.parse::<u32>()
                    .map(Aov::Light)
                    .map_err(|_| format!("`{word}`: expected `light:N`, N a light's index from 0"))
            });
            let aov = match light {
                Some(found) => found?,
                None => Aov::ALL
                    .into_iter()
                    .find(|a| a.name() == word)
                    .ok_or_else(|| {
                        let names: Vec<_> = Aov::ALL
                            .iter()
                            .map(|a| match a {
                                Aov::Light(_) => "light:N".into(),
                                _ => a.name(),
                            })
                            .collect();
                        format!("unknown pass `{word}`; the passes are {}", names.join(", "))
                    })?,
            };
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
                // The surface once per pixel, for every pass.
                let found = accel.intersect(&ray, f64::INFINITY).map(|(index, hit)| {
                    let object = &accel.objects()[index as usize];
                    (object, hit, object.shape().surface(&ray, &hit))
                });
                let mut at = 0;
                for &aov in aovs {
                    let out = &mut px[at..at + aov.channels()];
                    at += aov.channels();
                    let Some((object, hit, s)) = &found else {
                        if aov == Aov::Primitive {
                            out[0] = -1.0;
                        }
                        continue;
                    };
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
                        // Counted by the render itself, or tallied by pass 1.
                        Aov::Rays
                        | Aov::Light(_)
                        | Aov::Shade
                        | Aov::Why
                        | Aov::Clamp
                        | Aov::Cost
                        | Aov::Photons => {}
                        Aov::Albedo => {
                            let k = albedo(scene, &scene.material_of(object), s.uv);
                            put(out, &k.to_array());
                        }
                    }
                }
            }
        });
    split_planes(&all, aovs)
}

/// The planes of `aovs` out of `all`, each pixel's values of every pass in turn.
pub(crate) fn split_planes(all: &[f32], aovs: &[Aov]) -> Vec<(Aov, Vec<f32>)> {
    let per_pixel: usize = aovs.iter().map(|a| a.channels()).sum();
    let pixels = all.len() / per_pixel.max(1);
    let mut planes: Vec<(Aov, Vec<f32>)> = aovs
        .iter()
        .map(|&a| (a, Vec::with_capacity(pixels * a.channels())))
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

/// The material's colour × its texture at `uv` (what diffuse and specular scale).
pub(crate) fn albedo(scene: &Scene, m: &Material, uv: glam::DVec2) -> glam::DVec3 {
    match m.texture.and_then(|t| scene.textures().get(t as usize)) {
        Some(t) => m.color * t.sample(uv),
        None => m.color,
    }
}
