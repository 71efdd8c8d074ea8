//! Photon mapping against closed forms (`photon-mapping.md`, Tests): the
//! furnace, a point light over a floor, a mirror's caustic, the flux a
//! glass ball passes and where it focuses, the PPM recurrence, the caps
//! and black lights, and the same photons whatever the threads.

use crate::Scene;
use crate::integrator::photons::{
    Brdf, HitPoint, Photon, PhotonFilter, PhotonMap, PhotonMode, PhotonOptions, Plan, shoot,
    update_hit_point,
};
use crate::integrator::{Model, PhotonBounce, SceneAccel};
use crate::scene::Dialect;
use glam::DVec3;
use std::f64::consts::PI;

/// The scene of `text` in `dialect` with its acceleration structure.
fn prepared(text: &str, dialect: Dialect) -> (Scene, SceneAccel) {
    let mut scene = Scene::parse_as(text, ".", Some(dialect))
        .unwrap_or_else(|e| panic!("the test scene parses:\n{e}")); // invariant: the test's own fixed input (a failure fails the test)
    let accel = SceneAccel::build(scene.take_objects());
    (scene, accel)
}

/// PM's plan for `scene` with `emit` photons.
fn pm_plan(scene: &Scene, emit: u64) -> Plan {
    let options = PhotonOptions {
        mode: Some(PhotonMode::Pm),
        emit: Some(emit),
        ..PhotonOptions::default()
    };
    Plan::of(scene, &options).0
}

fn lambert() -> Brdf {
    Brdf {
        diff: 1.0,
        spec: 0.0,
        mirror: DVec3::Z,
        cosine: None,
    }
}

/// Points spread evenly over the unit sphere (a Fibonacci lattice).
fn fibonacci(n: usize) -> impl Iterator<Item = DVec3> {
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n).map(move |i| {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - z * z).sqrt();
        let phi = golden * i as f64;
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    })
}

#[test]
fn furnace_wall_gets_the_geometric_series_of_its_bounces() {
    // A closed diffuse sphere of radius 2, grey a = 0.5, a point light of
    // colour 1 at its centre, the 2014 model (every diffuse hit stored).
    // A photon stored at its h-th hit carries a^(h−1) of its power in the
    // mean (Russian roulette keeps it with p = a, power unchanged), and
    // every one of the 4π·c emitted lands on the wall spread evenly:
    // E = c/R² · Σ_{h=1..10} a^(h−1).
    let (radius, a, c) = (2.0f64, 0.5f64, 1.0f64);
    let text = format!(
        "camera\n O= 0 0 0\n N= 0 1 0\n sample_photons= 100\n sample_dist= 1\nend\n\
         light point\n O= 0 0 0\n color= {c} {c} {c}\nend\n\
         primitive sphere\n O= 0 0 0\n R= {radius}\n color= {a} {a} {a}\n diff= 1\nend\n"
    );
    let (scene, accel) = prepared(&text, Dialect::Z14);
    let plan = pm_plan(&scene, 400_000);
    let model = Model::of(Dialect::Z14, scene.camera());
    let pass = shoot(&scene, &accel, &model, &plan, 1, 0);
    let map = PhotonMap::new(pass.photons, plan.k, plan.radius, plan.filter);
    let expected: f64 = (0..10).map(|h| a.powi(h)).sum::<f64>() * c / (radius * radius);
    let mean = mean_on_sphere(&map, radius);
    assert!(
        (mean / expected - 1.0).abs() < 0.01,
        "furnace: mean E {mean}, expected {expected}"
    );
}

/// The mean of `map`'s estimate over 2000 points spread evenly just inside
/// the sphere of radius `radius` about the origin, facing its centre.
fn mean_on_sphere(map: &PhotonMap, radius: f64) -> f64 {
    let n = 2000;
    fibonacci(n)
        .map(|u| {
            map.estimate(u * radius * (1.0 - 1e-9), -u, &lambert())
                .value
                .x
        })
        .sum::<f64>()
        / n as f64
}

