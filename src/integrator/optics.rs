//! The directions of scattered rays, shared by the ray tracer and the
//! photon tracer: mirror, Snell, the two glossy blurs and the cosine lobe.

use crate::geometry::perpendiculars;
use glam::DVec3;
use rand::Rng;
use rand_pcg::Pcg32;

/// `d` mirrored about the unit normal `n`.
#[inline]
pub(crate) fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

/// Snell's law for unit `d` arriving against unit `n` with index ratio
/// `eta`; `None` on total internal reflection.
#[inline]
pub(crate) fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| (d * eta + n * (eta * cos_i - k.sqrt())).normalize())
}

/// The mirror direction perturbed by the `exp` blur: offset by
/// drefl·(x·a1 + y·a2) with radius 2^u − 1 and a uniform angle. A direction
/// pushed below the surface is folded back above it.
#[inline(always)]
pub(crate) fn glossy_direction(
    mirror: DVec3,
    side: DVec3,
    a1: DVec3,
    a2: DVec3,
    drefl: f64,
    rng: &mut Pcg32,
) -> DVec3 {
    let radius = (rng.random::<f64>()).exp2() - 1.0;
    // A uniform angle as a point of the unit circle, without sin and cos: a
    // point (x, y) uniform in the unit disc has a uniform angle θ, and so has
    // 2θ, whose cosine and sine are (x² − y², 2xy) / r² (no square root).
    let (c, s) = loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        let r2 = x * x + y * y;
        if r2 <= 1.0 && r2 > 1e-12 {
            let inv = 1.0 / r2;
            break ((x * x - y * y) * inv, 2.0 * x * y * inv);
        }
    };
    let mut dir = (mirror + (a1 * c + a2 * s) * (radius * drefl)).normalize();
    let below = dir.dot(side);
    if below < 0.0 {
        dir -= side * (2.0 * below);
    }
    dir
}

/// The lineages' glossy direction: the mirror direction offset by
/// drefl²·(x·a1 + y·a2), (x, y) uniform in the unit disk (the disk is
/// symmetric, so any perpendicular pair serves).
#[inline(always)]
pub(crate) fn disk_direction(
    mirror: DVec3,
    a1: DVec3,
    a2: DVec3,
    drefl: f64,
    rng: &mut Pcg32,
) -> DVec3 {
    let (x, y) = loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        if x * x + y * y <= 1.0 {
            break (x, y);
        }
    };
    (mirror + (a1 * x + a2 * y) * (drefl * drefl)).normalize()
}

/// A direction about the unit normal `n` with density cos θ / π.
#[inline]
pub(crate) fn cosine_direction(n: DVec3, rng: &mut Pcg32) -> DVec3 {
    let (a1, a2) = perpendiculars(n);
    let (x, y) = loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        if x * x + y * y <= 1.0 {
            break (x, y);
        }
    };
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    (a1 * x + a2 * y + n * z).normalize()
}

