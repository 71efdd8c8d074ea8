//! Photon mapping's costs: photon rays traced per second, one K = 100 (and
//! K = 10) estimate on one core, and a PPM iteration of 100 000 photons over a 1280×760
//! frame's worth of hit points on the machine's cores.
//!
//! `cargo bench --features bench --bench photons`.

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use glint::Scene;
use glint::photon_bench::Prepared;
use rand::{Rng, SeedableRng};
use std::hint::black_box;
use std::time::Duration;

/// A point light over a floor, a wall and a glass ball, in the 2014 model
/// (every diffuse hit stored).
const SCENE: &str = "camera\n O= 0 -6 2\n N= 0 1 -0.2\n sample_dist= 1\nend\n\
    light point\n O= 0 0 5\n color= 20 20 20\nend\n\
    primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 1\nend\n\
    primitive plane\n N= 0 -1 0\n R= -3\n color= 0.8 0.3 0.3\n diff= 1\nend\n\
    primitive sphere\n O= 0 0 1\n R= 1\n color= 1 1 1\n refr= 1\n rindex= 1.5\nend\n";

fn prepared(emit: u64, k: u64) -> Prepared {
    let scene = Scene::parse_as(SCENE, ".", Some(glint::Dialect::Z14)).expect("parses");
    Prepared::new(scene, emit, k)
}

fn photons(c: &mut Criterion) {
    let mut g = c.benchmark_group("photons");
    g.measurement_time(Duration::from_secs(10)).sample_size(10);
    // The same pass each time: its rays (one nearest-hit query a path
    // segment) are the throughput, comparable with the CLI's rays per second.
    let p = prepared(100_000, 100);
    let (_, rays) = p.shoot(1);
    g.throughput(Throughput::Elements(rays));
    g.bench_function("trace 100k photons", |b| b.iter(|| black_box(p.shoot(1))));
    // One estimate on one core, at random floor points (1M photons, K = 100);
    // the same with K = 10, the other lineages' default (a leaf is scanned
    // whole, so that small K pays for large leaves).
    let map = prepared(1_000_000, 100).map();
    let map10 = prepared(1_000_000, 10).map();
    let mut rng = rand_pcg::Pcg32::seed_from_u64(3);
    g.throughput(Throughput::Elements(1));
    for (name, m) in [
        ("estimate K=100 of 1M", &map),
        ("estimate K=10 of 1M", &map10),
    ] {
        g.bench_function(name, |b| {
            b.iter_batched(
                || {
                    DVec3::new(
                        rng.random_range(-2.0..2.0),
                        rng.random_range(-1.0..2.5),
                        0.0,
                    )
                },
                |x| black_box(m.estimate(x, DVec3::Z)),
                BatchSize::SmallInput,
            )
        });
    }
    drop(map10);
    // The same, at floor points in a render's order: a 1280×760 raster's
    // rows one after another, so that neighbouring queries share the map's
    // cache lines as a render's do (the random points above miss them).
    let raster = |i: u64| {
        let (x, y) = (
            (i % 1280) as f64 / 1280.0,
            ((i / 1280) % 760) as f64 / 760.0,
        );
        DVec3::new(4.0 * x - 2.0, 3.5 * y - 1.0, 0.0)
    };
    let mut next = 0u64;
    g.bench_function("estimate K=100 of 1M, raster order", |b| {
        b.iter_batched(
            || {
                next += 1;
                raster(next)
            },
            |x| black_box(map.estimate(x, DVec3::Z)),
            BatchSize::SmallInput,
        )
    });
    // A PPM iteration: 100k photons, 1280×760 hit points on the floor, R = 0.05.
    let p = prepared(100_000, 100);
    let mut points: Vec<(DVec3, f64)> = (0..1280 * 760)
        .map(|i| {
            let (x, y) = ((i % 1280) as f64 / 1280.0, (i / 1280) as f64 / 760.0);
            (DVec3::new(4.0 * x - 2.0, 3.5 * y - 1.0, 0.0), 0.05 * 0.05)
        })
        .collect();
    g.throughput(Throughput::Elements(1));
    g.bench_function("PPM iteration 100k photons 1280x760 points", |b| {
        let mut pass = 0;
        b.iter(|| {
            pass += 1;
            black_box(p.ppm_iteration(&mut points, pass))
        })
    });
    g.finish();
}

criterion_group!(benches, photons);
criterion_main!(benches);
