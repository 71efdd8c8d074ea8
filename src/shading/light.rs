//! Shadow rays: the fraction of a light that a point sees.

use crate::accel::Accel;
use crate::geometry::{Ray, Sphere, offset_origin};
use crate::scene::{Light, LightKind};
use glam::DVec3;
use rand::Rng;
use std::f64::consts::TAU;

/// Slots of [`ShadowHints`].
const HINT_SLOTS: usize = 8;

/// Per light (slot: its index modulo 8), the object that last
/// blocked a shadow ray towards it, tried first by the next one: shadow rays
/// from nearby points mostly meet the same blocker. A stale guess, or a slot
/// shared by two lights, costs one test; the answers never depend on it.
pub type ShadowHints = [Option<u32>; HINT_SLOTS];

/// Where shadow rays start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowFrom {
    /// A point on a surface.
    pub point: DVec3,
    /// The unit normal on the side the rays leave from (they start nudged along it).
    pub side: DVec3,
    /// The object whose surface it is, if any: its neighbours are tried first.
    pub object: Option<u32>,
}

/// The shade factor s in [0, 1]: the fraction of shadow rays from `from`
/// that reach light `index`. Point lights take one ray; area lights
/// `samples`, stratified. Returns s and the number of shadow rays traced;
/// `hints` is read and updated.
pub fn shade_factor(
    accel: &Accel,
    light: &Light,
    index: u32,
    from: &ShadowFrom,
    samples: u32,
    rng: &mut impl Rng,
    hints: &mut ShadowHints,
) -> (f64, u64) {
    let origin = offset_origin(from.point, from.side);
    // Every shadow ray of this point starts here (same sliver); only its
    // direction changes.
    let start = Ray::off_surface(origin, DVec3::ZERO);
    let towards = |dir: DVec3| Ray { dir, ..start };
    let leaving = from.object;
    let blocker = &mut hints[index as usize % HINT_SLOTS];
    // An area light's rays all run from `origin` into its box: the parts of
    // the tree they may enter are found once.
    let reach = match light.kind {
        LightKind::Point { .. } => None,
        _ if samples < 2 => None,
        LightKind::Square { center, dx, dy } => {
            let half = dx.abs() + dy.abs();
            Some(accel.shadow_reach(origin, center - half, center + half, Some(index)))
        }
        LightKind::Sphere { center, radius } => {
            Some(accel.shadow_reach(origin, center - radius, center + radius, Some(index)))
        }
    };
    let mut occluded = |ray: &Ray, t_max: f64| match &reach {
        Some(r) => accel.occluded_within(ray, t_max, Some(index), r, blocker),
        None => accel.occluded_hinted(ray, t_max, Some(index), leaving, blocker),
    };
    match light.kind {
        LightKind::Point { pos } => {
            let to = pos - origin;
            let dist = to.length();
            let blocked = dist > 0.0
                && accel.occluded_hinted(&towards(to / dist), dist, None, leaving, blocker);
            (if blocked { 0.0 } else { 1.0 }, 1)
        }
        LightKind::Square { center, dx, dy } => {
            let (rows, cols) = strata(samples);
            let (cell_a, cell_b) = (2.0 / cols as f64, 2.0 / rows as f64);
            let mut lit = 0u32;
            for r in 0..rows {
                for c in 0..cols {
                    let a = (c as f64 + rng.random::<f64>()) * cell_a - 1.0;
                    let b = (r as f64 + rng.random::<f64>()) * cell_b - 1.0;
                    let to = center + dx * a + dy * b - origin;
                    let dist = to.length();
                    if dist > 0.0 && !occluded(&towards(to * (1.0 / dist)), dist) {
                        lit += 1;
                    }
                }
            }
            let n = rows * cols;
            (lit as f64 / n as f64, n as u64)
        }
        LightKind::Sphere { center, radius } => {
            let to = center - origin;
            let d2 = to.length_squared();
            if d2 <= radius * radius {
                return (1.0, 0); // inside the light: nothing can block it
            }
            let dist = d2.sqrt();
            let w = to / dist;
            let cos_max = (1.0 - radius * radius / d2).max(0.0).sqrt();
            let (u_axis, v_axis) = perpendiculars(w);
            let sphere = Sphere::new(center, radius);
            let tangent = (d2 - radius * radius).max(0.0).sqrt();
            let (rows, cols) = strata(samples);
            let mut lit = 0u32;
            for r in 0..rows {
                for c in 0..cols {
                    // Uniform in solid angle over the cone: cos θ uniform in [cos_max, 1].
                    let cos_t =
                        1.0 - (r as f64 + rng.random::<f64>()) / rows as f64 * (1.0 - cos_max);
                    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                    let phi = TAU * (c as f64 + rng.random::<f64>()) / cols as f64;
                    let dir =
                        (w * cos_t + (u_axis * phi.cos() + v_axis * phi.sin()) * sin_t).normalize();
                    let ray = towards(dir);
                    // Up to the light's surface (the tangent distance for rounding at the rim).
                    let t_light = sphere.roots(&ray).map_or(tangent, |(t0, _)| t0);
                    if !occluded(&ray, t_light) {
                        lit += 1;
                    }
                }
            }
            let n = rows * cols;
            (lit as f64 / n as f64, n as u64)
        }
    }
}

/// A grid of exactly `n` strata as close to square as possible: (rows, cols).
pub fn strata(n: u32) -> (u32, u32) {
    let n = n.max(1);
    let mut rows = (n as f64).sqrt() as u32;
    while !n.is_multiple_of(rows) {
        rows -= 1;
    }
    (rows, n / rows)
}

/// Two unit vectors perpendicular to the unit vector `w` and to each other.
pub fn perpendiculars(w: DVec3) -> (DVec3, DVec3) {
    let a = if w.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let u = w.cross(a).normalize();
    (u, w.cross(u))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_are_exact_and_squarish() {
        assert_eq!(strata(16), (4, 4));
        assert_eq!(strata(32), (4, 8));
        assert_eq!(strata(64), (8, 8));
        assert_eq!(strata(7), (1, 7));
        assert_eq!(strata(0), (1, 1));
    }

    #[test]
    fn perpendiculars_are_orthonormal() {
        for w in [
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (u, v) = perpendiculars(w);
            assert!(u.dot(w).abs() < 1e-15 && v.dot(w).abs() < 1e-15 && u.dot(v).abs() < 1e-15);
            assert!((u.length() - 1.0).abs() < 1e-15 && (v.length() - 1.0).abs() < 1e-15);
        }
    }
}
