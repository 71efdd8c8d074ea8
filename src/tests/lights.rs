//! Area lights: the stratified shade factor converges to the exact visible
//! fraction (computed here by dense quadrature), with less noise than
//! independent sampling would give.

use crate::accel::Accel;
use crate::integrator::{ShadowFrom, ShadowHints, ShadowRays, shade_factor};
use crate::scene::{LightKind, Object, Scene};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// Shadow rays from `point` on an upward-facing surface of no known object.
fn at(point: DVec3) -> ShadowFrom {
    ShadowFrom {
        point,
        side: DVec3::Z,
        object: None,
    }
}

fn scene(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}")) // invariant: the test's own fixed input (a failure fails the test)
}

/// The shade factor of light `light` at `point` (on a surface facing +z)
/// and the rays it took, from its own random stream `seed`.
fn factor(
    accel: &Accel<Object>,
    s: &Scene,
    light: usize,
    point: DVec3,
    samples: u32,
    seed: u64,
) -> (f64, u64) {
    let mut rng = Pcg32::seed_from_u64(seed);
    let mut hints = ShadowHints::default();
    let l = &s.lights()[light];
    let to = ShadowRays {
        accel,
        light: l,
        index: light as u32,
        samples,
    };
    shade_factor(&to, &at(point), &mut rng, &mut hints, &mut ())
}

/// Mean and standard deviation of the shade factor at the origin over many seeds.
fn estimate(s: &Scene, samples: u32, runs: u64) -> (f64, f64) {
    estimate_at(s, DVec3::ZERO, samples, runs)
}

