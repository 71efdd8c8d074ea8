//! The colon family's blocks (hta1996/Raytracing @e574690, `object.h`,
//! `object.cpp`, `curve.h`): `key: values` lines, read as its reader reads
//! them, into the one scene model.
//!
//! ```text
//! camera
//!     eye: 0 -3 0.8        lookat: 0 0 0.8      up: 0 0 1
//!     fovy: 45             h: 540               w: 960
//!     aperture: 0.03       focal: 4
//! end
//! light area
//!     O: 0 0 1.6   N: 0 0 -1   Dx: 0.25 0 0   Dy: 0 0.25 0
//!     color: 1 1 1         power: 6
//! end
//! primitive rotationbody
//!     scale: 0.25
//!     curve: 0 0 1 0 1 2 0 2
//!     ratio: 1
//!     O: 0 0 0
//! end
//! ```
//!
//! Its reader keeps state from key to key: the camera's view is set up at
//! `w:` from the keys read before it, a `rotationbody`'s `scale:` scales the
//! curves after it and `ratio:` gives a number to each curve before it;
//! glint replays the keys in file order the same way. Where its reader
//! would read memory it never set (a `rotationbody` without `scale:`, a
//! camera without `w:`), glint takes the evident value and says so.

use super::assets::Assets;
use super::block_keys::BlockKeys;
use super::diags::Site;
use super::shapes::{AddTexture, Built, Shapes};
use super::values::{Value, unit};
use crate::geometry::{Bezier, BezierUv, Cylinder, Plane, Shape, Sphere, axis_frame};
use crate::scene::{
    Background, Camera, LightKind, MAX_IMAGE_SIDE, Material, PhotonEmission, Texture,
};
use glam::{DVec2, DVec3};

/// Its camera's depth-of-field rays per pixel (`const.h`
/// `depth_of_field_samples`).
pub(crate) const LENS_SAMPLES: u32 = 16;

/// Below this `aperture:` its camera is a pinhole (`raytracer.cpp` `calcCol`).
const PINHOLE: f64 = 1e-6;

/// `background`: `ambientcolor:`, which is both what a ray that meets
/// nothing sees and the ambient light (`raytracer.cpp` `rayTracing`,
/// `calcIllumination`).
pub(crate) fn background(bg: Background, b: &mut BlockKeys<'_>) -> Background {
    match b.fields.v3("ambientcolor") {
        Some((c, _)) => Background::Color(c),
        None => bg,
    }
}

/// What its camera's `w:` sets the view up from: the direction, `up:`,
/// `fovy:` (each with where it was read) and the image's w/h.
struct View {
    dir: Option<(DVec3, Site)>,
    up: Option<(DVec3, Site)>,
    fovy: Option<(f64, Site)>,
    aspect: f64,
}

