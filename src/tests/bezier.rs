//! Ray / Bézier-surface-of-revolution intersection checked against
//! independent references: closed-form quadrics (cylinder, cone,
//! paraboloid), a dense scan of the exact two-equation system in the curve
//! parameter with bisection, and a fine triangle tessellation.

use crate::geometry::{Bezier, Ray, SurfacePoint, offset_origin};
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use std::f64::consts::TAU;

use super::common::bezier::{GRAZING, Model, RefHit, casteljau, scan_roots};

/// glint's surface for the model's axis and profile.
fn surface_of(m: &Model) -> Bezier {
    let pts =
        m.z.iter()
            .zip(&m.r)
            .map(|(&z, &r)| DVec2::new(z, r))
            .collect();
    Bezier::new(m.o1, m.o2, pts)
}

/// Checks `intersect` on one ray against the reference hits `refs`:
/// a reported hit lies on the surface circle of its s (1e-9 relative; s is
/// not compared, as a folded profile may pass a point at several s) within the window,
/// and no clear (non-grazing, not on the rim) reference hit is nearer; no
/// hit is reported only if the reference has no clear hit; the any-hit
/// query agrees.
fn check(model: &Model, ray: &Ray, t_min: f64, t_max: f64, refs: &[RefHit]) -> Result<(), String> {
    let shape = surface_of(model);
    let span = model.scale + (ray.origin - model.o1).length();
    let tol = 1e-7 * span;
    let mine = shape.intersect(ray, t_min, t_max);
    let blocked = shape.blocks(ray, t_min, t_max);
    if blocked != mine.is_some() {
        return Err(format!("any-hit says {blocked}, the nearest hit {mine:?}"));
    }
    let clear = refs
        .iter()
        .filter(|h| {
            h.t > t_min + tol
                && h.t < t_max - tol
                && h.cos > GRAZING
                && h.s > 1e-6
                && h.s < 1.0 - 1e-6
        })
        .min_by(|a, b| a.t.total_cmp(&b.t));
    match (mine, clear) {
        (Some(h), _) if !(h.t > t_min && h.t < t_max) => {
            Err(format!("hit t={} outside ({t_min}, {t_max})", h.t))
        }
        (Some(h), _) if !(0.0..=1.0).contains(&h.u) => Err(format!("hit s={} outside [0, 1]", h.u)),
        (Some(h), _) if model.residual(h.u, ray.at(h.t)) > 1e-9 * span => Err(format!(
            "hit t={} s={} is off the surface by {:e}",
            h.t,
            h.u,
            model.residual(h.u, ray.at(h.t))
        )),
        (Some(h), Some(c)) if h.t > c.t + tol => Err(format!(
            "missed the nearer hit t={} s={} cos={} (got t={} s={})",
            c.t, c.s, c.cos, h.t, h.u
        )),
        (None, Some(c)) => Err(format!("missed hit t={} s={} cos={}", c.t, c.s, c.cos)),
        _ => Ok(()),
    }
}

fn ray_to(origin: DVec3, target: DVec3) -> Ray {
    Ray::new(origin, (target - origin).normalize())
}

// ---------------------------------------------------------------------------
// Closed forms.

/// Real roots of a·t² + b·t + c (a may be 0).
fn quadratic(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b == 0.0 { vec![] } else { vec![-c / b] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    if q == 0.0 {
        return vec![0.0];
    }
    vec![q / a, c / q]
}

/// The ray in the axis frame of `m`: (pa, da, A, B, C).
fn axis_coords(m: &Model, ray: &Ray) -> (f64, f64, f64, f64, f64) {
    let (pa, da, pp, dp) = m.split(ray.origin, ray.dir);
    (pa, da, dp.length_squared(), pp.dot(dp), pp.length_squared())
}

/// Hits of a quadric of revolution given as the quadratic in t, kept where
/// the height lies on the profile; s from the height via `s_of_h`.
fn quadric_hits(
    m: &Model,
    ray: &Ray,
    coeffs: (f64, f64, f64),
    h_range: (f64, f64),
    s_of: impl Fn(f64, f64) -> f64,
) -> Vec<RefHit> {
    let (pa, da, ..) = axis_coords(m, ray);
    quadratic(coeffs.0, coeffs.1, coeffs.2)
        .into_iter()
        .filter_map(|t| {
            let h = pa + t * da;
            let (_, rho) = m.axial(ray.at(t));
            let pad = 1e-12 * m.scale;
            (h >= h_range.0 - pad && h <= h_range.1 + pad).then(|| {
                let s = s_of(h, rho).clamp(0.0, 1.0);
                RefHit {
                    t,
                    s,
                    cos: m.normal(s, ray.at(t)).dot(ray.dir).abs(),
                }
            })
        })
        .collect()
}

/// Cylinder of radius `rad` over heights [0, h]: profile (0, R), (h, R).
fn cylinder_hits(m: &Model, ray: &Ray, h: f64, rad: f64) -> Vec<RefHit> {
    let (_, _, a, b, c) = axis_coords(m, ray);
    quadric_hits(m, ray, (a, 2.0 * b, c - rad * rad), (0.0, h), |z, _| z / h)
}

/// Cone with radius r0 + (r1 − r0)·z/h over [0, h] (both nappes if the radius changes sign).
fn cone_hits(m: &Model, ray: &Ray, h: f64, r0: f64, r1: f64) -> Vec<RefHit> {
    let (pa, da, a, b, c) = axis_coords(m, ray);
    let k = (r1 - r0) / h;
    let (alpha, beta) = (r0 + k * pa, k * da);
    quadric_hits(
        m,
        ray,
        (a - beta * beta, 2.0 * (b - alpha * beta), c - alpha * alpha),
        (0.0, h),
        |z, _| z / h,
    )
}

/// Paraboloid z = h·ρ²/R² for ρ ≤ R: profile z = (0, 0, h), r = (0, R/2, R).
fn paraboloid_hits(m: &Model, ray: &Ray, h: f64, rad: f64) -> Vec<RefHit> {
    let (pa, da, a, b, c) = axis_coords(m, ray);
    let k = h / (rad * rad);
    quadric_hits(
        m,
        ray,
        (k * a, 2.0 * k * b - da, k * c - pa),
        (0.0, h),
        |_, rho| rho / rad,
    )
}

/// Rays at `m`: aimed at random surface points from all around, some
/// nearly perpendicular to the axis (da = ±10⁻ᵏ, 0), some along it.
fn closed_form_rays(m: &Model, count: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Lcg(seed);
    let center = m.o1 + m.a * 0.5 * (m.z[0] + m.z[m.z.len() - 1]);
    let mut rays = Vec::new();
    for i in 0..count {
        let target = m.point(rng.next(), rng.next() * TAU);
        let origin = center + rng.unit() * m.scale * (0.2 + 3.0 * rng.next());
        let mut ray = ray_to(origin, target);
        match i % 4 {
            1 => {
                let perp = ray.dir - m.a * ray.dir.dot(m.a);
                let k = (i / 4) % 18;
                let eps = if k == 17 {
                    0.0
                } else {
                    10f64.powi(-(k as i32))
                };
                let sign = if rng.next() < 0.5 { -1.0 } else { 1.0 };
                let dir = (perp.normalize() + m.a * eps * sign).normalize();
                ray = Ray::new(target - dir * m.scale * (0.5 + 2.0 * rng.next()), dir);
            }
            2 => {
                let dir = if rng.next() < 0.5 { m.a } else { -m.a };
                ray = Ray::new(target - dir * m.scale * (0.5 + 2.0 * rng.next()), dir);
            }
            _ => {}
        }
        rays.push(ray);
    }
    rays
}

/// A small deterministic generator for the fixed-profile tests.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0;
            let l = v.length();
            if l > 0.1 && l < 1.0 {
                return v / l;
            }
        }
    }
}

