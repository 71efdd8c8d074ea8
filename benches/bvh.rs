//! Hierarchy build time and traversal throughput.
//!
//! `cargo bench --bench bvh`; prints bytes per primitive of each structure,
//! and the nodes visited and primitives tested per query (the tree's
//! quality, counted, free of the machine's noise).

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use glint::accel::{Accel, QueryCost};
use glint::geometry::{Ray, Shape, Sphere, Triangle, offset_origin};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::hint::black_box;
use std::time::Duration;

/// Rays per measured batch.
const BATCH: usize = 20_000;

/// The structure holds bare shapes here (the renderer's objects add a material).
type Object = Shape;

fn object(shape: Shape) -> Object {
    shape
}

/// `n` spheres in a cube of side n^(1/3) (about one per unit volume, so the
/// density does not change with n), radii 0.05 to 0.5.
fn random_spheres(n: usize, seed: u64) -> Vec<Object> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let side = (n as f64).cbrt();
    (0..n)
        .map(|_| {
            let c = DVec3::new(rng.random(), rng.random(), rng.random()) * side;
            object(Shape::Sphere(Sphere::new(c, rng.random_range(0.05..0.5))))
        })
        .collect()
}

/// The Stanford bunny's triangles (the crate's OBJ loader is another feature).
fn bunny() -> Vec<Object> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/scenes/meshes/stanford-bunny.obj"
    );
    let options = tobj::LoadOptions {
        triangulate: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(path, &options).expect("the bunny mesh is readable");
    let mut objects = Vec::new();
    for m in models {
        let p = &m.mesh.positions;
        let v = |i: u32| {
            let i = i as usize * 3;
            DVec3::new(p[i] as f64, p[i + 1] as f64, p[i + 2] as f64)
        };
        for f in m.mesh.indices.chunks_exact(3) {
            objects.push(object(Shape::Triangle(Box::new(Triangle::new(
                v(f[0]),
                v(f[1]),
                v(f[2]),
                None,
            )))));
        }
    }
    objects
}

/// Bounds of all objects.
fn scene_bounds(objects: &[Object]) -> (DVec3, DVec3) {
    objects
        .iter()
        .filter_map(|o| o.bounds())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), b| {
            (lo.min(b.min), hi.max(b.max))
        })
}

fn point_in(rng: &mut Pcg64, lo: DVec3, hi: DVec3) -> DVec3 {
    lo + (hi - lo) * DVec3::new(rng.random(), rng.random(), rng.random())
}

/// Camera-like rays: from outside the scene's box towards random points in it.
fn primary_rays(objects: &[Object], seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let (lo, hi) = scene_bounds(objects);
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
    (0..BATCH)
        .map(|_| {
            let o = loop {
                let d = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
                if d.length_squared() > 0.01 {
                    break c + d.normalize() * r;
                }
            };
            Ray::new(o, (point_in(&mut rng, lo, hi) - o).normalize())
        })
        .collect()
}

/// Shadow-like segments between two random points of the scene's box.
fn segments(objects: &[Object], seed: u64) -> Vec<(Ray, f64)> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let (lo, hi) = scene_bounds(objects);
    (0..BATCH)
        .map(|_| {
            let a = point_in(&mut rng, lo, hi);
            let d = point_in(&mut rng, lo, hi) - a;
            (Ray::new(a, d.normalize()), d.length())
        })
        .collect()
}

/// Camera tiles: 8x8 rays through neighbouring pixels of a 1024x1024 view
/// of the scene's box from one eye, at random places, tile after tile.
fn camera_tiles(objects: &[Object], seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let (lo, hi) = scene_bounds(objects);
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length());
    let eye = c - DVec3::new(0.3, 1.0, -0.4).normalize() * r;
    let n = (c - eye).normalize();
    let right = n.cross(DVec3::Z).normalize();
    let up = right.cross(n);
    let pixel = 0.7 / 1024.0;
    let mut rays = Vec::with_capacity(BATCH);
    while rays.len() + 64 <= BATCH {
        let (px, py) = (rng.random_range(0..1016), rng.random_range(0..1016));
        for k in 0..64 {
            let (x, y) = ((px + k % 8) as f64 - 512.0, (py + k / 8) as f64 - 512.0);
            let d = n + right * (x * pixel) + up * (y * pixel);
            rays.push(Ray::new(eye, d.normalize()));
        }
    }
    rays
}

/// Shadow rays from where `rays` hit, towards a light above the scene:
/// each ray, its length and the object it leaves.
fn shadow_rays(accel: &Accel<Object>, objects: &[Object], rays: &[Ray]) -> Vec<(Ray, f64, u32)> {
    let (lo, hi) = scene_bounds(objects);
    let light = (lo + hi) * 0.5 + DVec3::new(0.2, -0.5, 1.0) * (hi - lo).length();
    rays.iter()
        .filter_map(|r| {
            let (i, h) = accel.intersect(r, f64::INFINITY)?;
            let s = objects[i as usize].surface(r, &h);
            let side = if s.normal.dot(r.dir) < 0.0 {
                s.normal
            } else {
                -s.normal
            };
            let o = offset_origin(s.point, side);
            let to = light - o;
            Some((Ray::off_surface(o, to.normalize()), to.length(), i))
        })
        .collect()
}