/// `camera`: `eye: lookat: up: fovy: w: h: aperture: focal:`, replayed in
/// file order as `Camera::input` reads them: `lookat:` fixes the view
/// direction from the eye read so far (and the focus distance to 1),
/// `w:` sets the image plane up from the direction, `up:`, `fovy:` and
/// `h:` read so far: tan(fovy/2)·w/h wide and tan(fovy/2) high at
/// distance 1, right = unit(direction × up).
pub(crate) fn camera(mut cam: Camera, b: &mut BlockKeys<'_>) -> Camera {
    let mut eye = cam.origin;
    let mut dir: Option<(DVec3, Site)> = Some((cam.dir, b.header));
    let mut up: Option<(DVec3, Site)> = None;
    let mut fovy: Option<(f64, Site)> = None;
    let (mut width, mut height) = (f64::from(cam.width), f64::from(cam.height));
    let mut aperture = cam.dof.aperture;
    let mut focal = cam.dof.focal_len;
    // What `w:` saw.
    let mut view: Option<View> = None;
    for f in b.fields.list() {
        match (f.name, &f.value) {
            ("eye", Value::V3(v)) => eye = *v,
            ("lookat", Value::V3(v)) => {
                dir = unit(*v - eye).map(|d| (d, f.site));
                focal = if dir.is_some() { 1.0 } else { 0.0 };
            }
            ("up", Value::V3(v)) => up = Some((*v, f.site)),
            ("fovy", Value::Num(x)) => fovy = Some((*x, f.site)),
            ("h", Value::Num(x)) => height = *x,
            ("w", Value::Num(x)) => {
                width = *x;
                view = Some(View {
                    dir,
                    up,
                    fovy,
                    aspect: width / height,
                });
            }
            ("aperture", Value::Num(x)) => aperture = *x,
            ("focal", Value::Num(x)) => focal = *x,
            _ => {}
        }
    }
    for (key, x) in [("w", width), ("h", height)] {
        if (1.0..=f64::from(MAX_IMAGE_SIDE)).contains(&x) {
            continue;
        }
        let site = b.fields.get(key).map_or(b.header, |f| f.site);
        b.diags.error(
            site,
            format!("`{key}:` must be between 1 and {MAX_IMAGE_SIDE}, found {x}"),
            None,
        );
        return cam;
    }
    let view = view.unwrap_or_else(|| {
        b.diags.warn(
            b.header,
            "this camera has no `w:`, where its reader sets the view up; glint sets it up \
             from the block's keys",
            None,
        );
        View {
            dir,
            up,
            fovy,
            aspect: width / height,
        }
    });
    let View {
        dir,
        up,
        fovy,
        aspect,
    } = view;
    let Some((dir, _)) = dir else {
        let site = b.fields.get("lookat").map_or(b.header, |f| f.site);
        b.diags.error(
            site,
            "`lookat:` equals `eye:`: the camera has no view direction",
            None,
        );
        return cam;
    };
    let Some(right) = up.and_then(|(u, _)| unit(dir.cross(u))) else {
        let site = up.map_or(b.header, |(_, s)| s);
        b.diags.error(
            site,
            "`up:` is missing, zero or along the view direction: the camera has no image plane",
            Some("its files say `up: 0 0 1`".to_string()),
        );
        return cam;
    };
    let half = match fovy {
        Some((deg, _)) if deg > 0.0 && deg < 180.0 => (deg.to_radians() / 2.0).tan(),
        other => {
            let site = other.map_or(b.header, |(_, s)| s);
            b.diags.error(
                site,
                "`fovy:` (the vertical field of view, in degrees) must lie between 0 and 180",
                None,
            );
            return cam;
        }
    };
    if aperture < 0.0 || focal < 0.0 {
        let key = if aperture < 0.0 { "aperture" } else { "focal" };
        let site = b.fields.get(key).map_or(b.header, |f| f.site);
        b.diags
            .error(site, format!("`{key}:` must not be negative"), None);
        return cam;
    }
    cam.origin = eye;
    cam.dir = dir;
    cam.right = Some(right);
    cam.lens_h = 2.0 * half;
    cam.lens_w = 2.0 * half * aspect;
    (cam.width, cam.height) = (width as u32, height as u32);
    cam.dof.aperture = if aperture < PINHOLE { 0.0 } else { aperture };
    cam.dof.focal_len = focal;
    cam.dof.samples = LENS_SAMPLES;
    cam
}

/// `light area`: centre `O:`, half-edge vectors `Dx: Dy:` (its surface and
/// shadow samples; `N:` is the side its photons leave on, see [`emission`]).
pub(crate) fn area_light(b: &mut BlockKeys<'_>) -> Option<LightKind> {
    let center = b.origin();
    let (dx, dy) = b.span_pair("Dx", "Dy")?;
    Some(LightKind::Square { center, dx, dy })
}