/// A direction uniform over the unit sphere.
#[inline]
pub(crate) fn sphere_direction(rng: &mut Pcg32) -> DVec3 {
    let z = 2.0 * rng.random::<f64>() - 1.0;
    let phi = std::f64::consts::TAU * rng.random::<f64>();
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snell_and_total_internal_reflection() {
        // 45° into glass of index 1.5: sin t = sin 45° / 1.5.
        let d = DVec3::new(1.0, 0.0, -1.0).normalize();
        let t = refract(d, DVec3::Z, 1.0 / 1.5);
        let sin_t = (0.5f64.sqrt()) / 1.5;
        assert!(
            t.is_some_and(|t| (t.x - sin_t).abs() < 1e-14
                && (t.z + (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-14)
        );
        // Leaving glass at 45° with index 1.5: sin t would be 1.06 > 1.
        assert!(refract(d, DVec3::Z, 1.5).is_none());
        assert_eq!(reflect(d, DVec3::Z), DVec3::new(d.x, 0.0, -d.z));
    }

    #[test]
    fn glossy_directions_stay_above_the_surface_and_near_the_mirror() {
        use rand::SeedableRng;
        let mut rng = Pcg32::seed_from_u64(7);
        // Steep mirror direction: no folding, so the angle to it is at most atan(drefl).
        let mirror = DVec3::new(1.0, 0.0, 1.0).normalize();
        let (a1, a2) = perpendiculars(mirror);
        let mut max_angle: f64 = 0.0;
        for _ in 0..2000 {
            let d = glossy_direction(mirror, DVec3::Z, a1, a2, 0.25, &mut rng);
            assert!((d.length() - 1.0).abs() < 1e-12);
            max_angle = max_angle.max(d.dot(mirror).clamp(-1.0, 1.0).acos());
        }
        assert!(max_angle <= 0.25f64.atan() + 1e-12);
        assert!(
            max_angle > 0.2,
            "the blur reaches close to its radius: {max_angle}"
        );
        // Grazing mirror direction: every sample is folded above the surface.
        let mirror = DVec3::new(1.0, 0.0, 0.01).normalize();
        let (a1, a2) = perpendiculars(mirror);
        for _ in 0..2000 {
            assert!(glossy_direction(mirror, DVec3::Z, a1, a2, 0.25, &mut rng).z >= 0.0);
        }
    }

    #[test]
    fn glossy_blur_angle_is_uniform_and_radius_follows_exp() {
        use rand::SeedableRng;
        let mut rng = Pcg32::seed_from_u64(11);
        let mirror = DVec3::Z;
        let (a1, a2) = perpendiculars(mirror);
        let drefl = 0.5;
        let n = 64_000;
        let mut angle_bins = [0u32; 16];
        let mut below_half = 0u32;
        for _ in 0..n {
            let d = glossy_direction(mirror, DVec3::Z, a1, a2, drefl, &mut rng);
            // Back to the offset in the (a1, a2) plane: d ∝ mirror + offset.
            let off = d / d.dot(mirror) - mirror;
            let (x, y) = (off.dot(a1), off.dot(a2));
            let phi = y.atan2(x).rem_euclid(std::f64::consts::TAU);
            angle_bins[((phi / std::f64::consts::TAU) * 16.0) as usize % 16] += 1;
            // radius = drefl·(2^u − 1): below drefl·(√2 − 1) exactly when u < ½.
            if (x * x + y * y).sqrt() < drefl * (2f64.sqrt() - 1.0) {
                below_half += 1;
            }
        }
        // Chi-square with 15 degrees of freedom: 37.7 is its 0.999 quantile.
        let expected = n as f64 / 16.0;
        let chi2: f64 = angle_bins
            .iter()
            .map(|&k| (k as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 37.7, "angle not uniform: {angle_bins:?} chi2={chi2}");
        // Half the radii below the median of 2^u − 1, within 4 standard deviations.
        let sd = (n as f64 * 0.25).sqrt();
        assert!(
            (below_half as f64 - n as f64 / 2.0).abs() < 4.0 * sd,
            "{below_half} of {n} radii below the median"
        );
    }

    #[test]
    fn cosine_and_sphere_directions_have_their_densities() {
        use rand::SeedableRng;
        let mut rng = Pcg32::seed_from_u64(5);
        let n = DVec3::new(1.0, -2.0, 0.5).normalize();
        let count = 100_000;
        // cos θ/π: P(cos θ > c) = 1 − c², so the median of cos θ is 1/√2,
        // and the mean of cos θ is 2/3.
        let (mut above, mut mean) = (0u32, 0.0);
        for _ in 0..count {
            let d = cosine_direction(n, &mut rng);
            assert!((d.length() - 1.0).abs() < 1e-12 && d.dot(n) >= 0.0);
            above += u32::from(d.dot(n) > 0.5f64.sqrt());
            mean += d.dot(n) / count as f64;
        }
        let sd = (count as f64 * 0.25).sqrt();
        assert!(
            (above as f64 - count as f64 / 2.0).abs() < 4.0 * sd,
            "{above}"
        );
        assert!(
            (mean - 2.0 / 3.0).abs() < 4.0 * (1.0f64 / 18.0 / count as f64).sqrt(),
            "{mean}"
        );
        // Uniform on the sphere: each coordinate's mean is 0 and z is uniform.
        let (mut sum, mut low) = (DVec3::ZERO, 0u32);
        for _ in 0..count {
            let d = sphere_direction(&mut rng);
            assert!((d.length() - 1.0).abs() < 1e-12);
            sum += d;
            low += u32::from(d.z < -0.5);
        }
        let se = (1.0f64 / 3.0 / count as f64).sqrt();
        assert!(
            (sum / count as f64).abs().max_element() < 4.0 * se,
            "{sum:?}"
        );
        let sd = (count as f64 * 0.25 * 0.75).sqrt();
        assert!((low as f64 - count as f64 / 4.0).abs() < 4.0 * sd, "{low}");
    }
}
