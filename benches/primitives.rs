//! Ray/primitive intersection tests per second, per shape kind, on a mix of
//! hits and misses: rays from a sphere around the shape aimed at random
//! points of its (padded) bounding box.
//!
//! `cargo bench --bench primitives`; criterion reports elements/s = tests/s.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use glint::geometry::{Aabb, Cube, Cylinder, Hit, Ray, Sphere, Square, Triangle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::hint::black_box;
use std::time::Duration;

/// Rays per batch (one criterion element per ray).
const RAYS: usize = 1024;

/// Rays aimed at random points of `bounds` grown by a quarter of its size on
/// each side, from a sphere three sizes out.
fn rays_at(bounds: Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let size = (bounds.max - bounds.min).max_element();
    let padded = bounds.padded(0.25 * size);
    let mut unit = || loop {
        let p = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = p.length_squared();
        if l > 1e-6 && l <= 1.0 {
            return p.normalize();
        }
    };
    let dirs: Vec<DVec3> = (0..RAYS).map(|_| unit()).collect();
    dirs.into_iter()
        .map(|out| {
            let origin = bounds.center() + out * (3.0 * size);
            let target = padded.min
                + (padded.max - padded.min) * DVec3::new(rng.random(), rng.random(), rng.random());
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

fn bench_shape(
    c: &mut Criterion,
    name: &str,
    bounds: Aabb,
    intersect: impl Fn(&Ray) -> Option<Hit>,
) {
    let rays = rays_at(bounds, 7);
    let hits = rays.iter().filter(|r| intersect(r).is_some()).count();
    eprintln!("{name}: {hits} of {RAYS} rays hit");
    let mut group = c.benchmark_group("intersect");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .throughput(Throughput::Elements(RAYS as u64));
    group.bench_function(name, |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in &rays {
                n += intersect(black_box(r)).is_some() as u32;
            }
            n
        })
    });
    group.finish();
}

fn primitives(c: &mut Criterion) {
    let inf = f64::INFINITY;
    let sphere = Sphere::new(DVec3::new(1.0, 2.0, 3.0), 1.5);
    bench_shape(c, "sphere", sphere.bounds(), |r| {
        sphere.intersect(r, 0.0, inf)
    });
    let square = Square::new(
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(1.0, 0.2, 0.1),
        DVec3::new(-0.1, 0.8, 0.3),
    );
    bench_shape(c, "square", square.bounds(), |r| {
        square.intersect(r, 0.0, inf)
    });
    let (dx, dy) = (
        DVec3::new(0.6, 0.8, 0.0),
        DVec3::new(0.0, 0.0, 1.0).cross(DVec3::new(0.6, 0.8, 0.0)),
    );
    let cube = Cube::new(DVec3::new(1.0, 2.0, 3.0), dx, dy, DVec3::new(1.0, 0.5, 0.7));
    bench_shape(c, "cube", cube.bounds(), |r| cube.intersect(r, 0.0, inf));
    let cylinder = Cylinder::new(DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.5, 3.0, 4.5), 0.6);
    bench_shape(c, "cylinder", cylinder.bounds(), |r| {
        cylinder.intersect(r, 0.0, inf)
    });
    let triangle = Triangle::new(
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(2.0, 2.5, 3.1),
        DVec3::new(1.2, 3.0, 3.8),
        None,
    );
    bench_shape(c, "triangle", triangle.bounds(), |r| {
        triangle.intersect(r, 0.0, inf)
    });
}

criterion_group!(benches, primitives);
criterion_main!(benches);
