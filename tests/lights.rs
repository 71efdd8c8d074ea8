//! Area lights: the stratified shade factor converges to the exact visible
//! fraction (computed here by dense quadrature), with less noise than
//! independent sampling would give.

use glam::DVec3;
use glint::accel::Accel;
use glint::scene::{LightKind, Scene};
use glint::shading::shade_factor;
use rand::SeedableRng;
use rand_pcg::Pcg32;

fn scene(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}"))
}

/// Mean and standard deviation of the shade factor at the origin over many seeds.
fn estimate(s: &Scene, samples: u32, runs: u64) -> (f64, f64) {
    let accel = Accel::build(&s.objects);
    let values: Vec<f64> = (0..runs)
        .map(|seed| {
            let mut rng = Pcg32::seed_from_u64(seed);
            let (v, rays) = shade_factor(
                &accel,
                &s.lights[0],
                0,
                DVec3::ZERO,
                DVec3::Z,
                samples,
                &mut rng,
            );
            let point = matches!(s.lights[0].kind, LightKind::Point { .. });
            assert_eq!(rays, if point { 1 } else { samples as u64 });
            v
        })
        .collect();
    let mean = values.iter().sum::<f64>() / runs as f64;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (runs - 1) as f64;
    (mean, var.sqrt())
}

/// A blocker at z = 5: the square O ± Dx ± Dy turned by `angle` about z,
/// covering the half-plane x' < c (x' along the turned axis) out to 50 units.
fn blocker(angle: f64, c: f64) -> String {
    let (s, co) = angle.sin_cos();
    let ax = DVec3::new(co, s, 0.0);
    let ay = DVec3::new(-s, co, 0.0);
    let centre = ax * (c - 50.0) + DVec3::new(0.0, 0.0, 5.0);
    let dx = ax * 50.0;
    let dy = ay * 50.0;
    format!(
        "primitive square\n O= {} {} {}\n Dx= {} {} {}\n Dy= {} {} {}\nend\n",
        centre.x, centre.y, centre.z, dx.x, dx.y, dx.z, dy.x, dy.y, dy.z
    )
}

/// Whether a ray from the origin along `d` passes the blocker of [`blocker`].
fn passes(d: DVec3, angle: f64, c: f64) -> bool {
    let p = d * (5.0 / d.z);
    p.x * angle.cos() + p.y * angle.sin() >= c
}

fn check(s: &Scene, exact: f64, samples: u32) {
    let runs = 4000;
    let (mean, std) = estimate(s, samples, runs);
    let independent = (exact * (1.0 - exact) / samples as f64).sqrt();
    // Unbiased: the mean is within 4 standard errors of the exact fraction
    // (plus the quadrature's own error, below 1e-3).
    let bound = 4.0 * std / (runs as f64).sqrt() + 1e-3;
    assert!(
        (mean - exact).abs() < bound,
        "mean {mean} vs exact {exact} (bound {bound})"
    );
    // Stratified: clearly less noisy than independent samples.
    assert!(
        std < 0.7 * independent,
        "std {std} vs independent {independent}"
    );
}

#[test]
fn square_light_penumbra_converges_to_the_visible_area() {
    for (angle, c) in [(0.0, 0.2), (0.5, -0.1), (1.2, 0.35)] {
        let s = scene(&format!(
            "light square\n O= 0 0 10\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend\n{}",
            blocker(angle, c)
        ));
        // Exact: the fraction of the light's area whose segment to the origin
        // passes the blocker, by a 1000 × 1000 midpoint quadrature.
        let n = 1000;
        let mut visible = 0u64;
        for i in 0..n {
            for j in 0..n {
                let a = 2.0 * (i as f64 + 0.5) / n as f64 - 1.0;
                let b = 2.0 * (j as f64 + 0.5) / n as f64 - 1.0;
                visible += passes(DVec3::new(a, b, 10.0), angle, c) as u64;
            }
        }
        let exact = visible as f64 / (n * n) as f64;
        assert!(exact > 0.1 && exact < 0.9, "a real penumbra: {exact}");
        check(&s, exact, 16);
    }
}

#[test]
fn sphere_light_penumbra_converges_to_the_visible_solid_angle() {
    for (angle, c) in [(0.0, 0.3), (0.9, -0.4)] {
        let s = scene(&format!(
            "light sphere\n O= 0 0 10\n R= 2\n color= 1 1 1\nend\n{}",
            blocker(angle, c)
        ));
        // Exact: the fraction, by solid angle, of the cone the sphere subtends
        // whose directions pass the blocker (uniform in cos θ and φ).
        let cos_max = (1.0f64 - 4.0 / 100.0).sqrt();
        let n = 1000;
        let mut visible = 0u64;
        for i in 0..n {
            let cos_t = 1.0 - (i as f64 + 0.5) / n as f64 * (1.0 - cos_max);
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            for j in 0..n {
                let phi = std::f64::consts::TAU * (j as f64 + 0.5) / n as f64;
                let d = DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
                visible += passes(d, angle, c) as u64;
            }
        }
        let exact = visible as f64 / (n * n) as f64;
        assert!(exact > 0.1 && exact < 0.9, "a real penumbra: {exact}");
        check(&s, exact, 16);
        check(&s, exact, 64);
    }
}

#[test]
fn unblocked_and_fully_blocked_points_are_exact() {
    for light in [
        "light square\n O= 0 0 10\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend\n",
        "light sphere\n O= 0 0 10\n R= 2\n color= 1 1 1\nend\n",
        "light point\n O= 0 0 10\n color= 1 1 1\nend\n",
    ] {
        let open = scene(light);
        assert_eq!(estimate(&open, 16, 50), (1.0, 0.0), "{light}");
        let shut = scene(&format!("{light}{}", blocker(0.0, 40.0)));
        assert_eq!(estimate(&shut, 16, 50), (0.0, 0.0), "{light}");
    }
}

/// A light's own surface never blocks its samples, but another light's does.
#[test]
fn light_surfaces_block_other_lights_only() {
    let s = scene(
        "light sphere\n O= 0 0 10\n R= 2\n color= 1 1 1\nend
         light square\n O= 0 0 5\n Dx= 20 0 0\n Dy= 0 20 0\n color= 1 1 1\nend",
    );
    assert!(matches!(s.lights[1].kind, LightKind::Square { .. }));
    let accel = Accel::build(&s.objects);
    let mut rng = Pcg32::seed_from_u64(1);
    // The square light hides the sphere light completely.
    let (v, _) = shade_factor(&accel, &s.lights[0], 0, DVec3::ZERO, DVec3::Z, 16, &mut rng);
    assert_eq!(v, 0.0);
    // The square light sees itself.
    let (v, _) = shade_factor(&accel, &s.lights[1], 1, DVec3::ZERO, DVec3::Z, 16, &mut rng);
    assert_eq!(v, 1.0);
}