#[test]
fn z14s_photons_bounce_by_the_untextured_colour_and_spec() {
    // The furnace of grey a = 0.5 with diff 0.6, spec 0.4 and a dark grey
    // texture (byte 51). Z14's photons bounce with probability
    // (diff + spec)·P(color) = 0.5, power times color/P(color) = 1: the
    // texture does not tint them (Z14 `photontracer.cpp` `PhotonDiffusion`),
    // so E = c/R²·Σ_{h=0..9} 0.5^h. The textured rule of the other
    // lineages bounces with diff·P(color·t), t = 51/256 (the byte of Z14's
    // reader): E = c/R²·Σ (0.6·0.5·t)^h.
    let tmp = tempfile::Builder::new()
        .prefix("glint-z14-furnace-")
        .tempdir()
        .unwrap_or_else(|e| panic!("{e}")); // invariant: the test's scratch folder
    image::RgbImage::from_pixel(4, 4, image::Rgb([51, 51, 51]))
        .save(tmp.path().join("grey.bmp"))
        .unwrap_or_else(|e| panic!("{e}")); // invariant: the test's scratch file
    let (radius, c) = (2.0f64, 1.0f64);
    let text = format!(
        "camera\n O= 0 0 0\n N= 0 1 0\n sample_photons= 100\n sample_dist= 1\nend\n\
         light point\n O= 0 0 0\n color= {c} {c} {c}\nend\n\
         primitive sphere\n O= 0 0 0\n R= {radius}\n color= 0.5 0.5 0.5\n diff= 0.6\n spec= 0.4\n texture= grey.bmp\nend\n"
    );
    let mut scene = Scene::parse_as(&text, tmp.path(), Some(Dialect::Z14))
        .unwrap_or_else(|e| panic!("the test scene parses:\n{e}")); // invariant: the test's own fixed input
    let accel = SceneAccel::build(scene.take_objects());
    let plan = pm_plan(&scene, 400_000);
    let z14 = Model::of(Dialect::Z14, scene.camera());
    let textured = Model {
        photon_bounce: PhotonBounce::Textured,
        ..z14
    };
    let t: f64 = 51.0 / 256.0;
    for (model, albedo, what) in [(z14, 0.5f64, "z14"), (textured, 0.6 * 0.5 * t, "textured")] {
        let pass = shoot(&scene, &accel, &model, &plan, 1, 0);
        let map = PhotonMap::new(pass.photons, plan.k, plan.radius, plan.filter);
        let expected: f64 = (0..10).map(|h| albedo.powi(h)).sum::<f64>() * c / (radius * radius);
        let mean = mean_on_sphere(&map, radius);
        assert!(
            (mean / expected - 1.0).abs() < 0.01,
            "{what}: mean E {mean}, expected {expected}"
        );
    }
}

/// A point light of colour 1 at height 2 over the diffuse floor z = 0.
const FLOOR: &str = "camera\n O= 0 -5 2\n N= 0 1 0\n sample_dist= 1\nend\n\
    light point\n O= 0 0 2\n color= 1 1 1\nend\n\
    primitive plane\n N= 0 0 1\n R= 0\n color= 0.5 0.5 0.5\n diff= 1\nend\n";

/// The RMS relative error of the floor's E against c·cos θ/d² with K photons.
fn floor_error(k: usize) -> f64 {
    let (scene, accel) = prepared(FLOOR, Dialect::Z14);
    let plan = pm_plan(&scene, 400_000);
    let model = Model::of(Dialect::Z14, scene.camera());
    let pass = shoot(&scene, &accel, &model, &plan, 2, 0);
    let map = PhotonMap::new(pass.photons, k, plan.radius, plan.filter);
    let mut sum2 = 0.0;
    let mut n = 0;
    for i in -4..=4 {
        for j in -4..=4 {
            let p = DVec3::new(i as f64 * 0.3, j as f64 * 0.3, 0.0);
            let d = DVec3::new(0.0, 0.0, 2.0) - p;
            let exact = (d.z / d.length()) / d.length_squared();
            let e = map.estimate(p, DVec3::Z, &lambert()).value.x;
            sum2 += (e / exact - 1.0).powi(2);
            n += 1;
        }
    }
    (sum2 / n as f64).sqrt()
}

#[test]
fn floor_under_a_point_light_matches_cos_over_d_squared_better_with_more_photons() {
    let (coarse, fine) = (floor_error(25), floor_error(400));
    // K photons estimate with relative noise about 1/√K (20 % and 5 %);
    // the disc's bias grows with its radius but stays below the noise here.
    assert!(fine < 0.08, "K = 400: RMS relative error {fine}");
    assert!(coarse < 0.3, "K = 25: RMS relative error {coarse}");
    assert!(
        fine < coarse,
        "the error falls as K grows: {coarse} → {fine}"
    );
}

