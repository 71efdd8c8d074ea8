//! The hierarchy against a brute-force loop over every object: the same
//! nearest hit (index and distance, lowest index on ties) and the same
//! any-hit answer, on random and degenerate scenes of every kind of shape.

use super::common::{half_sizes, log_size, point_in, random_sign};
use crate::accel::{Accel, Isa};
use crate::geometry::{
    Bezier, Cube, Cylinder, Hit, Plane, Ray, Shape, Sphere, Square, Triangle, offset_origin,
};
use crate::scene::{Object, Origin, Scene};
use glam::{DMat3, DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// The reference: every object in index order, strict `<` on the distance.
fn brute_intersect(objects: &[Object], ray: &Ray, t_max: f64) -> Option<(u32, Hit)> {
    let mut best = None;
    let mut t_best = t_max;
    for (i, o) in objects.iter().enumerate() {
        if let Some(h) = o.shape.intersect(ray, 0.0, t_best) {
            t_best = h.t;
            best = Some((i as u32, h));
        }
    }
    best
}

/// Whether `o` blocks `ray` within (`t_min`, `t_max`), unless it belongs to
/// the light `ignore`.
fn blocks(o: &Object, ray: &Ray, t_min: f64, t_max: f64, ignore: Option<u32>) -> bool {
    let skip = ignore.is_some() && o.light() == ignore;
    !skip && o.shape.intersect(ray, t_min, t_max).is_some()
}

/// Whether `hint` is what an any-hit query of `ray` (up to `t_max`) that
/// answered `blocked` must leave: a blocker of the ray, or none if it got
/// through.
fn hint_left_right(
    objects: &[Object],
    hint: Option<u32>,
    ray: &Ray,
    t_max: f64,
    ignore: Option<u32>,
    blocked: bool,
) -> bool {
    let left = hint.map(|b| blocks(&objects[b as usize], ray, ray.t_min, t_max, ignore));
    left == blocked.then_some(true)
}

/// The reference any-hit query.
fn brute_occluded(objects: &[Object], ray: &Ray, t_max: f64, ignore_light: Option<u32>) -> bool {
    objects
        .iter()
        .any(|o| blocks(o, ray, 0.0, t_max, ignore_light))
}

fn object(shape: Shape, light: Option<u32>) -> Object {
    Object {
        shape,
        material: 0,
        origin: light.map_or(Origin::Block(0), Origin::Light),
    }
}

fn sphere(c: DVec3, r: f64) -> Shape {
    Shape::Sphere(Sphere::new(c, r))
}

fn triangle(a: DVec3, b: DVec3, c: DVec3) -> Shape {
    Shape::Triangle(Box::new(Triangle::new(a, b, c, None)))
}

fn plane(n: DVec3, r: f64) -> Shape {
    Shape::Plane(Box::new(Plane::new(n, r, DVec3::X, DVec3::Y)))
}

fn square(c: DVec3, dx: DVec3, dy: DVec3) -> Shape {
    Shape::Square(Box::new(Square::new(c, dx, dy)))
}

/// A box with orthonormal `dx`, `dy`.
fn cube(c: DVec3, dx: DVec3, dy: DVec3, half: DVec3) -> Shape {
    Shape::Cube(Box::new(Cube::new(c, dx, dy, half)))
}

fn cylinder(o1: DVec3, o2: DVec3, r: f64) -> Shape {
    Shape::Cylinder(Box::new(Cylinder::new(o1, o2, r)))
}

fn bezier(o1: DVec3, o2: DVec3, points: &[(f64, f64)]) -> Shape {
    let points = points.iter().map(|&(z, r)| DVec2::new(z, r)).collect();
    Shape::Bezier(Box::new(Bezier::new(o1, o2, points)))
}

/// An orthonormal pair (the first two axes of a random rotation).
fn frame(rng: &mut Pcg64) -> (DVec3, DVec3) {
    let x = unit_vector(rng);
    let y = x.cross(unit_vector(rng)).normalize();
    (x, y)
}

fn unit_vector(rng: &mut Pcg64) -> DVec3 {
    loop {
        let v = point_in(rng, 1.0);
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

/// A direction with some components exactly zero (of either sign).
fn axis_direction(rng: &mut Pcg64) -> DVec3 {
    let zero = |rng: &mut Pcg64| if rng.random_bool(0.5) { 0.0 } else { -0.0 };
    let mut v = DVec3::new(zero(rng), zero(rng), zero(rng));
    let a = rng.random_range(0..3usize);
    v[a] = random_sign(rng);
    if rng.random_bool(0.3) {
        // In a coordinate plane: one zero component.
        let b = (a + 1 + rng.random_range(0..2usize)) % 3;
        v[b] = random_sign(rng) * rng.random_range(0.1..1.0);
    }
    v.normalize()
}

/// Rays of every kind the renderer makes and some it does not: random,
/// aimed at objects, axis-aligned, starting exactly on an object's bounds.
fn random_ray(rng: &mut Pcg64, objects: &[Object], half: f64) -> Ray {
    let kind = rng.random_range(0..4u32);
    let target = objects
        .get(rng.random_range(0..objects.len().max(1)))
        .and_then(|o| o.shape.bounds());
    match (kind, target) {
        (1, Some(b)) => {
            // Aimed at a point of an object's box.
            let t = DVec3::new(rng.random(), rng.random(), rng.random());
            let p = b.min + (b.max - b.min) * t;
            let o = point_in(rng, half);
            let d = p - o;
            if d.length_squared() > 0.0 {
                Ray::new(o, d.normalize())
            } else {
                Ray::new(o, DVec3::X)
            }
        }
        (2, Some(b)) => {
            // Origin on a face plane of the box, moving along that plane or along an axis.
            let mut o = point_in(rng, half);
            let a = rng.random_range(0..3usize);
            o[a] = if rng.random_bool(0.5) {
                b.min[a]
            } else {
                b.max[a]
            };
            let c = b.center();
            for k in 0..3 {
                if k != a && rng.random_bool(0.5) {
                    o[k] = c[k];
                }
            }
            let mut d = axis_direction(rng);
            d[a] = if rng.random_bool(0.5) { 0.0 } else { -0.0 };
            if d.length_squared() == 0.0 {
                d[(a + 1) % 3] = 1.0;
            }
            Ray::new(o, d.normalize())
        }
        (3, _) => Ray::new(point_in(rng, half), axis_direction(rng)),
        _ => Ray::new(point_in(rng, half), unit_vector(rng)),
    }
}

/// Hands a light (counting 1, 2, … modulo `m`) to about one object in twenty.
fn light_flags(m: u32) -> impl FnMut(&mut Pcg64) -> Option<u32> {
    let mut light = 0;
    move |rng: &mut Pcg64| {
        rng.random_bool(0.05).then(|| {
            light += 1;
            light % m
        })
    }
}

/// Shuffles `objects` (Fisher–Yates) so the tree order differs from the index order.
fn shuffle(rng: &mut Pcg64, objects: &mut [Object]) {
    for i in (1..objects.len()).rev() {
        let j = rng.random_range(0..=i);
        objects.swap(i, j);
    }
}

/// A closed box of six `square` objects ([`super::common::box_faces`]), no light.
fn six_squares(c: DVec3, rot: DMat3, h: DVec3) -> impl Iterator<Item = Object> {
    super::common::box_faces(c, rot, h)
        .into_iter()
        .map(|(o, dx, dy)| object(square(o, dx, dy), None))
}

/// Asserts the tree's nearest hit is brute force's, and says whether several objects share its distance.
fn check_tie(accel: &Accel<Object>, objects: &[Object], ray: &Ray) -> bool {
    let expected = brute_intersect(objects, ray, f64::INFINITY);
    assert_eq!(accel.intersect(ray, f64::INFINITY), expected, "{ray:?}");
    expected.is_some_and(|(_, hit)| {
        let at_t = objects
            .iter()
            .filter(|o| o.shape.intersect(ray, 0.0, f64::INFINITY).map(|g| g.t) == Some(hit.t))
            .count();
        at_t > 1
    })
}

/// Checks `rays` random rays against brute force: nearest hit with several
/// t_max, and any-hit with several t_max and light exclusions.
fn check(objects: &[Object], rays: usize, half: f64, seed: u64) {
    for isa in Isa::available() {
        let accel = Accel::build(objects.to_vec()).with_isa(isa);
        check_queries(&accel, objects, rays, half, seed);
    }
}

/// [`check`] of one structure (its queries run in one instruction set).
fn check_queries(accel: &Accel<Object>, objects: &[Object], rays: usize, half: f64, seed: u64) {
    assert_eq!(accel.objects().len(), objects.len());
    let lights: Vec<u32> = objects.iter().filter_map(|o| o.light()).collect();
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut hits = 0;
    let (mut shadows, mut blocked) = (0, 0);
    // The blocker found by the previous hinted shadow ray.
    let mut carried = None;
    for n in 0..rays {
        let ray = random_ray(&mut rng, objects, half);
        let expected = brute_intersect(objects, &ray, f64::INFINITY);
        let got = accel.intersect(&ray, f64::INFINITY);
        assert_eq!(got, expected, "ray {n}: {ray:?}");
        let mut t_maxes = vec![rng.random_range(0.0..2.0 * half), f64::INFINITY];
        if let Some((i, h)) = expected {
            hits += 1;
            // Exactly at the hit (excluded: strict), just past it, and short of it.
            t_maxes.extend([h.t, h.t.next_up(), h.t * 0.5]);
            let l = objects[i as usize].light();
            assert_eq!(
                accel.occluded(&ray, h.t.next_up(), l),
                brute_occluded(objects, &ray, h.t.next_up(), l),
                "ray {n}: {ray:?}, ignoring the hit object's light {l:?}"
            );
            // A shadow ray leaving the hit surface, walked up from its leaf.
            let s = objects[i as usize].shape.surface(&ray, &h);
            let side = if s.normal.dot(ray.dir) < 0.0 {
                s.normal
            } else {
                -s.normal
            };
            let mut dir = unit_vector(&mut rng);
            if dir.dot(side) < 0.0 {
                dir = -dir;
            }
            let shadow = Ray::off_surface(offset_origin(s.point, side), dir);
            for t_max in [rng.random_range(0.0..2.0 * half), f64::INFINITY] {
                for ignore in [None, l] {
                    let want = objects
                        .iter()
                        .any(|o| blocks(o, &shadow, shadow.t_min, t_max, ignore));
                    let got =
                        accel.occluded_hinted(&shadow, t_max, ignore, Some(i), &mut None, &mut ());
                    assert_eq!(
                        got, want,
                        "ray {n}: shadow {shadow:?} from {i}, t_max {t_max}"
                    );
                    // A hint is only a guess to try first: the blocker of an
                    // earlier ray, or any object at all, changes nothing.
                    let mut guess = Some(rng.random_range(0..objects.len() as u32));
                    for hint in [&mut carried, &mut guess] {
                        let got =
                            accel.occluded_hinted(&shadow, t_max, ignore, Some(i), hint, &mut ());
                        assert_eq!(got, want, "ray {n}: shadow {shadow:?} hinted");
                        // A blocked ray leaves its blocker in the hint; one
                        // that gets through leaves none.
                        assert!(
                            hint_left_right(objects, *hint, &shadow, t_max, ignore, got),
                            "ray {n}: blocked {got}, hint left {hint:?}"
                        );
                    }
                    shadows += 1;
                    blocked += want as usize;
                }
            }
        }
        for &t_max in &t_maxes {
            let expected = brute_intersect(objects, &ray, t_max);
            assert_eq!(
                accel.intersect(&ray, t_max),
                expected,
                "ray {n}: {ray:?} t_max {t_max}"
            );
            let mut ignores = vec![None];
            if !lights.is_empty() {
                ignores.push(Some(lights[rng.random_range(0..lights.len())]));
            }
            ignores.push(Some(u32::MAX));
            for ignore in ignores {
                assert_eq!(
                    accel.occluded(&ray, t_max, ignore),
                    brute_occluded(objects, &ray, t_max, ignore),
                    "ray {n}: {ray:?} t_max {t_max} ignoring {ignore:?}"
                );
            }
        }
    }
    if !objects.is_empty() {
        // Guards against a generator that misses everything (vacuous test).
        assert!(hits * 10 >= rays, "only {hits} of {rays} rays hit");
    }
    if objects.len() > 100 {
        // Shadow rays both blocked and free were checked.
        assert!(
            blocked > 0 && blocked < shadows,
            "{blocked} of {shadows} shadow rays blocked"
        );
    }
}

/// Spheres and triangles of sizes spanning four decades, a few planes, some lights.
fn mixed_scene(rng: &mut Pcg64, spheres: usize, triangles: usize, planes: usize) -> Vec<Object> {
    let mut objects = Vec::new();
    let mut flag = light_flags(7);
    for _ in 0..spheres {
        let c = point_in(rng, 10.0);
        let r = log_size(rng, 1e-3, 3.0);
        let l = flag(rng);
        objects.push(object(sphere(c, r), l));
    }
    for k in 0..triangles {
        let a = point_in(rng, 10.0);
        let s = log_size(rng, 1e-3, 5.0);
        let (b, c) = if k % 4 == 0 {
            // Axis-aligned, on integer coordinates: flat boxes, exact faces.
            let a = a.round();
            let ax = rng.random_range(0..3usize);
            let (mut b, mut c) = (a, a);
            b[(ax + 1) % 3] += s.ceil();
            c[(ax + 2) % 3] += s.ceil();
            objects.push(object(triangle(a, b, c), flag(rng)));
            continue;
        } else {
            (a + unit_vector(rng) * s, a + unit_vector(rng) * s)
        };
        objects.push(object(triangle(a, b, c), flag(rng)));
    }
    for _ in 0..planes {
        let n = unit_vector(rng);
        objects.push(object(plane(n, rng.random_range(-12.0..-10.0)), flag(rng)));
    }
    // Shuffle so the tree order differs from the index order.
    shuffle(rng, &mut objects);
    objects
}

#[test]
fn random_mixed_scene_matches_brute_force() {
    let mut rng = Pcg64::seed_from_u64(1);
    let objects = mixed_scene(&mut rng, 3000, 3000, 3);
    check(&objects, 2000, 14.0, 2);
}

#[test]
fn small_random_scenes_match_brute_force() {
    let mut rng = Pcg64::seed_from_u64(3);
    for n in 0..60 {
        let objects = mixed_scene(&mut rng, n, n / 2, n % 3);
        check(&objects, 200, 14.0, 100 + n as u64);
    }
}

/// Every kind of shape, sizes over three decades: squares (random
/// parallelograms, axis-aligned ones on integer coordinates, six-square
/// boxes sharing edges), cubes (rotated and axis-aligned), cylinders
/// (tilted and along world axes), Bézier surfaces (degree 1–6, folded and
/// monotone profiles, radii of either sign), with spheres, triangles, a few
/// planes and some lights among them.
fn all_kinds_scene(rng: &mut Pcg64, each: usize, planes: usize) -> Vec<Object> {
    let mut objects = mixed_scene(rng, each, each, planes);
    let mut flag = light_flags(5);
    for k in 0..each {
        let c = point_in(rng, 10.0);
        let s = log_size(rng, 1e-2, 3.0);
        let shape = if k % 3 == 0 {
            // Axis-aligned on integer coordinates: faces on BVH box faces.
            let a = rng.random_range(0..3usize);
            let (mut dx, mut dy) = (DVec3::ZERO, DVec3::ZERO);
            dx[(a + 1) % 3] = s.ceil();
            dy[(a + 2) % 3] = s.ceil();
            square(c.round(), dx, dy)
        } else {
            square(
                c,
                unit_vector(rng) * s,
                unit_vector(rng) * log_size(rng, 1e-2, 3.0),
            )
        };
        objects.push(object(shape, flag(rng)));
    }
    for k in 0..each / 6 {
        // Closed boxes of six squares: rays through their edges hit two at once.
        let c = point_in(rng, 10.0);
        let (x, y) = if k % 2 == 0 {
            (DVec3::X, DVec3::Y)
        } else {
            frame(rng)
        };
        let h = half_sizes(rng, 0.05, 2.0);
        objects.extend(six_squares(c, DMat3::from_cols(x, y, x.cross(y)), h));
    }
    for k in 0..each {
        let c = point_in(rng, 10.0);
        let h = half_sizes(rng, 1e-2, 2.0);
        let shape = if k % 3 == 0 {
            cube(c.round(), DVec3::X, DVec3::Y, h.ceil() * 0.5)
        } else {
            let (x, y) = frame(rng);
            cube(c, x, y, h)
        };
        objects.push(object(shape, flag(rng)));
    }
    for k in 0..each {
        let o1 = point_in(rng, 10.0);
        let len = log_size(rng, 1e-2, 4.0);
        let axis = if k % 3 == 0 {
            let mut a = DVec3::ZERO;
            a[rng.random_range(0..3usize)] = random_sign(rng);
            a
        } else {
            unit_vector(rng)
        };
        objects.push(object(
            cylinder(o1, o1 + axis * len, log_size(rng, 1e-2, 2.0)),
            flag(rng),
        ));
    }
    for k in 0..each {
        let o1 = point_in(rng, 10.0);
        let axis = if k % 4 == 0 {
            DVec3::Z
        } else {
            unit_vector(rng)
        };
        let s = log_size(rng, 0.05, 2.0);
        let n = rng.random_range(2..=7usize);
        let mut pts: Vec<(f64, f64)> = (0..n)
            .map(|_| {
                (
                    rng.random_range(-1.0..1.0) * s,
                    rng.random_range(-1.0..1.0) * s,
                )
            })
            .collect();
        if k % 2 == 0 {
            // Monotone, positive: a vase. Otherwise folded, radii of either sign.
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            for p in &mut pts {
                p.1 = p.1.abs();
            }
        }
        objects.push(object(bezier(o1, o1 + axis, &pts), flag(rng)));
    }
    shuffle(rng, &mut objects);
    objects
}

#[test]
fn random_all_kinds_scene_matches_brute_force() {
    let mut rng = Pcg64::seed_from_u64(21);
    let objects = all_kinds_scene(&mut rng, 250, 2);
    check(&objects, 1500, 14.0, 22);
}

#[test]
fn small_random_all_kinds_scenes_match_brute_force() {
    let mut rng = Pcg64::seed_from_u64(23);
    for n in 0..40 {
        let objects = all_kinds_scene(&mut rng, n / 2, n % 3);
        check(&objects, 150, 14.0, 200 + n as u64);
    }
}

/// A packet of rays of one of the shapes the renderer makes and some it
/// does not: a camera tile (one origin, a grid of directions, narrow or
/// wide), one origin with directions of every sign (zeros included), or
/// unrelated rays; 1 to 100 rays, so packets longer than one are split.
fn random_packet(rng: &mut Pcg64, objects: &[Object], half: f64) -> Vec<Ray> {
    let n = rng.random_range(1..=100usize);
    match rng.random_range(0..3u32) {
        0 => {
            let aim = random_ray(rng, objects, half);
            let (u, v) = frame(rng);
            let spread = log_size(rng, 1e-6, 0.5);
            let side = (n as f64).sqrt().ceil() as usize;
            (0..n)
                .map(|k| {
                    let (a, b) = ((k % side) as f64, (k / side) as f64);
                    let d = aim.dir + (u * a + v * b) * (spread / side as f64);
                    Ray::new(aim.origin, d.normalize())
                })
                .collect()
        }
        1 => {
            let o = point_in(rng, half);
            (0..n)
                .map(|_| {
                    let d = if rng.random_bool(0.2) {
                        axis_direction(rng)
                    } else {
                        unit_vector(rng)
                    };
                    Ray::new(o, d)
                })
                .collect()
        }
        _ => (0..n).map(|_| random_ray(rng, objects, half)).collect(),
    }
}

/// Packet queries against brute force, ray by ray: the nearest hit.
/// Returns the rays that hit something and all rays.
/// Packets are traced in every instruction set this CPU has.
fn check_packets(objects: &[Object], packets: usize, half: f64, seed: u64) -> (usize, usize) {
    let accels: Vec<_> = Isa::available()
        .into_iter()
        .map(|isa| (isa, Accel::build(objects.to_vec()).with_isa(isa)))
        .collect();
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut hits = 0;
    let mut rays_seen = 0;
    for p in 0..packets {
        let rays = random_packet(&mut rng, objects, half);
        let expected: Vec<_> = rays
            .iter()
            .map(|r| brute_intersect(objects, r, f64::INFINITY))
            .collect();
        for (isa, accel) in &accels {
            let mut got = vec![None; rays.len()];
            accel.intersect_packet(&rays, &mut got);
            assert_eq!(got, expected, "packet {p} in {}: {rays:?}", isa.name());
        }
        hits += expected.iter().flatten().count();
        rays_seen += rays.len();
    }
    (hits, rays_seen)
}

#[test]
fn packets_match_brute_force() {
    let mut rng = Pcg64::seed_from_u64(31);
    let objects = all_kinds_scene(&mut rng, 250, 2);
    let (hits, rays) = check_packets(&objects, 300, 14.0, 32);
    // Guards against a generator that misses everything (vacuous test).
    assert!(hits * 10 >= rays, "only {hits} of {rays} rays hit");
    for n in 0..30 {
        let objects = all_kinds_scene(&mut rng, n / 2, n % 3);
        check_packets(&objects, 20, 14.0, 300 + n as u64);
    }
}

#[test]
fn packets_in_a_dense_cloud_match_single_queries() {
    // Many small spheres and no planes: deep trees, where a packet's
    // rays part ways and rejoin.
    let mut rng = Pcg64::seed_from_u64(35);
    let objects = mixed_scene(&mut rng, 20_000, 0, 0);
    let (hits, rays) = check_packets(&objects, 150, 14.0, 36);
    assert!(hits * 2 >= rays, "only {hits} of {rays} rays hit");
}

#[test]
fn coincident_boxes_tie_to_lowest_index() {
    // Each box three times over, as a cube, as six squares and as a cube
    // again, in shuffled order: axis-aligned rays hit all of them at the
    // same distance (exactly: integer coordinates), the lowest index wins.
    let mut rng = Pcg64::seed_from_u64(25);
    let mut objects = Vec::new();
    for _ in 0..150 {
        let c = point_in(&mut rng, 10.0).round();
        let h = DVec3::new(
            rng.random_range(1..3) as f64,
            rng.random_range(1..3) as f64,
            rng.random_range(1..3) as f64,
        );
        let mut group = vec![object(cube(c, DVec3::X, DVec3::Y, h), None)];
        group.extend(six_squares(c, DMat3::IDENTITY, h));
        group.push(object(
            cube(c, DVec3::Y, DVec3::Z, DVec3::new(h.y, h.z, h.x)),
            None,
        ));
        objects.extend(group);
    }
    shuffle(&mut rng, &mut objects);
    let accel = Accel::build(objects.to_vec());
    let mut ties = 0;
    for _ in 0..3000 {
        let ray = Ray::new(
            point_in(&mut rng, 14.0).round() * 0.5,
            axis_direction(&mut rng),
        );
        ties += check_tie(&accel, &objects, &ray) as u32;
    }
    assert!(ties > 500, "only {ties} ties");
    check(&objects, 1000, 14.0, 26);
}

#[test]
fn empty_scene_hits_nothing() {
    let accel = Accel::<Object>::build(Vec::new());
    let ray = Ray::new(DVec3::ZERO, DVec3::X);
    assert!(accel.intersect(&ray, f64::INFINITY).is_none());
    assert!(!accel.occluded(&ray, f64::INFINITY, None));
    assert!(accel.objects().is_empty());
}

#[test]
fn one_object_of_each_kind() {
    for (shape, t) in [
        (sphere(DVec3::new(0.0, 5.0, 0.0), 1.0), 4.0),
        (
            triangle(
                DVec3::new(-1.0, 5.0, -1.0),
                DVec3::new(1.0, 5.0, -1.0),
                DVec3::new(0.0, 5.0, 1.0),
            ),
            5.0,
        ),
        (plane(DVec3::Y, 5.0), 5.0),
        (
            square(DVec3::new(0.0, 5.0, 0.0), DVec3::X, DVec3::Z * 2.0),
            5.0,
        ),
        (
            cube(
                DVec3::new(0.0, 5.0, 0.0),
                DVec3::X,
                DVec3::Y,
                DVec3::new(1.0, 0.5, 2.0),
            ),
            4.5,
        ),
        (
            cylinder(DVec3::new(0.0, 3.0, 0.0), DVec3::new(0.0, 7.0, 0.0), 1.0),
            3.0,
        ),
        (
            cylinder(DVec3::new(-2.0, 5.0, 0.0), DVec3::new(2.0, 5.0, 0.0), 0.5),
            4.5,
        ),
        (
            // A cone about the x axis, radius 1 − z/4 over z in [−2, 2]: radius 1 at x = 0.
            bezier(
                DVec3::new(0.0, 5.0, 0.0),
                DVec3::new(1.0, 5.0, 0.0),
                &[(-2.0, 1.5), (2.0, 0.5)],
            ),
            4.0,
        ),
    ] {
        let objects = vec![object(shape, Some(0))];
        let accel = Accel::build(objects.to_vec());
        let ray = Ray::new(DVec3::ZERO, DVec3::Y);
        let (i, h) = accel.intersect(&ray, f64::INFINITY).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert_eq!((i, h.t), (0, t));
        assert!(accel.intersect(&ray, h.t).is_none());
        assert!(accel.occluded(&ray, 10.0, None));
        assert!(accel.occluded(&ray, 10.0, Some(1)));
        assert!(!accel.occluded(&ray, 10.0, Some(0)));
        assert!(!accel.occluded(&ray, h.t, None));
        check(&objects, 300, 8.0, 5);
    }
}

#[test]
fn only_planes() {
    let mut rng = Pcg64::seed_from_u64(6);
    let objects: Vec<_> = (0..20)
        .map(|k| {
            object(
                plane(unit_vector(&mut rng), rng.random_range(-5.0..5.0)),
                (k % 3 == 0).then_some(k),
            )
        })
        .collect();
    check(&objects, 2000, 6.0, 7);
}

#[test]
fn all_objects_at_one_centroid() {
    let mut rng = Pcg64::seed_from_u64(8);
    let c = DVec3::new(1.0, -2.0, 3.0);
    let mut objects = Vec::new();
    for k in 0..400 {
        let r = log_size(&mut rng, 1e-3, 4.0);
        objects.push(object(sphere(c, r), (k % 5 == 0).then_some(k % 3)));
        // Triangles centred on c: vertices c + u, c + v, c - u - v.
        let u = unit_vector(&mut rng) * r;
        let v = unit_vector(&mut rng) * r;
        objects.push(object(triangle(c + u, c + v, c - u - v), None));
    }
    // Identical copies: every ray that hits one hits all at the same t; the lowest index wins.
    for _ in 0..50 {
        objects.push(object(sphere(c, 0.5), None));
    }
    check(&objects, 2000, 6.0, 9);
    let accel = Accel::build(objects.to_vec());
    let ray = Ray::new(c - DVec3::new(10.0, 0.0, 0.0), DVec3::X);
    let (i, h) = accel.intersect(&ray, f64::INFINITY).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        (i, h),
        brute_intersect(&objects, &ray, f64::INFINITY).unwrap() // invariant: the test's own fixed input (a failure fails the test)
    );
}

#[test]
fn identical_objects_tie_to_lowest_index() {
    // 300 copies of the same sphere spread through the list among other spheres.
    let mut rng = Pcg64::seed_from_u64(10);
    let mut objects = Vec::new();
    for k in 0..3000 {
        if k % 10 == 3 {
            objects.push(object(sphere(DVec3::ZERO, 1.0), None));
        } else {
            objects.push(object(sphere(point_in(&mut rng, 20.0), 0.2), None));
        }
    }
    let accel = Accel::build(objects.to_vec());
    let ray = Ray::new(DVec3::new(0.0, 0.0, -0.5), DVec3::Z);
    assert_eq!(
        accel.intersect(&ray, f64::INFINITY).map(|(i, h)| (i, h.t)),
        Some((3, 1.5))
    );
    check(&objects, 2000, 22.0, 11);
}

#[test]
fn shared_edges_and_vertices_tie_to_lowest_index() {
    // A height field on an integer grid: rays straight down onto vertices and
    // edges hit up to six triangles at the same distance.
    let n = 40;
    let h = |i: i32, j: i32| ((i * 7 + j * 3) % 5) as f64 * 0.25;
    let p = |i: i32, j: i32| DVec3::new(i as f64, j as f64, h(i, j));
    let mut objects = Vec::new();
    for i in 0..n {
        for j in 0..n {
            objects.push(object(
                triangle(p(i, j), p(i + 1, j), p(i + 1, j + 1)),
                None,
            ));
            objects.push(object(
                triangle(p(i, j), p(i + 1, j + 1), p(i, j + 1)),
                None,
            ));
        }
    }
    let accel = Accel::build(objects.to_vec());
    let mut rng = Pcg64::seed_from_u64(12);
    let mut ties = 0;
    for _ in 0..4000 {
        let x = rng.random_range(0..=2 * n) as f64 * 0.5;
        let y = rng.random_range(0..=2 * n) as f64 * 0.5;
        let ray = Ray::new(DVec3::new(x, y, 5.0), DVec3::new(0.0, -0.0, -1.0));
        ties += check_tie(&accel, &objects, &ray) as u32;
        assert_eq!(
            accel.occluded(&ray, 6.0, None),
            brute_occluded(&objects, &ray, 6.0, None)
        );
    }
    assert!(ties > 1000, "only {ties} ties");
    check(&objects, 2000, n as f64, 13);
}

#[test]
fn huge_and_tiny_objects_mixed() {
    // The framework's Cornell box: walls are spheres of radius 1e5; add
    // specks of 1e-5 and ordinary objects.
    let mut rng = Pcg64::seed_from_u64(14);
    let mut objects = Vec::new();
    let r = 1e5;
    for (a, s) in [
        (0, 1.0),
        (0, -1.0),
        (1, 1.0),
        (1, -1.0),
        (2, 1.0),
        (2, -1.0),
    ] {
        let mut c = DVec3::ZERO;
        c[a] = s * (r + 10.0);
        objects.push(object(sphere(c, r), None));
    }
    for k in 0..2000 {
        let c = point_in(&mut rng, 9.0);
        let s = if k % 2 == 0 {
            log_size(&mut rng, 1e-6, 1e-4)
        } else {
            log_size(&mut rng, 0.1, 2.0)
        };
        objects.push(object(sphere(c, s), (k % 11 == 0).then_some(1)));
    }
    // A giant triangle and a huge far sphere.
    objects.push(object(
        triangle(
            DVec3::new(-1e6, -1e6, -9.0),
            DVec3::new(1e6, -1e6, -9.0),
            DVec3::new(0.0, 1e6, -9.0),
        ),
        None,
    ));
    objects.push(object(sphere(DVec3::splat(1e12), 1e11), None));
    check(&objects, 3000, 9.5, 15);
    // Specks are found when aimed at.
    let accel = Accel::build(objects.to_vec());
    for (i, o) in objects.iter().enumerate().skip(6).step_by(2).take(500) {
        let Shape::Sphere(s) = &o.shape else {
            unreachable!() // invariant: the test built every object as a sphere
        };
        let ray = Ray::new(
            DVec3::new(0.5, 0.25, 0.125),
            (s.center - DVec3::new(0.5, 0.25, 0.125)).normalize(),
        );
        let expected = brute_intersect(&objects, &ray, f64::INFINITY);
        assert_eq!(accel.intersect(&ray, f64::INFINITY), expected, "speck {i}");
    }
}

#[test]
fn geometric_progression_builds_a_deep_tree() {
    // Centroids at 2^k: each SAH split peels off a few, so the depth limit's
    // median splits take over.
    let mut objects = Vec::new();
    for k in -120..99 {
        let x = 2f64.powi(k);
        objects.push(object(sphere(DVec3::new(x, 0.0, 0.0), x * 0.25), None));
        objects.push(object(sphere(DVec3::new(0.0, -x, 0.0), x * 0.25), Some(0)));
    }
    let accel = Accel::build(objects.to_vec());
    let mut rng = Pcg64::seed_from_u64(16);
    for (i, o) in objects.iter().enumerate() {
        let Shape::Sphere(s) = &o.shape else {
            unreachable!() // invariant: the test built every object as a sphere
        };
        for _ in 0..4 {
            let from = s.center + unit_vector(&mut rng) * s.radius * 3.0;
            let ray = Ray::new(from, (s.center - from).normalize());
            let expected = brute_intersect(&objects, &ray, f64::INFINITY);
            assert!(expected.is_some());
            assert_eq!(accel.intersect(&ray, f64::INFINITY), expected, "sphere {i}");
            let t = expected.unwrap().1.t; // invariant: the test's own fixed input (a failure fails the test)
            assert_eq!(
                accel.occluded(&ray, t.next_up(), Some(0)),
                brute_occluded(&objects, &ray, t.next_up(), Some(0))
            );
        }
    }
}

#[test]
fn scene_built_in_code_with_area_lights() {
    // Lights' visible surfaces come from Scene::add_light and are skipped by
    // occluded() for their own light only.
    use crate::scene::{Light, LightKind};
    let mut scene = Scene::empty();
    let m = scene.add_material(Default::default());
    let mut rng = Pcg64::seed_from_u64(17);
    for b in 0..500 {
        scene.add_object(
            sphere(point_in(&mut rng, 8.0), log_size(&mut rng, 0.01, 1.0)),
            m,
            b,
        );
    }
    for _ in 0..20 {
        let c = point_in(&mut rng, 8.0);
        if rng.random_bool(0.5) {
            scene.add_light(Light {
                kind: LightKind::Sphere {
                    center: c,
                    radius: 0.5,
                },
                color: DVec3::ONE,
                emission: Default::default(),
            });
        } else {
            scene.add_light(Light {
                kind: LightKind::Square {
                    center: c,
                    dx: DVec3::X * 0.7,
                    dy: DVec3::Y * 0.4,
                },
                color: DVec3::ONE,
                emission: Default::default(),
            });
        }
    }
    check(scene.objects(), 2000, 10.0, 18);
}

#[test]
fn large_scene_built_on_threads_matches_brute_force() {
    // Big enough for several levels of parallel build.
    let mut rng = Pcg64::seed_from_u64(19);
    let objects = mixed_scene(&mut rng, 25_000, 25_000, 2);
    let accel = Accel::build(objects.to_vec());
    let mut hits = 0;
    for n in 0..400 {
        let ray = random_ray(&mut rng, &objects, 14.0);
        let expected = brute_intersect(&objects, &ray, f64::INFINITY);
        hits += expected.is_some() as u32;
        assert_eq!(
            accel.intersect(&ray, f64::INFINITY),
            expected,
            "ray {n}: {ray:?}"
        );
        let t_max = rng.random_range(0.0..3.0);
        assert_eq!(
            accel.occluded(&ray, t_max, Some(3)),
            brute_occluded(&objects, &ray, t_max, Some(3)),
            "ray {n}: {ray:?}"
        );
    }
    assert!(hits > 300);
}

#[test]
fn astronomic_and_nan_objects_are_tested_too() {
    // Bounds beyond f32 range or not finite keep an object out of the tree;
    // it must still be found (or, for NaN, never reported).
    let far = DVec3::new(4e31, 0.0, 0.0);
    let objects = vec![
        object(sphere(DVec3::new(f64::NAN, 0.0, 0.0), 1.0), None),
        object(sphere(DVec3::new(5.0, 3.0, 0.0), 1.0), None),
        object(sphere(far, 1e31), Some(2)),
        object(sphere(DVec3::new(0.0, 0.0, 5.0), f64::INFINITY), None),
        object(sphere(DVec3::new(5.0, -3.0, 0.0), 1.0), None),
    ];
    let accel = Accel::build(objects.to_vec());
    let ray = Ray::new(DVec3::ZERO, DVec3::X);
    let (i, h) = accel.intersect(&ray, f64::INFINITY).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        (i, h),
        brute_intersect(&objects, &ray, f64::INFINITY).unwrap() // invariant: the test's own fixed input (a failure fails the test)
    );
    assert_eq!(i, 2);
    assert!((h.t - 3e31).abs() <= 3e31 * 1e-12);
    assert!(accel.occluded(&ray, f64::INFINITY, None));
    assert!(!accel.occluded(&ray, f64::INFINITY, Some(2)));
    check(&objects, 1000, 10.0, 20);
}

/// Checks the shadow rays of random surface points towards random boxes
/// (area lights' extents, or objects' boxes taken as lights): each ray's
/// answer within the subtrees [`Accel::shadow_reach`] finds is brute
/// force's. Returns how many points were checked, and how many rays were
/// blocked and free.
fn check_shadow_reach(objects: &[Object], points: usize, seed: u64) -> (usize, usize, usize) {
    let accel = Accel::build(objects.to_vec());
    let lit: Vec<&Object> = objects.iter().filter(|o| o.light().is_some()).collect();
    let mut rng = Pcg64::seed_from_u64(seed);
    let (mut checked, mut blocked, mut free) = (0, 0, 0);
    let mut hint = None;
    for n in 0..points {
        let ray = random_ray(&mut rng, objects, 12.0);
        let Some((i, h)) = brute_intersect(objects, &ray, f64::INFINITY) else {
            continue;
        };
        let s = objects[i as usize].shape.surface(&ray, &h);
        let side = if s.normal.dot(ray.dir) < 0.0 {
            s.normal
        } else {
            -s.normal
        };
        let origin = offset_origin(s.point, side);
        // The light: an object's box (that object then its own light's
        // surface, skipped), a small box anywhere, or a flat one.
        let target = if !lit.is_empty() && rng.random_bool(0.5) {
            lit[rng.random_range(0..lit.len())]
        } else {
            &objects[rng.random_range(0..objects.len())]
        };
        let (min, max, ignore) = match (rng.random_range(0..3), target.shape.bounds()) {
            (0, Some(b)) if b.min.is_finite() && b.max.is_finite() => {
                (b.min, b.max, target.light())
            }
            (k, _) => {
                let c = point_in(&mut rng, 12.0);
                let mut half = half_sizes(&mut rng, 0.05, 1.0);
                if k == 2 {
                    half[rng.random_range(0..3usize)] = 0.0;
                }
                (c - half, c + half, None)
            }
        };
        let reach = accel.shadow_reach(origin, min, max, ignore);
        checked += 1;
        for _ in 0..16 {
            let u = DVec3::new(rng.random(), rng.random(), rng.random());
            let q = min + (max - min) * u;
            let to = q - origin;
            let dist = to.length();
            if dist == 0.0 {
                continue;
            }
            let shadow = Ray::off_surface(origin, to * (1.0 / dist));
            let want = objects
                .iter()
                .any(|o| blocks(o, &shadow, shadow.t_min, dist, ignore));
            let got = accel.occluded_within(&shadow, dist, ignore, &reach, &mut hint, &mut ());
            assert_eq!(
                got, want,
                "point {n}: {shadow:?} to {q}, ignoring {ignore:?}"
            );
            assert!(
                hint_left_right(objects, hint, &shadow, dist, ignore, got),
                "point {n}: blocked {got}, hint left {hint:?}"
            );
            if want {
                blocked += 1;
            } else {
                free += 1;
            }
        }
    }
    (checked, blocked, free)
}

#[test]
fn shadow_rays_within_their_hull_match_brute_force() {
    let mut rng = Pcg64::seed_from_u64(41);
    let (mut points, mut blocked, mut free) = (0, 0, 0);
    for n in 0..60 {
        let objects = all_kinds_scene(&mut rng, 1 + n / 3, n % 3);
        let (p, b, f) = check_shadow_reach(&objects, 80, 300 + n as u64);
        points += p;
        blocked += b;
        free += f;
    }
    // A larger scene, whose hulls meet more subtrees than are kept.
    let objects = all_kinds_scene(&mut rng, 120, 1);
    let (p, b, f) = check_shadow_reach(&objects, 600, 42);
    assert!(b > 500 && f > 500, "large scene: {b} blocked, {f} free");
    points += p;
    blocked += b;
    free += f;
    // Rays of both answers were checked, from many points.
    assert!(points > 2500, "{points} points");
    assert!(
        blocked > 2000 && free > 2000,
        "{blocked} blocked, {free} free"
    );
}
