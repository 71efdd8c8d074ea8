//! Ray / Bézier-surface intersection throughput: rays from outside the
//! surface's bounding box aimed at random points inside it (hits and
//! misses), one core, for profiles of degree 1 to 8 (the root search on
//! fixed-size arrays) and 20 and 30 (the same search in the per-thread
//! scratch buffer). Run with `cargo bench --features bench --bench bezier`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec2, DVec3};
use glint::geometry::{Bezier, Ray};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::hint::black_box;
use std::time::Duration;

const RAYS: usize = 100_000;

/// Rays from a sphere around the box through uniform points of the box.
fn box_rays(shape: &Bezier) -> Vec<Ray> {
    let b = shape.bounds();
    let center = b.center();
    let radius = (b.max - b.min).length();
    let mut rng = Pcg64::seed_from_u64(7);
    (0..RAYS)
        .map(|_| {
            let target =
                b.min + (b.max - b.min) * DVec3::new(rng.random(), rng.random(), rng.random());
            let origin = loop {
                let v = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
                let l = v.length();
                if l > 0.1 && l <= 1.0 {
                    break center + v / l * radius;
                }
            };
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

fn profile(points: &[(f64, f64)]) -> Vec<DVec2> {
    points.iter().map(|&(z, r)| DVec2::new(z, r)).collect()
}

/// A vase of degree `n` whose radius has `ribs` waves (z = 6s exactly).
fn ribbed(n: usize, ribs: f64) -> Vec<DVec2> {
    (0..=n)
        .map(|k| {
            let x = k as f64 / n as f64;
            DVec2::new(
                6.0 * x,
                1.6 + 0.9 * (std::f64::consts::TAU * ribs * x).sin(),
            )
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let shapes = [
        (
            "stacks_cubic",
            // scene_stacks.txt
            Bezier::new(
                DVec3::new(80.0, -10.0, 0.0),
                DVec3::new(80.0, -10.0, 30.0),
                profile(&[(5.0, 5.0), (10.0, 6.0), (15.0, 7.0), (2.0, 9.0)]),
            ),
        ),
        (
            "cylinder_degree1",
            Bezier::new(
                DVec3::ZERO,
                DVec3::new(0.3, 0.2, 1.0),
                profile(&[(0.0, 2.0), (5.0, 2.0)]),
            ),
        ),
        (
            "vase_degree8",
            Bezier::new(
                DVec3::ZERO,
                DVec3::Z,
                profile(&[
                    (0.0, 0.0),
                    (0.0, 3.0),
                    (1.0, 4.0),
                    (3.0, 1.0),
                    (5.0, 0.5),
                    (6.0, 2.5),
                    (8.0, 3.0),
                    (9.0, 1.0),
                    (7.0, 0.5),
                ]),
            ),
        ),
        (
            // Above the fixed-size arrays (degree 16): the per-thread scratch buffer.
            "ribbed_degree20",
            Bezier::new(DVec3::ZERO, DVec3::Z, ribbed(20, 2.0)),
        ),
        (
            "ribbed_degree30",
            Bezier::new(DVec3::ZERO, DVec3::Z, ribbed(30, 3.0)),
        ),
    ];
    let mut group = c.benchmark_group("bezier");
    group
        .throughput(Throughput::Elements(RAYS as u64))
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
        .sample_size(20);
    for (name, shape) in &shapes {
        let rays = box_rays(shape);
        let misses: Vec<Ray> = rays
            .iter()
            .filter(|r| shape.intersect(r, 0.0, f64::INFINITY).is_none())
            .copied()
            .collect();
        println!(
            "{name}: {:.1}% of the box rays hit",
            100.0 - 100.0 * misses.len() as f64 / RAYS as f64
        );
        if *name == "stacks_cubic" {
            // The misses alone (they all reach the surface's bounding box).
            group.throughput(Throughput::Elements(misses.len() as u64));
            group.bench_function("stacks_cubic_misses", |b| {
                b.iter(|| {
                    misses
                        .iter()
                        .filter(|r| shape.intersect(black_box(r), 0.0, f64::INFINITY).is_some())
                        .count()
                })
            });
            group.throughput(Throughput::Elements(RAYS as u64));
        }
        group.bench_function(*name, |b| {
            b.iter(|| {
                let mut n = 0u32;
                for ray in &rays {
                    if shape
                        .intersect(black_box(ray), 0.0, f64::INFINITY)
                        .is_some()
                    {
                        n += 1;
                    }
                }
                n
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
