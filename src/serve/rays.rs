//! A pixel's rays drawn over the picture: each ray of its `explain` trees
//! projected to the image with the camera (the framework's pinhole), as
//! segments in pixel coordinates the page draws on a canvas.

use crate::integrator::{RayKind, RayNode};
use crate::scene::{Camera, Light, LightKind};
use glam::DVec3;
use serde_json::{Value, json};

/// Segments drawn at most (a 7×7 grid of glossy fans holds thousands).
const MAX_SEGMENTS: usize = 2000;
/// How far a ray that hits nothing is drawn, in units of the camera's
/// distance to the ray's origin (plus one).
const MISS_LENGTH: f64 = 1e3;
/// Points closer than this in front of the camera are clipped away.
const NEAR: f64 = 1e-6;

/// The camera's projection of a `width` × `height` image.
pub(crate) struct Projection {
    origin: DVec3,
    dir: DVec3,
    right: DVec3,
    up: DVec3,
    half_w: f64,
    half_h: f64,
    width: f64,
    height: f64,
}

impl Projection {
    /// The projection of `camera` rendering `width` × `height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Projection {
        let dir = camera.dir.normalize_or(DVec3::Y);
        let right = {
            let r = dir.cross(DVec3::Z);
            if r.length_squared() < 1e-24 {
                DVec3::X
            } else {
                r.normalize()
            }
        };
        Projection {
            origin: camera.origin,
            dir,
            right,
            up: right.cross(dir),
            half_w: camera.lens_w / 2.0,
            half_h: camera.lens_h / 2.0,
            width: width as f64,
            height: height as f64,
        }
    }

    /// Depth of `p` along the view direction.
    fn depth(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.dir)
    }

    /// Where `p` (in front of the camera) lands: (column, row from the top),
    /// in pixels (pixel k's centre at k + ½).
    pub fn point(&self, p: DVec3) -> Option<[f64; 2]> {
        let d = p - self.origin;
        let s = d.dot(self.dir);
        // (A point cut to NEAR may land a rounding step short of it.)
        if s < NEAR / 2.0 || self.half_w == 0.0 || self.half_h == 0.0 {
            return None;
        }
        let b = d.dot(self.right) / s / self.half_w;
        let a = d.dot(self.up) / s / self.half_h;
        let j = (b + 1.0) * self.width / 2.0;
        let i = (a + 1.0) * self.height / 2.0;
        let (x, y) = (j, self.height - i);
        (x.is_finite() && y.is_finite()).then_some([x, y])
    }

    /// The segment a → b cut to the part in front of the camera, projected.
    pub fn segment(&self, a: DVec3, b: DVec3) -> Option<[[f64; 2]; 2]> {
        let (da, db) = (self.depth(a), self.depth(b));
        if da < NEAR && db < NEAR {
            return None;
        }
        let cut = |p: DVec3, dp: f64, q: DVec3, dq: f64| {
            if dp >= NEAR {
                p
            } else {
                p + (q - p) * ((NEAR - dp) / (dq - dp))
            }
        };
        let a2 = cut(a, da, b, db);
        let b2 = cut(b, db, a, da);
        Some([self.point(a2)?, self.point(b2)?])
    }
}

/// The segments of `samples`' rays, and of the shadow rays towards point
/// lights and the centres of area lights: `{"kind", "depth", "from", "to", "hit"}`.
pub(crate) fn segments(samples: &[RayNode], lights: &[Light], view: &Projection) -> Vec<Value> {
    let mut out = Vec::new();
    for s in samples {
        walk(s, lights, view, &mut out);
    }
    out
}

fn walk(node: &RayNode, lights: &[Light], view: &Projection, out: &mut Vec<Value>) {
    if out.len() >= MAX_SEGMENTS {
        return;
    }
    let end = match &node.hit {
        Some(h) if h.t.is_finite() => node.origin + node.direction * h.t,
        _ => {
            let scale = (node.origin - view.origin).length() + 1.0;
            node.origin + node.direction * scale * MISS_LENGTH
        }
    };
    if let Some([from, to]) = view.segment(node.origin, end) {
        out.push(json!({
            "kind": kind(node.kind),
            "depth": node.depth,
            "from": from,
            "to": to,
            "hit": node.hit.is_some(),
        }));
    }
    for term in &node.lights {
        if term.rays == 0 {
            continue;
        }
        let target = match lights.get(term.light as usize).map(|l| &l.kind) {
            Some(LightKind::Point { pos }) => *pos,
            Some(LightKind::Square { center, .. }) | Some(LightKind::Sphere { center, .. }) => {
                *center
            }
            None => continue,
        };
        if let Some([from, to]) = view.segment(end, target)
            && out.len() < MAX_SEGMENTS
        {
            out.push(json!({
                "kind": "shadow",
                "depth": node.depth,
                "from": from,
                "to": to,
                "hit": term.reached < term.rays,
            }));
        }
    }
    for child in &node.children {
        walk(child, lights, view, out);
    }
}

/// The ray kind's name, as `explain --json` writes it.
fn kind(k: RayKind) -> &'static str {
    match k {
        RayKind::Camera => "camera",
        RayKind::Reflection => "reflection",
        RayKind::Glossy { .. } => "glossy",
        RayKind::Refraction => "refraction",
        RayKind::TotalInternalReflection => "total_internal_reflection",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            origin: DVec3::ZERO,
            dir: DVec3::Y,
            lens_w: 1.0,
            lens_h: 0.6,
            ..Camera::default()
        }
    }

    #[test]
    fn points_land_where_the_camera_rays_through_them_start() {
        let v = Projection::new(&camera(), 100, 60);
        // The view direction is the image's centre.
        assert_eq!(v.point(DVec3::new(0.0, 5.0, 0.0)), Some([50.0, 30.0]));
        // N + Dx + Dy (Dx = x·lens_W/2, Dy = z·lens_H/2) is the top-right corner.
        let [x, y] = v.point(DVec3::new(0.5, 1.0, 0.3)).unwrap_or_default();
        assert!((x - 100.0).abs() < 1e-9 && y.abs() < 1e-9, "{x} {y}");
        // Behind the camera: nothing.
        assert_eq!(v.point(DVec3::new(0.0, -1.0, 0.0)), None);
    }

    #[test]
    fn a_segment_through_the_camera_plane_is_cut_at_it() {
        let v = Projection::new(&camera(), 100, 60);
        let s = v.segment(DVec3::new(0.0, -1.0, 0.0), DVec3::new(0.0, 2.0, 0.0));
        assert!(s.is_some());
        assert_eq!(
            v.segment(DVec3::new(0.0, -1.0, 0.0), DVec3::new(1.0, -2.0, 0.0)),
            None
        );
    }
}