/// What a light's `power:` and an area light's `N:` say of its photons.
pub(crate) fn emission(b: &mut BlockKeys<'_>) -> PhotonEmission {
    let mut e = PhotonEmission::default();
    if let Some((p, site)) = b.fields.num("power") {
        if p >= 0.0 {
            e.power = Some(p);
        } else {
            b.diags.error(
                site,
                format!("`power:` must not be negative, found {p}"),
                None,
            );
        }
    }
    if b.title == "light area" {
        match b.fields.v3("N").map(|(n, site)| (unit(n), site)) {
            Some((Some(n), _)) => e.normal = Some(n),
            Some((None, site)) => b.diags.warn(
                site,
                "`N:` has zero length: the light's photons leave on both sides",
                None,
            ),
            None => b.diags.warn(
                b.header,
                "this area light has no `N:`: its photons leave on both sides",
                Some("its files say `N: 0 0 -1` for a light facing down".to_string()),
            ),
        }
    }
    e
}

/// The material keys of a colon-family primitive, with its defaults (colour
/// 1 1 1, diff 0.8, spec 0.2, rindex 1: `object.h` `Material`). Its reader
/// draws spheres and cylinders untextured, so a `texture:` there is not loaded.
pub(crate) fn material(
    assets: &mut Assets,
    b: &mut BlockKeys<'_>,
    add_texture: &mut dyn FnMut(Texture) -> u32,
) -> Option<Material> {
    let f = &b.fields;
    let num = |k: &str, d: f64| f.num(k).map_or(d, |(x, _)| x);
    let mut m = Material {
        color: f.v3("color").map_or(DVec3::ONE, |(v, _)| v),
        diff: num("diff", 0.8),
        spec: num("spec", 0.2),
        refl: num("refl", 0.0),
        drefl: 0.0,
        refr: num("refr", 0.0),
        rindex: num("rindex", 1.0),
        absor: f.v3("absor").map_or(DVec3::ZERO, |(v, _)| v),
        texture: None,
        normal_map: None,
    };
    if let Some((name, site)) = b.fields.text("texture") {
        if matches!(b.title, "primitive sphere" | "primitive cylinder") {
            b.diags.warn(
                site,
                format!(
                    "its reader draws a `{}` untextured (`textureColor` is white); `texture:` ignored",
                    b.title
                ),
                None,
            );
        } else {
            let name = name.to_string();
            m.texture = Some(assets.texture_run_below(&name, site, b.diags, add_texture)?);
        }
    }
    Some(m)
}

/// `primitive sphere`: `O: R:` (`Dx: Dz:` orient a texture its reader never draws).
pub(crate) fn sphere(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let origin = b.origin();
    let r = b.radius("R")?;
    Built::one(Shape::Sphere(Sphere::new(origin, r)))
}

/// `primitive plane`: the points P with N·P + d = 0; a texture tiles it
/// from the corner `Do:`, its columns along `Dx:` and its rows down `Dy:`
/// (u = (P − Do)·Dx/|Dx|², v = (P − Do)·Dy/|Dy|², row v from the top).
pub(crate) fn plane(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let textured = b.textured();
    let (n, site) = b.need_v3("N", "its normal")?;
    let Some(un) = unit(n) else {
        b.diags
            .error(site, "`N:` has zero length; a plane needs a normal", None);
        return None;
    };
    let d = b.fields.num("d").map_or(0.0, |(x, _)| x);
    let corner = b.fields.v3("Do").map_or(DVec3::ZERO, |(v, _)| v);
    let dx = b.texture_axis("Dx", textured);
    let dy = b.texture_axis("Dy", textured);
    let (columns, rows) = match (dx?, dy?) {
        (Some(dx), Some(dy)) => (dx, dy),
        (Some(dx), None) => (dx, un.cross(dx)),
        (None, Some(dy)) => (dy.cross(un), dy),
        (None, None) => axis_frame(un),
    };
    // glint's plane texture takes its row (from the bottom) along `dx` and
    // its column along `dy`: the rows run up against `Dy:`, from `Do:`.
    let mut plane = Plane::new(un, -d / n.length(), -rows, columns);
    plane.uv_shift = DVec2::new(
        corner.dot(rows) / rows.length_squared(),
        -corner.dot(columns) / columns.length_squared(),
    );
    Built::one(Shape::Plane(Box::new(plane)))
}

