//! Lights and the camera inside closed objects. A point is inside block b
//! when every one of 14 rays from it (the axes and the diagonals) first
//! meets a primitive surface on its back, always b's: a room made of
//! several objects (the framework's Cornell box of huge spheres) is not
//! one object, and an open shape lets some ray out.

use super::finding::{Code, Findings};
use super::primitive_blocks::{PrimitiveBlock, name};
use crate::geometry::Ray;
use crate::render::Renderer;
use crate::scene::{LightKind, Origin};
use glam::DVec3;

/// The directions the test looks in.
fn directions() -> Vec<DVec3> {
    let mut out = Vec::with_capacity(14);
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        out.extend([axis, -axis]);
    }
    for x in [-1.0, 1.0] {
        for y in [-1.0, 1.0] {
            for z in [-1.0, 1.0] {
                out.push(DVec3::new(x, y, z).normalize());
            }
        }
    }
    out
}

/// The block whose inside `p` is in, by the test above; area lights'
/// surfaces are looked through.
pub(crate) fn enclosing(renderer: &Renderer, p: DVec3) -> Option<u32> {
    let objects = renderer.accel().objects();
    let mut found = None;
    for dir in directions() {
        let ray = Ray::new(p, dir);
        let mut best: Option<(crate::geometry::Hit, usize)> = None;
        for (i, o) in objects.iter().enumerate() {
            if o.light().is_some() {
                continue;
            }
            let limit = best.as_ref().map_or(f64::INFINITY, |(h, _)| h.t);
            if let Some(h) = o.shape().intersect(&ray, ray.t_min, limit) {
                best = Some((h, i));
            }
        }
        let (hit, i) = best?;
        let o = &objects[i];
        let s = o.shape().surface(&ray, &hit);
        let Origin::Block(b) = o.origin() else {
            return None;
        };
        let back = s.normal.dot(dir) > 0.0;
        if !back || found.is_some_and(|f| f != b) {
            return None;
        }
        found = Some(b);
    }
    found
}

/// Lights inside closed objects or glass, and the camera inside an object.
pub(crate) fn check(renderer: &Renderer, blocks: &[PrimitiveBlock], out: &mut Findings) {
    let scene = renderer.scene();
    let block = |b: u32| blocks.iter().find(|k| k.index == b);
    for (li, light) in scene.lights().iter().enumerate() {
        let Some(b) = enclosing(renderer, light.center()).and_then(block) else {
            continue;
        };
        let kind = match light.kind {
            LightKind::Point { .. } => "point",
            LightKind::Square { .. } => "square",
            LightKind::Sphere { .. } => "sphere",
        };
        let what = name(b);
        let at = crate::render::place(out.file.as_deref(), scene.block_line(b.index));
        if b.material.refr > 0.0 {
            out.light(
                Code::LightInsideGlass,
                li as u32,
                format!(
                    "light #{li} ({kind}) is inside the glass of {what} ({at}): in this model glass blocks shadow rays, so the light reaches nothing outside it"
                ),
                format!("move the light out of {what}, or make {what} opaque"),
            );
        } else {
            out.light(
                Code::LightInsideObject,
                li as u32,
                format!(
                    "light #{li} ({kind}) is inside {what} ({at}): it lights only the inside, and everything outside is in its shadow"
                ),
                format!("move the light out of {what} (or shrink {what})"),
            );
        }
    }
    let camera = scene.camera();
    if let Some(b) = enclosing(renderer, camera.origin).and_then(block) {
        let what = name(b);
        out.block(
            Code::CameraInsideObject,
            b.index,
            format!(
                "the camera (O= {} {} {}) is inside {what}: every camera ray first meets its inside",
                camera.origin.x, camera.origin.y, camera.origin.z
            ),
            format!("move the camera's `O=` out of {what}"),
        );
    }
}
