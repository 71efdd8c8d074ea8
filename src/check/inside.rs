//! Lights and the camera inside closed objects. A point is inside block b
//! when every one of 14 rays from it (the axes and the diagonals) leaves
//! b's own surfaces by their back, and that is the first surface the ray
//! meets, or one of those it meets first at the same distance (to 1e-9
//! relative): the floor a ball rests on, a neighbour sharing a face. A
//! room made of several objects (the framework's Cornell box of huge
//! spheres, each of which holds the room) is not one object: some ray
//! meets another wall first. An open shape lets some ray out.

use super::finding::{Code, Findings};
use super::primitive_blocks::{PrimitiveBlock, name};
use crate::geometry::{Hit, Ray};
use crate::render::Renderer;
use crate::scene::LightKind;
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

/// The block of `blocks` whose inside `p` is in, by the test above (of
/// several, the smallest; planes, unbounded, enclose nothing). Area
/// lights' surfaces are looked through.
pub(crate) fn enclosing<'b>(
    renderer: &Renderer,
    blocks: &'b [PrimitiveBlock],
    p: DVec3,
) -> Option<&'b PrimitiveBlock> {
    let holding: Vec<&PrimitiveBlock> = blocks
        .iter()
        .filter(|b| {
            b.bounds
                .is_some_and(|x| p.cmpge(x.min).all() && p.cmple(x.max).all())
        })
        .collect();
    if holding.is_empty() {
        return None;
    }
    let objects = renderer.accel().objects();
    let every: Vec<u32> = (0..objects.len() as u32)
        .filter(|&i| objects[i as usize].light().is_none())
        .collect();
    // Along each ray, the distance to the first surface of any object.
    let first: Vec<f64> = directions()
        .into_iter()
        .map(|dir| nearest(renderer, &every, p, dir).map_or(f64::INFINITY, |(t, _)| t))
        .collect();
    let volume = |b: &PrimitiveBlock| {
        b.bounds
            .map_or(f64::INFINITY, |x| (x.max - x.min).element_product())
    };
    holding
        .into_iter()
        .filter(|b| {
            directions().into_iter().zip(&first).all(|(dir, &t_first)| {
                nearest(renderer, &b.objects, p, dir)
                    .is_some_and(|(t, back)| back && t <= t_first + 1e-9 * t_first.max(1.0))
            })
        })
        .min_by(|a, b| volume(a).total_cmp(&volume(b)))
}

/// The nearest hit of the ray from `p` towards `dir` on the objects
/// `among`: its distance, and whether it meets a surface's back.
fn nearest(renderer: &Renderer, among: &[u32], p: DVec3, dir: DVec3) -> Option<(f64, bool)> {
    let objects = renderer.accel().objects();
    let ray = Ray::new(p, dir);
    let mut best: Option<(Hit, usize)> = None;
    for &i in among {
        let limit = best.as_ref().map_or(f64::INFINITY, |(h, _)| h.t);
        if let Some(h) = objects[i as usize]
            .shape()
            .intersect(&ray, ray.t_min, limit)
        {
            best = Some((h, i as usize));
        }
    }
    best.map(|(hit, i)| {
        let back = objects[i].shape().surface(&ray, &hit).normal.dot(dir) > 0.0;
        (hit.t, back)
    })
}

/// Lights inside closed objects or glass, and the camera inside an object.
pub(crate) fn check(renderer: &Renderer, blocks: &[PrimitiveBlock], out: &mut Findings) {
    let scene = renderer.scene();
    for (li, light) in scene.lights().iter().enumerate() {
        let Some(b) = enclosing(renderer, blocks, light.center()) else {
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
    if let Some(b) = enclosing(renderer, blocks, camera.origin) {
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
