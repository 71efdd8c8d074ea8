//! Lighting, from a coarse grid of camera rays (through the centres of a
//! [`GRID`]-column image of the camera's aspect, the renderer's own camera
//! rays): primitives that the camera sees only on their side facing away
//! from every light, and visible primitives that no light reaches (every
//! shadow ray from where the camera sees them blocked; an area light is
//! tried at its centre and corners). Only surfaces with a `diff=` or
//! `spec=` are judged: a mirror's or glass's colour comes from elsewhere.

use super::finding::{Code, Findings};
use crate::geometry::{Ray, offset_origin};
use crate::integrator::{Ambient, Model};
use crate::render::Renderer;
use crate::scene::{LightKind, Origin};
use glam::DVec3;
use std::collections::BTreeMap;

/// Columns of the grid of camera rays (rows follow the image's aspect).
pub const GRID: u32 = 96;

/// What the grid saw of one block.
#[derive(Default)]
struct Seen {
    /// Camera rays that hit it.
    hits: u32,
    /// Of those, the ones where some light is in front of the surface (L·N > 0).
    facing: u32,
    /// Of those, the ones some light reaches (a shadow ray gets through).
    reached: u32,
}

/// Where shadow rays towards light `light` are aimed: its centre, and the
/// corners of a square light (just inside).
fn targets(kind: LightKind) -> Vec<DVec3> {
    match kind {
        LightKind::Point { pos } => vec![pos],
        LightKind::Sphere { center, .. } => vec![center],
        LightKind::Square { center, dx, dy } => {
            let mut v = vec![center];
            for (a, b) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                v.push(center + (dx * a + dy * b) * 0.99);
            }
            v
        }
    }
}

/// The lighting lints.
pub(crate) fn check(renderer: &Renderer, out: &mut Findings) {
    let scene = renderer.scene();
    let accel = renderer.accel();
    let camera = scene.camera();
    let cols = GRID;
    let rows = ((GRID as f64 * camera.height as f64 / camera.width as f64).round() as u32).max(1);
    let ray_at = renderer.centre_rays(cols, rows);
    let lights = scene.lights();
    let mut seen: BTreeMap<u32, Seen> = BTreeMap::new();
    for y in 0..rows {
        for x in 0..cols {
            let ray = ray_at(x, y);
            let Some((index, hit)) = accel.intersect(&ray, f64::INFINITY) else {
                continue;
            };
            let object = &accel.objects()[index as usize];
            let Origin::Block(b) = object.origin() else {
                continue;
            };
            let m = scene.material_of(object);
            if m.diff <= 0.0 && m.spec <= 0.0 {
                continue;
            }
            let s = object.shape().surface(&ray, &hit);
            let front = s.normal.dot(ray.dir) < 0.0;
            let (side, n) = if front {
                (s.normal, s.shading_normal)
            } else {
                (-s.normal, -s.shading_normal)
            };
            let entry = seen.entry(b).or_default();
            entry.hits += 1;
            let origin = offset_origin(s.point, side);
            let mut facing = false;
            let mut reached = false;
            for (li, light) in lights.iter().enumerate() {
                if (light.center() - s.point).normalize_or_zero().dot(n) <= 0.0 {
                    continue;
                }
                facing = true;
                let own = (!matches!(light.kind, LightKind::Point { .. })).then_some(li as u32);
                reached |= targets(light.kind).into_iter().any(|t| {
                    let to = t - origin;
                    let dist = to.length();
                    dist > 0.0
                        && !accel.occluded_hinted(
                            &Ray::off_surface(origin, to / dist),
                            dist,
                            own,
                            Some(index),
                            &mut None,
                            &mut (),
                        )
                });
            }
            entry.facing += u32::from(facing);
            entry.reached += u32::from(reached);
        }
    }
    // What a surface no light reaches shows: black, or the ambient term of
    // the lineages that have one.
    let unlit = match Model::of(scene.dialect().dialect, camera).ambient {
        Ambient::None => "renders black (the model has no ambient term)",
        _ => "shows the ambient term alone (the background's colour times the surface's)",
    };
    let table = renderer.primitive_table();
    let named = |b: u32| {
        let kind = table.get(&b).map_or("primitive", |e| e.0);
        format!("{kind} #{b}")
    };
    if lights.is_empty() {
        if !seen.is_empty() {
            out.at(
                Code::Unlit,
                None,
                format!("the scene has no light: every diffuse or specular surface {unlit}"),
                "add a `light point` block (e.g. `O=` above the camera, `color= 1 1 1`)"
                    .to_string(),
            );
        }
        return;
    }
    for (b, s) in seen {
        let what = named(b);
        if s.facing == 0 {
            out.block(
                Code::FacesAway,
                b,
                format!("the camera sees {what} only on its side that faces away from every light ({} of {} grid rays): it {unlit}", s.hits, s.hits),
                "move a light to the side of it that the camera sees (or move the camera round to its lit side)".to_string(),
            );
        } else if s.reached == 0 {
            out.block(
                Code::Unlit,
                b,
                format!("no light reaches {what} where the camera sees it: all {} grid rays that face a light find it blocked, so it {unlit}", s.facing),
                "move a light or what blocks it (glass blocks shadow rays in this model); `glint explain` on one of its pixels names the blocker".to_string(),
            );
        }
    }
}