/// `primitive cylinder`: upright, its base centred at `O:`, radius `R:`,
/// height `H:`, closed at both ends (`ang:` turns a texture its reader never draws).
pub(crate) fn cylinder(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let origin = b.origin();
    let r = b.radius("R");
    let h = b.height("H");
    let (r, h) = (r?, h?);
    Built::one(Shape::Cylinder(Box::new(Cylinder::new(
        origin,
        origin + DVec3::Z * h,
        r,
    ))))
}

/// `primitive rotationbody`: cubic Bézier curves `curve: x0 y0 … x3 y3`
/// (radius x, height y, times the `scale:` read before them) turned about
/// the upright axis through its base centre `O:`; each curve is an exact
/// glint `bezier`, its texture's rows the curve's share of `ratio:` (one
/// number a curve, from the bottom of the picture up as the curves go) and
/// its columns the angle about +z from `ang:` degrees, counter-clockwise
/// (`object.h` `RotationBody`).
pub(crate) fn rotation_body(
    _: &mut Assets,
    b: &mut BlockKeys<'_>,
    _: &mut AddTexture<'_>,
) -> Shapes {
    let base = b.need_v3(
        "O",
        "its base centre, read last: its reader builds the body there",
    );
    let mut scale: Option<f64> = None;
    let mut curves: Vec<[DVec2; 4]> = Vec::new();
    let mut ratios: Vec<f64> = Vec::new();
    let mut ang = 0.0;
    let mut unscaled: Option<Site> = None;
    for f in b.fields.list() {
        match (f.name, &f.value) {
            ("scale", Value::Num(x)) => scale = Some(*x),
            ("ang", Value::Num(x)) => ang = x.to_radians(),
            ("curve", Value::List(v)) => {
                if v.len() != 8 {
                    b.diags.warn(
                        f.site,
                        format!(
                            "`curve:` takes 8 numbers (4 points x y), found {}: {}",
                            v.len(),
                            if v.len() < 8 {
                                "the missing ones read as 0"
                            } else {
                                "the rest is ignored"
                            }
                        ),
                        None,
                    );
                }
                if scale.is_none() {
                    unscaled.get_or_insert(f.site);
                }
                let s = scale.unwrap_or(1.0);
                let at = |k: usize| v.get(k).copied().unwrap_or(0.0) * s;
                curves.push([0, 2, 4, 6].map(|k| DVec2::new(at(k), at(k + 1))));
            }
            ("ratio", Value::List(v)) => {
                ratios.extend((0..curves.len()).map(|k| v.get(k).copied().unwrap_or(0.0)));
            }
            _ => {}
        }
    }
    if let Some(site) = unscaled {
        b.diags.warn(
            site,
            "no `scale:` before this curve: its reader would scale it by memory it never set; \
             glint scales by 1",
            Some("add `scale: 1` before the curves".to_string()),
        );
    }
    let (base, _) = base?;
    if curves.is_empty() {
        b.diags.error(
            b.header,
            "a `primitive rotationbody` needs at least one `curve:` (8 numbers: 4 points x y)",
            None,
        );
        return None;
    }
    let (e1, e2) = (
        DVec3::new(ang.cos(), ang.sin(), 0.0),
        DVec3::new(-ang.sin(), ang.cos(), 0.0),
    );
    let mut start = 0.0;
    let shapes = curves
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let share = ratios.get(k).copied().unwrap_or(0.0);
            // glint's profile points are (height, radius).
            let profile = c.iter().map(|p| DVec2::new(p.y, p.x)).collect();
            let shape = Bezier::new(base, base + DVec3::Z, profile)
                .with_angle_frame(e1, e2)
                .with_uv(BezierUv::Span {
                    start,
                    length: share,
                });
            start += share;
            Shape::Bezier(Box::new(shape))
        })
        .collect();
    Built::of(shapes)
}