/// Compares every ray of `rays` with the closed form `hits`, exactly:
/// t to 1e-9 relative, s, and the outward normal.
fn closed_form_check(m: &Model, rays: &[Ray], hits: impl Fn(&Ray) -> Vec<RefHit>) {
    let shape = surface_of(m);
    let mut compared = 0;
    for ray in rays {
        let refs = hits(ray);
        check(m, ray, 0.0, f64::INFINITY, &refs).unwrap_or_else(|e| panic!("{ray:?}: {e}")); // invariant: the test's own fixed input (a failure fails the test)
        let near = refs
            .iter()
            .filter(|h| h.t > 0.0)
            .min_by(|a, b| a.t.total_cmp(&b.t));
        let mine = shape.intersect(ray, 0.0, f64::INFINITY);
        if let (Some(h), Some(c)) = (mine, near)
            && c.cos > GRAZING
            && c.s > 1e-6
            && c.s < 1.0 - 1e-6
        {
            let span = m.scale + (ray.origin - m.o1).length();
            assert!(
                (h.t - c.t).abs() <= 1e-9 * span,
                "{ray:?}: t {} vs closed form {}",
                h.t,
                c.t
            );
            let sp = shape.surface(ray, &h);
            let want = m.normal(c.s, ray.at(c.t));
            // (At an apex on the axis the normal is undefined.)
            assert!(
                sp.normal.dot(want) > 1.0 - 1e-9 || m.axial(sp.point).1 < 1e-6 * m.scale,
                "{ray:?}: normal {} vs {want}",
                sp.normal
            );
            compared += 1;
        }
    }
    assert!(compared > rays.len() / 3, "only {compared} hits compared");
}

#[test]
fn cylinder_matches_closed_form_at_every_degree() {
    let m = Model::new(
        DVec3::new(1.0, -2.0, 0.5),
        DVec3::new(2.0, 1.0, 3.0),
        &[(0.0, 1.5), (4.0, 1.5)],
    );
    let rays = closed_form_rays(&m, 2000, 1);
    let mut e = m.clone();
    // Up to the fixed-size path's limit (16), just past it, and the most
    // glint accepts (64).
    for degree in 1..=Bezier::MAX_DEGREE {
        if [1, 2, 3, 8, 16, 17, 20, 30, 64].contains(&degree) {
            let rays = if degree > 16 { &rays[..800] } else { &rays[..] };
            closed_form_check(&e, rays, |r| cylinder_hits(&e, r, 4.0, 1.5));
        }
        e = e.elevated();
    }
    assert_eq!(
        e.z.len(),
        Bezier::MAX_DEGREE + 2,
        "the loop reached the cap"
    );
}

/// A cone (through its apex) and a paraboloid elevated to degrees 20, 30
/// and 64 still match their closed forms exactly.
#[test]
fn high_degree_elevations_match_closed_forms() {
    let o1 = DVec3::new(0.5, 0.25, -1.0);
    let cone = Model::new(
        o1,
        o1 + DVec3::new(0.3, -0.2, 1.0),
        &[(0.0, -1.0), (3.0, 2.0)],
    );
    let bowl = Model::new(
        DVec3::new(-3.0, 1.0, 2.0),
        DVec3::new(-2.8, 1.9, 1.6),
        &[(0.0, 0.0), (0.0, 1.0), (2.5, 2.0)],
    );
    let cone_rays = closed_form_rays(&cone, 600, 21);
    let bowl_rays = closed_form_rays(&bowl, 600, 22);
    let (mut c, mut b) = (cone.clone(), bowl.clone());
    while c.z.len() <= Bezier::MAX_DEGREE + 1 {
        let degree = c.z.len() - 1;
        if [20, 30, 64].contains(&degree) {
            closed_form_check(&c, &cone_rays, |r| cone_hits(&c, r, 3.0, -1.0, 2.0));
            apex_rays_check(&c, 3.0, -1.0, 2.0, 1000);
        }
        if [20, 30, 64].contains(&(b.z.len() - 1)) {
            closed_form_check(&b, &bowl_rays, |r| paraboloid_hits(&b, r, 2.5, 2.0));
        }
        c = c.elevated();
        b = b.elevated();
    }
}

/// Rays through the apex of the cone `m` (radius r0 → r1 over height h,
/// changing sign), from all sides: the closed form has a double root there,
/// so check against the apex itself.
fn apex_rays_check(m: &Model, h: f64, r0: f64, r1: f64, count: usize) {
    let apex = m.o1 + m.a * h * r0 / (r0 - r1);
    let cos_half_angle = h / h.hypot(r1 - r0);
    let mut rng = Lcg(9);
    let shape = surface_of(m);
    for _ in 0..count {
        let dir = rng.unit();
        let dist = 0.5 + 3.0 * rng.next();
        let ray = Ray::new(apex - dir * dist, dir);
        let hit = shape.intersect(&ray, 0.0, f64::INFINITY);
        assert_eq!(
            shape.blocks(&ray, 0.0, f64::INFINITY),
            hit.is_some(),
            "{ray:?}"
        );
        let inside = dir.dot(m.a).abs() > cos_half_angle + 1e-6;
        let outside = dir.dot(m.a).abs() < cos_half_angle - 1e-6;
        if inside || (outside && hit.is_some()) {
            let h = hit.unwrap_or_else(|| panic!("{ray:?} misses the apex")); // invariant: the test's own fixed input (a failure fails the test)
            assert!(
                (h.t - dist).abs() < 1e-9 * dist,
                "{ray:?}: t {} vs {dist}",
                h.t
            );
        }
    }
}