#[test]
fn mirror_caustic_is_the_mirrored_lights_irradiance() {
    // The framework's model with photons forced on keeps only photons that
    // passed a mirror or glass: on the floor z = 0 those from the mirror
    // x = 0, which come from the light's image at (−1, 0, 1). The floor is
    // nearly black, so photons it sends on carry almost nothing.
    let text = "camera\n O= 3 -5 2\n N= 0 1 0\n sample_photons= 200\n sample_dist= 1\nend\n\
        light point\n O= 1 0 1\n color= 1 1 1\nend\n\
        primitive plane\n N= 0 0 1\n R= 0\n color= 0.001 0.001 0.001\n diff= 1\nend\n\
        primitive plane\n N= 1 0 0\n R= 0\n color= 1 1 1\n refl= 1\nend\n";
    let (scene, accel) = prepared(text, Dialect::F);
    let plan = pm_plan(&scene, 400_000);
    let model = Model::of(Dialect::F, scene.camera());
    let pass = shoot(&scene, &accel, &model, &plan, 3, 0);
    assert!(pass.photons.iter().all(|p| p.bounces >= 1));
    let map = PhotonMap::new(pass.photons, plan.k, plan.radius, plan.filter);
    let image = DVec3::new(-1.0, 0.0, 1.0);
    let mut sum2 = 0.0;
    let points = [(1.5, 0.0), (2.0, 0.5), (1.0, -0.8), (2.5, 0.0), (3.0, 1.0)];
    for &(x, y) in &points {
        let p = DVec3::new(x, y, 0.0);
        let d = image - p;
        let exact = (d.z / d.length()) / d.length_squared();
        let e = map.estimate(p, DVec3::Z, &lambert()).value.x;
        sum2 += (e / exact - 1.0).powi(2);
    }
    let rms = (sum2 / points.len() as f64).sqrt();
    // K = 200: relative noise about 7 % a point.
    assert!(rms < 0.12, "caustic against the mirrored light: RMS {rms}");
}

#[test]
fn glass_ball_passes_the_flux_it_intercepts_and_focuses_on_the_axis() {
    // A ball of radius 1 at height 2, a point light 4 above its centre:
    // it intercepts the share (1 − cos α)/2 of the light's 4π·c, sin α = R/D.
    // With refr= 1 every photon that enters leaves (no Fresnel, no
    // absorption) and lands on the floor after two refractions.
    let text = "camera\n O= 0 -8 3\n N= 0 1 0\n sample_dist= 0.5\nend\n\
        light point\n O= 0 0 6\n color= 1 1 1\nend\n\
        primitive plane\n N= 0 0 1\n R= 0\n color= 0.001 0.001 0.001\n diff= 1\nend\n\
        primitive sphere\n O= 0 0 2\n R= 1\n color= 1 1 1\n refr= 1\n rindex= 1.5\nend\n";
    let (scene, accel) = prepared(text, Dialect::F);
    let emit = 400_000u64;
    let plan = pm_plan(&scene, emit);
    let model = Model::of(Dialect::F, scene.camera());
    let pass = shoot(&scene, &accel, &model, &plan, 4, 0);
    let through: Vec<_> = pass.photons.iter().filter(|p| p.bounces == 2).collect();
    let flux: f64 = through.iter().map(|p| p.power.x).sum();
    let sin_a: f64 = 1.0 / 4.0;
    let share = (1.0 - (1.0 - sin_a * sin_a).sqrt()) / 2.0;
    let expected = 4.0 * PI * share;
    // The count of photons that hit the ball is binomial: 4 standard deviations.
    let sd = (emit as f64 * share * (1.0 - share)).sqrt() * 4.0 * PI / emit as f64;
    assert!(
        (flux - expected).abs() < 4.0 * sd,
        "flux through the ball {flux}, intercepted {expected} ± {sd}"
    );
    // The caustic is centred under the ball: the mean landing point lies on
    // the light–centre axis within 4 standard errors of its spread.
    let n = through.len() as f64;
    let mean = through.iter().fold(DVec3::ZERO, |s, p| s + p.pos) / n;
    let spread = (through
        .iter()
        .map(|p| (p.pos - mean).truncate().length_squared())
        .sum::<f64>()
        / n)
        .sqrt();
    assert!(
        mean.truncate().length() < 4.0 * spread / n.sqrt(),
        "caustic centre {mean:?}, spread {spread}"
    );
    // And focused: most of the flux lands closer to the axis than the
    // ball's own radius (its shadow without refraction).
    let inside = through
        .iter()
        .filter(|p| p.pos.truncate().length() < 1.0)
        .count();
    assert!(
        inside as f64 > 0.9 * n,
        "{inside} of {n} within the ball's radius"
    );
}

