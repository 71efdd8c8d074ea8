//! The blocks other than primitives: `background`, `camera`, the lights,
//! and the material keys every primitive block shares.
//!
//! Defaults chosen where the format leaves them open:
//! - background: a gradient end that is not given (`top=` alone, or
//!   `bottom=` alone) is white;
//! - a light without `color=` is black (and a warning says so);
//! - `refr=` > 0 with `rindex=` ≤ 0 refracts with index 1 in the framework's
//!   dialect (the framework divides by it and produces NaN); the index is
//!   kept as written for the lineages' total internal reflection.

use super::assets::Assets;
use super::block_keys::BlockKeys;
use super::diags::{Site, When};
use super::suggest::closest;
use super::values::{Value, unit};
use crate::scene::{Background, Camera, Dialect, LightKind, MAX_IMAGE_SIDE, Material, Texture};
use glam::DVec3;

/// Above this `shade_quality=` or `drefl_quality=` (16 times the
/// framework's default) a warning says the render will be slow.
const SLOW_QUALITY: u32 = 64;

/// The largest `shade_quality=` or `drefl_quality=` (16384 rays per
/// shading point or glossy reflection); beyond, a render would not finish.
pub(crate) const MAX_QUALITY: u32 = 1024;

/// `background`: `color=`, or a gradient `top=` / `bottom=`, over `bg`
/// (a second block's keys override the first's).
pub(crate) fn background(mut bg: Background, b: &mut BlockKeys<'_>) -> Background {
    for f in b.fields.list() {
        let Value::V3(c) = f.value else { continue };
        bg = match (f.name, bg) {
            ("color", _) => Background::Color(c),
            ("top", Background::Gradient { bottom, .. }) => Background::Gradient { top: c, bottom },
            ("top", Background::Color(_)) => Background::Gradient {
                top: c,
                bottom: DVec3::ONE,
            },
            ("bottom", Background::Gradient { top, .. }) => Background::Gradient { top, bottom: c },
            ("bottom", Background::Color(_)) => Background::Gradient {
                top: DVec3::ONE,
                bottom: c,
            },
            _ => bg,
        };
    }
    bg
}

