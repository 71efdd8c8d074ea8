//! Each lineage's shading model (`lineages.md` §3.1) as data, fixed per
//! render from the scene's dialect: the tracer reads these fields, no
//! dialect is looked at per ray.

use crate::scene::{Camera, Dialect, Material, Texture};
use glam::{DVec2, DVec3};

/// How the light of one light source reaches a diffuse hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Direct {
    /// The framework: L towards the light's centre, times the shade factor;
    /// diffuse L·N and specular (L·N)^20, counted where L·N exceeds `min_dot`.
    Centre,
    /// The 1/d² lineages: per shadow sample, c·(diff·N·L + spec·(R·L)^50)/d²
    /// (without the specular term when `specular` is false).
    Falloff {
        /// Whether the eye-hit specular spec·(R_I·L)^50 is added.
        specular: bool,
    },
    /// The colon family's: as `Centre`, with Phong's specular
    /// spec·(R_I·L)^50 (an even power: its `pow` of a negative cosine).
    Phong,
    /// lazycal's: the share of a fixed (2q+1)² grid of points over the
    /// light (q = `half`) that the point sees, times the light's colour over
    /// its mean; diffuse L·N and Blinn's specular (H·N)^50, L towards the
    /// light's centre (`lineages.md`, L17).
    Grid {
        /// q: the grid's points lie at i/q, j/q of the light's half-edges.
        half: u32,
    },
}

/// Which hits get the ambient term k·background.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Ambient {
    /// None (the framework).
    None,
    /// diff·k·background at a lit hit (the relatives).
    Diffuse,
    /// k·background at every hit, whatever its material (lazycal).
    Every,
}

/// How glossy reflections are sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Glossy {
    /// The framework's `exp` blur (scene-format.md).
    Exp,
    /// The lineages' disk: R + drefl²·(x·e1 + y·e2), (x, y) uniform in
    /// the unit disk; beyond depth 2 a plain mirror.
    Disk,
    /// No glossy reflection: `drefl=` is not read.
    Mirror,
}

/// Which side of a surface a ray is on, for refraction and absorption.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Inside {
    /// Inside when the ray meets the surface's back face.
    FrontFace,
    /// A flag toggled at each actual refraction (Z17, PM3, V).
    Parity,
}

/// How a surface that both reflects and refracts shares its light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Split {
    /// The reflected ray weighs colour × refl=, the refracted refr=.
    Separate,
    /// The colon family's (`raytracer.cpp` `rayTracing`): with both refl=
    /// and refr= set, Fresnel's reflectance R splits it, colour × R and
    /// 1 − R; total internal reflection weighs colour × (refl + refr).
    Fresnel,
}

/// Where Beer absorption (`absor=`) is applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Absorb {
    /// To the refracted ray leaving the inside, over its length inside.
    Refracted,
    /// To everything seen at a hit reached from inside, over the ray's
    /// length (the colon family's).
    AtHit,
}

/// What a camera ray sees of an emitter's surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Emitter {
    /// Its colour, clamped to 1.
    Clamped,
    /// Its colour divided by its largest component.
    Normalised,
}

/// How a photon meeting a diffuse surface is bounced diffusely.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PhotonBounce {
    /// With probability diff·P(k), k the textured colour, its power times
    /// k/P(k) (`photon-mapping.md`, Tracing).
    Textured,
    /// Z14's: with probability (diff + spec)·P(color), its power times
    /// color/P(color): the texture does not tint photons (Z14
    /// `photontracer.cpp` `PhotonDiffusion`).
    Untextured,
}

/// Which pixels get more camera rays, and which.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AntiAlias {
    /// The framework's 7×7 grid where the hash differs from a neighbour's.
    Grid7,
    /// A 3×3 grid (rays ⅓ px apart) there: the framework's 2015 ancestor,
    /// abcbdf's and lazycal's.
    Grid3,
    /// PM3's and V's: (c + the four rays ⅓ px away along each axis) / 5
    /// where the hash differs from a neighbour's.
    Cross5,
    /// The colon family's: the mean of a 10×10 grid of step ⅕ px turned by
    /// atan ½, the points within the pixel (`raytracer.cpp` `antiAliasing`),
    /// where the hash differs from a neighbour's.
    Rotated,
    /// One ray per pixel.
    None,
}

