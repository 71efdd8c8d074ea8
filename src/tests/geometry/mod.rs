//! Exact plane, square, cube, cylinder and triangle intersection and
//! closed meshes, one file per shape, checked against closed forms and
//! independent references: Cramer's-rule plane solves for flat shapes, and for the
//! solids a root search on their convex implicit functions ([`convex`]).
//! The helpers below are shared by the shapes' files (and the OBJ reader's
//! tests); the closed boxes the square and cube suites shoot at are in [`boxes`].

mod boxes;
mod convex;
mod cube;
mod cylinder;
mod mesh;
mod plane;
mod solid_edges;
mod square;
mod triangle;

use crate::geometry::{Hit, Ray};
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use rand::Rng;
use rand_pcg::Pcg64;

/// No upper bound on a ray's distance.
pub(crate) const INF: f64 = f64::INFINITY;

/// A vector from its three coordinates.
pub(crate) fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A ray from `o` along `d`, normalised.
fn ray(o: DVec3, d: DVec3) -> Ray {
    Ray::new(o, d.normalize())
}

/// +1 or −1 from one random `bool`.
fn coin_sign(rng: &mut Pcg64) -> f64 {
    if rng.random::<bool>() { 1.0 } else { -1.0 }
}

/// Asserts `a` is within `tol` of `b`.
#[track_caller]
fn assert_close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tol {tol})");
}

/// Asserts every coordinate of `a` is within `tol` of `b`'s.
#[track_caller]
pub(crate) fn assert_vclose(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).abs().max_element() <= tol, "{a} vs {b} (tol {tol})");
}

/// Asserts both texture coordinates of `a` are within `tol` of `b`'s.
#[track_caller]
fn assert_uv(a: DVec2, b: DVec2, tol: f64) {
    assert!(
        (a - b).abs().max_element() <= tol,
        "uv {a} vs {b} (tol {tol})"
    );
}

/// Vectors with every coordinate in (−r, r).
fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    prop::array::uniform3(-r..r).prop_map(DVec3::from_array)
}

/// The nearest hit among several shapes (a mesh, a cube made of squares).
pub(crate) fn nearest<S>(
    shapes: &[S],
    r: &Ray,
    hit: impl Fn(&S, &Ray, f64, f64) -> Option<Hit>,
) -> Option<(usize, Hit)> {
    let mut best: Option<(usize, Hit)> = None;
    for (i, s) in shapes.iter().enumerate() {
        let t_max = best.map_or(INF, |(_, h)| h.t);
        if let Some(h) = hit(s, r, 0.0, t_max) {
            best = Some((i, h));
        }
    }
    best
}
