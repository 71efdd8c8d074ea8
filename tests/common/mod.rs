//! Reference helpers shared by the integration tests: independent plane
//! solves, rotations, boxes made of squares written as scene text, and (in
//! [`bezier`]) an independent model of Bézier surfaces of revolution.
//!
//! Each test crate uses only part of this module.
#![allow(dead_code)]

pub mod bezier;

use std::path::{Path, PathBuf};

/// Folder `sub` of the shared scene corpus: `$GLINT_SCENES/sub`, or
/// `../shared/scenes/sub` beside the repository. When it is not there the
/// test says it was skipped and why, and gets `None`; with
/// `GLINT_REQUIRE_CORPUS` set (as `.ci/run` sets it) that is a failure.
pub fn corpus(sub: &str) -> Option<PathBuf> {
    let root = std::env::var_os("GLINT_SCENES")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes"));
    let dir = root.join(sub);
    if dir.is_dir() {
        return Some(dir);
    }
    let why = format!(
        "{} is not there (the shared scenes: ../shared/scenes beside the repository, or set GLINT_SCENES)",
        dir.display()
    );
    if std::env::var_os("GLINT_REQUIRE_CORPUS").is_some() {
        panic!("GLINT_REQUIRE_CORPUS is set but {why}");
    }
    // Straight to stderr, not through eprintln!, which the test harness
    // captures: the note shows in a plain `cargo test` run.
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {why}");
    None
}

/// The `*.txt` scene files of corpus folder `sub`, sorted (none when the
/// corpus is not there; see [`corpus`]).
pub fn corpus_scenes(sub: &str) -> Vec<PathBuf> {
    let Some(dir) = corpus(sub) else {
        return Vec::new();
    };
    let entries =
        std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()));
    let mut files: Vec<_> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "txt"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no scene files in {}", dir.display());
    files
}

use glam::{DMat3, DQuat, DVec3, EulerRot};
use rand::Rng;
use rand_pcg::Pcg64;

/// A rotation from three Euler angles (test-side: glam's quaternion).
pub fn rotation(angles: DVec3) -> DMat3 {
    DMat3::from_quat(DQuat::from_euler(
        EulerRot::XYZ,
        angles.x,
        angles.y,
        angles.z,
    ))
}

/// Solves o + t·d = p0 + β·e1 + γ·e2 by Cramer's rule, as (t, β, γ).
pub fn solve_plane(o: DVec3, d: DVec3, p0: DVec3, e1: DVec3, e2: DVec3) -> Option<(f64, f64, f64)> {
    let det = DMat3::from_cols(-d, e1, e2).determinant();
    if det.abs() < 1e-14 * e1.length() * e2.length() {
        return None;
    }
    let r = o - p0;
    Some((
        DMat3::from_cols(r, e1, e2).determinant() / det,
        DMat3::from_cols(-d, r, e2).determinant() / det,
        DMat3::from_cols(-d, e1, r).determinant() / det,
    ))
}

/// Distance from `p` to the segment [a, b].
pub fn dist_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let s = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (p - (a + ab * s)).length()
}

/// The six faces of a box with centre `c`, orthonormal axes (columns of
/// `rot`) and half-lengths `h`, as `(centre, Dx, Dy)` of `square` blocks,
/// built the way scene files build them: faces normal to +x, −x, +y, −y, +z, −z.
pub fn box_faces(c: DVec3, rot: DMat3, h: DVec3) -> Vec<(DVec3, DVec3, DVec3)> {
    let mut out = Vec::new();
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        for s in [1.0, -1.0] {
            out.push((
                c + rot.col(i) * (h[i] * s),
                rot.col(j) * h[j],
                rot.col(k) * h[k],
            ));
        }
    }
    out
}

/// A vector as scene-file text, every component exactly (shortest round trip).
pub fn scene_vec(v: DVec3) -> String {
    format!("{:?} {:?} {:?}", v.x, v.y, v.z)
}

/// The scene text of a closed box of six `square` blocks ([`box_faces`]).
pub fn box_of_squares_text(c: DVec3, rot: DMat3, h: DVec3) -> String {
    let mut text = String::new();
    for (o, dx, dy) in box_faces(c, rot, h) {
        text += &format!(
            "primitive square\n    O= {}\n    Dx= {}\n    Dy= {}\n    color= 1 1 1\n    diff= 1\nend\n\n",
            scene_vec(o),
            scene_vec(dx),
            scene_vec(dy)
        );
    }
    text
}