#[test]
fn cones_match_closed_form() {
    for (r0, r1, axis) in [
        (2.0, 0.5, DVec3::Z),
        (0.0, 2.0, DVec3::new(0.3, -0.2, 1.0)),
        (-1.0, 2.0, DVec3::X),
        (1.5, -1.5, DVec3::new(1.0, 1.0, -1.0)),
        (1.0, -2.0, DVec3::new(-0.3, 0.1, 0.7)),
        (-2.5, 0.5, DVec3::Y),
    ] {
        let o1 = DVec3::new(0.5, 0.25, -1.0);
        let m = Model::new(o1, o1 + axis, &[(0.0, r0), (3.0, r1)]);
        let rays = closed_form_rays(&m, 1500, 2);
        closed_form_check(&m, &rays, |r| cone_hits(&m, r, 3.0, r0, r1));
        if r0 * r1 <= 0.0 {
            apex_rays_check(&m, 3.0, r0, r1, 2000);
        }
        let e = m.elevated().elevated();
        closed_form_check(&e, &rays, |r| cone_hits(&e, r, 3.0, r0, r1));
    }
}

#[test]
fn paraboloid_matches_closed_form() {
    for axis in [DVec3::Z, -DVec3::Z, DVec3::new(0.2, 0.9, -0.4)] {
        let o1 = DVec3::new(-3.0, 1.0, 2.0);
        let m = Model::new(o1, o1 + axis * 7.0, &[(0.0, 0.0), (0.0, 1.0), (2.5, 2.0)]);
        let rays = closed_form_rays(&m, 2000, 3);
        closed_form_check(&m, &rays, |r| paraboloid_hits(&m, r, 2.5, 2.0));
    }
}

/// Sweeps the ray's slope against the axis through 0 in powers of ten,
/// through fixed points of the surface: the hit must not flicker.
#[test]
fn near_perpendicular_rays_have_no_gap() {
    type Reference = Box<dyn Fn(&Model, &Ray) -> Vec<RefHit>>;
    let shapes: Vec<(Model, Reference)> = vec![
        (
            Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 1.5), (4.0, 1.5)]),
            Box::new(|m, r| cylinder_hits(m, r, 4.0, 1.5)),
        ),
        (
            Model::new(
                DVec3::ONE,
                DVec3::new(1.0, 2.0, 3.0),
                &[(0.0, 2.0), (3.0, 0.5)],
            ),
            Box::new(|m, r| cone_hits(m, r, 3.0, 2.0, 0.5)),
        ),
        (
            Model::new(DVec3::ZERO, DVec3::X, &[(0.0, 0.0), (0.0, 1.0), (2.5, 2.0)]),
            Box::new(|m, r| paraboloid_hits(m, r, 2.5, 2.0)),
        ),
        (
            // A lip folding back over itself: z is not monotone.
            Model::new(
                DVec3::ZERO,
                DVec3::Z,
                &[(0.0, 1.0), (4.0, 1.2), (5.0, 3.0), (1.0, 2.5)],
            ),
            Box::new(|m, r| m.scan(r.origin, r.dir, 8000)),
        ),
    ];
    let mut rng = Lcg(4);
    for (m, hits) in &shapes {
        for _ in 0..40 {
            let target = m.point(0.02 + 0.96 * rng.next(), rng.next() * TAU);
            let perp = {
                let v = rng.unit();
                (v - m.a * v.dot(m.a)).normalize()
            };
            for k in 0..=20 {
                for sign in [-1.0, 1.0] {
                    let eps = if k == 20 { 0.0 } else { sign * 10f64.powi(-k) };
                    let dir = (perp + m.a * eps).normalize();
                    let ray = Ray::new(target - dir * 6.0, dir);
                    check(m, &ray, 0.0, f64::INFINITY, &hits(m, &ray))
                        .unwrap_or_else(|e| panic!("eps {eps:e} {ray:?}: {e}")); // invariant: the test's own fixed input (a failure fails the test)
                    // Rays aimed straight at a surface point hit something by t ≈ 6.
                    let h = surface_of(m).intersect(&ray, 0.0, f64::INFINITY);
                    let clear = hits(m, &ray)
                        .iter()
                        .any(|h| (h.t - 6.0).abs() < 1e-6 && h.cos > GRAZING);
                    if clear {
                        assert!(h.is_some_and(|h| h.t <= 6.0 + 1e-9), "gap at eps {eps:e}");
                    }
                }
            }
        }
    }
}

/// Rays tangent to the surface, and just inside and outside of tangent:
/// silhouettes of a cylinder and a cone, the top of a folded lip, a waist.
#[test]
fn tangent_rays() {
    let lip = Model::new(
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.0, 0.0, 2.0),
        &[(0.0, 1.0), (4.0, 1.2), (5.0, 3.0), (1.0, 2.5)],
    );
    // Height and radius of the lip's top: where z' = 0.
    let top = scan_roots(&|s| lip.dzr(s).0, 1000)[0];
    let (z_top, r_top) = lip.zr(top);
    let waist = Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 2.0), (2.0, 0.0), (4.0, 2.0)]);
    let (z_w, r_w) = waist.zr(0.5);
    let cylinder = Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 1.5), (4.0, 1.5)]);
    let mut rng = Lcg(8);
    for k in 2..=16 {
        for sign in [-1.0, 1.0, 0.0] {
            let eps = sign * 10f64.powi(-k);
            let phi = rng.next() * TAU;
            let (c, s) = (phi.cos(), phi.sin());
            let side = DVec3::new(-s, c, 0.0);
            let radial = DVec3::new(c, s, 0.0);
            let cases = [
                // Horizontal over the lip's top, and tilted a little.
                (
                    &lip,
                    Ray::new(
                        DVec3::new(0.0, 0.0, 1.0 + z_top + eps) + radial * r_top - side * 5.0,
                        side,
                    ),
                ),
                (
                    &lip,
                    Ray::new(
                        DVec3::new(0.0, 0.0, 1.0 + z_top + eps) - radial * 6.0,
                        radial,
                    ),
                ),
                (
                    &lip,
                    Ray::new(
                        DVec3::new(0.0, 0.0, 1.0 + z_top + eps) - radial * 6.0,
                        (radial + DVec3::Z * 1e-4).normalize(),
                    ),
                ),
                // Tangent to the cylinder's side, to the waist's circle.
                (
                    &cylinder,
                    Ray::new(radial * (1.5 + eps) + DVec3::Z * 2.0 - side * 4.0, side),
                ),
                (
                    &waist,
                    Ray::new(radial * (r_w + eps) + DVec3::Z * z_w - side * 4.0, side),
                ),
                (
                    &waist,
                    Ray::new(
                        radial * (r_w + eps) + DVec3::Z * z_w - DVec3::Z * 3.0,
                        DVec3::Z,
                    ),
                ),
            ];
            for (m, ray) in cases {
                check(
                    m,
                    &ray,
                    0.0,
                    f64::INFINITY,
                    &m.scan(ray.origin, ray.dir, 20000),
                )
                .unwrap_or_else(|e| panic!("eps {eps:e} {ray:?}: {e}")); // invariant: the test's own fixed input (a failure fails the test)
            }
        }
    }
}