/// Mean and standard deviation of the shade factor at `point` (on a
/// surface facing +z) over many seeds.
fn estimate_at(s: &Scene, point: DVec3, samples: u32, runs: u64) -> (f64, f64) {
    let accel = Accel::build(s.objects().to_vec());
    let values: Vec<f64> = (0..runs)
        .map(|seed| {
            let (v, rays) = factor(&accel, s, 0, point, samples, seed);
            let point = matches!(s.lights()[0].kind, LightKind::Point { .. });
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
    blocker_at(5.0, angle, c)
}

/// [`blocker`] at the height `h`.
fn blocker_at(h: f64, angle: f64, c: f64) -> String {
    let (s, co) = angle.sin_cos();
    let ax = DVec3::new(co, s, 0.0);
    let ay = DVec3::new(-s, co, 0.0);
    let centre = ax * (c - 50.0) + DVec3::new(0.0, 0.0, h);
    let dx = ax * 50.0;
    let dy = ay * 50.0;
    format!(
        "primitive square\n O= {} {} {}\n Dx= {} {} {}\n Dy= {} {} {}\nend\n",
        centre.x, centre.y, centre.z, dx.x, dx.y, dx.z, dy.x, dy.y, dy.z
    )
}

/// Whether a ray from the origin along `d` passes the blocker of [`blocker`].
fn passes(d: DVec3, angle: f64, c: f64) -> bool {
    passes_at(d, 5.0, angle, c)
}

/// [`passes`] for the blocker of [`blocker_at`] at the height `h`.
fn passes_at(d: DVec3, h: f64, angle: f64, c: f64) -> bool {
    let p = d * (h / d.z);
    p.x * angle.cos() + p.y * angle.sin() >= c
}

/// The fraction of an `n` × `n` midpoint grid over [−1, 1]² where `pass(a, b)` holds.
fn square_grid_fraction(n: usize, pass: impl Fn(f64, f64) -> bool) -> f64 {
    let mut visible = 0u64;
    for i in 0..n {
        for j in 0..n {
            let a = 2.0 * (i as f64 + 0.5) / n as f64 - 1.0;
            let b = 2.0 * (j as f64 + 0.5) / n as f64 - 1.0;
            visible += pass(a, b) as u64;
        }
    }
    visible as f64 / (n * n) as f64
}

/// The fraction of an `n` × `n` midpoint grid over a cone (cos θ from 1 to `cos_max`, φ over 2π) where `pass(cos θ, sin θ, φ)` holds.
fn cone_grid_fraction(n: usize, cos_max: f64, pass: impl Fn(f64, f64, f64) -> bool) -> f64 {
    let mut visible = 0u64;
    for i in 0..n {
        let cos_t = 1.0 - (i as f64 + 0.5) / n as f64 * (1.0 - cos_max);
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        for j in 0..n {
            let phi = std::f64::consts::TAU * (j as f64 + 0.5) / n as f64;
            visible += pass(cos_t, sin_t, phi) as u64;
        }
    }
    visible as f64 / (n * n) as f64
}

fn check(s: &Scene, exact: f64, samples: u32) {
    check_at(s, DVec3::ZERO, exact, samples);
}

/// [`check`] at the shading point `point`.
fn check_at(s: &Scene, point: DVec3, exact: f64, samples: u32) {
    let runs = 4000;
    let (mean, std) = estimate_at(s, point, samples, runs);
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
        let exact = square_grid_fraction(1000, |a, b| passes(DVec3::new(a, b, 10.0), angle, c));
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
        let exact = cone_grid_fraction(1000, cos_max, |cos_t, sin_t, phi| {
            let d = DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            passes(d, angle, c)
        });
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
    assert!(matches!(s.lights()[1].kind, LightKind::Square { .. }));
    let accel = Accel::build(s.objects().to_vec());
    // The square light hides the sphere light completely.
    assert_eq!(factor(&accel, &s, 0, DVec3::ZERO, 16, 1).0, 0.0);
    // The square light sees itself.
    assert_eq!(factor(&accel, &s, 1, DVec3::ZERO, 16, 2).0, 1.0);
}

// ---------------------------------------------------------------------------
// Oblique and wide-cone layouts, and convergence with shade_quality.
//
// With the half-plane blocker of [`blocker_at`] at height h, the segment from
// a point P (below h) to a point L (above h) crosses z = h at
// X = P + (L − P)·(h − Pz)/(Lz − Pz), and passes iff n·X ≥ c with
// n = (cos angle, sin angle, 0). Multiplied by Lz − Pz > 0 this is
// k·(L − P) ≥ 0 with k = (n·P − c)·ẑ + (h − Pz)·n: a half-space in L. So
// the visible part of a square light is the part of its parameter square on
// one side of a line (exact by polygon clipping), and the visible part of a
// sphere light's cone is the part on one side of a plane through P (exact
// per ring of the cone by an arc length).

/// The blocker's half-space normal k of the comment above.
fn cut_normal(p: DVec3, h: f64, angle: f64, c: f64) -> DVec3 {
    let n = DVec3::new(angle.cos(), angle.sin(), 0.0);
    DVec3::Z * (n.dot(p) - c) + n * (h - p.z)
}

/// Area fraction of [−1, 1]² where α·a + β·b + γ ≥ 0 (one Sutherland–Hodgman
/// clip of the square and the shoelace formula).
fn clipped_square_fraction(alpha: f64, beta: f64, gamma: f64) -> f64 {
    let f = |q: (f64, f64)| alpha * q.0 + beta * q.1 + gamma;
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut poly: Vec<(f64, f64)> = Vec::new();
    for i in 0..4 {
        let (a, b) = (square[i], square[(i + 1) % 4]);
        let (fa, fb) = (f(a), f(b));
        if fa >= 0.0 {
            poly.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            let t = fa / (fa - fb);
            poly.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    let mut area2 = 0.0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        area2 += a.0 * b.1 - b.0 * a.1;
    }
    area2.abs() / 2.0 / 4.0
}

/// Exact visible fraction of the square light O ± Dx ± Dy from `p` past the
/// blocker (h, angle, c); the light lies wholly above h.
fn square_exact(o: DVec3, dx: DVec3, dy: DVec3, p: DVec3, h: f64, angle: f64, c: f64) -> f64 {
    let k = cut_normal(p, h, angle, c);
    // k·(O + a·Dx + b·Dy − P) ≥ 0.
    clipped_square_fraction(k.dot(dx), k.dot(dy), k.dot(o - p))
}

/// Exact visible fraction (by solid angle) of the cone that the sphere light
/// (centre, radius) subtends from `p`, past the blocker (h, angle, c); the
/// sphere lies wholly above h. Rings of the cone (uniform in cos θ) are
/// integrated by the midpoint rule; on each ring the visible arc is exact.
fn sphere_exact(centre: DVec3, radius: f64, p: DVec3, h: f64, angle: f64, c: f64) -> f64 {
    let k = cut_normal(p, h, angle, c);
    let to = centre - p;
    let w = to.normalize();
    // Any frame around w will do: the fraction does not depend on it.
    let u = w
        .cross(if w.y.abs() < 0.9 { DVec3::Y } else { DVec3::X })
        .normalize();
    let v = w.cross(u);
    let (kw, rho) = (k.dot(w), k.dot(u).hypot(k.dot(v)));
    let cos_max = (1.0 - radius * radius / to.length_squared()).sqrt();
    let n = 20_000;
    let mut sum = 0.0;
    for i in 0..n {
        let cos_t = 1.0 - (i as f64 + 0.5) / n as f64 * (1.0 - cos_max);
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        // k·d = kw·cos θ + ρ·sin θ·cos(φ − φ0) ≥ 0 on an arc of the ring.
        sum += if rho * sin_t == 0.0 {
            if kw * cos_t >= 0.0 { 1.0 } else { 0.0 }
        } else {
            (-kw * cos_t / (rho * sin_t)).clamp(-1.0, 1.0).acos() / std::f64::consts::PI
        };
    }
    sum / n as f64
}

fn vec_text(v: DVec3) -> String {
    format!("{} {} {}", v.x, v.y, v.z)
}

/// The oblique square light of the tests below: off to the side of the
/// origin, tilted, and a blocker edge through its penumbra at the origin.
struct Oblique {
    o: DVec3,
    dx: DVec3,
    dy: DVec3,
    angle: f64,
    c: f64,
}

const OBLIQUE: Oblique = Oblique {
    o: DVec3::new(4.0, -3.0, 6.0),
    dx: DVec3::new(0.9, 0.2, 0.35),
    dy: DVec3::new(-0.3, 0.8, 0.3),
    angle: 2.2,
    // Near n·(O·5/6), where the segment to the light's centre crosses z = 5.
    c: -3.9,
};

impl Oblique {
    fn scene(&self) -> Scene {
        scene(&format!(
            "light square\n O= {}\n Dx= {}\n Dy= {}\n color= 1 1 1\nend\n{}",
            vec_text(self.o),
            vec_text(self.dx),
            vec_text(self.dy),
            blocker(self.angle, self.c)
        ))
    }

    fn exact(&self, p: DVec3) -> f64 {
        square_exact(self.o, self.dx, self.dy, p, 5.0, self.angle, self.c)
    }
}

/// A square light off to the side and tilted (its edges along no axis, its
/// centre 5 units sideways): the shade factor is unbiased and stratified.
#[test]
fn oblique_square_light_penumbra_converges_to_the_visible_area() {
    let ob = &OBLIQUE;
    assert!(
        ob.o.z - ob.dx.z.abs() - ob.dy.z.abs() > 5.0,
        "light above the blocker"
    );
    let exact = ob.exact(DVec3::ZERO);
    // The clipping formula against a direct 1000 × 1000 midpoint quadrature.
    let quadrature = square_grid_fraction(1000, |a, b| {
        passes(ob.o + ob.dx * a + ob.dy * b, ob.angle, ob.c)
    });
    assert!((exact - quadrature).abs() < 2e-3, "{exact} vs {quadrature}");
    assert!(exact > 0.2 && exact < 0.8, "a real penumbra: {exact}");
    let s = ob.scene();
    check(&s, exact, 16);
    check(&s, exact, 48);
}

/// The wide-cone layouts: a sphere light of radius 1 seen from 1.5 and
/// 1.66 units from its centre (cones of half-angle 42° and 37°), behind a
/// blocker at z = 0.3 between the point and the light.
fn wide_cone_cases() -> [(DVec3, f64, f64); 2] {
    [
        (DVec3::new(0.0, 0.0, 1.5), 0.4, 0.05),
        (DVec3::new(0.8, 0.4, 1.4), -0.7, 0.1),
    ]
}

fn sphere_scene(centre: DVec3, h: f64, angle: f64, c: f64) -> Scene {
    scene(&format!(
        "light sphere\n O= {}\n R= 1\n color= 1 1 1\nend\n{}",
        vec_text(centre),
        blocker_at(h, angle, c)
    ))
}

/// A point close to a sphere light (a wide cone): the shade factor is
/// unbiased and stratified.
#[test]
fn sphere_light_close_up_converges_to_the_visible_solid_angle() {
    for (centre, angle, c) in wide_cone_cases() {
        let (h, radius) = (0.3, 1.0);
        assert!(centre.z - radius > h, "light above the blocker");
        let exact = sphere_exact(centre, radius, DVec3::ZERO, h, angle, c);
        // The ring formula against a direct quadrature over (cos θ, φ) in
        // another frame, testing each direction against the blocker.
        let to = centre.normalize();
        let u = to.cross(DVec3::X).normalize();
        let v = to.cross(u);
        let cos_max = (1.0 - radius * radius / centre.length_squared()).sqrt();
        let quadrature = cone_grid_fraction(1000, cos_max, |cos_t, sin_t, phi| {
            let d = to * cos_t + (u * phi.cos() + v * phi.sin()) * sin_t;
            passes_at(d, h, angle, c)
        });
        assert!((exact - quadrature).abs() < 2e-3, "{exact} vs {quadrature}");
        assert!(exact > 0.2 && exact < 0.8, "a real penumbra: {exact}");
        let s = sphere_scene(centre, h, angle, c);
        check(&s, exact, 16);
        check(&s, exact, 64);
    }
}

/// RMS error of the shade factor against `exact` over `points`, for
/// shade_quality 1 to 4 (16 to 64 samples); each point and quality has its
/// own fixed seed.
fn rms_by_quality(s: &Scene, points: &[(DVec3, f64)]) -> [f64; 4] {
    let accel = Accel::build(s.objects().to_vec());
    std::array::from_fn(|q| {
        let samples = 16 * (q as u32 + 1);
        let sum: f64 = points
            .iter()
            .enumerate()
            .map(|(i, &(p, exact))| {
                let seed = 1_000_003 * q as u64 + i as u64;
                let (v, _) = factor(&accel, s, 0, p, samples, seed);
                (v - exact).powi(2)
            })
            .sum();
        (sum / points.len() as f64).sqrt()
    })
}

/// Points of the plane z = 0 (random, fixed seed) in a penumbra: those whose
/// exact fraction is strictly between 0.02 and 0.98.
fn penumbra_points(count: usize, seed: u64, exact: impl Fn(DVec3) -> f64) -> Vec<(DVec3, f64)> {
    let mut rng = Pcg32::seed_from_u64(seed);
    let mut out = Vec::new();
    for _ in 0..100 * count {
        let p = DVec3::new(
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            0.0,
        );
        let e = exact(p);
        if e > 0.02 && e < 0.98 {
            out.push((p, e));
            if out.len() == count {
                break;
            }
        }
    }
    assert_eq!(out.len(), count, "penumbra points found");
    out
}

/// The RMS error shrinks at every step of shade_quality from 1 to 4, and
/// from 1 to 4 by more than the factor 2 that independent samples would
/// give (4× the rays), as stratified samples should.
fn assert_converges(rms: [f64; 4], what: &str) {
    for q in 1..4 {
        assert!(rms[q] < rms[q - 1], "{what}: RMS by quality {rms:?}");
    }
    assert!(rms[3] < 0.45 * rms[0], "{what}: RMS by quality {rms:?}");
}

#[test]
fn shade_error_shrinks_with_shade_quality() {
    let ob = &OBLIQUE;
    let points = penumbra_points(1500, 31, |p| ob.exact(p));
    let rms = rms_by_quality(&ob.scene(), &points);
    assert_converges(rms, "oblique square light");

    let plain = Oblique {
        o: DVec3::new(0.0, 0.0, 10.0),
        dx: DVec3::X,
        dy: DVec3::Y,
        angle: 0.5,
        c: 0.0,
    };
    let points = penumbra_points(1500, 32, |p| plain.exact(p));
    let rms = rms_by_quality(&plain.scene(), &points);
    assert_converges(rms, "square light overhead");

    for (k, (centre, angle, c)) in wide_cone_cases().into_iter().enumerate() {
        let points = penumbra_points(1500, 33 + k as u64, |p| {
            sphere_exact(centre, 1.0, p, 0.3, angle, c)
        });
        let rms = rms_by_quality(&sphere_scene(centre, 0.3, angle, c), &points);
        assert_converges(rms, &format!("sphere light at {centre}"));
    }
}