/// `camera`: the eye, the lens, the image size and the quality keys, over
/// `cam` (a second block's keys override the first's).
pub(crate) fn camera(mut cam: Camera, b: &mut BlockKeys<'_>) -> Camera {
    if let Some((o, _)) = b.fields.v3("O") {
        cam.origin = o;
    }
    if let Some((n, site)) = b.fields.v3("N") {
        match unit(n) {
            Some(n) => cam.dir = n,
            None => b.diags.error(
                site,
                "`N=` has zero length; the camera needs a view direction",
                None,
            ),
        }
    }
    for (key, target) in [("lens_W", &mut cam.lens_w), ("lens_H", &mut cam.lens_h)] {
        if let Some((x, site)) = b.fields.num(key) {
            if x > 0.0 {
                *target = x;
            } else {
                b.diags.error(
                    site,
                    format!("`{key}=` must be greater than 0, found {x}"),
                    None,
                );
            }
        }
    }
    for (key, target) in [("image_W", &mut cam.width), ("image_H", &mut cam.height)] {
        if let Some((x, site)) = b.fields.num(key) {
            if (1.0..=f64::from(MAX_IMAGE_SIDE)).contains(&x) {
                *target = x as u32;
            } else {
                b.diags.error(
                    site,
                    format!("`{key}=` must be between 1 and {MAX_IMAGE_SIDE}, found {x}"),
                    None,
                );
            }
        }
    }
    // Reals, as every lineage's camera holds them; at most MAX_QUALITY (an
    // error at the line); above SLOW_QUALITY a warning says what they cost.
    let max_quality = f64::from(MAX_QUALITY);
    for (key, target, rays, what) in [
        (
            "shade_quality",
            &mut cam.shade_quality,
            "shadow rays per shading point towards each area light",
            "area lights",
        ),
        (
            "drefl_quality",
            &mut cam.drefl_quality,
            "rays per glossy reflection",
            "glossy reflections",
        ),
    ] {
        let Some((quality, site)) = b.fields.num(key) else {
            continue;
        };
        if quality < 0.0 {
            let message = format!("`{key}=` must not be negative, found {quality}");
            b.diags.error(site, message, None);
            continue;
        }
        let Some((quality, site)) = b.count(key, max_quality) else {
            continue;
        };
        *target = quality;
        if quality > f64::from(SLOW_QUALITY) {
            let message = format!(
                "`{key}={quality}` means {} {rays} (the default, 4, means 64): \
                 a scene with {what} will render very slowly",
                (16.0 * quality) as u64
            );
            b.diags.warn(site, message, None);
        }
        fractional_quality(b, key, quality, site);
    }
    if let Some((x, _)) = b.count("dofSample", f64::from(u32::MAX)) {
        cam.dof.samples = x as u32;
    }
    // Exactly 2^64: the first whole number that does not fit.
    let max64 = 18_446_744_073_709_551_615.0;
    let photons = &mut cam.photons;
    for (key, target) in [
        ("max_photons", &mut photons.max_photons),
        ("emit_photons", &mut photons.emit_photons),
        ("sample_photons", &mut photons.sample_photons),
    ] {
        if let Some((x, _)) = b.count(key, max64) {
            *target = x as u64;
        }
    }
    for (key, target) in [
        ("max_hitpoints", &mut photons.max_hitpoints),
        ("iterations", &mut photons.iterations),
    ] {
        if let Some((x, _)) = b.count(key, max64) {
            *target = Some(x as u64);
        }
    }
    if let Some(x) = b.non_negative("sample_dist") {
        photons.sample_dist = x;
    }
    if let Some((x, site)) = b.fields.num("reduction") {
        if x > 0.0 && x <= 1.0 {
            photons.reduction = Some(x);
        } else {
            let message = format!("`reduction=` must be in (0, 1], found {x}");
            let help = "the radius update keeps this share of each pass's photons: 0.7 is usual";
            b.diags.error(site, message, Some(help.to_string()));
        }
    }
    for key in [
        "emit_photons",
        "max_photons",
        "sample_photons",
        "sample_dist",
        "max_hitpoints",
        "iterations",
        "reduction",
    ] {
        if b.fields.get(key).is_some() {
            photons.keys.push(key);
        }
    }
    if let Some(x) = b.non_negative("aperture") {
        cam.dof.aperture = x;
    }
    if let Some(x) = b.non_negative("focalLen") {
        cam.dof.focal_len = x;
    }
    if let Some((dx, site)) = b.fields.v3("Dx") {
        match unit(dx) {
            Some(dx) => cam.right = Some(dx),
            None => b.diags.warn(
                site,
                "`Dx=` has zero length; the image's right-hand direction is taken from `N=`",
                None,
            ),
        }
    }
    if let Some((name, site)) = b.fields.text("algorithm") {
        const ALGORITHMS: [&str; 5] = ["RC", "RT", "PM", "PPM", "SPPM"];
        if ALGORITHMS.contains(&name) {
            cam.algorithm = Some(name.to_string());
        } else {
            b.diags.warn(
                site,
                format!("unknown algorithm `{name}`; the lineage's default is used"),
                closest(name, &ALGORITHMS).map(|c| format!("did you mean `{c}`?")),
            );
        }
    }
    cam
}

/// Warns where a quality that is not a whole number is read otherwise than
/// as written: the framework's readers count int(16·q) rays (glint at least
/// one), the relatives' dialects read it rounded, as before.
fn fractional_quality(b: &mut BlockKeys<'_>, key: &str, quality: f64, site: Site) {
    if quality.fract() == 0.0 {
        return;
    }
    if quality < 1.0 / 16.0 {
        b.diags.warn_when(
            When::In(Dialect::F),
            site,
            format!(
                "`{key}= {quality}`: int(16 × {quality}) = 0 rays, where the framework would \
                 divide by zero; glint traces 1"
            ),
            None,
        );
    }
    let whole = quality.round().max(1.0);
    b.diags.warn_when(
        When::NotIn(Dialect::F),
        site,
        format!(
            "`{key}= {quality}` is read as {whole} in this dialect (only the framework's \
             readers keep a fraction: int(16 × {quality}) rays)"
        ),
        Some(format!("write `{key}= {whole}`")),
    );
}