/// `count` random profiles (degree `degree_of(i)`) running from r > 0 to
/// r < 0, half on the z axis, half on slanted axes: rays along the axis
/// both ways hit the first apex (a zero of r) exactly.
fn axis_apex_check(count: usize, seed: u64, degree_of: impl Fn(usize) -> usize) {
    let mut rng = Lcg(seed);
    let mut checked = 0;
    for i in 0..count {
        let degree = degree_of(i);
        let mut pts: Vec<(f64, f64)> = (0..=degree)
            .map(|k| (k as f64 + 0.5 * rng.next(), 2.0 * rng.next() - 1.0))
            .collect();
        pts[0].1 = 0.5 + rng.next();
        pts[degree].1 = -0.5 - rng.next();
        // Half on the z axis, where a ray up the axis is exactly on it.
        let m = if i % 2 == 0 {
            Model::new(DVec3::ZERO, DVec3::Z, &pts)
        } else {
            let o1 = rng.unit();
            Model::new(o1, o1 + rng.unit(), &pts)
        };
        let zeros = scan_roots(&|s| casteljau(&m.r, s), 2000);
        let s0 = zeros[0];
        let apex = m.o1 + m.a * casteljau(&m.z, s0);
        for dir in [m.a, -m.a] {
            let ray = Ray::new(apex - dir * (1.0 + 10.0 * rng.next()), dir);
            let want = (apex - ray.origin).dot(dir);
            let surface = surface_of(&m);
            let h = surface.intersect(&ray, 0.0, f64::INFINITY);
            assert_eq!(
                surface.blocks(&ray, 0.0, f64::INFINITY),
                h.is_some(),
                "{ray:?}"
            );
            // Only the nearest apex on the ray counts; skip rays that meet
            // another (where r has several zeros) first.
            let first = zeros
                .iter()
                .map(|&s| (m.o1 + m.a * casteljau(&m.z, s) - ray.origin).dot(dir))
                .filter(|&t| t > 0.0)
                .fold(f64::INFINITY, f64::min);
            if (first - want).abs() > 1e-9 {
                continue;
            }
            let h = h.unwrap_or_else(|| panic!("{pts:?} {ray:?}: missed the apex at {want}")); // invariant: the test's own fixed input (a failure fails the test)
            assert!(
                (h.t - want).abs() < 1e-9 * (1.0 + want),
                "t {} vs {want}",
                h.t
            );
            checked += 1;
        }
    }
    assert!(checked >= count / 2, "only {checked} apexes checked");
}

#[test]
fn rays_along_the_axis() {
    // Paraboloid: a ray up the axis at offset ρ meets it at height h·ρ²/R².
    let m = Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 0.0), (0.0, 1.0), (2.5, 2.0)]);
    let shape = surface_of(&m);
    for rho in [0.0, 1e-300, 1e-12, 1e-6, 0.3, 1.0, 1.9] {
        let ray = Ray::new(DVec3::new(rho, 0.0, -1.0), DVec3::Z);
        let h = shape.intersect(&ray, 0.0, f64::INFINITY).expect("hit"); // invariant: the test's own fixed input (a failure fails the test)
        let want = 1.0 + 2.5 * rho * rho / 4.0;
        assert!((h.t - want).abs() < 1e-12, "ρ {rho}: t {} vs {want}", h.t);
        let n = shape.surface(&ray, &h).normal;
        assert!(
            n.dot(ray.dir) < 0.0,
            "ρ {rho}: the bowl's underside faces down: {n}"
        );
        // From above, inside the bowl.
        let down = Ray::new(DVec3::new(rho, 0.0, 5.0), -DVec3::Z);
        let h = shape.intersect(&down, 0.0, f64::INFINITY).expect("hit"); // invariant: the test's own fixed input (a failure fails the test)
        assert!(
            (h.t - (5.0 - want + 1.0)).abs() < 1e-12,
            "ρ {rho} down: {}",
            h.t
        );
    }
    // An hourglass (r from 1 to −1): up the axis through the apex at height 1.
    let m = Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 1.0), (2.0, -1.0)]);
    let shape = surface_of(&m);
    for rho in [0.0, 1e-15, 1e-9, 0.5] {
        let ray = Ray::new(DVec3::new(0.0, rho, -1.0), DVec3::Z);
        let h = shape.intersect(&ray, 0.0, f64::INFINITY).expect("hit"); // invariant: the test's own fixed input (a failure fails the test)
        let want = 2.0 - rho;
        assert!((h.t - want).abs() < 1e-12, "ρ {rho}: t {} vs {want}", h.t);
    }
    // Apexes where the zero of r is not a dyadic parameter (on slanted axes).
    axis_apex_check(200, 10, |i| 1 + i % 5);
    // A cylinder has no hit along its axis (inside or outside it).
    let m = Model::new(DVec3::ZERO, DVec3::Z, &[(0.0, 1.0), (2.0, 1.0)]);
    for x in [0.0, 0.5, 0.999, 1.001, 3.0] {
        let ray = Ray::new(DVec3::new(x, 0.0, -1.0), DVec3::Z);
        assert!(
            surface_of(&m).intersect(&ray, 0.0, f64::INFINITY).is_none(),
            "x {x}"
        );
    }
}

// ---------------------------------------------------------------------------
// Random profiles against the scan reference.

fn arb_unit() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        3 => (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("not tiny", |v| DVec3::new(v.0, v.1, v.2).length() > 0.1)
            .prop_map(|v| DVec3::new(v.0, v.1, v.2).normalize()),
        1 => prop::sample::select(vec![DVec3::Z, -DVec3::Z, DVec3::X, DVec3::Y]),
    ]
}

/// Sorts the control points' z (keeping their r in place) when `monotone`, and makes every r positive when `positive`.
fn sort_z_and_fold_r(pts: &mut [(f64, f64)], monotone: bool, positive: bool) {
    if monotone {
        let mut z: Vec<f64> = pts.iter().map(|p| p.0).collect();
        z.sort_by(f64::total_cmp);
        for (p, z) in pts.iter_mut().zip(z) {
            p.0 = z;
        }
    }
    if positive {
        for p in pts {
            p.1 = p.1.abs();
        }
    }
}