fn build(c: &mut Criterion) {
    let mut g = c.benchmark_group("build");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for n in [10_000, 100_000, 1_000_000] {
        let objects = random_spheres(n, 1);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("spheres", n), &objects, |b, o| {
            b.iter_batched(
                || o.clone(),
                |o| Accel::build(black_box(o)),
                BatchSize::LargeInput,
            )
        });
        let accel = Accel::build(objects.clone());
        eprintln!(
            "spheres {n}: {} nodes, {:.1} bytes per primitive (plus {} per Object)",
            accel.node_count(),
            accel.memory_bytes() as f64 / n as f64,
            size_of::<Object>()
        );
    }
    g.finish();
}

fn traverse(c: &mut Criterion) {
    let mut g = c.benchmark_group("traverse");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .throughput(Throughput::Elements(BATCH as u64));
    let scenes = [
        ("spheres-10k", random_spheres(10_000, 2)),
        ("spheres-1M", random_spheres(1_000_000, 3)),
        ("bunny", bunny()),
    ];
    for (name, objects) in &scenes {
        let accel = Accel::build(objects.clone());
        let rays = primary_rays(objects, 4);
        let hits = rays
            .iter()
            .filter(|r| accel.intersect(r, f64::INFINITY).is_some())
            .count();
        let shadow = segments(objects, 5);
        let blocked = shadow
            .iter()
            .filter(|(r, t)| accel.occluded(r, *t, None))
            .count();
        eprintln!(
            "{name}: {} primitives, {:.1} bytes per primitive; {:.0}% of rays hit, {:.0}% of segments blocked",
            objects.len(),
            accel.memory_bytes() as f64 / objects.len() as f64,
            100.0 * hits as f64 / BATCH as f64,
            100.0 * blocked as f64 / BATCH as f64,
        );
        g.bench_function(BenchmarkId::new("closest-hit", name), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| accel.intersect(r, f64::INFINITY).is_some())
                    .count()
            })
        });
        g.bench_function(BenchmarkId::new("any-hit", name), |b| {
            b.iter(|| {
                shadow
                    .iter()
                    .filter(|(r, t)| accel.occluded(r, *t, None))
                    .count()
            })
        });
        // Coherent camera rays: one by one, then a tile (64) at a time.
        let tiles = camera_tiles(objects, 6);
        g.throughput(Throughput::Elements(tiles.len() as u64));
        g.bench_function(BenchmarkId::new("camera-tiles-single", name), |b| {
            b.iter(|| {
                tiles
                    .iter()
                    .filter(|r| accel.intersect(r, f64::INFINITY).is_some())
                    .count()
            })
        });
        let mut found = vec![None; tiles.len()];
        g.bench_function(BenchmarkId::new("camera-tiles-packet", name), |b| {
            b.iter(|| {
                accel.intersect_packet(&tiles, &mut found);
                found.iter().flatten().count()
            })
        });
        // Shadow rays from the tiles' hits: walked from the root, then up
        // from the leaf of the surface they leave.
        let from_hits = shadow_rays(&accel, objects, &tiles);
        let mut costs = [QueryCost::default(); 4];
        for r in &rays {
            accel.intersect_tallied(r, f64::INFINITY, &mut costs[0]);
        }
        for (r, t) in &shadow {
            accel.occluded_hinted(r, *t, None, None, &mut None, &mut costs[1]);
        }
        for r in &tiles {
            accel.intersect_tallied(r, f64::INFINITY, &mut costs[2]);
        }
        for (r, t, i) in &from_hits {
            accel.occluded_hinted(r, *t, None, Some(*i), &mut None, &mut costs[3]);
        }
        let counts = [rays.len(), shadow.len(), tiles.len(), from_hits.len()];
        let per = |k: usize| {
            let n = counts[k].max(1) as f64;
            format!(
                "{:.2} {:.2}",
                costs[k].nodes as f64 / n,
                costs[k].tests as f64 / n
            )
        };
        eprintln!(
            "{name}: nodes and tests per query: closest hit {}, any hit {}, camera tiles {}, shadow from the leaf {}",
            per(0),
            per(1),
            per(2),
            per(3),
        );
        g.throughput(Throughput::Elements(from_hits.len() as u64));
        g.bench_function(BenchmarkId::new("shadow-from-root", name), |b| {
            b.iter(|| {
                from_hits
                    .iter()
                    .filter(|(r, t, _)| accel.occluded(r, *t, None))
                    .count()
            })
        });
        g.bench_function(BenchmarkId::new("shadow-from-leaf", name), |b| {
            b.iter(|| {
                from_hits
                    .iter()
                    .filter(|(r, t, i)| {
                        accel.occluded_hinted(r, *t, None, Some(*i), &mut None, &mut ())
                    })
                    .count()
            })
        });
        g.throughput(Throughput::Elements(BATCH as u64));
    }
    g.finish();
}

