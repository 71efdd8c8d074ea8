//! `glint probe`: first hits of arbitrary rays, for exact geometry tests and debugging.

use crate::geometry::Ray;
use crate::render::Renderer;
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

impl Renderer {
    /// The first hit along `dir` (any length but zero) from `origin`.
    pub fn probe(&self, origin: DVec3, dir: DVec3) -> Option<ProbeHit> {
        let ray = Ray::new(origin, dir.normalize());
        let accel = self.accel();
        let (index, hit) = accel.intersect(&ray, f64::INFINITY)?;
        let object = &accel.objects()[index as usize];
        let s = object.shape().surface(&ray, &hit);
        let front = s.normal.dot(ray.dir) < 0.0;
        Some(ProbeHit {
            t: hit.t,
            point: s.point,
            normal: if front { s.normal } else { -s.normal },
            front,
            primitive: object.block(),
            uv: s.uv,
        })
    }
}

/// Why a probe input line is not a ray.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RayError {
    /// 1-based column of the offending word (1 for the line as a whole).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// Parses one probe input line `ox oy oz dx dy dz`.
pub fn parse_ray(line: &str) -> Result<(DVec3, DVec3), RayError> {
    let mut nums = [0.0f64; 6];
    let mut count = 0;
    for (col, word) in words(line) {
        let err = |message: String| RayError {
            column: col,
            message,
        };
        if count == 6 {
            return Err(err(format!(
                "unexpected `{word}`: a ray is 6 numbers `ox oy oz dx dy dz`"
            )));
        }
        let v: f64 = word
            .parse()
            .map_err(|_| err(format!("`{word}` is not a number")))?;
        if !v.is_finite() {
            return Err(err(format!("`{word}` is not a finite number")));
        }
        nums[count] = v;
        count += 1;
    }
    if count != 6 {
        return Err(RayError {
            column: line.chars().count() + 1,
            message: format!("expected 6 numbers `ox oy oz dx dy dz`, found {count}"),
        });
    }
    let d = DVec3::new(nums[3], nums[4], nums[5]);
    let len2 = d.length_squared();
    if len2 == 0.0 || !len2.is_finite() {
        return Err(RayError {
            column: 1,
            message: "the direction must be a non-zero finite vector".to_string(),
        });
    }
    Ok((DVec3::new(nums[0], nums[1], nums[2]), d))
}

/// The whitespace-separated words of a line with their 1-based columns.
fn words(line: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut col = 0;
    let mut rest = line;
    std::iter::from_fn(move || {
        let skip = rest.len() - rest.trim_start().len();
        col += rest[..skip].chars().count();
        rest = &rest[skip..];
        if rest.is_empty() {
            return None;
        }
        let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
        let (word, tail) = rest.split_at(end);
        let at = col + 1;
        col += word.chars().count();
        rest = tail;
        Some((at, word))
    })
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

/// A human-readable line for a probe answer.
pub fn to_text(hit: Option<&ProbeHit>) -> String {
    let Some(h) = hit else {
        return "miss".to_string();
    };
    let prim = h
        .primitive
        .map_or("light".to_string(), |p| format!("primitive {p}"));
    format!(
        "hit {prim} t={} point=({}, {}, {}) normal=({}, {}, {}) {} uv=({}, {})",
        h.t,
        h.point.x,
        h.point.y,
        h.point.z,
        h.normal.x,
        h.normal.y,
        h.normal.z,
        if h.front { "front" } else { "back" },
        h.uv.x,
        h.uv.y
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_rays_and_points_at_bad_words() {
        assert_eq!(
            parse_ray("  1 2 3   0 .5 -1e-3").ok(),
            Some((DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.0, 0.5, -1e-3)))
        );
        let e = parse_ray("1 2 x 0 0 1").unwrap_err();
        assert_eq!(e.column, 5);
        let e = parse_ray("1 2 3 0 0").unwrap_err();
        assert!(e.message.contains("found 5"), "{}", e.message);
        let e = parse_ray("1 2 3 0 0 1 7").unwrap_err();
        assert_eq!(e.column, 13);
        assert!(parse_ray("0 0 0 0 0 0").is_err());
        assert!(parse_ray("0 0 0 1e999 0 0").is_err());
    }
}