/// The K nearest photons within √`r2` of `x` whose direction d has
/// d·`side` < 0, by brute force: (d², index) nearest first (ties by index),
/// and r² (the K-th d², at least the least positive f64, or `r2` when fewer).
fn brute_nearest(
    photons: &[Photon],
    x: DVec3,
    side: DVec3,
    k: usize,
    r2: f64,
) -> (Vec<(f64, u32)>, f64) {
    let mut all: Vec<(f64, u32)> = photons
        .iter()
        .enumerate()
        .filter(|(_, p)| p.dir.dot(side) < 0.0)
        .map(|(i, p)| ((p.pos - x).length_squared(), i as u32))
        .filter(|&(d2, _)| d2 <= r2)
        .collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    all.truncate(k);
    let r = if all.len() == k {
        all[k - 1].0.max(f64::MIN_POSITIVE)
    } else {
        r2
    };
    (all, r)
}

/// `n` photons at multiples of 1/8 in [−2, 2]³ (so that distances to
/// points at multiples of 1/32 are exact, and tie often),
/// a share `back` of them travelling up (+z) and the rest down.
fn lattice_photons(rng: &mut rand_pcg::Pcg32, n: usize, back: f64) -> Vec<Photon> {
    use rand::Rng;
    let mut cell = || f64::from(rng.random_range(-16i32..=16)) / 8.0;
    let mut photons: Vec<Photon> = (0..n)
        .map(|_| Photon {
            pos: DVec3::new(cell(), cell(), cell()),
            dir: DVec3::ZERO,
            power: DVec3::ZERO,
            bounces: 0,
        })
        .collect();
    for p in &mut photons {
        let t = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            0.0,
        );
        let up = rng.random::<f64>() < back;
        p.dir = (t + DVec3::Z * if up { 1.0 } else { -1.0 }).normalize();
        p.power = DVec3::new(rng.random(), rng.random(), rng.random());
    }
    photons
}

#[test]
fn the_k_nearest_are_exactly_a_brute_force_searchs() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg32::seed_from_u64(19);
    // The empty map: nothing found, r² = R².
    let empty = PhotonMap::new(Vec::new(), 10, 0.5, PhotonFilter::Box);
    assert_eq!(empty.nearest(DVec3::ZERO, DVec3::Z), (Vec::new(), 0.25));
    assert_eq!(empty.estimate(DVec3::ZERO, DVec3::Z, &lambert()).count, 0);
    let mut checked = [0usize; 3];
    for (n, back) in [(1, 0.0), (7, 0.5), (300, 0.3), (5000, 0.1), (20_000, 0.9)] {
        let photons = lattice_photons(&mut rng, n, back);
        // R below and above the K-radius (radii with exact squares).
        for (k, radius) in [
            (1, 0.25),
            (8, 0.5),
            (30, 4.0),
            (100, 0.375),
            (100, 8.0),
            (400, 1.0),
        ] {
            let map = PhotonMap::new(photons.clone(), k, radius, PhotonFilter::Box);
            for _ in 0..60 {
                let mut at = || f64::from(rng.random_range(-80i32..=80)) / 32.0;
                let x = DVec3::new(at(), at(), at());
                // Front means travelling down (d·z < 0), or up for the −z side.
                let side = if rng.random::<bool>() {
                    DVec3::Z
                } else {
                    -DVec3::Z
                };
                let (near, r2) = map.nearest(x, side);
                let (brute, brute_r2) = brute_nearest(&photons, x, side, k, radius * radius);
                assert_eq!(
                    near, brute,
                    "n {n}, K {k}, R {radius}, at {x:?} facing {side:?}"
                );
                assert_eq!(r2, brute_r2, "n {n}, K {k}, R {radius}, at {x:?}");
                assert_eq!(map.radius2(x, side), r2);
                checked[match near.len() {
                    0..8 => 0,
                    m if m < k => 1,
                    _ => 2,
                }] += 1;
                // The estimate: Σ Φ/(π r²) over those photons, 0 below 8.
                let e = map.estimate(x, side, &lambert());
                let sum: f64 = brute
                    .iter()
                    .map(|&(_, i)| photons[i as usize].power.x)
                    .sum();
                let expected = if brute.len() < 8 {
                    0.0
                } else {
                    sum / (PI * brute_r2)
                };
                assert_eq!(e.count, brute.len());
                assert_eq!(e.r2, brute_r2);
                assert!(
                    (e.value.x - expected).abs() <= 1e-12 * expected,
                    "{e:?} {expected}"
                );
            }
        }
    }
    // Fewer than 8 found, 8 to K − 1 found, and K found: each case was met.
    assert!(checked.iter().all(|&c| c > 50), "{checked:?}");
}