/// `light point`: `O=`.
pub(crate) fn point_light(b: &mut BlockKeys<'_>) -> Option<LightKind> {
    Some(LightKind::Point { pos: b.origin() })
}

/// `light square` (`light area`): centre `O=`, half-edge vectors `Dx= Dy=`.
pub(crate) fn square_light(b: &mut BlockKeys<'_>) -> Option<LightKind> {
    b.diags.warn_when(
        When::In(Dialect::W),
        b.header,
        "W samples only a quarter of an area light (shade_quality rays): glint samples \
         all of it, with 16 × shade_quality rays",
        None,
    );
    let center = b.origin();
    let (dx, dy) = b.span_pair("Dx", "Dy")?;
    Some(LightKind::Square { center, dx, dy })
}

/// `light sphere`: centre `O=`, radius `R=`.
pub(crate) fn sphere_light(b: &mut BlockKeys<'_>) -> Option<LightKind> {
    let center = b.origin();
    let radius = b.radius("R")?;
    Some(LightKind::Sphere { center, radius })
}

/// The material keys of a primitive block (its texture loaded through
/// `assets`, a new one handed to `add_texture`).
pub(crate) fn material(
    assets: &mut Assets,
    b: &mut BlockKeys<'_>,
    add_texture: &mut dyn FnMut(Texture) -> u32,
) -> Option<Material> {
    let f = &b.fields;
    let num = |k: &str, d: f64| f.num(k).map_or(d, |(x, _)| x);
    let mut m = Material {
        color: f.v3("color").map_or(DVec3::ZERO, |(v, _)| v),
        diff: num("diff", 0.0),
        spec: num("spec", 0.0),
        refl: num("refl", 0.0),
        drefl: num("drefl", 0.0),
        refr: num("refr", 0.0),
        rindex: num("rindex", 0.0),
        absor: f.v3("absor").map_or(DVec3::ZERO, |(v, _)| v),
        texture: None,
        normal_map: None,
    };
    if let Some((drefl, site)) = f.num("drefl")
        && drefl > 0.0
    {
        b.diags.warn_when(
            When::In(Dialect::W),
            site,
            "W's reader never reads `drefl=` (it is left uninitialised): a plain mirror",
            None,
        );
    }
    let f = &b.fields;
    if let Some((blur, site)) = f.text("blur")
        && blur != "exp"
    {
        b.diags.warn(
            site,
            format!("unknown blur `{blur}`; using `exp`, the only one"),
            closest(blur, &["exp"]).map(|c| format!("did you mean `{c}`?")),
        );
    }
    // Kept as written: the framework's model refracts with index 1, the
    // lineages' take the total-internal-reflection path (integrator/model.rs).
    if m.refr > 0.0 && m.rindex <= 0.0 {
        let site = f
            .num("rindex")
            .or_else(|| f.num("refr"))
            .map_or(b.header, |(_, s)| s);
        b.diags.warn_when(
            When::In(Dialect::F),
            site,
            format!(
                "`refr=` is {} but `rindex=` is {}; using rindex 1 (the framework would produce NaN)",
                m.refr, m.rindex
            ),
            None,
        );
        b.diags.warn_when(
            When::NotIn(Dialect::F),
            site,
            format!(
                "`refr=` is {} but `rindex=` is {}: as in the lineages' renderers, light \
                 entering it is reflected (total internal reflection), so it acts as a mirror",
                m.refr, m.rindex
            ),
            Some("give it an index, e.g. `rindex= 1.5` for glass".to_string()),
        );
    }
    if let Some((name, site)) = b.fields.text("texture") {
        let name = name.to_string();
        m.texture = Some(assets.texture(&name, site, b.diags, add_texture)?);
    }
    if let Some((name, site)) = b.fields.text("NT") {
        let name = name.to_string();
        m.normal_map = Some(assets.texture(&name, site, b.diags, add_texture)?);
    }
    Some(m)
}