prop_compose! {
    /// Degree 1–8 profiles: z free (folds back) or sorted, r of any sign or
    /// positive; some flat (one z: an annulus), some with a repeated end
    /// point (the tangent vanishes there).
    fn arb_model()(
        pts in prop::collection::vec((-5.0..5.0f64, -4.0..4.0f64), 2..=8),
        monotone in any::<bool>(),
        positive in any::<bool>(),
        shape in prop_oneof![6 => Just(0), 1 => Just(1), 1 => Just(2)],
        o1 in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        axis in arb_unit(),
        len in 0.5..3.0f64,
    ) -> Model {
        let mut pts = pts;
        sort_z_and_fold_r(&mut pts, monotone, positive);
        match shape {
            1 => {
                let z = pts[0].0;
                for p in &mut pts {
                    p.0 = z;
                }
            }
            2 => pts.insert(0, pts[0]),
            _ => {}
        }
        let o1 = DVec3::new(o1.0, o1.1, o1.2);
        Model::new(o1, o1 + axis * len, &pts)
    }
}

#[derive(Clone, Debug)]
enum RayKind {
    /// From outside towards a surface point (plus a miss distance).
    Aimed,
    /// From anywhere near the surface, possibly inside it.
    Inside,
    /// Aimed, with the direction's axial part set to ±10⁻ᵏ (or 0).
    Perpendicular(i32),
    /// Along the axis.
    Axial,
}

/// A random profile of degree 1–8 with a random ray (see [`arb_case_from`]).
fn arb_case() -> impl Strategy<Value = (Model, Ray, RayKind)> {
    arb_case_from(arb_model().boxed())
}

prop_compose! {
    /// A profile from `models` with a random ray of every [`RayKind`].
    fn arb_case_from(models: BoxedStrategy<Model>)(
        m in models,
        s in 0.0..1.0f64,
        phi in 0.0..TAU,
        miss in prop_oneof![3 => Just(0.0), 1 => 0.0..0.3f64],
        from in arb_unit(),
        dist in 0.0..4.0f64,
        kind in prop_oneof![
            4 => Just(RayKind::Aimed),
            2 => Just(RayKind::Inside),
            2 => (0..18i32).prop_map(RayKind::Perpendicular),
            1 => Just(RayKind::Axial),
        ],
        jitter in arb_unit(),
        sign in prop::bool::ANY,
    ) -> (Model, Ray, RayKind) {
        let target = m.point(s, phi) + jitter * miss * m.scale;
        let center = m.o1 + m.a * 0.5 * (casteljau(&m.z, 0.0) + casteljau(&m.z, 1.0));
        let ray = match kind {
            RayKind::Aimed => ray_to(center + from * m.scale * (1.5 + dist), target),
            RayKind::Inside => Ray::new(center + jitter * m.scale * dist * 0.5, from),
            RayKind::Perpendicular(k) => {
                let perp = from - m.a * from.dot(m.a);
                let perp = if perp.length() < 1e-3 { m.u } else { perp.normalize() };
                let eps = if k == 17 { 0.0 } else { 10f64.powi(-k) };
                let dir = (perp + m.a * if sign { eps } else { -eps }).normalize();
                Ray::new(target - dir * m.scale * (0.2 + dist), dir)
            }
            RayKind::Axial => {
                let dir = if sign { m.a } else { -m.a };
                Ray::new(target - dir * m.scale * (0.2 + dist), dir)
            }
        };
        (m, ray, kind)
    }
}

/// [`check`] over the whole ray against the scan reference (4000 steps), which it returns.
fn scan_check(m: &Model, ray: &Ray) -> Result<Vec<RefHit>, TestCaseError> {
    let refs = m.scan(ray.origin, ray.dir, 4000);
    check(m, ray, 0.0, f64::INFINITY, &refs).map_err(TestCaseError::fail)?;
    Ok(refs)
}

/// [`check`] in the window (w0, w1 as fractions of the farthest reference hit, at least 1) against the scan reference.
fn window_check(m: &Model, ray: &Ray, w0: f64, w1: f64) -> Result<(), TestCaseError> {
    let refs = m.scan(ray.origin, ray.dir, 4000);
    let far = refs.iter().map(|h| h.t).fold(1.0, f64::max);
    let (t_min, t_max) = (w0.min(w1) * far, w0.max(w1) * far * 1.1);
    check(m, ray, t_min, t_max, &refs).map_err(TestCaseError::fail)
}

/// The ray's line, started 10^`k` object sizes before its point nearest O1.
fn far_ray(m: &Model, ray: &Ray, k: i32) -> Ray {
    let target = ray.at((m.o1 - ray.origin).dot(ray.dir));
    Ray::new(target - ray.dir * m.scale * 10f64.powi(k), ray.dir)
}

fn config(cases: u32, seed: u64) -> Config {
    Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config(4000, 11))]

    #[test]
    fn random_profiles_match_scan_reference((m, ray, _kind) in arb_case()) {
        scan_check(&m, &ray)?;
    }
}

proptest! {
    #![proptest_config(config(500, 17))]

    /// Rays from far away (up to 10⁶ times the object's size).
    #[test]
    fn far_origins_match_scan_reference((m, ray, _kind) in arb_case(), k in 1..=6i32) {
        scan_check(&m, &far_ray(&m, &ray, k))?;
    }
}

proptest! {
    #![proptest_config(config(1500, 12))]

    /// Windows (t_min, t_max) cut through the hits: the nearest one inside wins.
    #[test]
    fn random_windows_match_scan_reference(
        (m, ray, _kind) in arb_case(),
        w0 in 0.0..1.0f64,
        w1 in 0.0..1.0f64,
    ) {
        window_check(&m, &ray, w0, w1)?;
    }
}

proptest! {
    #![proptest_config(config(1500, 13))]

    /// A negative radius draws the same surface with the same normals.
    #[test]
    fn negative_radius_is_the_same_surface((m, ray, _kind) in arb_case()) {
        // Flip the sign of the whole profile: r → −r.
        let mut neg = m.clone();
        for r in &mut neg.r {
            *r = -*r;
        }
        let (a, b) = (surface_of(&m), surface_of(&neg));
        let (ha, hb) = (a.intersect(&ray, 0.0, f64::INFINITY), b.intersect(&ray, 0.0, f64::INFINITY));
        let refs = m.scan(ray.origin, ray.dir, 4000);
        check(&neg, &ray, 0.0, f64::INFINITY, &refs).map_err(TestCaseError::fail)?;
        if let (Some(ha), Some(hb)) = (ha, hb) {
            let span = m.scale + (ray.origin - m.o1).length();
            prop_assert!((ha.t - hb.t).abs() < 1e-9 * span, "t {} vs {}", ha.t, hb.t);
            let cos = m.normal(ha.u, ray.at(ha.t)).dot(ray.dir).abs();
            if cos > 1e-3 && (ha.u - hb.u).abs() < 1e-6 {
                let (na, nb) = (a.surface(&ray, &ha).normal, b.surface(&ray, &hb).normal);
                prop_assert!(na.dot(nb) > 1.0 - 1e-9, "{na} vs {nb}");
            }
        }
    }
}