/// How camera rays leave the eye.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lens {
    /// The framework's: N + Dy·(2i/H − 1) + Dx·(2j/W − 1).
    Framework,
    /// PM3's and V's: N + Dy·lens_H·(i/(H−1) − ½) + Dx·lens_W·(j/(W−1) − ½).
    Spanned,
    /// W's: N + Dy·2i/H + Dx·2j/W, i from the top, Dx the user's `Dx=`.
    Corner,
    /// The colon family's: the framework's formula with the right-hand
    /// direction unit(N × up) from its `up:`; an open lens focuses at
    /// `focal:` along each ray (a sphere), not on a plane.
    Hta,
}

/// One lineage's shading model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Model {
    /// How direct light is computed.
    pub direct: Direct,
    /// Where k·background is added.
    pub ambient: Ambient,
    /// Whether a specular-only material gets the light term (else only diff > 0 does).
    pub lit_by_specular: bool,
    /// The light term counts where L·N exceeds this (framework: 0; W: 10⁻⁶).
    pub min_dot: f64,
    /// Glossy sampling.
    pub glossy: Glossy,
    /// Glossy rays per reflection.
    pub glossy_samples: u32,
    /// Shadow rays per shading point towards an area light.
    pub shadow_rays: u32,
    /// Whether every ray's colour is clamped to 1 (else the camera ray's only).
    pub clamp_every_ray: bool,
    /// A ray deeper than this returns black (the camera ray has depth 1).
    pub max_depth: u32,
    /// A ray whose weight (the product of the refl=, refr= or Fresnel
    /// shares that led to it) is below this is not traced.
    pub min_weight: f64,
    /// How reflection and refraction share a surface's light.
    pub split: Split,
    /// Where absorption is applied.
    pub absorb: Absorb,
    /// The refraction side rule.
    pub inside: Inside,
    /// Whether `rindex=` ≤ 0 refracts with index 1 (the framework's fix of
    /// its NaN); else the index is used as written (the lineages: light
    /// entering takes the total-internal-reflection path, §7.8).
    pub unit_index_fallback: bool,
    /// Whether a reflected ray is weighted by the colour × `refl=` (else
    /// by `refl=` alone: lazycal's ray tracer).
    pub tinted_reflection: bool,
    /// Whether a texture replaces the colour (else multiplies it).
    pub texture_replaces: bool,
    /// What an emitter's surface shows.
    pub emitter: Emitter,
    /// Whether a ray that meets nothing shows the background (the
    /// framework); the relatives' rays show black there, their background
    /// being only the ambient term (Z14, PM3, V, W `RayTracing`).
    pub background_seen: bool,
    /// A photon's diffuse bounce.
    pub photon_bounce: PhotonBounce,
    /// Whether reflection and refraction rays are traced (V's `algorithm= RC` traces none).
    pub secondary: bool,
    /// Anti-aliasing.
    pub anti_alias: AntiAlias,
    /// The camera's lens formula.
    pub lens: Lens,
}

impl Model {
    /// k: the colour of material `m` at texture coordinates `uv`, its
    /// texture (one of `textures`) multiplying or replacing its colour.
    pub fn albedo(&self, m: &Material, textures: &[Texture], uv: DVec2) -> DVec3 {
        match m.texture.and_then(|t| textures.get(t as usize)) {
            Some(texture) if self.texture_replaces => texture.sample(uv),
            Some(texture) => m.color * texture.sample(uv),
            None => m.color,
        }
    }

