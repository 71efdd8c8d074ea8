//! `glint probe`: first hits of arbitrary rays, for exact geometry tests and debugging.

use crate::accel::Accel;
use crate::geometry::Ray;
use crate::scene::Scene;
use glam::{DVec2, DVec3};
use std::fmt::Write;

/// The first hit of a ray, as the probe reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeHit {
    /// Distance along the normalised direction.
    pub t: f64,
    /// The hit point.
    pub point: DVec3,
    /// Unit geometric normal, turned to face against the ray.
    pub normal: DVec3,
    /// Whether the ray hit the outside (front) of the surface.
    pub front: bool,
    /// 0-based index of the `primitive` block, in file order (`None` for a light's surface).
    pub primitive: Option<u32>,
    /// Texture coordinates.
    pub uv: DVec2,
}

/// Answers first-hit queries over a scene.
pub struct Prober<'a> {
    accel: Accel<'a>,
}

impl<'a> Prober<'a> {
    /// Builds the acceleration structure for `scene`.
    pub fn new(scene: &'a Scene) -> Self {
        Prober {
            accel: Accel::build(&scene.objects),
        }
    }

    /// The first hit along `dir` (any length but zero) from `origin`.
    pub fn probe(&self, origin: DVec3, dir: DVec3) -> Option<ProbeHit> {
        let ray = Ray::new(origin, dir.normalize());
        let (index, hit) = self.accel.intersect(&ray, f64::INFINITY)?;
        let object = &self.accel.objects()[index as usize];
        let s = object.shape.surface(&ray, &hit);
        let front = s.normal.dot(ray.dir) < 0.0;
        Some(ProbeHit {
            t: hit.t,
            point: s.point,
            normal: if front { s.normal } else { -s.normal },
            front,
            primitive: object.block,
            uv: s.uv,
        })
    }
}

/// Parses one probe input line `ox oy oz dx dy dz`.
pub fn parse_ray(line: &str) -> Result<(DVec3, DVec3), String> {
    let nums: Vec<f64> = line
        .split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .map_err(|_| format!("`{w}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    if nums.len() != 6 {
        return Err(format!(
            "expected 6 numbers `ox oy oz dx dy dz`, found {}",
            nums.len()
        ));
    }
    if nums.iter().any(|v| !v.is_finite()) {
        return Err("numbers must be finite".to_string());
    }
    let d = DVec3::new(nums[3], nums[4], nums[5]);
    if d.length_squared() == 0.0 || !d.length_squared().is_finite() {
        return Err("the direction must not be zero".to_string());
    }
    Ok((DVec3::new(nums[0], nums[1], nums[2]), d))
}

/// The JSON line for a probe answer (`{"hit":false}` for a miss).
pub fn to_json(hit: Option<&ProbeHit>) -> String {
    let Some(h) = hit else {
        return "{\"hit\":false}".to_string();
    };
    let v = |v: DVec3| format!("[{:e},{:e},{:e}]", v.x, v.y, v.z);
    let mut s = String::with_capacity(200);
    let _ = write!(
        s,
        "{{\"hit\":true,\"t\":{:e},\"point\":{},\"normal\":{},\"front\":{},\"primitive\":{},\"uv\":[{:e},{:e}]}}",
        h.t,
        v(h.point),
        v(h.normal),
        h.front,
        h.primitive.map_or("null".to_string(), |p| p.to_string()),
        h.uv.x,
        h.uv.y
    );
    s
}