/// A primitive's box for obvhs: glint's f64 box padded by 2^-20 of its
/// extent and magnitude, rounded outward to f32 (obvhs tests f32 boxes with
/// an f32 ray; the pad is far above that arithmetic's rounding for rays that
/// start within a few scene sizes of the box).
struct Padded(obvhs::aabb::Aabb);

impl obvhs::Boundable for Padded {
    fn aabb(&self) -> obvhs::aabb::Aabb {
        self.0
    }
}

fn padded(o: &Object) -> Padded {
    let b = o.bounds().expect("the bench scenes are bounded");
    let pad = ((b.max - b.min).max_element() + b.min.abs().max(b.max.abs()).max_element())
        / (1u64 << 20) as f64;
    let down = |x: f64| {
        let f = x as f32;
        if f as f64 > x { f.next_down() } else { f }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x { f.next_up() } else { f }
    };
    let lo = b.min - pad;
    let hi = b.max + pad;
    Padded(obvhs::aabb::Aabb {
        min: glam34::Vec3A::new(down(lo.x), down(lo.y), down(lo.z)),
        max: glam34::Vec3A::new(up(hi.x), up(hi.y), up(hi.z)),
    })
}

/// The nearest hit through obvhs's compressed 8-wide BVH, each candidate
/// tested exactly (f64) as glint's `Accel::intersect` tests it: the same
/// object and hit whenever no candidate is culled wrongly.
fn obvhs_nearest(bvh: &obvhs::cwbvh::CwBvh, objects: &[Object], r: &Ray) -> Option<(u32, f64)> {
    let ray = obvhs::ray::Ray::new_inf(
        glam34::Vec3A::new(r.origin.x as f32, r.origin.y as f32, r.origin.z as f32),
        glam34::Vec3A::new(r.dir.x as f32, r.dir.y as f32, r.dir.z as f32),
    );
    let mut best: Option<(u32, f64)> = None;
    let mut hit = obvhs::ray::RayHit::none();
    bvh.ray_traverse(ray, &mut hit, |_, k| {
        let i = bvh.primitive_indices[k];
        let limit = match best {
            Some((b, t)) if i < b => t.next_up(),
            Some((_, t)) => t,
            None => f64::INFINITY,
        };
        if let Some(h) = objects[i as usize].intersect(r, r.t_min, limit) {
            best = Some((i, h.t));
        }
        // Rounded up: no box nearer than the best hit is culled.
        best.map_or(f32::INFINITY, |(_, t)| {
            let f = t as f32;
            if (f as f64) < t { f.next_up() } else { f }
        })
    });
    best
}

/// glint's wide BVH beside obvhs's CWBVH (PLOC build, 8-wide compressed
/// nodes, SIMD node tests) on the same rays, the primitives tested exactly
/// by glint in both; prints the build times and the rays whose answers differ.
fn obvhs_side_by_side(c: &mut Criterion) {
    let mut g = c.benchmark_group("obvhs");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    let scenes = [
        ("spheres-1M", random_spheres(1_000_000, 3)),
        ("bunny", bunny()),
    ];
    for (name, objects) in &scenes {
        let t0 = std::time::Instant::now();
        let accel = Accel::build(objects.clone());
        let ours = t0.elapsed();
        let boxes: Vec<Padded> = objects.iter().map(padded).collect();
        let t0 = std::time::Instant::now();
        let bvh = obvhs::cwbvh::builder::build_cwbvh(
            &boxes,
            obvhs::BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let theirs = t0.elapsed();
        let rays = primary_rays(objects, 4);
        let tiles = camera_tiles(objects, 6);
        let differ = rays
            .iter()
            .chain(&tiles)
            .filter(|r| {
                let a = accel.intersect(r, f64::INFINITY).map(|(i, h)| (i, h.t));
                a != obvhs_nearest(&bvh, objects, r)
            })
            .count();
        eprintln!(
            "{name}: build glint {:.3} s, obvhs {:.3} s (medium_build, {} threads); {differ} of {} answers differ",
            ours.as_secs_f64(),
            theirs.as_secs_f64(),
            rayon::current_num_threads(),
            rays.len() + tiles.len()
        );
        for (kind, set) in [("closest-hit", &rays), ("camera-tiles-single", &tiles)] {
            g.throughput(Throughput::Elements(set.len() as u64));
            g.bench_function(BenchmarkId::new(format!("{kind}-glint"), name), |b| {
                b.iter(|| {
                    set.iter()
                        .filter(|r| accel.intersect(r, f64::INFINITY).is_some())
                        .count()
                })
            });
            g.bench_function(BenchmarkId::new(format!("{kind}-obvhs"), name), |b| {
                b.iter(|| {
                    set.iter()
                        .filter(|r| obvhs_nearest(&bvh, objects, r).is_some())
                        .count()
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, build, traverse, obvhs_side_by_side);
criterion_main!(benches);