#[test]
fn the_k_nearest_of_scattered_photons_are_exactly_a_brute_force_searchs() {
    use rand::{Rng, SeedableRng};
    // Positions anywhere, far from the origin, directions any way, the cone
    // filter: the same photons, distances and r² as a brute force.
    let mut rng = rand_pcg::Pcg32::seed_from_u64(20);
    let centre = DVec3::new(1000.0, -300.0, 50.0);
    let photons: Vec<Photon> = (0..20_000)
        .map(|_| {
            let u = DVec3::new(rng.random(), rng.random(), rng.random());
            let d = DVec3::new(rng.random(), rng.random(), rng.random()) - 0.5;
            Photon {
                pos: centre + (u - 0.5) * 10.0,
                dir: d.normalize(),
                power: DVec3::new(rng.random(), 1.0, 1.0),
                bounces: 0,
            }
        })
        .collect();
    for (k, radius) in [(50, 0.3), (50, 3.0), (200, 1.0)] {
        let map = PhotonMap::new(photons.clone(), k, radius, PhotonFilter::Cone);
        for _ in 0..100 {
            let u = DVec3::new(rng.random(), rng.random(), rng.random());
            let x = centre + (u - 0.5) * 11.0;
            let side = (DVec3::new(rng.random(), rng.random(), rng.random()) - 0.5).normalize();
            let (near, r2) = map.nearest(x, side);
            let (brute, brute_r2) = brute_nearest(&photons, x, side, k, radius * radius);
            assert_eq!(
                (&near, r2),
                (&brute, brute_r2),
                "K {k}, R {radius} at {x:?}"
            );
            // The cone filter: weight 1 − d/(1.1 r), normalised by 1 − 2/(3·1.1).
            let e = map.estimate(x, side, &lambert());
            let r = brute_r2.sqrt();
            let sum: f64 = brute
                .iter()
                .map(|&(d2, i)| photons[i as usize].power.x * (1.0 - d2.sqrt() / (1.1 * r)))
                .sum();
            let norm = 1.0 - 2.0 / (3.0 * 1.1);
            let expected = if brute.len() < 8 {
                0.0
            } else {
                sum / (norm * PI * brute_r2)
            };
            assert!(
                (e.value.x - expected).abs() <= 1e-12 * expected,
                "{e:?} {expected}"
            );
        }
    }
}

#[test]
fn the_grid_finds_exactly_the_photons_a_brute_force_search_finds() {
    use crate::integrator::photons::PhotonGrid;
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg32::seed_from_u64(12);
    let photons: Vec<Photon> = (0..5000)
        .map(|_| Photon {
            pos: DVec3::new(rng.random(), rng.random(), rng.random()) * 4.0 - 2.0,
            dir: DVec3::Z,
            power: DVec3::ONE,
            bounces: 0,
        })
        .collect();
    for cell in [0.05, 0.3, 1.0] {
        let grid = PhotonGrid::new(&photons, cell);
        for _ in 0..200 {
            let x = DVec3::new(rng.random(), rng.random(), rng.random()) * 4.4 - 2.2;
            let r: f64 = cell * rng.random::<f64>();
            let r2 = r * r;
            let mut found = Vec::new();
            grid.for_each_within(x, r2, |p| found.push(p.pos.to_array()));
            let mut brute: Vec<[f64; 3]> = photons
                .iter()
                .filter(|p| (p.pos - x).length_squared() <= r2)
                .map(|p| p.pos.to_array())
                .collect();
            let key = |a: &[f64; 3], b: &[f64; 3]| a.partial_cmp(b).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
            found.sort_by(key);
            brute.sort_by(key);
            assert_eq!(found, brute, "cell {cell}, radius {r} at {x:?}");
        }
    }
}

