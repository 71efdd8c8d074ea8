//! `glint probe`: first hits of arbitrary rays, for exact geometry tests and debugging.

use crate::format::{Limits, NumberError, parse_number, read_bounded};
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

/// How many bad lines of a rays file are reported; the rest are counted.
pub const MAX_RAY_ERRORS: usize = 200;

/// Why a rays file gave no rays.
#[derive(Debug)]
pub enum RaysError {
    /// It could not be read, or broke a limit (1 GiB, 1 MiB a line): what happened.
    Read(String),
    /// Lines that are not rays: the first [`MAX_RAY_ERRORS`] (1-based line,
    /// error) and how many more.
    Lines(Vec<(usize, RayError)>, usize),
}

/// Reads a rays file: one `ox oy oz dx dy dz` per line, `#` comments and
/// blank lines skipped, every line checked before any ray is returned.
pub fn read_rays(input: impl std::io::Read) -> Result<Vec<(DVec3, DVec3)>, RaysError> {
    let bytes = read_bounded(input, Limits::DEFAULT).map_err(|e| RaysError::Read(e.to_string()))?;
    let mut rays = Vec::new();
    let mut errors = Vec::new();
    let mut more = 0;
    for (n, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let parsed = match std::str::from_utf8(line) {
            Ok(text) => {
                let body = text.split('#').next().unwrap_or("");
                if body.trim().is_empty() {
                    continue;
                }
                parse_ray(body)
            }
            Err(e) => Err(RayError {
                column: String::from_utf8_lossy(line.get(..e.valid_up_to()).unwrap_or_default())
                    .chars()
                    .count()
                    + 1,
                message: "not UTF-8 text".to_string(),
            }),
        };
        match parsed {
            Ok(r) => rays.push(r),
            Err(e) if errors.len() < MAX_RAY_ERRORS => errors.push((n + 1, e)),
            Err(_) => more += 1,
        }
    }
    if errors.is_empty() {
        Ok(rays)
    } else {
        Err(RaysError::Lines(errors, more))
    }
}

/// Parses one probe input line `ox oy oz dx dy dz`: numbers as the scene
/// format writes them, within its limits (|x| ≤ 1e100).
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
        let v = parse_number(word).map_err(|e| {
            err(match e {
                NumberError::Malformed => format!("`{word}` is not a number"),
                NumberError::NotFinite => format!("`{word}` is not a finite number"),
                NumberError::TooLarge => {
                    format!("`{word}` is too large (numbers must lie within ±1e100)")
                }
            })
        })?;
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

/// The JSON line for a probe answer (`{"hit":false}` for a miss). JSON has
/// no infinity or NaN: a field with a non-finite number in it (the point of
/// a hit far along a grazing ray, its uv) is written as `null`.
pub fn to_json(hit: Option<&ProbeHit>) -> String {
    let Some(h) = hit else {
        return "{\"hit\":false}".to_string();
    };
    let array = |xs: &[f64]| {
        if xs.iter().all(|x| x.is_finite()) {
            let xs: Vec<String> = xs.iter().map(|x| format!("{x:e}")).collect();
            format!("[{}]", xs.join(","))
        } else {
            "null".to_string()
        }
    };
    let t = if h.t.is_finite() {
        format!("{:e}", h.t)
    } else {
        "null".to_string()
    };
    let mut s = String::with_capacity(200);
    let _ = write!(
        s,
        "{{\"hit\":true,\"t\":{t},\"point\":{},\"normal\":{},\"front\":{},\"primitive\":{},\"uv\":{}}}",
        array(&h.point.to_array()),
        array(&h.normal.to_array()),
        h.front,
        h.primitive.map_or("null".to_string(), |p| p.to_string()),
        array(&h.uv.to_array()),
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
        // The scene's limits: |x| ≤ 1e100, the scene's number syntax.
        let e = parse_ray("1e308 7 -1e308 1e100 1 1e100").unwrap_err();
        assert_eq!(e.column, 1);
        assert!(e.message.contains("1e100"), "{}", e.message);
        assert!(parse_ray("0 0 0 1e100 0 -1e100").is_ok());
        assert_eq!(parse_ray("0 0 0 0x1 0 1").unwrap_err().column, 7);
        assert!(parse_ray("0 0 0 infinity 0 1").is_err());
    }

    #[test]
    fn rays_files_name_their_bad_lines() {
        let r = read_rays(&b"0 0 0 0 0 1 # a\n\n# b\n1 2 3 0 1 0\r\n"[..]).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert_eq!(r.len(), 2);
        let Err(RaysError::Lines(e, 0)) = read_rays(&b"0 0 0 0 0 1\n0 0 \xc3\xa9\xff 0 1"[..])
        else {
            panic!("bad UTF-8 is an error"); // invariant: the test's own fixed input (a failure fails the test)
        };
        assert_eq!((e[0].0, e[0].1.column), (2, 6));
        let many = "x\n".repeat(MAX_RAY_ERRORS + 5);
        let Err(RaysError::Lines(e, 5)) = read_rays(many.as_bytes()) else {
            panic!("errors are capped"); // invariant: the test's own fixed input (a failure fails the test)
        };
        assert_eq!(e.len(), MAX_RAY_ERRORS);
        assert!(matches!(
            read_rays(std::io::repeat(0)),
            Err(RaysError::Read(_))
        ));
    }

    #[test]
    fn json_never_holds_a_non_finite_number() {
        let h = ProbeHit {
            t: 1e300,
            point: DVec3::new(f64::INFINITY, 7.0, f64::NAN),
            normal: DVec3::Z,
            front: true,
            primitive: Some(0),
            uv: DVec2::new(f64::NAN, 0.0),
        };
        let j = to_json(Some(&h));
        assert!(!j.contains("inf") && !j.contains("NaN"), "{j}");
        assert!(
            j.contains("\"point\":null") && j.contains("\"uv\":null"),
            "{j}"
        );
        assert!(j.contains("\"normal\":[0e0,0e0,1e0]"), "{j}");
    }
}
