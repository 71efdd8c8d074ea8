//! Exact square, cube, cylinder and triangle intersection, boxes of squares
//! read from scene files (no crack, leak or double hit), and OBJ loading,
//! checked against closed forms and independent references: Cramer's-rule
//! plane solves for flat shapes, and for the solids a root search on their
//! convex implicit functions (golden-section minimum + bisection).

use super::common::{box_faces, dist_to_segment, point_in, rotation, solve_plane};
use crate::Scene;
use crate::accel::Accel;
use crate::format::load_obj;
use crate::geometry::*;
use crate::scene::Object;
use glam::{DMat3, DVec2, DVec3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

const INF: f64 = f64::INFINITY;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn ray(o: DVec3, d: DVec3) -> Ray {
    Ray::new(o, d.normalize())
}

/// +1 or −1 from one random `bool`.
fn coin_sign(rng: &mut Pcg64) -> f64 {
    if rng.random::<bool>() { 1.0 } else { -1.0 }
}

#[track_caller]
fn assert_close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b} (tol {tol})");
}

#[track_caller]
fn assert_vclose(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).abs().max_element() <= tol, "{a} vs {b} (tol {tol})");
}

#[track_caller]
fn assert_uv(a: DVec2, b: DVec2, tol: f64) {
    assert!(
        (a - b).abs().max_element() <= tol,
        "uv {a} vs {b} (tol {tol})"
    );
}

fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    prop::array::uniform3(-r..r).prop_map(DVec3::from_array)
}