/// Checks the hit's unit normal against the model where it is well defined, and uv.x = s; returns the hit's surface point.
fn check_normal(m: &Model, ray: &Ray) -> Result<Option<SurfacePoint>, TestCaseError> {
    let shape = surface_of(m);
    let Some(h) = shape.intersect(ray, 0.0, f64::INFINITY) else {
        return Ok(None);
    };
    let sp = shape.surface(ray, &h);
    prop_assert!((sp.normal.length() - 1.0).abs() < 1e-12);
    let (_, rho) = m.axial(sp.point);
    let (dz, dr) = m.dzr(h.u);
    if rho > 1e-6 * m.scale && dz.hypot(dr) > 1e-6 * m.scale {
        let want = m.normal(h.u, sp.point);
        prop_assert!(sp.normal.dot(want) > 1.0 - 1e-9, "{} vs {want}", sp.normal);
    }
    prop_assert_eq!(sp.uv.x, h.u);
    Ok(Some(sp))
}

proptest! {
    #![proptest_config(config(1500, 14))]

    /// The normal is the unit outward normal of the |r| profile, and uv is
    /// (s, angle around the axis / 2π) in the spec's frame.
    #[test]
    fn normal_and_uv_follow_the_spec((m, ray, _kind) in arb_case()) {
        if let Some(sp) = check_normal(&m, &ray)? {
            let (_, rho) = m.axial(sp.point);
            // The spec's frame: e1 = unit(a × z), or x when a ∥ z; e2 = a × e1.
            let c = m.a.cross(DVec3::Z);
            let e1 = if c.length() < 1e-12 { DVec3::X } else { c.normalize() };
            let e2 = m.a.cross(e1);
            let q = sp.point - m.o1;
            if rho > 1e-6 * m.scale {
                let mut want = q.dot(e2).atan2(q.dot(e1)) / TAU;
                if want < 0.0 {
                    want += 1.0;
                }
                let diff = (sp.uv.y - want).abs();
                prop_assert!(diff.min(1.0 - diff) < 1e-9, "v {} vs {want}", sp.uv.y);
                prop_assert!((0.0..1.0).contains(&sp.uv.y));
            }
        }
    }
}