#[test]
fn ppm_radius_flux_and_count_follow_the_recurrence() {
    // A scripted sequence of photon counts M and fluxes; with N₀ = 0 the
    // recurrence gives N after pass i as α·ΣM, and each pass shrinks R² and
    // τ by f = (N + αM)/(N + M).
    let alpha = 0.7;
    let mut h = HitPoint {
        pixel: 0,
        point: DVec3::ZERO,
        side: DVec3::Z,
        brdf: lambert(),
        weight: DVec3::ONE,
        r2: 0.25,
        n: 0.0,
        m: 0,
        tau: DVec3::ZERO,
    };
    let script = [(10u64, 2.0), (0, 0.0), (5, 1.0), (20, 4.0), (1, 0.5)];
    let (mut r2, mut tau, mut n) = (0.25f64, 0.0f64, 0.0f64);
    for &(m, flux) in &script {
        h.m = m;
        h.tau += DVec3::splat(flux);
        update_hit_point(&mut h, alpha);
        // By hand, pass by pass.
        tau += flux;
        if m > 0 {
            let f = (n + alpha * m as f64) / (n + m as f64);
            r2 *= f;
            tau *= f;
            n += alpha * m as f64;
        }
        assert_eq!(h.m, 0);
        assert!((h.r2 - r2).abs() < 1e-15 && (h.tau.x - tau).abs() < 1e-15 && h.n == n);
    }
    // The first pass keeps R²·α exactly (N = 0: f = α); N = α·ΣM.
    assert!((n - alpha * 36.0).abs() < 1e-12);
    let first = 0.25 * alpha;
    assert!(h.r2 < first && h.r2 > 0.0);
}

#[test]
fn photons_are_the_same_whatever_the_threads() {
    let (scene, accel) = prepared(FLOOR, Dialect::Z14);
    let plan = pm_plan(&scene, 50_000);
    let model = Model::of(Dialect::Z14, scene.camera());
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        pool.install(|| shoot(&scene, &accel, &model, &plan, 9, 3).photons)
    };
    let one = run(1);
    assert!(one.len() > 10_000);
    assert_eq!(one, run(2));
    assert_eq!(one, run(7));
}

#[test]
fn max_photons_thins_evenly_and_keeps_the_power() {
    let text = FLOOR.replace(" sample_dist= 1\n", " sample_dist= 1\n max_photons= 5000\n");
    let (scene, accel) = prepared(&text, Dialect::Z14);
    let plan = pm_plan(&scene, 20_000);
    let model = Model::of(Dialect::Z14, scene.camera());
    let capped = shoot(&scene, &accel, &model, &plan, 5, 0);
    let full = shoot(
        &scene,
        &accel,
        &model,
        &Plan {
            max_photons: u64::MAX,
            ..plan.clone()
        },
        5,
        0,
    );
    assert_eq!(capped.photons.len(), 5000);
    assert_eq!(capped.thinned, full.photons.len() as u64 - 5000);
    // Every kept photon is one of the full pass's, scaled by stored/kept.
    let scale = full.photons.len() as f64 / 5000.0;
    for p in &capped.photons {
        assert!(
            full.photons
                .iter()
                .any(|q| q.pos == p.pos && (q.power * scale - p.power).abs().max_element() < 1e-12)
        );
    }
    let total = |v: &[Photon]| v.iter().map(|p| p.power.x).sum::<f64>();
    assert!((total(&capped.photons) / total(&full.photons) - 1.0).abs() < 0.05);
}

#[test]
fn black_lights_and_zero_settings_switch_photons_off_with_a_warning() {
    let black = FLOOR.replace("color= 1 1 1", "color= 0 0 0");
    let (scene, _) = prepared(&black, Dialect::Z14);
    let (plan, notes) = Plan::of(&scene, &PhotonOptions::default());
    assert_eq!(plan.mode, PhotonMode::Off);
    assert!(
        notes
            .iter()
            .any(|n| n.starts_with("warning:") && n.contains("no light")),
        "{notes:?}"
    );
    let zero = FLOOR.replace(" sample_dist= 1\n", " sample_dist= 0\n");
    let (scene, _) = prepared(&zero, Dialect::Z14);
    let (plan, notes) = Plan::of(&scene, &PhotonOptions::default());
    assert_eq!(plan.mode, PhotonMode::Off);
    assert!(notes.iter().any(|n| n.contains("sample_dist")), "{notes:?}");
    // The framework's files trace none, and say their keys do nothing.
    let (scene, _) = prepared(FLOOR, Dialect::F);
    let (plan, notes) = Plan::of(&scene, &PhotonOptions::default());
    assert_eq!(plan.mode, PhotonMode::Off);
    assert!(
        notes
            .iter()
            .any(|n| n.contains("`sample_dist=`") && n.contains("no effect")),
        "{notes:?}"
    );
}
