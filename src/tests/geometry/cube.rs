//! Cubes (boxes): the closed form on every face, from inside, along edges
//! and through corners, no crack at the edges, and the implicit reference.

use super::boxes::{edge_box_configs, shoot_at_box_edges};
use super::convex::{Expect, convex_reference};
use super::{INF, assert_close, assert_uv, assert_vclose, ray, v, vec3};
use crate::geometry::{Cube, Ray};
use crate::tests::common::rotation;
use glam::{DMat3, DVec2, DVec3};
use proptest::prelude::*;
use std::f64::consts::PI;

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
