//! The view: objects wholly behind the camera or outside its view (their
//! bounding box against the pyramid of the lens), and a lens whose aspect
//! is not the image's.

use super::finding::{Code, Findings};
use super::primitive_blocks::{PrimitiveBlock, name};
use crate::render::Renderer;
use crate::scene::Camera;
use glam::DVec3;

/// How far the lens's aspect may differ from the image's (relatively)
/// before it is said: the framework's own scene1 differs by 1.1 %.
pub const ASPECT_TOLERANCE: f64 = 0.02;

/// The camera's frame as the renderer builds it: right and up (unit) of
/// the view direction `N=` (the framework's rule: right = N × Z).
fn basis(camera: &Camera) -> (DVec3, DVec3, DVec3) {
    let n = camera.dir.normalize_or_zero();
    let right = n.cross(DVec3::Z);
    let right = if right.length_squared() < 1e-24 {
        DVec3::X
    } else {
        right.normalize()
    };
    (n, right, right.cross(n))
}

/// Whether the box's eight corners all lie behind the camera (`Some(true)`),
/// all outside one side of the view (`Some(false)`), or neither (`None`).
fn out_of_view(camera: &Camera, min: DVec3, max: DVec3) -> Option<bool> {
    let (n, right, up) = basis(camera);
    let (hw, hh) = (camera.lens_w / 2.0, camera.lens_h / 2.0);
    let corners: Vec<(f64, f64, f64)> = (0..8)
        .map(|k| {
            let p = DVec3::new(
                if k & 1 == 0 { min.x } else { max.x },
                if k & 2 == 0 { min.y } else { max.y },
                if k & 4 == 0 { min.z } else { max.z },
            ) - camera.origin;
            (p.dot(n), p.dot(right), p.dot(up))
        })
        .collect();
    if corners.iter().all(|&(z, _, _)| z <= 0.0) {
        return Some(true);
    }
    // Outside the side of the view at `x = limit·z` (x: along right or up).
    let beyond = |pick: fn(&(f64, f64, f64)) -> f64, limit: f64, sign: f64| {
        corners.iter().all(|c| sign * pick(c) > c.0 * limit)
    };
    let right = |c: &(f64, f64, f64)| c.1;
    let up = |c: &(f64, f64, f64)| c.2;
    (beyond(right, hw, 1.0)
        || beyond(right, hw, -1.0)
        || beyond(up, hh, 1.0)
        || beyond(up, hh, -1.0))
    .then_some(false)
}

/// The view lints.
pub(crate) fn check(renderer: &Renderer, blocks: &[PrimitiveBlock], out: &mut Findings) {
    let camera = renderer.scene().camera();
    for b in blocks {
        let Some(bounds) = b.bounds.filter(|a| !a.is_empty()) else {
            continue;
        };
        let what = name(b);
        match out_of_view(camera, bounds.min, bounds.max) {
            Some(true) => out.block(
                Code::BehindCamera,
                b.index,
                format!("{what} is wholly behind the camera: no camera ray can see it (only reflections can)"),
                "check its `O=` and the camera's `N=` (the view direction)".to_string(),
            ),
            Some(false) => out.block(
                Code::OutsideView,
                b.index,
                format!("{what} is wholly outside the view of the lens: no camera ray can see it (only reflections can)"),
                "check its position, the camera's `N=`, or widen `lens_W=`/`lens_H=`".to_string(),
            ),
            None => {}
        }
    }
    let (lens, image) = (
        camera.lens_w / camera.lens_h,
        camera.width as f64 / camera.height as f64,
    );
    if lens.is_finite() && image.is_finite() && (lens / image - 1.0).abs() > ASPECT_TOLERANCE {
        let line = renderer.scene().path().and_then(camera_line);
        out.at(
            Code::LensAspect,
            line,
            format!(
                "the lens is {} x {} (aspect {lens:.3}) but the image {} x {} (aspect {image:.3}): the picture is stretched by {:.1} %",
                camera.lens_w,
                camera.lens_h,
                camera.width,
                camera.height,
                (lens / image - 1.0).abs() * 100.0
            ),
            format!(
                "set `lens_H= {:.4}` (lens_W x image_H / image_W), or change the image size",
                camera.lens_w * camera.height as f64 / camera.width as f64
            ),
        );
    }
}

/// The 1-based line of the file's `camera` header (the scene does not keep
/// it), found by reading the file's lines; `None` when it cannot be.
fn camera_line(path: &std::path::Path) -> Option<u32> {
    use std::io::BufRead;
    let file = std::fs::File::open(path).ok()?;
    std::io::BufReader::new(file)
        .lines()
        .map_while(Result::ok)
        .position(|l| l.split_whitespace().next() == Some("camera"))
        .map(|i| i as u32 + 1)
}
