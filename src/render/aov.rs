//! AOVs (arbitrary output values): what the centre sample of each pixel meets, stored as
//! named planes of the film beside the picture: its first hit's surface
//! and shading, tallied by pass 1 itself (`shading_aovs`), and the rays
//! and BVH work the render counts as it traces.

use crate::scene::{Material, Scene};

/// An AOV (arbitrary output value): a layer a render can write beside its picture.
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
    /// Every AOV, in the order they are documented (`light:N` as light 0).
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

    /// Whether it comes from the camera hit, its surface or its shading
    /// (tallied by pass 1).
    pub(crate) fn shaded(self) -> bool {
        !self.rendered()
    }

    /// Whether it shows the camera hit's surface (normal, depth...).
    pub(crate) fn of_surface(self) -> bool {
        matches!(
            self,
            Aov::Normal | Aov::Depth | Aov::Position | Aov::Uv | Aov::Primitive | Aov::Albedo
        )
    }

    /// Whether the render counts it as it traces (rays, queries).
    pub(crate) fn rendered(self) -> bool {
        matches!(self, Aov::Rays | Aov::Cost)
    }

    /// A comma-separated list of AOV names (repeats kept once).
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
                        format!("unknown AOV `{word}`; the AOVs are {}", names.join(", "))
                    })?,
            };
            if !out.contains(&aov) {
                out.push(aov);
            }
        }
        Ok(out)
    }
}

/// The material's colour × its texture at `uv` (what diffuse and specular scale).
pub(crate) fn albedo(scene: &Scene, m: &Material, uv: glam::DVec2) -> glam::DVec3 {
    match m.texture.and_then(|t| scene.textures().get(t as usize)) {
        Some(t) => m.color * t.sample(uv),
        None => m.color,
    }
}