proptest! {
    #![proptest_config(config(300, 15))]

    /// The box holds every point of the surface and touches its extremes.
    #[test]
    fn bounds_are_tight((m, _ray, _kind) in arb_case()) {
        let b = surface_of(&m).bounds();
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for i in 0..=400 {
            for j in 0..360 {
                let p = m.point(i as f64 / 400.0, j as f64 / 360.0 * TAU);
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        let eps = 1e-9 * (m.scale + m.o1.abs().max_element()) * 2.0;
        prop_assert!(b.min.cmple(lo + eps).all() && b.max.cmpge(hi - eps).all(), "{b:?} vs {lo} {hi}");
        // Sampling every 1/400 in s and 1° in φ misses the extremes by at most this.
        let slack = 1e-3 * m.scale;
        prop_assert!(b.min.cmpge(lo - slack).all() && b.max.cmple(hi + slack).all(), "{b:?} vs {lo} {hi}");
    }
}

proptest! {
    #![proptest_config(config(1500, 16))]

    /// Rays leaving a hit point (reflected and transmitted, nudged off the
    /// surface the renderer's way) do not hit the same spot again.
    #[test]
    fn secondary_rays_do_not_rehit((m, ray, _kind) in arb_case()) {
        let shape = surface_of(&m);
        let Some(h) = shape.intersect(&ray, 0.0, f64::INFINITY) else { return Ok(()) };
        let sp = shape.surface(&ray, &h);
        let cos = sp.normal.dot(ray.dir);
        if cos.abs() < 0.05 || h.u < 1e-6 || h.u > 1.0 - 1e-6 {
            return Ok(());
        }
        let reflected = ray.dir - sp.normal * 2.0 * cos;
        for dir in [reflected, ray.dir] {
            let side = if dir.dot(sp.normal) > 0.0 { sp.normal } else { -sp.normal };
            let next = Ray::new(offset_origin(sp.point, side), dir);
            if let Some(g) = shape.intersect(&next, 0.0, f64::INFINITY) {
                let refs = scan_check(&m, &next)?;
                prop_assert!(
                    g.t > 1e-6 * m.scale || refs.iter().any(|r| (r.t - g.t).abs() < 1e-7 * m.scale),
                    "re-hit at t={} s={} (from s={})", g.t, g.u, h.u
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------
// High degrees (above the fixed-size path's 16).

/// A "ribbed" profile of degree `n`, control points sampled from sines:
/// z_k = h·x + a·sin(2π·fz·x + pz), r_k = r0 + b·sin(2π·fr·x + pr) at x = k/n.
/// With a large `a` the profile folds back (z not monotone); with `b` > `r0`
/// it crosses the axis (negative r). `z` is (h, a, fz, pz), `r` (r0, b, fr, pr).
fn ribbed(n: usize, z: (f64, f64, f64, f64), r: (f64, f64, f64, f64)) -> Vec<(f64, f64)> {
    let ((h, a, fz, pz), (r0, b, fr, pr)) = (z, r);
    (0..=n)
        .map(|k| {
            let x = k as f64 / n as f64;
            (
                h * x + a * (TAU * fz * x + pz).sin(),
                r0 + b * (TAU * fr * x + pr).sin(),
            )
        })
        .collect()
}

prop_compose! {
    /// Profiles of a degree from `degrees`: random control points (free or
    /// sorted z, any sign or positive r), or ribbed ones (see [`ribbed`]);
    /// some with a repeated end point (the tangent vanishes there).
    fn arb_high_model(degrees: Vec<usize>)(n in prop::sample::select(degrees))(
        n in Just(n),
        pts in prop::collection::vec((-5.0..5.0f64, -4.0..4.0f64), n + 1),
        is_ribbed in any::<bool>(),
        rib_z in (0.5..6.0f64, 0.0..2.0f64, 0.5..3.0f64, 0.0..TAU),
        rib_r in (0.0..3.0f64, 0.0..2.0f64, 0.5..3.0f64, 0.0..TAU),
        monotone in any::<bool>(),
        positive in any::<bool>(),
        repeat_end in prop::bool::weighted(0.15),
        o1 in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        axis in arb_unit(),
        len in 0.5..3.0f64,
    ) -> Model {
        let mut pts = if is_ribbed {
            ribbed(n, rib_z, rib_r)
        } else {
            pts
        };
        sort_z_and_fold_r(&mut pts, monotone && !is_ribbed, positive);
        if repeat_end {
            pts[1] = pts[0];
        }
        let o1 = DVec3::new(o1.0, o1.1, o1.2);
        Model::new(o1, o1 + axis * len, &pts)
    }
}

proptest! {
    #![proptest_config(config(1500, 18))]

    /// Degree-20 and degree-30 profiles against the scan reference, and
    /// their normals against the model's.
    #[test]
    fn degree_20_and_30_profiles_match_scan_reference(
        (m, ray, _kind) in arb_case_from(arb_high_model(vec![20, 30]).boxed()),
    ) {
        scan_check(&m, &ray)?;
        check_normal(&m, &ray)?;
    }
}

proptest! {
    #![proptest_config(config(200, 19))]

    /// Degree-20 and degree-30 profiles from far away, and in windows.
    #[test]
    fn degree_20_and_30_far_origins_and_windows(
        (m, ray, _kind) in arb_case_from(arb_high_model(vec![20, 30]).boxed()),
        k in 1..=6i32,
        w0 in 0.0..1.0f64,
        w1 in 0.0..1.0f64,
    ) {
        scan_check(&m, &far_ray(&m, &ray, k))?;
        window_check(&m, &ray, w0, w1)?;
    }
}

proptest! {
    #![proptest_config(config(120, 20))]

    /// The highest degree glint accepts (64) against the scan reference.
    #[test]
    fn degree_64_profiles_match_scan_reference(
        (m, ray, _kind) in arb_case_from(arb_high_model(vec![Bezier::MAX_DEGREE]).boxed()),
    ) {
        scan_check(&m, &ray)?;
        check_normal(&m, &ray)?;
    }
}

/// Rays along the axis through an apex of degree-20, -30 and -64 profiles.
#[test]
fn high_degree_apexes_on_the_axis() {
    axis_apex_check(90, 23, |i| [20, 30, 64][i % 3]);
}

/// A degree-64 profile is hit, one of degree 65 is refused (never hit).
#[test]
fn degree_cap_is_64() {
    let pts = |count: usize| -> Vec<DVec2> {
        (0..count)
            .map(|k| DVec2::new(k as f64 / (count - 1) as f64, 1.0))
            .collect()
    };
    let ray = Ray::new(DVec3::new(0.0, -5.0, 0.5), DVec3::Y);
    let ok = Bezier::new(DVec3::ZERO, DVec3::Z, pts(Bezier::MAX_DEGREE + 1));
    let h = ok
        .intersect(&ray, 0.0, f64::INFINITY)
        .expect("degree 64 is hit"); // invariant: the test's own fixed input (a failure fails the test)
    assert!((h.t - 4.0).abs() < 1e-12, "{}", h.t);
    let refused = Bezier::new(DVec3::ZERO, DVec3::Z, pts(Bezier::MAX_DEGREE + 2));
    assert!(refused.intersect(&ray, 0.0, f64::INFINITY).is_none());
    assert_eq!(Bezier::MAX_DEGREE, 64);
    assert_eq!(Bezier::MAX_FIXED_DEGREE, 16);
}

// ---------------------------------------------------------------------------
// Tessellation.

/// The surface as a grid of triangles (vertices on the surface).
fn tessellate(m: &Model, ns: usize, nphi: usize) -> Vec<[DVec3; 3]> {
    let mut tris = Vec::with_capacity(2 * ns * nphi);
    let p =
        |i: usize, j: usize| m.point(i as f64 / ns as f64, (j % nphi) as f64 / nphi as f64 * TAU);
    for i in 0..ns {
        for j in 0..nphi {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

/// Nearest triangle hit (Möller–Trumbore): (t, |cos| against the triangle).
fn tess_hit(tris: &[[DVec3; 3]], ray: &Ray) -> Option<(f64, f64)> {
    let mut best: Option<(f64, f64)> = None;
    for [a, b, c] in tris {
        let e1 = *b - *a;
        let e2 = *c - *a;
        let pv = ray.dir.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            continue;
        }
        let inv = 1.0 / det;
        let tv = ray.origin - *a;
        let u = tv.dot(pv) * inv;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let qv = tv.cross(e1);
        let v = ray.dir.dot(qv) * inv;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let t = e2.dot(qv) * inv;
        if t > 1e-9 && best.is_none_or(|b| t < b.0) {
            let n = e1.cross(e2).normalize();
            best = Some((t, n.dot(ray.dir).abs()));
        }
    }
    best
}

#[test]
fn tessellation_agrees() {
    let profiles: Vec<Model> = vec![
        // scene_stacks.txt: a cubic lip folding back outward.
        Model::new(
            DVec3::new(80.0, -10.0, 0.0),
            DVec3::new(80.0, -10.0, 30.0),
            &[(5.0, 5.0), (10.0, 6.0), (15.0, 7.0), (2.0, 9.0)],
        ),
        // A closed vase touching the axis at both ends.
        Model::new(
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 1.0),
            &[(0.0, 0.0), (0.0, 3.0), (2.0, 0.5), (4.0, 3.5), (5.0, 0.0)],
        ),
        // An hourglass with negative r, degree 6.
        Model::new(
            DVec3::ZERO,
            DVec3::new(0.0, 1.0, 0.0),
            &[
                (0.0, 2.0),
                (1.0, 1.0),
                (2.0, 3.0),
                (3.0, -1.0),
                (4.0, -2.0),
                (5.0, 0.5),
                (6.0, -1.5),
            ],
        ),
    ];
    for m in &profiles {
        tessellation_check(m, 300, 256, 120);
    }
}

/// Fixed degree-20 and degree-30 profiles with ribs, a lip folding back and
/// an apex on the axis, against their tessellations.
#[test]
fn high_degree_tessellation_agrees() {
    let profiles = [
        // Degree 20: a ribbed vase closed at the bottom (r = 0 there).
        Model::new(DVec3::new(1.0, -2.0, 0.0), DVec3::new(1.0, -2.0, 1.0), &{
            let mut p = ribbed(20, (6.0, 0.0, 1.0, 0.0), (1.6, 0.9, 2.0, 0.0));
            p[0].1 = 0.0;
            p
        }),
        // Degree 30: z folds back (three ribs), r crosses the axis.
        Model::new(
            DVec3::new(-0.5, 0.3, 0.2),
            DVec3::new(0.1, 1.0, 0.9),
            &(0..=30)
                .map(|k| {
                    let x = k as f64 / 30.0;
                    (
                        5.0 * x + 1.5 * (TAU * 3.0 * x).sin(),
                        1.8 * (1.3 * std::f64::consts::PI * x).cos() + 0.3,
                    )
                })
                .collect::<Vec<_>>(),
        ),
    ];
    // The degree-30 profile does fold back and cross the axis.
    let folded = &profiles[1];
    assert!(
        scan_roots(&|s| folded.dzr(s).0, 1000).len() >= 2,
        "z folds back"
    );
    assert_eq!(
        scan_roots(&|s| folded.zr(s).1, 1000).len(),
        1,
        "r crosses the axis"
    );
    for m in &profiles {
        tessellation_check(m, 400, 256, 150);
    }
}

/// Compares `intersect` with the first hit on an `ns` × `nphi` tessellation
/// for `rays` rays aimed near random surface points.
fn tessellation_check(m: &Model, ns: usize, nphi: usize, rays: usize) {
    let tris = tessellate(m, ns, nphi);
    let shape = surface_of(m);
    let mut rng = Lcg(5);
    let mut compared = 0;
    for _ in 0..rays {
        let target = m.point(rng.next(), rng.next() * TAU) + rng.unit() * 0.05 * m.scale;
        let center = m.o1 + m.a * 0.5 * (m.z[0] + m.z[m.z.len() - 1]);
        let ray = ray_to(
            center + rng.unit() * m.scale * (1.5 + 3.0 * rng.next()),
            target,
        );
        let mine = shape.intersect(&ray, 0.0, f64::INFINITY);
        let tess = tess_hit(&tris, &ray);
        let rim = |s: f64| s < 3.0 / ns as f64 || s > 1.0 - 3.0 / ns as f64;
        let mine_clear = mine.map(|h| {
            let cos = m.normal(h.u, ray.at(h.t)).dot(ray.dir).abs();
            (h, cos > 0.1 && !rim(h.u), cos)
        });
        match (mine_clear, tess) {
            (None, Some((t, cos))) => {
                assert!(cos < 0.1, "missed tessellated hit t={t} cos={cos}")
            }
            (Some((h, true, _)), None) => {
                panic!("hit t={} s={} not in the tessellation", h.t, h.u) // invariant: the test's own fixed input (a failure fails the test)
            }
            (Some((h, true, cos)), Some((t, tcos))) if tcos > 0.1 => {
                let tol = 2e-3 * m.scale / cos.min(tcos);
                assert!(
                    (h.t - t).abs() < tol,
                    "t {} vs tessellation {t} (tol {tol})",
                    h.t
                );
                compared += 1;
            }
            _ => {}
        }
    }
    assert!(compared > rays / 3, "only {compared} compared");
}

// ---------------------------------------------------------------------------
// Orientation, degenerate input.

/// A closed profile (axis to axis, counter-clockwise around its inside):
/// rays from outside hit the front, rays from inside the back.
#[test]
fn closed_profile_has_consistent_front() {
    let m = Model::new(
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(0.5, 0.0, 1.0),
        &[(0.0, 0.0), (0.0, 2.0), (2.0, 2.5), (3.0, 1.0), (3.0, 0.0)],
    );
    let shape = surface_of(&m);
    // Inside iff ρ < r(s) where z(s) = h (z is monotone here).
    let inside = |p: DVec3| {
        let (h, rho) = m.axial(p);
        if !(0.0..=3.0).contains(&h) {
            return false;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if casteljau(&m.z, mid) < h {
                lo = mid
            } else {
                hi = mid
            }
        }
        rho < casteljau(&m.r, lo)
    };
    let mut rng = Lcg(6);
    let (mut front, mut back) = (0, 0);
    for _ in 0..4000 {
        let origin = DVec3::new(0.5, 0.0, 1.5) + rng.unit() * 4.0 * rng.next();
        let ray = Ray::new(origin, rng.unit());
        if let Some(h) = shape.intersect(&ray, 0.0, f64::INFINITY) {
            let sp = shape.surface(&ray, &h);
            let cos = sp.normal.dot(ray.dir);
            if cos.abs() < 1e-6 {
                continue;
            }
            assert_eq!(cos < 0.0, !inside(origin), "{ray:?} s={} cos={cos}", h.u);
            if cos < 0.0 { front += 1 } else { back += 1 }
        }
    }
    assert!(front > 200 && back > 200, "{front} {back}");
}

#[test]
fn degenerate_input_does_not_panic() {
    let ray = Ray::new(DVec3::new(0.0, -5.0, 0.5), DVec3::Y);
    let many: Vec<DVec2> = (0..20).map(|i| DVec2::new(i as f64 * 0.1, 1.0)).collect();
    let cases = vec![
        Bezier::new(
            DVec3::ZERO,
            DVec3::ZERO,
            vec![DVec2::new(0.0, 1.0), DVec2::new(1.0, 1.0)],
        ),
        Bezier::new(DVec3::ZERO, DVec3::Z, vec![DVec2::new(0.0, 1.0)]),
        Bezier::new(DVec3::ZERO, DVec3::Z, vec![]),
        Bezier::new(
            DVec3::ZERO,
            DVec3::Z,
            vec![DVec2::new(f64::NAN, 1.0), DVec2::new(1.0, 1.0)],
        ),
        Bezier::new(DVec3::ZERO, DVec3::Z, many),
        // A point, a circle, a flat disc, a doubly covered annulus.
        Bezier::new(DVec3::ZERO, DVec3::Z, vec![DVec2::new(0.5, 0.0); 4]),
        Bezier::new(DVec3::ZERO, DVec3::Z, vec![DVec2::new(0.5, 1.0); 3]),
        Bezier::new(
            DVec3::ZERO,
            DVec3::Z,
            vec![DVec2::new(0.5, 0.0), DVec2::new(0.5, 2.0)],
        ),
        Bezier::new(
            DVec3::ZERO,
            DVec3::Z,
            vec![
                DVec2::new(0.5, 1.0),
                DVec2::new(0.5, 3.0),
                DVec2::new(0.5, 1.0),
            ],
        ),
    ];
    for shape in &cases {
        let _ = shape.bounds();
        for dir in [DVec3::Y, DVec3::Z, DVec3::new(0.0, 1.0, 1e-9).normalize()] {
            let ray = Ray::new(ray.origin, dir);
            if let Some(h) = shape.intersect(&ray, 0.0, f64::INFINITY) {
                let sp = shape.surface(&ray, &h);
                assert!(sp.normal.is_finite() && sp.uv.is_finite());
            }
        }
    }
    // The flat disc z = 0.5, radius 2, seen from above at an angle.
    let disc = &cases[7];
    let ray = Ray::new(DVec3::new(0.3, 0.0, 2.0), DVec3::new(0.0, 0.6, -0.8));
    let h = disc.intersect(&ray, 0.0, f64::INFINITY).expect("disc hit"); // invariant: the test's own fixed input (a failure fails the test)
    assert!((h.t - 1.5 / 0.8).abs() < 1e-12);
    let n = disc.surface(&ray, &h).normal;
    assert!(
        (n - DVec3::Z).length() < 1e-12 || (n + DVec3::Z).length() < 1e-12,
        "{n}"
    );
    const { assert!(Bezier::MAX_DEGREE >= 16) };
}