/// The nearest hit among several shapes (a mesh, a cube made of squares).
fn nearest<S>(
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

// ---------------------------------------------------------------- squares

#[test]
fn square_closed_form_hit_normal_and_uv() {
    let sq = Square::new(v(1.0, 2.0, 3.0), v(2.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
    // From above, straight down onto (1.5, 2.5, 3).
    let r = ray(v(1.5, 2.5, 10.0), -DVec3::Z);
    let h = sq.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 7.0);
    let s = sq.surface(&r, &h);
    assert_eq!(s.point, v(1.5, 2.5, 3.0));
    assert_eq!(s.normal, DVec3::Z);
    assert_eq!(s.shading_normal, DVec3::Z);
    // u = 0.5·2/4/2 + 1/2, v = 0.5·1/1/2 + 1/2.
    assert_uv(s.uv, DVec2::new(0.625, 0.75), 1e-15);
    // Two-sided: from below, same normal (the spec's unit(Dx × Dy)).
    let r = ray(v(1.5, 2.5, -1.0), DVec3::Z);
    let h = sq.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 4.0);
    assert_eq!(sq.surface(&r, &h).normal, DVec3::Z);
    // Corners map to uv (0,0) and (1,1).
    let r = ray(v(-1.0, 1.0, 5.0), -DVec3::Z);
    let h = sq.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_uv(sq.surface(&r, &h).uv, DVec2::new(0.0, 0.0), 1e-15);
    let r = ray(v(3.0, 3.0, 5.0), -DVec3::Z);
    let h = sq.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_uv(sq.surface(&r, &h).uv, DVec2::new(1.0, 1.0), 1e-15);
    // Outside, behind, beyond t_max, parallel: misses.
    assert!(
        sq.intersect(&ray(v(3.1, 2.5, 10.0), -DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert!(
        sq.intersect(&ray(v(1.5, 2.5, 10.0), DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert!(
        sq.intersect(&ray(v(1.5, 2.5, 10.0), -DVec3::Z), 0.0, 7.0)
            .is_none()
    );
    assert!(
        sq.intersect(&ray(v(1.5, 2.5, 10.0), -DVec3::Z), 7.0, INF)
            .is_none()
    );
    assert!(
        sq.intersect(&ray(v(-5.0, 2.5, 3.0), DVec3::X), 0.0, INF)
            .is_none()
    );
    assert!(
        sq.intersect(&ray(v(-5.0, 2.5, 4.0), DVec3::X), 0.0, INF)
            .is_none()
    );
}

#[test]
fn square_skewed_parallelogram() {
    // Dx = (1,0,0), Dy = (1,1,0): the parallelogram with corners O ± Dx ± Dy.
    let sq = Square::new(DVec3::ZERO, v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0));
    // (1.9, 0.95) = 0.95·Dx + 0.95·Dy: inside; (−1.5, 0.5) = −2·Dx + 0.5·Dy: outside
    // although inside the square's axis-aligned box.
    let r = ray(v(1.9, 0.95, 2.0), -DVec3::Z);
    assert_eq!(sq.intersect(&r, 0.0, INF).unwrap().t, 2.0); // invariant: the test's own fixed input (a failure fails the test)
    assert!(
        sq.intersect(&ray(v(-1.5, 0.5, 2.0), -DVec3::Z), 0.0, INF)
            .is_none()
    );
    // The spec's uv is a projection on Dx, Dy: at C = (1.9, 0.95, 0)
    // u = 1.9/1/2 + 1/2, v = (1.9 + 0.95)/2/2 + 1/2.
    let h = sq.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_uv(sq.surface(&r, &h).uv, DVec2::new(1.45, 1.2125), 1e-12);
    // A degenerate square (Dx ∥ Dy) is never hit and does not panic.
    let flat = Square::new(DVec3::ZERO, DVec3::X, DVec3::X * 2.0);
    assert!(
        flat.intersect(&ray(v(0.0, 0.0, 1.0), -DVec3::Z), 0.0, INF)
            .is_none()
    );
}

/// Boxes (centre, rotation, half-lengths) to shoot at the edges of: unit, rotated and flat, rotated, tiny and far from the origin.
fn edge_box_configs() -> [(DVec3, DMat3, DVec3); 3] {
    [
        (DVec3::ZERO, DMat3::IDENTITY, DVec3::ONE),
        (
            v(0.1, -0.3, 0.7),
            rotation(v(0.3, -1.1, 2.0)),
            v(0.3, 1.7, 0.05),
        ),
        (
            v(1000.1, -999.7, 250.3),
            rotation(v(-0.7, 0.2, 0.9)),
            v(0.011, 0.013, 0.017),
        ),
    ]
}

/// Rays through edges, corners and points a hair from an edge of a closed
/// box, all of which must hit: entering from outside (expected distance
/// known) and leaving from inside. `hit` finds the nearest hit of the solid.
fn shoot_at_box_edges(
    c: DVec3,
    rot: DMat3,
    h: DVec3,
    seed: u64,
    rays: usize,
    hit: impl Fn(&Ray) -> Option<Hit>,
) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let size = h.max_element();
    let scale = c.abs().max_element() + size;
    for n in 0..rays {
        // An edge along axis k, on the faces normal to axes i and j.
        let k = rng.random_range(0..3usize);
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (si, sj) = (coin_sign(&mut rng), coin_sign(&mut rng));
        let corner = n % 4 == 0;
        let lambda: f64 = if corner {
            coin_sign(&mut rng)
        } else if n % 4 == 1 {
            0.0
        } else {
            rng.random_range(-0.999..0.999)
        };
        let mut target = super::common::box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
        // Slide a hair onto face j (still on the closed box): 0 or 1e-16 .. 1e-10 of the size.
        if n % 3 == 2 {
            let eps = size * 10f64.powf(rng.random_range(-16.0..-10.0));
            target -= rot.col(i) * (si * eps);
        }
        // Outside, beyond both faces (and beyond the end face at a corner): the
        // ray enters the box through `target`.
        let (a, b) = (rng.random_range(0.05..1.0), rng.random_range(0.05..1.0));
        let g = if corner {
            lambda * rng.random_range(0.05..1.0)
        } else {
            rng.random_range(-0.5..0.5)
        };
        let out = (rot.col(i) * (si * a) + rot.col(j) * (sj * b) + rot.col(k) * g).normalize();
        let dist = size * rng.random_range(0.5..20.0);
        let r = Ray::new(target + out * dist, -out);
        let got = hit(&r).unwrap_or_else(|| panic!("crack: ray {r:?} entering at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(got.t, dist, 1e-9 * (scale + dist));
        // From inside towards the same point.
        let l = point_in(&mut rng, 0.99) * h;
        let inside = c + rot * l;
        let r = Ray::new(inside, (target - inside).normalize());
        let got = hit(&r).unwrap_or_else(|| panic!("crack: ray {r:?} leaving at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(got.t, (target - inside).length(), 1e-9 * scale);
    }
}

#[test]
fn six_squares_forming_a_cube_leave_no_crack() {
    for (n, (c, rot, h)) in edge_box_configs().into_iter().enumerate() {
        let squares: Vec<Square> = box_faces(c, rot, h)
            .into_iter()
            .map(|(o, dx, dy)| Square::new(o, dx, dy))
            .collect();
        shoot_at_box_edges(c, rot, h, 10 + n as u64, 20_000, |r| {
            nearest(&squares, r, |s, r, a, b| s.intersect(r, a, b)).map(|(_, h)| h)
        });
    }
}

/// Boxes as scene files build them from six `square` blocks: unit, the
/// framework's kind (axis-aligned, decimal), rotated and flat, far from the
/// origin and tiny, rotated and long, axis-aligned thin and far.
fn square_box_configs() -> Vec<(DVec3, DMat3, DVec3)> {
    let [unit, flat, tiny] = edge_box_configs();
    vec![
        unit,
        (v(1.5, 6.2, -0.3), DMat3::IDENTITY, v(0.5, 0.7, 0.9)),
        flat,
        tiny,
        (DVec3::ZERO, rotation(v(0.0, 0.0, 0.785)), v(10.0, 0.1, 0.1)),
        (v(-3.7, 0.25, 12.9), DMat3::IDENTITY, v(2.3, 0.01, 4.4)),
        (
            v(1000.1, -999.7, 250.3),
            DMat3::IDENTITY,
            v(0.011, 0.013, 0.017),
        ),
    ]
}

/// A random point of the box's edges: on an edge, at its middle, at a
/// corner, or a hair (1e-16 .. 1e-10 of the size) from an edge onto one of
/// its two faces (still on the closed surface).
fn random_edge_point(rng: &mut Pcg64, c: DVec3, rot: DMat3, h: DVec3, m: usize) -> DVec3 {
    let i = rng.random_range(0..3usize);
    let j = (i + 1 + rng.random_range(0..2usize)) % 3;
    let si = coin_sign(rng);
    let sj = coin_sign(rng);
    let lambda = match m % 4 {
        0 => si * sj,
        1 => 0.0,
        _ => rng.random_range(-1.0..1.0),
    };
    let mut p = super::common::box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
    if m % 3 == 2 {
        let eps = h.max_element() * 10f64.powf(rng.random_range(-16.0..-10.0));
        p -= if rng.random::<bool>() {
            rot.col(i) * (si * eps)
        } else {
            rot.col(j) * (sj * eps)
        };
    }
    p
}

/// A closed box of six `square` blocks, read from scene text and queried
/// through the acceleration structure the renderer's shadow rays use:
/// every shadow ray from inside (from an interior point, or from a point of
/// an inner face nudged off it as the renderer does) to a light outside,
/// passing exactly through an edge or a corner or a hair beside one, is
/// blocked; from interior points its nearest hit is where it crosses the edge.
#[test]
fn six_square_box_scene_leaks_no_light_through_edges_or_corners() {
    let mut rng = Pcg64::seed_from_u64(51);
    for (c, rot, h) in square_box_configs() {
        let scene = Scene::parse(&super::common::box_of_squares_text(c, rot, h), ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert_eq!(scene.objects().len(), 6);
        let accel = Accel::build(scene.objects().to_vec());
        let size = h.max_element();
        let scale = c.abs().max_element() + size;
        for m in 0..6000 {
            let target = random_edge_point(&mut rng, c, rot, h, m);
            let interior = m % 2 == 0;
            let origin = if interior {
                let l = point_in(&mut rng, 0.99);
                c + rot * (l * h)
            } else {
                let fa = rng.random_range(0..3usize);
                let fs = coin_sign(&mut rng);
                let mut l = point_in(&mut rng, 1.0) * h;
                l[fa] = fs * h[fa];
                offset_origin(c + rot * l, -rot.col(fa) * fs)
            };
            let to = target - origin;
            if to.length() < 1e-6 * size {
                continue;
            }
            let light = target + to.normalize() * (size * rng.random_range(0.01..10.0));
            let dist = (light - origin).length();
            let r = Ray::new(origin, (light - origin) / dist);
            assert!(
                accel.occluded(&r, dist, None),
                "light leak: {r:?} to {light} through {target}"
            );
            let (_, hit) = accel
                .intersect(&r, dist)
                .unwrap_or_else(|| panic!("light leak: {r:?} through {target}")); // invariant: the test's own fixed input (a failure fails the test)
            if interior {
                assert_close(hit.t, to.length(), 1e-9 * scale);
            }
        }
    }
}

/// A ray that hits a six-square box at an edge or a corner goes on from
/// there the renderer's way (from `offset_origin` on the side it goes to);
/// the neighbouring square must not be hit again at t ≈ 0 (a double hit: a
/// glass box would refract twice there, an opaque one shadow its own edge):
/// - entering, then straight on (refraction with index 1): the next hit is
///   the far side, at the slab-exit distance;
/// - entering, then reflected: nothing (the box is convex);
/// - leaving from inside, then straight on: nothing.
///
/// On rotated boxes the nudged origin lies on the neighbour's plane only up
/// to rounding: without the sliver of [`Ray::off_surface`] about a quarter
/// of the continuations hit it again at t ~ 1e-16.
#[test]
fn six_square_box_edge_hits_do_not_double_hit() {
    let mut rng = Pcg64::seed_from_u64(53);
    for (c, rot, h) in square_box_configs() {
        let scene = Scene::parse(&super::common::box_of_squares_text(c, rot, h), ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let accel = Accel::build(scene.objects().to_vec());
        // The nearest hit: distance, point, and the normal facing the ray
        // (squares are two-sided; the renderer nudges along this one).
        let first = |r: &Ray| {
            let (i, hit) = accel.intersect(r, INF)?;
            let sp = scene.objects()[i as usize].shape.surface(r, &hit);
            let side = if sp.normal.dot(r.dir) < 0.0 {
                sp.normal
            } else {
                -sp.normal
            };
            Some((hit.t, sp.point, side))
        };
        let size = h.max_element();
        let scale = c.abs().max_element() + size;
        for m in 0..6000 {
            let target = random_edge_point(&mut rng, c, rot, h, m);
            let l = rot.transpose() * (target - c);
            // Outside every face the target lies on: the ray enters through it.
            let mut out = DVec3::ZERO;
            for k in 0..3 {
                let on_face = (l[k].abs() - h[k]).abs() <= 1e-9 * scale;
                out += rot.col(k)
                    * if on_face {
                        l[k].signum() * rng.random_range(0.05..1.0)
                    } else {
                        rng.random_range(-0.5..0.5)
                    };
            }
            let out = out.normalize();
            let d = -out;
            let dist = size * rng.random_range(0.5..20.0);
            let r = Ray::new(target + out * dist, d);
            let (t, point, side) = first(&r).unwrap_or_else(|| panic!("crack: {r:?}")); // invariant: the test's own fixed input (a failure fails the test)
            assert_close(t, dist, 1e-9 * (scale + dist));
            // Straight on, into the box.
            let next = Ray::off_surface(offset_origin(point, -side), d);
            let (exit, cos) = super::common::box_exit(c, rot, h, next.origin, d);
            let (t2, ..) = first(&next)
                .unwrap_or_else(|| panic!("no exit after entering at {target}: {next:?}")); // invariant: the test's own fixed input (a failure fails the test)
            assert!(
                (t2 - exit).abs() <= 1e-9 * scale / cos,
                "double hit entering at {target}: went on {next:?}, hit t={t2:e}, exit at {exit}"
            );
            // Reflected, away from the box.
            let refl = d - side * (2.0 * d.dot(side));
            let next = Ray::off_surface(offset_origin(point, side), refl);
            assert!(
                first(&next).is_none() && !accel.occluded(&next, INF, None),
                "double hit reflecting at {target}: {next:?} hit {:?}",
                first(&next).map(|x| x.0)
            );
            // From inside, leaving through the target, then straight on.
            let inside = c + rot * (point_in(&mut rng, 0.99) * h);
            let r = Ray::new(inside, (target - inside).normalize());
            let (t, point, side) = first(&r).unwrap_or_else(|| panic!("crack: {r:?}")); // invariant: the test's own fixed input (a failure fails the test)
            assert_close(t, (target - inside).length(), 1e-9 * scale);
            let next = Ray::off_surface(offset_origin(point, -side), r.dir);
            // A ray leaving a hair (1e-16 to 1e-10) beside an edge crosses the
            // plane of the face it passes at that gap over its slope, inside
            // the square's crack-closing slack (1e-9 of its size), which can be
            // beyond the sliver: an ambiguous exit, not a rounding artefact.
            let beside = m % 3 == 2;
            assert!(
                beside || first(&next).is_none(),
                "double hit leaving at {target}: {next:?} hit {:?}",
                first(&next).map(|x| x.0)
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Squares against their decomposition into two triangles, each solved by
    /// Cramer's rule; rays within 1e-7 of the outline are not compared (the
    /// square is deliberately closed with a 1e-9 slack there).
    #[test]
    fn square_matches_two_triangle_reference(
        c in vec3(5.0), dx in vec3(3.0), dy in vec3(3.0),
        o in vec3(10.0), a in -1.3..1.3f64, b in -1.3..1.3f64, lift in -0.1..0.1f64,
        window in 0usize..3,
    ) {
        let n = dx.cross(dy);
        prop_assume!(n.length() > 0.05 * dx.length() * dy.length() && dx.length() > 0.1 && dy.length() > 0.1);
        let sq = Square::new(c, dx, dy);
        let target = c + dx * a + dy * b + n.normalize() * lift;
        prop_assume!((target - o).length() > 1e-3);
        let r = ray(o, target - o);
        let (t_lo, t_hi) = [(0.0, INF), (0.0, (target - o).length() * 0.5), (1.0, 30.0)][window];
        let got = sq.intersect(&r, t_lo, t_hi);

        let corners = [c - dx - dy, c + dx - dy, c + dx + dy, c - dx + dy];
        let mut reference = None;
        for (p1, p2) in [(corners[1], corners[2]), (corners[2], corners[3])] {
            if let Some((t, be, ga)) = solve_plane(r.origin, r.dir, corners[0], p1 - corners[0], p2 - corners[0]) {
                // -1e-12: a point on the shared diagonal is in one triangle or the other.
                if be >= -1e-12 && ga >= -1e-12 && be + ga <= 1.0 + 1e-12 {
                    reference = Some(t);
                }
            }
        }
        let plane_t = solve_plane(r.origin, r.dir, corners[0], corners[1] - corners[0], corners[3] - corners[0]).map(|s| s.0);
        let scale = 1.0 + c.length() + o.length() + dx.length() + dy.length();
        let near_outline = plane_t.is_some_and(|t| {
            let p = r.at(t);
            (0..4).map(|k| dist_to_segment(p, corners[k], corners[(k + 1) % 4])).fold(INF, f64::min)
                < 1e-7 * scale
        });
        let near_window = plane_t.is_some_and(|t| (t - t_lo).abs() < 1e-9 * scale || (t - t_hi).abs() < 1e-9 * scale);
        prop_assume!(!near_outline && !near_window);
        let reference = reference.filter(|t| *t > t_lo && *t < t_hi);
        match (got, reference) {
            (None, None) => {}
            (Some(h), Some(t)) => {
                prop_assert!((h.t - t).abs() < 1e-9 * scale, "t {} vs reference {}", h.t, t);
                let s = sq.surface(&r, &h);
                prop_assert!((s.point - r.at(t)).length() < 1e-9 * scale);
                prop_assert!((s.normal - n.normalize()).length() < 1e-12);
                let q = s.point - c;
                let uv = DVec2::new(q.dot(dx) / dx.length_squared() / 2.0 + 0.5, q.dot(dy) / dy.length_squared() / 2.0 + 0.5);
                prop_assert!((s.uv - uv).abs().max_element() < 1e-9);
            }
            (got, reference) => prop_assert!(false, "square {:?} vs reference {:?}", got, reference),
        }
    }
}

// ---------------------------------------------------------------- convex solids

/// What an independent search on a convex implicit function f (f < 0 inside)
/// says the nearest hit in (t_lo, t_hi) is.
#[derive(Debug)]
enum Expect {
    Miss,
    /// Distance and how far a correct answer may be from it (1e-9 of the
    /// scene's scale, divided by how steeply f changes along the ray there).
    Hit(f64, f64),
    /// Tangent rays, origins on the surface, hits at a window bound.
    Unsure,
}

fn convex_reference(
    f: &dyn Fn(DVec3) -> f64,
    r: &Ray,
    t_lo: f64,
    t_hi: f64,
    t_far: f64,
    scale: f64,
) -> Expect {
    let g = |t: f64| f(r.at(t));
    let band = 1e-9 * scale;
    let bisect = |mut a: f64, mut b: f64| {
        // g(a) and g(b) of opposite signs.
        let sa = g(a) < 0.0;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (g(m) < 0.0) == sa {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    // Golden-section search for the minimum of the convex g on [0, t_far].
    let (mut a, mut b) = (0.0, t_far);
    let k = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..300 {
        let (m1, m2) = (b - k * (b - a), a + k * (b - a));
        if g(m1) < g(m2) {
            b = m2;
        } else {
            a = m1;
        }
    }
    let t_star = 0.5 * (a + b);
    let (g0, g_star) = (g(0.0), g(t_star));
    if g0.abs() <= band || g(t_far) <= band {
        return Expect::Unsure;
    }
    let mut roots = Vec::new();
    if g0 > 0.0 {
        if g_star > band {
            return Expect::Miss;
        }
        if g_star >= -band {
            return Expect::Unsure;
        }
        roots.push(bisect(0.0, t_star));
    }
    roots.push(bisect(if g0 < 0.0 { 0.0 } else { t_star }, t_far));
    for t in roots {
        // How fast f changes along the ray at the root: rounding moves any
        // computed root by about (error in f) / slope.
        let step = 1e-6 * scale;
        let slope = ((g(t + step) - g(t - step)) / (2.0 * step)).abs();
        if slope < 1e-4 {
            return Expect::Unsure;
        }
        let tol = 1e-9 * scale / slope;
        if (t - t_lo).abs() <= tol || (t - t_hi).abs() <= tol {
            return Expect::Unsure;
        }
        if t > t_lo && t < t_hi {
            return Expect::Hit(t, tol);
        }
    }
    Expect::Miss
}

// ---------------------------------------------------------------- cubes

/// f for a box: max over axes of |local coordinate| − half-length.
fn box_f(c: DVec3, rot: DMat3, h: DVec3) -> impl Fn(DVec3) -> f64 {
    move |p: DVec3| {
        let l = rot.transpose() * (p - c);
        (l.abs() - h).max_element()
    }
}

/// The spec's cube mapping, straight from its text: each face like a square
/// with (Dx, Dy) = (Dx·x, Dy·y) on ±Dz, (Dy·y, Dz·z) on ±Dx, (Dz·z, Dx·x) on ±Dy.
fn spec_cube_uv(c: DVec3, rot: DMat3, h: DVec3, face_axis: usize, p: DVec3) -> DVec2 {
    let (sx, sy) = match face_axis {
        2 => (rot.col(0) * h.x, rot.col(1) * h.y),
        0 => (rot.col(1) * h.y, rot.col(2) * h.z),
        _ => (rot.col(2) * h.z, rot.col(0) * h.x),
    };
    let n = rot.col(face_axis);
    let face_center = c + n * n.dot(p - c);
    let q = p - face_center;
    DVec2::new(
        q.dot(sx) / sx.length_squared() / 2.0 + 0.5,
        q.dot(sy) / sy.length_squared() / 2.0 + 0.5,
    )
}

#[test]
fn cube_closed_form_every_face() {
    let c = v(1.0, 2.0, 3.0);
    let h = v(1.0, 2.0, 3.0);
    let cube = Cube::new(c, DVec3::X, DVec3::Y, h);
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let n = DVec3::AXES[axis] * sign;
            // Aim at the face point offset by (0.5, 0.25) of the other half-lengths.
            let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
            let p =
                c + n * h[axis] + DVec3::AXES[j] * (0.5 * h[j]) + DVec3::AXES[k] * (0.25 * h[k]);
            let r = Ray::new(p + n * 5.0, -n);
            let hit = cube.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
            assert_eq!(hit.t, 5.0);
            let s = cube.surface(&r, &hit);
            assert_eq!(s.point, p);
            assert_eq!(s.normal, n);
            assert_eq!(s.shading_normal, n);
            assert_uv(s.uv, spec_cube_uv(c, DMat3::IDENTITY, h, axis, p), 1e-15);
        }
    }
    // The ±Dx faces use (y, z): at local (1, 1, 1.5) u = 1/2/2 + 1/2, v = 1.5/3/2 + 1/2.
    let r = Ray::new(v(7.0, 3.0, 4.5), -DVec3::X);
    let hit = cube.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_uv(cube.surface(&r, &hit).uv, DVec2::new(0.75, 0.75), 1e-15);
    // The ±Dy faces use (z, x): at local (0.5, 2, −1.5) u = −1.5/3/2 + 1/2, v = 0.5/1/2 + 1/2.
    let r = Ray::new(v(1.5, 10.0, 1.5), -DVec3::Y);
    let hit = cube.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(hit.t, 6.0);
    assert_uv(cube.surface(&r, &hit).uv, DVec2::new(0.25, 0.75), 1e-15);
}

#[test]
fn cube_from_inside_hits_exit_face_with_outward_normal() {
    let h = v(1.0, 2.0, 3.0);
    let rot = rotation(v(0.4, -0.2, 1.3));
    let c = v(-3.0, 0.5, 2.0);
    let cube = Cube::new(c, rot.col(0), rot.col(1), h);
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let d = rot.col(axis) * sign;
            let r = Ray::new(c, d);
            let hit = cube.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
            assert_close(hit.t, h[axis], 1e-14);
            let s = cube.surface(&r, &hit);
            assert_vclose(s.normal, d, 1e-15);
            // Outward: the glass exit face's normal points along the ray.
            assert!(s.normal.dot(r.dir) > 0.0);
        }
    }
    // From outside, a t_min past the entry gives the exit face.
    let r = Ray::new(c - rot.col(0) * 5.0, rot.col(0));
    assert_close(cube.intersect(&r, 0.0, INF).unwrap().t, 4.0, 1e-13); // invariant: the test's own fixed input (a failure fails the test)
    let exit = cube.intersect(&r, 4.5, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(exit.t, 6.0, 1e-13);
    assert_vclose(cube.surface(&r, &exit).normal, rot.col(0), 1e-15);
    assert!(cube.intersect(&r, 6.5, INF).is_none());
}

#[test]
fn cube_edge_corner_and_parallel_rays() {
    let cube = Cube::new(DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE);
    // Along an edge line (in two face planes at once): hits the end face's corner.
    let r = Ray::new(v(1.0, 1.0, -5.0), DVec3::Z);
    let h = cube.intersect(&r, 0.0, INF).expect("edge-line ray"); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 4.0);
    let s = cube.surface(&r, &h);
    assert_eq!(s.point, v(1.0, 1.0, -1.0));
    assert_eq!(s.normal, -DVec3::Z);
    // Parallel to two face pairs, inside their slabs; and sliding on a face plane.
    let r = Ray::new(v(-4.0, 0.3, -0.2), DVec3::X);
    assert_eq!(cube.intersect(&r, 0.0, INF).unwrap().t, 3.0); // invariant: the test's own fixed input (a failure fails the test)
    let r = Ray::new(v(-4.0, 1.0, 0.5), DVec3::X);
    assert_eq!(cube.intersect(&r, 0.0, INF).unwrap().t, 3.0); // invariant: the test's own fixed input (a failure fails the test)
    // Parallel, a hair outside a slab: miss, not NaN.
    let r = Ray::new(v(-4.0, 1.0 + 1e-15, 0.5), DVec3::X);
    assert!(cube.intersect(&r, 0.0, INF).is_none());
    // Through a corner along the diagonal: t = √3·(5 − 1).
    let r = ray(v(5.0, 5.0, 5.0), v(-1.0, -1.0, -1.0));
    let h = cube.intersect(&r, 0.0, INF).expect("corner ray"); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 4.0 * 3f64.sqrt(), 1e-14);
    assert_vclose(cube.surface(&r, &h).point, DVec3::ONE, 1e-14);
    // Through an edge at 45°: enters at (1, 1, 0.5).
    let r = ray(v(3.0, 3.0, 0.5), v(-1.0, -1.0, 0.0));
    let h = cube.intersect(&r, 0.0, INF).expect("edge ray"); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 2.0 * 2f64.sqrt(), 1e-14);
    // Origin on a face, leaving: no hit at t = 0, none after.
    let r = Ray::new(v(1.0, 0.0, 0.0), DVec3::X);
    assert!(cube.intersect(&r, 0.0, INF).is_none());
    // Origin on a face, entering: the far face.
    let r = Ray::new(v(1.0, 0.0, 0.0), -DVec3::X);
    assert_eq!(cube.intersect(&r, 0.0, INF).unwrap().t, 2.0); // invariant: the test's own fixed input (a failure fails the test)
    // A misses-by-a-lot ray.
    assert!(
        cube.intersect(&ray(v(5.0, 5.0, 5.0), v(1.0, 0.0, 0.0)), 0.0, INF)
            .is_none()
    );
}

#[test]
fn cube_edges_and_corners_leave_no_crack() {
    for (n, (c, rot, h)) in edge_box_configs().into_iter().enumerate() {
        let cube = Cube::new(c, rot.col(0), rot.col(1), h);
        shoot_at_box_edges(c, rot, h, 20 + n as u64, 10_000, |r| {
            cube.intersect(r, 0.0, INF)
        });
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Random boxes and rays (from outside and inside, with random windows)
    /// against the convex-implicit reference: distance, face normal, point on
    /// the surface, and the spec's uv.
    #[test]
    fn cube_matches_implicit_reference(
        c in vec3(5.0), angles in vec3(PI), h in prop::array::uniform3(0.05..3.0f64),
        o in vec3(10.0), aim in vec3(1.3), inside in any::<bool>(), window in 0usize..3,
    ) {
        let h = DVec3::from_array(h);
        let rot = rotation(angles);
        let cube = Cube::new(c, rot.col(0), rot.col(1), h);
        let f = box_f(c, rot, h);
        let origin = if inside { c + rot * (aim / 1.3 * h * 0.999) } else { o };
        let target = c + rot * (aim * h);
        prop_assume!((target - origin).length() > 1e-3);
        let r = ray(origin, target - origin);
        let scale = 1.0 + c.length() + o.length() + h.length();
        let t_far = (origin - c).length() + h.length() * 2.0 + 1.0;
        let (t_lo, t_hi) = [(0.0, INF), (0.0, (target - origin).length() * 0.5), (0.7, 8.0)][window];
        let got = cube.intersect(&r, t_lo, t_hi);
        match convex_reference(&f, &r, t_lo, t_hi, t_far, scale) {
            Expect::Unsure => {}
            Expect::Miss => prop_assert!(got.is_none(), "false hit {:?}", got),
            Expect::Hit(t, tol) => {
                let hit = got.ok_or_else(|| TestCaseError::fail(format!("missed, reference t = {t}")))?;
                prop_assert!((hit.t - t).abs() <= tol, "t {} vs reference {} (tol {})", hit.t, t, tol);
                let s = cube.surface(&r, &hit);
                prop_assert!(f(s.point).abs() < 1e-12 * scale, "point off the surface");
                prop_assert!((s.point - r.at(t)).length() < tol + 1e-12 * scale);
                // The face: the axis whose slab is active at the hit, if clearly one.
                let l = rot.transpose() * (s.point - c);
                let mut d = (l.abs() - h).to_array();
                let axis = (0..3).max_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
                d[axis] = -INF;
                if d.iter().all(|x| *x < -1e-7 * scale) {
                    let n = rot.col(axis) * l[axis].signum();
                    prop_assert!((s.normal - n).length() < 1e-12, "normal {} vs {}", s.normal, n);
                    let uv = spec_cube_uv(c, rot, h, axis, s.point);
                    prop_assert!((s.uv - uv).abs().max_element() < 1e-9, "uv {} vs {}", s.uv, uv);
                }
                prop_assert!((s.normal.length() - 1.0).abs() < 1e-14);
            }
        }
    }
}

// ---------------------------------------------------------------- cylinders

/// f for a closed cylinder: max(distance to axis − R, −z, z − L).
fn cylinder_f(o1: DVec3, o2: DVec3, radius: f64) -> impl Fn(DVec3) -> f64 {
    let len = (o2 - o1).length();
    let a = (o2 - o1) / len;
    move |p: DVec3| {
        let q = p - o1;
        let z = q.dot(a);
        ((q - a * z).length() - radius).max(-z).max(z - len)
    }
}

#[test]
fn cylinder_closed_form_side_caps_and_uv() {
    let cyl = Cylinder::new(DVec3::ZERO, v(0.0, 0.0, 2.0), 1.0);
    // Side from outside, at angle π (e1 = x for a z axis, e2 = y): v = 1/2.
    let r = Ray::new(v(-5.0, 0.0, 1.5), DVec3::X);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 4.0);
    let s = cyl.surface(&r, &h);
    assert_eq!(s.point, v(-1.0, 0.0, 1.5));
    assert_vclose(s.normal, -DVec3::X, 1e-15);
    assert_uv(s.uv, DVec2::new(0.75, 0.5), 1e-15);
    // At angle π/2 (along e2 = y): v = 1/4.
    let r = Ray::new(v(0.0, 5.0, 0.5), -DVec3::Y);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = cyl.surface(&r, &h);
    assert_eq!(h.t, 4.0);
    assert_vclose(s.normal, DVec3::Y, 1e-15);
    assert_uv(s.uv, DVec2::new(0.25, 0.25), 1e-15);
    // Offset side hit: t = 5 − √(1 − 0.6²) = 4.2.
    let r = Ray::new(v(-5.0, 0.6, 1.0), DVec3::X);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 4.2, 1e-15);
    assert_vclose(cyl.surface(&r, &h).normal, v(-0.8, 0.6, 0.0), 1e-15);
    // Caps: top at O2 (+axis), bottom at O1 (−axis), cap uv = 1/2 + (C − P)·e/(2R).
    let r = Ray::new(v(0.5, -0.25, 5.0), -DVec3::Z);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 3.0);
    let s = cyl.surface(&r, &h);
    assert_eq!(s.normal, DVec3::Z);
    assert_eq!(s.point, v(0.5, -0.25, 2.0));
    assert_uv(s.uv, DVec2::new(0.75, 0.375), 1e-15);
    let r = Ray::new(v(0.5, -0.25, -5.0), DVec3::Z);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 5.0);
    assert_eq!(cyl.surface(&r, &h).normal, -DVec3::Z);
    // Parallel to the axis: caps only; outside the radius: miss (not NaN).
    assert!(
        cyl.intersect(&Ray::new(v(1.5, 0.0, -5.0), DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert!(
        cyl.intersect(&Ray::new(v(0.0, 1.0 + 1e-12, -5.0), DVec3::Z), 0.0, INF)
            .is_none()
    );
    // Along the axis itself.
    let r = Ray::new(v(0.0, 0.0, -5.0), DVec3::Z);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!((h.t, cyl.surface(&r, &h).normal), (5.0, -DVec3::Z));
    // Through the axis, from inside: exit through the side, outward normal.
    let r = Ray::new(v(0.0, 0.0, 1.0), DVec3::Y);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 1.0);
    assert_vclose(cyl.surface(&r, &h).normal, DVec3::Y, 1e-15);
    // From inside along the axis: exit through the top cap.
    let r = Ray::new(v(0.2, 0.1, 1.0), DVec3::Z);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!((h.t, cyl.surface(&r, &h).normal), (1.0, DVec3::Z));
    // Perpendicular to the axis above the top: miss.
    assert!(
        cyl.intersect(&Ray::new(v(-5.0, 0.0, 2.5), DVec3::X), 0.0, INF)
            .is_none()
    );
    // Through the rim at 45°, entering: (−1, 0, 2) at distance √2.
    let r = ray(v(-2.0, 0.0, 3.0), v(1.0, 0.0, -1.0));
    let h = cyl.intersect(&r, 0.0, INF).expect("rim ray"); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 2f64.sqrt(), 1e-15);
    assert_vclose(cyl.surface(&r, &h).point, v(-1.0, 0.0, 2.0), 1e-15);
    // Exactly tangent to the rim circle, in the cap plane: either answer is
    // right, but it is finite (rays moved off tangency are checked in
    // `cylinder_rays_displaced_from_tangency`).
    if let Some(h) = cyl.intersect(&Ray::new(v(1.0, -5.0, 2.0), DVec3::Y), 0.0, INF) {
        let s = cyl.surface(&Ray::new(v(1.0, -5.0, 2.0), DVec3::Y), &h);
        assert!(s.point.is_finite() && s.normal.is_finite() && s.uv.is_finite());
    }
    // Degenerate cylinders are never hit.
    assert!(
        Cylinder::new(DVec3::ZERO, DVec3::ZERO, 1.0)
            .intersect(&r, 0.0, INF)
            .is_none()
    );
    assert!(
        Cylinder::new(DVec3::ZERO, DVec3::Z, 0.0)
            .intersect(&r, 0.0, INF)
            .is_none()
    );
}

#[test]
fn tilted_cylinder_closed_form() {
    // Axis (1, 2, 2)/3, length 6, R = 0.5.
    let a = v(1.0, 2.0, 2.0) / 3.0;
    let o1 = v(1.0, -2.0, 0.5);
    let cyl = Cylinder::new(o1, o1 + a * 6.0, 0.5);
    // A ray perpendicular to the axis through the axis point at z = 4: hits
    // at distance 7 − 0.5 from a start 7 away.
    let perp = v(2.0, -1.0, 0.0) / 5f64.sqrt();
    let r = Ray::new(o1 + a * 4.0 + perp * 7.0, -perp);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 6.5, 1e-14);
    let s = cyl.surface(&r, &h);
    assert_vclose(s.normal, perp, 1e-15);
    assert_close(s.uv.x, 4.0 / 6.0, 1e-15);
    // The spec's angle: e1 = unit(a × z), e2 = a × e1.
    let e1 = a.cross(DVec3::Z).normalize();
    let e2 = a.cross(e1);
    let ang = perp.dot(e2).atan2(perp.dot(e1)).rem_euclid(TAU);
    assert_close(s.uv.y, ang / TAU, 1e-15);
    // Along the axis from before O1: the O1 cap, normal −a, at distance 3.
    let r = Ray::new(o1 - a * 3.0 + e1 * 0.2, a);
    let h = cyl.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_close(h.t, 3.0, 1e-14);
    let s = cyl.surface(&r, &h);
    assert_vclose(s.normal, -a, 1e-15);
    assert_uv(s.uv, DVec2::new(0.5 + 0.2 / 1.0, 0.5), 1e-14);
}

#[test]
fn cylinder_rim_leaves_no_crack() {
    // Rays entering exactly through rim points (side and cap meet) must hit there.
    let mut rng = Pcg64::seed_from_u64(7);
    for (o1, o2, radius) in [
        (DVec3::ZERO, v(0.0, 0.0, 2.0), 1.0),
        (v(0.3, -1.7, 2.9), v(-1.1, 0.4, 0.7), 0.37),
        (v(500.3, 200.1, -70.7), v(500.9, 200.2, -70.0), 0.013),
    ] {
        let cyl = Cylinder::new(o1, o2, radius);
        let len = (o2 - o1).length();
        let a = (o2 - o1) / len;
        let (e1, e2) = axis_frame(a);
        let scale = o1.abs().max_element() + len + radius;
        for n in 0..5000 {
            let ang = rng.random_range(0.0..TAU);
            let radial = e1 * ang.cos() + e2 * ang.sin();
            let (cap, out_axis) = if n % 2 == 0 { (o2, a) } else { (o1, -a) };
            let rim = cap + radial * radius;
            // Outside both the side and the cap plane: the ray enters at the rim.
            let out = (radial * rng.random_range(0.05..1.0)
                + out_axis * rng.random_range(0.05..1.0))
            .normalize();
            let dist = (len + radius) * rng.random_range(0.1..10.0);
            let r = Ray::new(rim + out * dist, -out);
            let h = cyl
                .intersect(&r, 0.0, INF)
                .unwrap_or_else(|| panic!("crack at rim: {r:?}")); // invariant: the test's own fixed input (a failure fails the test)
            assert_close(h.t, dist, 1e-9 * (scale + dist));
        }
    }
}

/// The cylinders of the tangency and axis-parallel tests: unit, tilted, far
/// from the origin and thin, long and thin.
const CYLINDERS: [([f64; 3], [f64; 3], f64); 4] = [
    ([0.0, 0.0, 0.0], [0.0, 0.0, 2.0], 1.0),
    ([0.3, -1.7, 2.9], [-1.1, 0.4, 0.7], 0.37),
    ([500.3, 200.1, -70.7], [500.9, 200.2, -70.0], 0.013),
    ([-3.0, 2.0, 1.0], [5.0, -2.0, 7.0], 0.2),
];

/// `got` when a hit is `wanted` (else a panic "`what` missed: ray"); when not, asserts there is none ("`what` hit: ray hit").
#[track_caller]
fn expect_hit(got: Option<Hit>, wanted: bool, what: impl Fn() -> String, r: &Ray) -> Option<Hit> {
    if wanted {
        Some(got.unwrap_or_else(|| panic!("{} missed: {r:?}", what()))) // invariant: the test's own fixed input (a failure fails the test)
    } else {
        assert!(got.is_none(), "{} hit: {r:?} {got:?}", what());
        None
    }
}

/// Rays tangent to the side, and tangent to a rim circle, moved off
/// tangency by k·1e-9 of the scene's scale: moved outwards they miss, moved
/// inwards they hit at the closed-form distance, on the part (side or cap)
/// the geometry says, with its normal (to within what the distance
/// tolerance allows: tol / R for a side normal).
#[test]
fn cylinder_rays_displaced_from_tangency() {
    let mut rng = Pcg64::seed_from_u64(41);
    let mut hits = 0;
    for (o1, o2, radius) in CYLINDERS {
        let (o1, o2) = (DVec3::from_array(o1), DVec3::from_array(o2));
        let cyl = Cylinder::new(o1, o2, radius);
        let len = (o2 - o1).length();
        let a = (o2 - o1) / len;
        let (e1, e2) = axis_frame(a);
        let scale = o1.abs().max_element() + len + radius;
        // The outward side normal where the ray is at `p`.
        let side_normal = |p: DVec3| {
            let q = p - o1;
            (q - a * q.dot(a)).normalize()
        };
        // Asserts the hit `h` on `r` is on the side `chord` short of `dist`, with the side normal there.
        let assert_side_hit = |r: &Ray, h: &Hit, dist: f64, chord: f64, tol: f64| {
            assert_close(h.t, dist - chord, tol);
            let sp = cyl.surface(r, h);
            assert_vclose(
                sp.normal,
                side_normal(r.at(dist - chord)),
                tol / radius + 1e-12,
            );
        };
        for n in 0..400 {
            let phi = rng.random_range(0.0..TAU);
            // Radial direction of the tangent point, and the circle's tangent there.
            let u = e1 * phi.cos() + e2 * phi.sin();
            let w = a.cross(u);
            let dist = (len + radius) * rng.random_range(0.5..10.0);
            let tol = 1e-9 * (scale + dist);
            for k in [1.0, 3.0, 30.0, 1e3, 1e5] {
                let s = k * 1e-9 * scale;
                if s > 0.1 * radius {
                    continue; // (the thin far cylinder: not a near-tangent any more)
                }
                for inward in [false, true] {
                    // Distance of the ray from the axis at the tangent point.
                    let rho = if inward { radius - s } else { radius + s };
                    let moved = if inward { "in" } else { "out" };
                    // sqrt(R² − ρ²) for ρ < R, without cancellation.
                    let half_chord = (s * (2.0 * radius - s)).sqrt();

                    // 1. Tangent to the side at mid-height, perpendicular to
                    //    the axis (beta = 0) or slanted.
                    let beta: f64 = if n % 3 == 0 {
                        0.0
                    } else {
                        rng.random_range(-1.2..1.2)
                    };
                    let z = len * rng.random_range(0.3..0.7);
                    let d = (w * beta.cos() + a * beta.sin()).normalize();
                    let chord = half_chord / beta.cos();
                    // The chord must stay clear of the caps for the closed form.
                    if (chord * beta.sin()).abs() < 0.2 * len {
                        let p = o1 + a * z + u * rho;
                        let r = Ray::new(p - d * dist, d);
                        let got = cyl.intersect(&r, 0.0, INF);
                        let what = || format!("side tangent moved {moved} by {s:e}");
                        if let Some(h) = expect_hit(got, inward, what, &r) {
                            assert_side_hit(&r, &h, dist, chord, tol);
                            hits += 1;
                        }
                    }

                    // 2. Tangent to a rim circle, slanted: crossing the cap
                    //    plane at the tangent point. Going into the slab it
                    //    enters through the cap there; going out of it, it
                    //    entered through the side half a chord earlier.
                    let (cap, out) = if n % 2 == 0 { (o2, a) } else { (o1, -a) };
                    let beta: f64 =
                        rng.random_range(0.15..1.3) * if n % 4 < 2 { 1.0 } else { -1.0 };
                    let d = (w * beta.cos() - out * beta.sin()).normalize();
                    let p = cap + u * rho;
                    let r = Ray::new(p - d * dist, d);
                    let got = cyl.intersect(&r, 0.0, INF);
                    let what = || format!("rim tangent moved {moved} by {s:e}");
                    if let Some(h) = expect_hit(got, inward, what, &r) {
                        if beta > 0.0 {
                            assert_close(h.t, dist, tol);
                            assert_vclose(cyl.surface(&r, &h).normal, out, 1e-12);
                        } else {
                            assert_side_hit(&r, &h, dist, half_chord / beta.cos(), tol);
                        }
                        hits += 1;
                    }

                    // 3. In a plane perpendicular to the axis, tangent to a rim
                    //    circle: moved off it radially and along the axis. Only
                    //    inside both (below the cap, within the radius) is
                    //    there a hit, on the side.
                    for below in [false, true] {
                        let p = cap + u * rho + out * if below { -s } else { s };
                        let r = Ray::new(p - w * dist, w);
                        let got = cyl.intersect(&r, 0.0, INF);
                        let what = || {
                            if inward && below {
                                format!("rim tangent moved in and below by {s:e}")
                            } else {
                                format!(
                                    "rim tangent moved off by {s:e} (inward {inward}, below {below})"
                                )
                            }
                        };
                        if let Some(h) = expect_hit(got, inward && below, what, &r) {
                            assert_side_hit(&r, &h, dist, half_chord, tol);
                            hits += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(hits > 10_000, "{hits}");
}

/// Rays exactly along ±axis (the direction is the unit axis itself), on
/// random tilted and world-aligned axes, from radius R·(1 ± δ) and from the
/// axis, starting before, between and beyond the caps, and a hair either
/// side of a cap: against the closed form (caps only; the side is never hit).
#[test]
fn cylinder_exactly_axis_parallel_rays() {
    let mut rng = Pcg64::seed_from_u64(43);
    let mut axes: Vec<DVec3> = vec![DVec3::X, -DVec3::Y, DVec3::Z, v(1.0, 2.0, 2.0) / 3.0];
    for _ in 0..60 {
        axes.push(rotation(v(rng.random(), rng.random(), rng.random()) * TAU).col(0));
    }
    let (mut hits, mut misses) = (0, 0);
    for a in axes {
        let o1 = v(
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
        );
        let len = rng.random_range(0.05..6.0);
        let radius = rng.random_range(0.05..3.0);
        let o2 = o1 + a * len;
        let cyl = Cylinder::new(o1, o2, radius);
        // The test's own axis: the direction the rays use, exactly.
        let axis = (o2 - o1).normalize();
        let len = (o2 - o1).length();
        let (e1, e2) = axis_frame(axis);
        let scale = o1.abs().max_element() + len + radius;
        for _ in 0..100 {
            let phi = rng.random_range(0.0..TAU);
            let u = e1 * phi.cos() + e2 * phi.sin();
            let delta = [1e-2, 1e-5, 1e-8][rng.random_range(0..3usize)];
            let (rho, inside_radius) = match rng.random_range(0..4u32) {
                0 => (0.0, true),
                1 => (radius * (1.0 - delta), true),
                2 => (radius * (1.0 + delta), false),
                _ => (radius * rng.random_range(0.0..1.0), true),
            };
            let hair = 10f64.powf(rng.random_range(-8.0..-4.0)) * scale;
            for z0 in [
                -len * rng.random_range(0.1..3.0),
                len * rng.random_range(0.1..0.9),
                len * (1.0 + rng.random_range(0.1..3.0)),
                -hair,
                hair,
                len - hair,
                len + hair,
            ] {
                let origin = o1 + axis * z0 + u * rho;
                for sign in [1.0, -1.0] {
                    let r = Ray::new(origin, axis * sign);
                    let got = cyl.intersect(&r, 0.0, INF);
                    // Heights of the caps ahead of the origin, nearest first.
                    let ahead: Vec<(f64, DVec3, DVec3)> = if sign > 0.0 {
                        vec![(0.0, o1, -axis), (len, o2, axis)]
                    } else {
                        vec![(len, o2, axis), (0.0, o1, -axis)]
                    }
                    .into_iter()
                    .filter(|&(zc, _, _)| (zc - z0) * sign > 0.0)
                    .collect();
                    match ahead.first() {
                        Some(&(zc, center, normal)) if inside_radius => {
                            let h =
                                got.unwrap_or_else(|| panic!("axis-parallel ray missed: {r:?}")); // invariant: the test's own fixed input (a failure fails the test)
                            let t = (zc - z0).abs();
                            assert_close(h.t, t, 1e-9 * scale);
                            let sp = cyl.surface(&r, &h);
                            assert_vclose(sp.normal, normal, 1e-12);
                            assert_vclose(sp.point, center + u * rho, 1e-9 * scale);
                            hits += 1;
                        }
                        _ => {
                            assert!(got.is_none(), "axis-parallel ray hit: {r:?} {got:?}");
                            misses += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(
        hits > 30_000 && misses > 30_000,
        "{hits} hits, {misses} misses"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Random cylinders and rays (outside, inside, near or exactly along the
    /// axis direction, random windows) against the convex-implicit reference.
    #[test]
    fn cylinder_matches_implicit_reference(
        o1 in vec3(5.0), dir in vec3(1.0), len in 0.05..6.0f64, radius in 0.05..3.0f64,
        o in vec3(10.0), aim in vec3(1.3), inside in any::<bool>(), along in 0usize..4, window in 0usize..3,
    ) {
        prop_assume!(dir.length() > 0.1);
        let a = dir.normalize();
        let o2 = o1 + a * len;
        let cyl = Cylinder::new(o1, o2, radius);
        let f = cylinder_f(o1, o2, radius);
        let (e1, e2) = axis_frame(a);
        let local = |p: DVec3| o1 + e1 * (p.x * radius) + e2 * (p.y * radius) + a * ((p.z + 1.0) * 0.5 * len);
        let origin = if inside { local(aim / 1.3 * 0.7) } else { o };
        let target = local(aim);
        prop_assume!((target - origin).length() > 1e-3);
        // One ray in four runs nearly along the axis, one in four exactly.
        let d = match along {
            0 => a * aim.z.signum() + (target - origin).normalize() * 1e-7,
            1 => a * aim.z.signum(),
            _ => target - origin,
        };
        let r = ray(origin, d);
        let scale = 1.0 + o1.length() + o.length() + len + radius;
        let t_far = (origin - o1).length() + len + radius + 1.0;
        let (t_lo, t_hi) = [(0.0, INF), (0.0, (target - origin).length() * 0.5), (0.7, 8.0)][window];
        let got = cyl.intersect(&r, t_lo, t_hi);
        match convex_reference(&f, &r, t_lo, t_hi, t_far, scale) {
            Expect::Unsure => {}
            Expect::Miss => prop_assert!(got.is_none(), "false hit {:?}", got),
            Expect::Hit(t, tol) => {
                let hit = got.ok_or_else(|| TestCaseError::fail(format!("missed, reference t = {t}")))?;
                prop_assert!((hit.t - t).abs() <= tol, "t {} vs reference {} (tol {})", hit.t, t, tol);
                let s = cyl.surface(&r, &hit);
                prop_assert!(f(s.point).abs() < 1e-12 * scale, "point off the surface: {}", f(s.point));
                prop_assert!((s.point - r.at(t)).length() < tol + 1e-12 * scale);
                prop_assert!((s.normal.length() - 1.0).abs() < 1e-14);
                // The active piece of f at the hit, if clearly one, gives the normal and uv.
                let q = s.point - o1;
                let z = q.dot(a);
                let rad = q - a * z;
                let pieces = [rad.length() - radius, -z, z - len];
                let k = (0..3).max_by(|&x, &y| pieces[x].total_cmp(&pieces[y])).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
                let clear = (0..3).all(|j| j == k || pieces[j] < -1e-7 * scale);
                if clear {
                    let (n, uv) = match k {
                        0 => {
                            let n = rad.normalize();
                            let ang = n.dot(e2).atan2(n.dot(e1)).rem_euclid(TAU);
                            (n, DVec2::new(z / len, ang / TAU))
                        }
                        1 => (-a, DVec2::new(0.5 + rad.dot(e1) / (2.0 * radius), 0.5 + rad.dot(e2) / (2.0 * radius))),
                        _ => (a, DVec2::new(0.5 + rad.dot(e1) / (2.0 * radius), 0.5 + rad.dot(e2) / (2.0 * radius))),
                    };
                    prop_assert!((s.normal - n).length() < 1e-9, "normal {} vs {}", s.normal, n);
                    // v wraps at the seam (angle 0 ≡ 2π).
                    let dv = (s.uv.y - uv.y).abs();
                    prop_assert!((s.uv.x - uv.x).abs() < 1e-9 && dv.min((dv - 1.0).abs()) < 1e-9, "uv {} vs {}", s.uv, uv);
                }
            }
        }
    }
}

// ---------------------------------------------------------------- triangles

#[test]
fn triangle_closed_form_both_sides_and_smooth_normals() {
    let o = v(1.0, 1.0, 1.0);
    let tri = Triangle::new(o, o + DVec3::X, o + DVec3::Y, None);
    let r = Ray::new(v(1.25, 1.5, 3.0), -DVec3::Z);
    let h = tri.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 2.0);
    assert_close(h.u, 0.25, 1e-15);
    assert_close(h.v, 0.5, 1e-15);
    let s = tri.surface(&r, &h);
    assert_vclose(s.point, v(1.25, 1.5, 1.0), 1e-15);
    assert_eq!(s.normal, DVec3::Z);
    assert_eq!(s.shading_normal, DVec3::Z);
    assert_uv(s.uv, DVec2::new(0.25, 0.5), 1e-15);
    // From behind: hit, same (geometric, winding) normal.
    let r = Ray::new(v(1.25, 1.5, -3.0), DVec3::Z);
    let h = tri.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(h.t, 4.0);
    assert_eq!(tri.surface(&r, &h).normal, DVec3::Z);
    // Outside the hypotenuse, behind, parallel: misses.
    assert!(
        tri.intersect(&Ray::new(v(1.6, 1.6, 3.0), -DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert!(
        tri.intersect(&Ray::new(v(1.25, 1.5, 3.0), DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert!(
        tri.intersect(&Ray::new(v(0.0, 1.2, 1.0), DVec3::X), 0.0, INF)
            .is_none()
    );
    // Vertex normals: interpolated with the barycentric weights, normalised.
    let ns = [
        DVec3::Z,
        v(1.0, 0.0, 1.0).normalize(),
        v(0.0, 1.0, 1.0).normalize(),
    ];
    let smooth = Triangle::new(o, o + DVec3::X, o + DVec3::Y, Some(ns));
    let r = Ray::new(v(1.25, 1.5, 3.0), -DVec3::Z);
    let h = smooth.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = smooth.surface(&r, &h);
    let expect = (ns[0] * 0.25 + ns[1] * 0.25 + ns[2] * 0.5).normalize();
    assert_vclose(s.shading_normal, expect, 1e-15);
    assert_eq!(s.normal, DVec3::Z);
    // A degenerate triangle is never hit and reports nothing odd.
    let flat = Triangle::new(o, o + DVec3::X, o + DVec3::X * 2.0, None);
    assert_eq!(flat.double_area(), 0.0);
    assert!(
        flat.intersect(&Ray::new(v(1.5, 1.0, 3.0), -DVec3::Z), 0.0, INF)
            .is_none()
    );
    assert_eq!(tri.bounds(), Aabb::from_points(o, o + v(1.0, 1.0, 0.0)));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Random triangles and rays against Cramer's rule; rays within 1e-7
    /// (barycentric) of an edge are not compared.
    #[test]
    fn triangle_matches_cramer_reference(
        a in vec3(5.0), b in vec3(5.0), c in vec3(5.0), o in vec3(10.0),
        w in prop::array::uniform3(-0.2..1.0f64), lift in -0.1..0.1f64,
    ) {
        let n = (b - a).cross(c - a);
        prop_assume!(n.length() > 0.05 * (b - a).length() * (c - a).length());
        let tri = Triangle::new(a, b, c, None);
        let sum = w[0] + w[1] + w[2];
        prop_assume!(sum.abs() > 0.1);
        let target = (a * w[0] + b * w[1] + c * w[2]) / sum + n.normalize() * lift;
        prop_assume!((target - o).length() > 1e-3);
        let r = ray(o, target - o);
        let got = tri.intersect(&r, 0.0, INF);
        let scale = 1.0 + a.length() + b.length() + c.length() + o.length();
        let Some((t, be, ga)) = solve_plane(r.origin, r.dir, a, b - a, c - a) else {
            prop_assert!(got.is_none());
            return Ok(());
        };
        let margin = be.min(ga).min(1.0 - be - ga);
        prop_assume!(margin.abs() > 1e-7 && t.abs() > 1e-9 * scale);
        if margin > 0.0 && t > 0.0 {
            let h = got.ok_or_else(|| TestCaseError::fail("missed"))?;
            prop_assert!((h.t - t).abs() < 1e-9 * scale, "t {} vs {}", h.t, t);
            prop_assert!((h.u - be).abs() < 1e-9 && (h.v - ga).abs() < 1e-9);
            let s = tri.surface(&r, &h);
            prop_assert!((s.point - r.at(t)).length() < 1e-9 * scale);
            prop_assert!((s.normal - n.normalize()).length() < 1e-12);
        } else {
            prop_assert!(got.is_none(), "false hit {:?}", got);
        }
    }
}

/// A unit icosphere subdivided `level` times, as vertex list + outward CCW faces.
fn icosphere(level: usize) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let p = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<DVec3> = [
        v(-1.0, p, 0.0),
        v(1.0, p, 0.0),
        v(-1.0, -p, 0.0),
        v(1.0, -p, 0.0),
        v(0.0, -1.0, p),
        v(0.0, 1.0, p),
        v(0.0, -1.0, -p),
        v(0.0, 1.0, -p),
        v(p, 0.0, -1.0),
        v(p, 0.0, 1.0),
        v(-p, 0.0, -1.0),
        v(-p, 0.0, 1.0),
    ]
    .iter()
    .map(|x| x.normalize())
    .collect();
    let mut faces = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |i: usize, j: usize, verts: &mut Vec<DVec3>| {
            *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                verts.push(((verts[i] + verts[j]) * 0.5).normalize());
                verts.len() - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                midpoint(a, b, &mut verts),
                midpoint(b, c, &mut verts),
                midpoint(c, a, &mut verts),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    (verts, faces)
}

/// Rays at the vertices and edges of a closed convex mesh: from inside (a
/// point within `inner` of `center`) they must all hit; from outside,
/// entering through the point, they must hit it.
#[allow(clippy::too_many_arguments)]
fn shoot_at_mesh_edges(
    verts: &[DVec3],
    faces: &[[usize; 3]],
    center: DVec3,
    inner: f64,
    size: f64,
    seed: u64,
    rays: usize,
) {
    let tris: Vec<Triangle> = faces
        .iter()
        .map(|f| Triangle::new(verts[f[0]], verts[f[1]], verts[f[2]], None))
        .collect();
    let scale = center.abs().max_element() + size;
    let mut rng = Pcg64::seed_from_u64(seed);
    for n in 0..rays {
        let f = faces[rng.random_range(0..faces.len())];
        let e = rng.random_range(0..3usize);
        let (p, q) = (verts[f[e]], verts[f[(e + 1) % 3]]);
        let target = match n % 3 {
            0 => p,
            1 => (p + q) * 0.5,
            _ => p + (q - p) * rng.random_range(0.0..1.0),
        };
        let inside = center + point_in(&mut rng, 1.0) * (inner / 3f64.sqrt());
        let r = Ray::new(inside, (target - inside).normalize());
        let (_, h) = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b))
            .unwrap_or_else(|| panic!("crack: ray {r:?} from inside at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(h.t, (target - inside).length(), 1e-9 * scale);
        // From outside through the same point towards the inside point.
        let dist = size * rng.random_range(0.1..10.0);
        let r = Ray::new(target + r.dir * dist, -r.dir);
        let (_, h) = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b))
            .unwrap_or_else(|| panic!("crack: ray {r:?} entering at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(h.t, dist, 1e-9 * (scale + dist));
    }
}

#[test]
fn octahedron_and_icosphere_meshes_leave_no_crack() {
    let rot = rotation(v(0.3, 1.2, -0.4));
    let c = v(0.1, -2.3, 0.7);
    let h = v(0.7, 1.3, 0.3);
    let octa: Vec<DVec3> = (0..6)
        .map(|k| c + rot.col(k / 2) * (h[k / 2] * if k % 2 == 0 { 1.0 } else { -1.0 }))
        .collect();
    // Faces: one per octant (x±, y±, z±).
    let mut faces = Vec::new();
    for xs in [0, 1] {
        for ys in [2, 3] {
            for zs in [4, 5] {
                faces.push([xs, ys, zs]);
            }
        }
    }
    // The octahedron's inscribed sphere has radius 1/√(Σ 1/h²).
    let inscribed = 1.0 / (1.0 / (h * h)).element_sum().sqrt();
    shoot_at_mesh_edges(&octa, &faces, c, 0.9 * inscribed, 1.3, 1, 20_000);
    let (verts, faces) = icosphere(3);
    for (center, radius) in [(v(0.1, -2.3, 0.7), 1.7), (v(300.7, 120.1, -55.3), 0.05)] {
        let verts: Vec<DVec3> = verts.iter().map(|p| center + rot * (*p * radius)).collect();
        // The subdivided icosahedron's inscribed sphere is larger than 0.9·R.
        shoot_at_mesh_edges(&verts, &faces, center, 0.9 * radius, radius, 2, 10_000);
        // The geometric normal is the winding's, outward for this mesh.
        for f in &faces {
            let t = Triangle::new(verts[f[0]], verts[f[1]], verts[f[2]], None);
            let centroid = (verts[f[0]] + verts[f[1]] + verts[f[2]]) / 3.0;
            let r = Ray::new(center, (centroid - center).normalize());
            let hit = t.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
            assert!(t.surface(&r, &hit).normal.dot(centroid - center) > 0.0);
        }
    }
}

// ---------------------------------------------------------------- OBJ loading

/// A fresh temporary folder for this test process.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-geometry-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    p
}

#[test]
fn obj_transform_order_normals_and_degenerates() {
    let dir = temp_dir("obj");
    let path = write(
        &dir,
        "two.obj",
        "# a quad, a smooth triangle in a second object, a degenerate one\n\
         mtllib missing.mtl\n\
         o quad\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
         f 1 2 3 4\n\
         o smooth\n\
         v 1 2 3\nv 2 2 3\nv 1 3 3\n\
         vn 0 0 1\nvn 1 1 0\n\
         f 5//1 6//1 7//2\n\
         o flat\n\
         v 0 0 0\nv 1 1 1\nv 2 2 2\n\
         f 8 9 10\n",
    );
    let origin = v(10.0, 20.0, 30.0);
    let scale = v(2.0, 3.0, 4.0);
    // Rx(π/2) then Rz(π/2): (x, y, z) → (x, −z, y) → (z, x, y).
    let rotation = v(PI / 2.0, 0.0, PI / 2.0);
    let tris = load_obj(&path, origin, scale, rotation).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        tris.len(),
        3,
        "quad → 2 triangles, smooth → 1, degenerate skipped"
    );
    let place = |p: DVec3| {
        let s = p * scale;
        origin + v(s.z, s.x, s.y)
    };
    // The quad's vertices, in some triangulation, all placed.
    for t in &tris[..2] {
        for p in t.vertices {
            let found = [
                v(0.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                v(1.0, 1.0, 0.0),
                v(0.0, 1.0, 0.0),
            ]
            .iter()
            .any(|q| (place(*q) - p).length() < 1e-12);
            assert!(found, "vertex {p} not a placed quad vertex");
        }
        assert!(t.normals().is_none());
    }
    // (1, 2, 3) → scaled (2, 6, 12) → (12, 2, 6) + origin.
    let smooth = &tris[2];
    assert_vclose(smooth.vertices[0], v(22.0, 22.0, 36.0), 1e-12);
    let ns = smooth.normals().expect("vertex normals kept"); // invariant: the test's own fixed input (a failure fails the test)
    // (0,0,1): S⁻¹ keeps it, then → (1, 0, 0).
    assert_vclose(ns[0], DVec3::X, 1e-12);
    // (1,1,0): S⁻¹ → (1/2, 1/3, 0), normalised, then (x, y, z) → (z, x, y).
    let m = v(0.5, 1.0 / 3.0, 0.0).normalize();
    assert_vclose(ns[2], v(m.z, m.x, m.y), 1e-12);
    // Its winding normal was (0,0,1) too: after the transform it still agrees with the vertex normals.
    let r = Ray::new(smooth.vertices[0] + v(5.0, 0.2, 0.2), -DVec3::X);
    let hit = smooth.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = smooth.surface(&r, &hit);
    assert!(s.normal.dot(ns[0]) > 0.99);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn obj_winding_follows_normals_and_mirroring_keeps_outside() {
    let dir = temp_dir("wind");
    // Winding says +z, the vertex normals say −z: the normals win.
    let path = write(
        &dir,
        "w.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n",
    );
    let tris = load_obj(&path, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let r = Ray::new(v(0.2, 0.2, 1.0), -DVec3::Z);
    let h = tris[0].intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = tris[0].surface(&r, &h);
    assert_vclose(s.normal, -DVec3::Z, 1e-15);
    assert_vclose(s.shading_normal, -DVec3::Z, 1e-15);
    // No normals, mirrored in x: the plane z = 0 keeps its +z outside.
    let path = write(&dir, "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let tris = load_obj(&path, DVec3::ZERO, v(-1.0, 1.0, 1.0), DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let r = Ray::new(v(-0.2, 0.2, 1.0), -DVec3::Z);
    let h = tris[0].intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_vclose(tris[0].surface(&r, &h).normal, DVec3::Z, 1e-15);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn obj_errors_are_messages_not_panics() {
    let dir = temp_dir("err");
    let missing = dir.join("nope.obj");
    let e = load_obj(&missing, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("nope.obj"), "{e}");
    for (name, text) in [
        ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        ("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
        ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
        ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        ("garbage.obj", "v 0 zero 0\nf 1 2 3\n"),
        ("empty.obj", ""),
    ] {
        let p = write(&dir, name, text);
        let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
        assert!(e.contains(name), "{name}: {e}");
    }
    // Bad OBJ text is reported at its line, invalid UTF-8 too.
    for (text, line) in [
        ("v 0 0 0\nv 1 0 0\n# c\nv 0 zero 0\nf 1 2 3\n", "line 4:"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvn 1 x 0", "line 5:"),
    ] {
        let p = write(&dir, "line.obj", text);
        let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
        assert!(e.contains(line), "{text:?}: {e}");
    }
    let p = dir.join("utf8.obj");
    std::fs::write(&p, b"v 0 0 0\nv 1 0 0\n\nv 0 1 0 \xff\n").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("line 4:"), "{e}");
    let p = dir.join("nul.obj");
    std::fs::write(&p, vec![0u8; (1 << 20) + 10]).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("line 1 is longer than 1 MiB"), "{e}");
    let e = load_obj(&dir, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("is a directory"), "{e}");
    // A flattening scale: every triangle degenerate → an error, no NaN triangles.
    let p = write(&dir, "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(load_obj(&p, DVec3::ZERO, v(1.0, 1.0, 0.0), DVec3::ZERO).is_ok());
    assert!(load_obj(&p, DVec3::ZERO, v(1.0, 0.0, 1.0), DVec3::ZERO).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn shipped_meshes_load() {
    let Some(meshes) = super::common::corpus("meshes") else {
        return;
    };
    let path = &meshes.join("stanford-bunny.obj");
    let start = std::time::Instant::now();
    // The transform of community/scene_final.txt.
    let tris = load_obj(
        path,
        v(74.0, -138.0, -8.0),
        DVec3::splat(240.0),
        v(1.6, 0.0, -1.0),
    )
    .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    eprintln!("bunny: {} triangles in {:?}", tris.len(), start.elapsed());
    assert!(
        tris.len() > 69_000 && tris.len() <= 69_451,
        "{} triangles",
        tris.len()
    );
    assert!(
        tris.iter()
            .all(|t| t.double_area() > 0.0 && t.vertices.iter().all(|p| p.is_finite()))
    );
    let b = tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    // The bunny is about 0.15 units across, so about 36 once scaled.
    let size = b.max - b.min;
    assert!(
        size.max_element() > 20.0 && size.max_element() < 60.0,
        "{size}"
    );
    // Rotated about x by 1.6 rad: the model's up (y) is now about +z, so the
    // box is taller in z than the model is deep.
    let r = Ray::new(v(b.center().x, b.center().y, b.max.z + 10.0), -DVec3::Z);
    let hit = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b));
    assert!(
        hit.is_some(),
        "a ray down through the bunny's middle hits it"
    );
    for lucy in ["lucy3_tris_normalized.obj", "lucy3_tris_smooth.obj"] {
        let path = meshes.join(lucy);
        let tris = load_obj(&path, DVec3::ZERO, DVec3::splat(3.0), DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert!(
            tris.len() > 33_000 && tris.len() <= 33_446,
            "{lucy}: {} triangles",
            tris.len()
        );
    }
}

#[test]
fn mesh_triangles_stay_compact() {
    // Meshes hold up to a million triangles, each boxed in a Shape.
    assert!(
        std::mem::size_of::<Triangle>() <= 80,
        "{}",
        std::mem::size_of::<Triangle>()
    );
}

/// A ray that enters a `cube` exactly through an edge, or a `cylinder`
/// exactly through a rim, and goes straight on from the point the renderer
/// would start it from, next hits the solid where it really leaves it (slab
/// exits; for the cylinder the cap planes and the side's far root), not the
/// neighbouring face or the side again at t ≈ 1e-16.
#[test]
fn cube_edges_and_cylinder_rims_do_not_double_hit() {
    let mut rng = Pcg64::seed_from_u64(57);
    // Continues the first hit of `r` straight on; returns (t, exit reference check).
    let continued = |accel: &Accel<Object>, objects: &[crate::scene::Object], r: &Ray| {
        let (i, hit) = accel.intersect(r, INF)?;
        let sp = objects[i as usize].shape.surface(r, &hit);
        let side = if sp.normal.dot(r.dir) < 0.0 {
            sp.normal
        } else {
            -sp.normal
        };
        let next = Ray::off_surface(offset_origin(sp.point, -side), r.dir);
        let (_, h2) = accel.intersect(&next, INF)?;
        Some((next, h2.t))
    };
    for (c, rot, h) in square_box_configs() {
        let text = format!(
            "primitive cube\n O= {}\n Dx= {}\n Dy= {}\n x= {:?}\n y= {:?}\n z= {:?}\nend\n",
            super::common::scene_vec(c),
            super::common::scene_vec(rot.col(0)),
            super::common::scene_vec(rot.col(1)),
            h.x,
            h.y,
            h.z
        );
        let scene = Scene::parse(&text, ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let accel = Accel::build(scene.objects().to_vec());
        let scale = c.abs().max_element() + h.max_element();
        for m in 0..2000 {
            let i = rng.random_range(0..3usize);
            let j = (i + 1 + rng.random_range(0..2usize)) % 3;
            let (si, sj) = (coin_sign(&mut rng), coin_sign(&mut rng));
            let lambda = if m % 4 == 0 {
                si * sj
            } else {
                rng.random_range(-1.0..1.0)
            };
            let target = super::common::box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
            // Outside both faces of the edge (all three at a corner): the ray
            // enters through it.
            let k = 3 - i - j;
            let along = if lambda.abs() == 1.0 {
                lambda * rng.random_range(0.05..1.0)
            } else {
                rng.random_range(-0.5..0.5)
            };
            let out = (rot.col(i) * (si * rng.random_range(0.05..1.0))
                + rot.col(j) * (sj * rng.random_range(0.05..1.0))
                + rot.col(k) * along)
                .normalize();
            let r = Ray::new(target + out * (h.max_element() * 3.0), -out);
            let (next, t2) = continued(&accel, scene.objects(), &r)
                .unwrap_or_else(|| panic!("no exit after entering the cube at {target}")); // invariant: the test's own fixed input (a failure fails the test)
            let (exit, cos) = super::common::box_exit(c, rot, h, next.origin, next.dir);
            assert!(
                (t2 - exit).abs() <= 1e-9 * scale / cos,
                "cube: entering at {target}, went on {next:?}, hit t={t2:e}, exit at {exit}"
            );
        }
    }
    let cylinders = [
        (DVec3::ZERO, v(0.0, 0.0, 2.0), 1.0),
        (v(0.3, -1.2, 0.5), v(1.7, 0.4, 2.9), 0.45),
        (v(100.0, 250.0, -30.0), v(100.2, 250.1, -29.5), 0.03),
    ];
    for (o1, o2, radius) in cylinders {
        let text = format!(
            "primitive cylinder\n O1= {}\n O2= {}\n R= {radius:?}\nend\n",
            super::common::scene_vec(o1),
            super::common::scene_vec(o2)
        );
        let scene = Scene::parse(&text, ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let accel = Accel::build(scene.objects().to_vec());
        let axis = (o2 - o1).normalize();
        let length = (o2 - o1).length();
        let (e1, e2) = crate::geometry::perpendiculars(axis);
        let scale = o1.abs().max(o2.abs()).max_element() + length + radius;
        for m in 0..2000 {
            let phi = rng.random_range(0.0..TAU);
            let radial = e1 * phi.cos() + e2 * phi.sin();
            let top = m % 2 == 0;
            let target = if top { o2 } else { o1 } + radial * radius;
            let cap_out = if top { axis } else { -axis };
            let tangent = axis.cross(radial);
            let out = (cap_out * rng.random_range(0.05..1.0)
                + radial * rng.random_range(0.05..1.0)
                + tangent * rng.random_range(-0.5..0.5))
            .normalize();
            let r = Ray::new(target + out * (length + radius) * 3.0, -out);
            let (next, t2) = continued(&accel, scene.objects(), &r)
                .unwrap_or_else(|| panic!("no exit after entering the cylinder at {target}")); // invariant: the test's own fixed input (a failure fails the test)
            // Exit from inside: the cap plane ahead, or the side's far root.
            let (s, d) = (next.origin - o1, next.dir);
            let (sa, da) = (s.dot(axis), d.dot(axis));
            let cap = if da > 0.0 {
                (length - sa) / da
            } else {
                -sa / da
            };
            let (sp, dp) = (s - axis * sa, d - axis * da);
            let (a, b, cc) = (
                dp.length_squared(),
                sp.dot(dp),
                sp.length_squared() - radius * radius,
            );
            let side = (-b + (b * b - a * cc).max(0.0).sqrt()) / a;
            let exit = cap.min(side);
            let cos = if cap < side {
                da.abs()
            } else {
                (sp + dp * side).normalize().dot(d).abs()
            };
            assert!(
                (t2 - exit).abs() <= 1e-9 * scale / cos,
                "cylinder: entering at {target}, went on {next:?}, hit t={t2:e}, exit at {exit}"
            );
        }
    }
}