    /// The model of dialect `d`, with `camera`'s quality keys (and V's `algorithm=`).
    pub fn of(d: Dialect, camera: &Camera) -> Model {
        let (sq, dq) = (camera.shade_quality, camera.drefl_quality);
        let f = Model {
            direct: Direct::Centre,
            ambient: Ambient::None,
            lit_by_specular: true,
            min_dot: 0.0,
            glossy: Glossy::Exp,
            glossy_samples: sixteenths(dq),
            shadow_rays: sixteenths(sq),
            clamp_every_ray: true,
            max_depth: 10,
            min_weight: 0.0,
            split: Split::Separate,
            absorb: Absorb::Refracted,
            inside: Inside::FrontFace,
            unit_index_fallback: true,
            tinted_reflection: true,
            texture_replaces: false,
            emitter: Emitter::Clamped,
            background_seen: true,
            photon_bounce: PhotonBounce::Textured,
            secondary: true,
            anti_alias: AntiAlias::Grid7,
            lens: Lens::Framework,
        };
        let lineage = Model {
            unit_index_fallback: false,
            direct: Direct::Falloff { specular: true },
            ambient: Ambient::Diffuse,
            lit_by_specular: false,
            glossy: Glossy::Disk,
            glossy_samples: 16 * whole(dq),
            shadow_rays: 16 * whole(sq),
            clamp_every_ray: false,
            background_seen: false,
            ..f
        };
        match d {
            Dialect::F => f,
            Dialect::Z14 => Model {
                direct: Direct::Falloff { specular: false },
                photon_bounce: PhotonBounce::Untextured,
                anti_alias: AntiAlias::None,
                ..lineage
            },
            Dialect::Pm3 | Dialect::V => Model {
                glossy_samples: whole(dq),
                max_depth: 20,
                inside: Inside::Parity,
                emitter: Emitter::Normalised,
                secondary: !(d == Dialect::V && camera.algorithm.as_deref() == Some("RC")),
                anti_alias: AntiAlias::Cross5,
                lens: Lens::Spanned,
                ..lineage
            },
            Dialect::W => Model {
                glossy_samples: 16 * whole(dq),
                shadow_rays: 16 * whole(sq),
                unit_index_fallback: false,
                ambient: Ambient::Diffuse,
                min_dot: 1e-6,
                glossy: Glossy::Mirror,
                max_depth: 5,
                texture_replaces: true,
                background_seen: false,
                anti_alias: AntiAlias::None,
                lens: Lens::Corner,
                ..f
            },
            // The framework's ancestor (2015): W's light with the 2014
            // engine's glossy disk and a 3×3 anti-aliasing grid.
            Dialect::A18 => Model {
                glossy_samples: 16 * whole(dq),
                shadow_rays: 16 * whole(sq),
                unit_index_fallback: false,
                ambient: Ambient::Diffuse,
                min_dot: 1e-6,
                glossy: Glossy::Disk,
                anti_alias: AntiAlias::Grid3,
                ..f
            },
            Dialect::L17 => Model {
                direct: Direct::Grid { half: 4 },
                ambient: Ambient::Every,
                glossy: Glossy::Mirror,
                clamp_every_ray: false,
                max_depth: 20,
                inside: Inside::Parity,
                unit_index_fallback: false,
                tinted_reflection: false,
                texture_replaces: true,
                anti_alias: AntiAlias::Grid3,
                ..f
            },
            // hta1996/Raytracing `raytracer.cpp`, `object.h`, `const.h`.
            Dialect::Colon => Model {
                direct: Direct::Phong,
                ambient: Ambient::Diffuse,
                min_dot: 1e-6,
                glossy: Glossy::Mirror,
                shadow_rays: COLON_SHADOW_GRID * COLON_SHADOW_GRID,
                clamp_every_ray: false,
                max_depth: 20,
                min_weight: 0.04,
                split: Split::Fresnel,
                absorb: Absorb::AtHit,
                anti_alias: AntiAlias::Rotated,
                lens: Lens::Hta,
                ..f
            },
        }
    }
}

/// The colon family's shadow rays to an area light: a jittered 5×5 grid
/// (`const.h` `softShadowT`).
const COLON_SHADOW_GRID: u32 = 5;

/// The framework's ray count for a quality key: int(16·q), as both of its
/// readers compute it from the real they read (F `src/raytracer.cpp`
/// `CalnDiffusion`; CUDA `Scene_Material.cu`), at least one; 0 or less
/// means the default minimum, 16.
fn sixteenths(q: f64) -> u32 {
    if q > 0.0 {
        ((16.0 * q) as u32).max(1)
    } else {
        16
    }
}

/// The relatives' reading of a quality key: a whole number (rounded), at least 1.
fn whole(q: f64) -> u32 {
    q.round().max(1.0) as u32
}
