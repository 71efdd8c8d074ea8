//! Triangles: the closed form from both sides with smooth normals, and
//! Cramer's rule as the reference.

use super::{INF, assert_close, assert_uv, assert_vclose, ray, v, vec3};
use crate::geometry::{Aabb, Ray, Triangle};
use crate::tests::common::solve_plane;
use glam::{DVec2, DVec3};
use proptest::prelude::*;

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
