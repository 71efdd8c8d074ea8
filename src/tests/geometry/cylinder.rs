//! Closed cylinders: the closed form on the side and caps, tilted, no crack
//! at the rims, rays a hair from tangency or exactly along the axis, and
//! the implicit reference.

use super::convex::{Expect, convex_reference};
use super::{INF, assert_close, assert_uv, assert_vclose, ray, v, vec3};
use crate::geometry::{Cylinder, Hit, Ray, axis_frame};
use crate::tests::common::rotation;
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::TAU;

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