/// A point on the edge (or, with `lambda` = ±1, at a corner) of the box:
/// on the faces normal to axes `i` and `j` (sides `si`, `sj`), at `lambda`
/// (in [−1, 1]) along the third axis.
pub fn box_edge_point(
    c: DVec3,
    rot: DMat3,
    h: DVec3,
    (i, si): (usize, f64),
    (j, sj): (usize, f64),
    lambda: f64,
) -> DVec3 {
    let k = 3 - i - j;
    c + rot.col(i) * (h[i] * si) + rot.col(j) * (h[j] * sj) + rot.col(k) * (h[k] * lambda)
}

/// Where a ray from `o` along unit `d` leaves the box (`o` inside or on
/// it): the smallest slab exit distance, computed per axis in the box
/// frame, and |cos| between the ray and the exit face's normal.
pub fn box_exit(c: DVec3, rot: DMat3, h: DVec3, o: DVec3, d: DVec3) -> (f64, f64) {
    let l = rot.transpose() * (o - c);
    let dl = rot.transpose() * d;
    (0..3)
        .filter(|&i| dl[i] != 0.0)
        .map(|i| ((h[i] * dl[i].signum() - l[i]) / dl[i], dl[i].abs()))
        .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
}

/// The value of `"key":` in a one-line JSON object of the probe's shape (numbers, booleans, null, flat arrays).
pub fn json_field<'a>(line: &'a str, key: &str) -> &'a str {
    let k = format!("\"{key}\":");
    let i = line
        .find(&k)
        .unwrap_or_else(|| panic!("no {key} in {line}"))
        + k.len();
    let rest = &line[i..];
    let end = if rest.starts_with('[') {
        rest.find(']').unwrap() + 1
    } else {
        rest.find([',', '}']).unwrap()
    };
    &rest[..end]
}

/// A JSON number (as `json_field` gives it).
pub fn json_number(s: &str) -> f64 {
    s.parse()
        .unwrap_or_else(|_| panic!("`{s}` is not a JSON number"))
}

/// The numbers of a JSON array of `n` of them, such as `[1,-0.5,2e-7]`.
pub fn json_numbers(s: &str, n: usize) -> Vec<f64> {
    let inner = s
        .strip_prefix('[')
        .and_then(|s| s.strip_suffix(']'))
        .unwrap_or_else(|| panic!("`{s}` is not a JSON array"));
    let v: Vec<f64> = inner.split(',').map(json_number).collect();
    assert_eq!(v.len(), n, "{s}");
    v
}

/// A JSON array of exactly three numbers.
pub fn json_vec3(s: &str) -> DVec3 {
    let v = json_numbers(s, 3);
    DVec3::new(v[0], v[1], v[2])
}

/// A uniform random point in the cube [−`half`, `half`)³.
pub fn point_in(rng: &mut Pcg64, half: f64) -> DVec3 {
    DVec3::new(
        rng.random_range(-half..half),
        rng.random_range(-half..half),
        rng.random_range(-half..half),
    )
}

/// A log-uniform size in [lo, hi].
pub fn log_size(rng: &mut Pcg64, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo.ln()..hi.ln()).exp()
}

/// Three log-uniform half-lengths in [lo, hi] (x, y, z drawn in that order).
pub fn half_sizes(rng: &mut Pcg64, lo: f64, hi: f64) -> DVec3 {
    DVec3::new(
        log_size(rng, lo, hi),
        log_size(rng, lo, hi),
        log_size(rng, lo, hi),
    )
}

/// +1 or −1 with even odds.
pub fn random_sign(rng: &mut Pcg64) -> f64 {
    if rng.random_bool(0.5) { 1.0 } else { -1.0 }
}

/// The spec's camera ray through the centre of pixel (x, y) (y counted from
/// the top) of a W × H image: row i = H − 1 − y from the bottom, column j = x,
/// direction N + Dy·(2(i + ½)/H − 1) + Dx·(2(j + ½)/W − 1), with
/// Dx = unit(N × z)·lens_W/2 and Dy = unit(Dx × N)·lens_H/2 (N unit, not
/// along z).
pub fn camera_dir(n: DVec3, lens: (f64, f64), size: (u32, u32), x: u32, y: u32) -> DVec3 {
    let n = n.normalize();
    let right = n.cross(DVec3::Z).normalize();
    let up = right.cross(n);
    let (w, h) = (size.0 as f64, size.1 as f64);
    let i = (size.1 - 1 - y) as f64 + 0.5;
    let j = x as f64 + 0.5;
    (n + up * (lens.1 / 2.0) * (2.0 * i / h - 1.0) + right * (lens.0 / 2.0) * (2.0 * j / w - 1.0))
        .normalize()
}
