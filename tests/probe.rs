//! `glint probe --json` end to end: the built binary reads a random
//! one-primitive scene of each kind and hundreds of seeded random rays, and
//! its first hits are compared with independent references (closed forms,
//! Cramer's rule, candidate enumeration over faces and caps, and for Bézier
//! surfaces a dense scan of the exact equations with bisection): distance to
//! 1e-6 relative, the normal (turned against the ray) to 1e-6, `front`, the
//! point and the primitive index. Hard cases for every kind: rays from
//! inside, along axes, grazing (tangent rays moved in and out).

mod common;

use common::bezier::Model;
use common::{
    half_sizes, json_field, json_number, json_numbers, json_vec3, log_size, point_in, random_sign,
    rotation, scene_vec, solve_plane,
};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::TAU;
use std::io::Write;
use std::process::{Command, Stdio};

// ---------------------------------------------------------------- running the probe

/// One line of `glint probe --json`.
#[derive(Clone, Copy, Debug)]
struct Answer {
    t: f64,
    point: DVec3,
    normal: DVec3,
    front: bool,
    primitive: Option<u32>,
    uv: (f64, f64),
}

fn parse_answer(line: &str) -> Option<Answer> {
    assert!(line.starts_with('{') && line.ends_with('}'), "{line}");
    match json_field(line, "hit") {
        "false" => {
            assert_eq!(line, "{\"hit\":false}");
            None
        }
        "true" => Some(Answer {
            t: json_number(json_field(line, "t")),
            point: json_vec3(json_field(line, "point")),
            normal: json_vec3(json_field(line, "normal")),
            front: match json_field(line, "front") {
                "true" => true,
                "false" => false,
                f => panic!("front {f}"),
            },
            primitive: match json_field(line, "primitive") {
                "null" => None,
                p => Some(p.parse().unwrap()),
            },
            uv: {
                let v = json_numbers(json_field(line, "uv"), 2);
                (v[0], v[1])
            },
        }),
        h => panic!("hit {h}"),
    }
}

/// Runs `glint probe SCENE --rays - --json` on `rays` (written exactly) and
/// returns its answers, one per ray; `warns` says whether the scene is one
/// glint must warn about (else its standard error must stay empty).
fn probe(scene: &str, rays: &[(DVec3, DVec3)], warns: bool) -> Vec<Option<Answer>> {
    let tmp = tempfile::Builder::new()
        .prefix("glint-probe-test-")
        .tempdir()
        .unwrap();
    let path = tmp.path().join("scene.txt");
    std::fs::write(&path, scene).unwrap();
    let mut input = String::new();
    for (o, d) in rays {
        input += &format!("{} {}\n", scene_vec(*o), scene_vec(*d));
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["probe", path.to_str().unwrap(), "--rays", "-", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "probe failed: {stderr}\n{scene}");
    assert_eq!(
        stderr.contains("warning"),
        warns,
        "standard error: {stderr}\n{scene}"
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let answers: Vec<_> = text.lines().map(parse_answer).collect();
    assert_eq!(answers.len(), rays.len());
    answers
}

// ---------------------------------------------------------------- comparing

/// What the reference says the first hit of a ray is.
#[derive(Clone, Copy, Debug)]
enum Expect {
    Miss,
    /// Distance and the outward normal there (`None` where it is ambiguous:
    /// an edge, a rim, an apex).
    Hit(f64, Option<DVec3>),
    /// The reference cannot decide (a ray on a surface, a tangent ray).
    Skip,
}

/// Counts of what a batch compared, to keep the tests from passing vacuously.
#[derive(Debug, Default)]
struct Tally {
    hits: usize,
    normals: usize,
    misses: usize,
}

/// Compares the probe's answers with the references: t to 1e-6 relative
/// (and at least 1e-9 of the scene's scale), the point on the ray there, the
/// normal facing the ray to 1e-6, `front`, primitive 0.
fn compare(
    what: &str,
    scene: &str,
    rays: &[(DVec3, DVec3)],
    expected: &[Expect],
    scale: f64,
    tally: &mut Tally,
) {
    compare_warned(what, scene, false, rays, expected, scale, tally);
}

/// [`compare`] for a scene that glint warns about (`warns`) or not.
fn compare_warned(
    what: &str,
    scene: &str,
    warns: bool,
    rays: &[(DVec3, DVec3)],
    expected: &[Expect],
    scale: f64,
    tally: &mut Tally,
) {
    let answers = probe(scene, rays, warns);
    for ((&(o, d), e), got) in rays.iter().zip(expected).zip(answers) {
        let context = || format!("{what}: ray {} {}\n{scene}", scene_vec(o), scene_vec(d));
        match (*e, got) {
            (Expect::Skip, _) => {}
            (Expect::Miss, None) => tally.misses += 1,
            (Expect::Miss, Some(a)) => panic!("false hit {a:?}; {}", context()),
            (Expect::Hit(t, _), None) => panic!("missed the hit at t = {t}; {}", context()),
            (Expect::Hit(t, n), Some(a)) => {
                let tol = 1e-6 * t + 1e-9 * scale;
                assert!(
                    (a.t - t).abs() <= tol,
                    "t {} vs reference {t}; {}",
                    a.t,
                    context()
                );
                let p = o + d * t;
                assert!(
                    (a.point - p).length() <= tol,
                    "point {} vs {p}; {}",
                    a.point,
                    context()
                );
                assert_eq!(a.primitive, Some(0), "{}", context());
                assert!((a.normal.length() - 1.0).abs() < 1e-12, "{}", context());
                assert!(
                    a.normal.dot(d) <= 0.0,
                    "normal not against the ray; {}",
                    context()
                );
                if let Some(n) = n {
                    assert_facing_normal(&a, n, d, &context);
                    tally.normals += 1;
                }
                tally.hits += 1;
            }
        }
    }
}

/// Asserts the probe's normal is the outward `n` turned against `d` (to 1e-6) and `front` says which side it hit.
fn assert_facing_normal(a: &Answer, n: DVec3, d: DVec3, context: &dyn Fn() -> String) {
    let front = n.dot(d) < 0.0;
    let facing = if front { n } else { -n };
    assert!(
        (a.normal - facing).length() <= 1e-6,
        "normal {} vs {facing}; {}",
        a.normal,
        context()
    );
    assert_eq!(a.front, front, "front; {}", context());
}

/// The rays `case(k)` makes for k in 0..`count`, and their references.
fn cases<E>(
    count: usize,
    case: impl FnMut(usize) -> ((DVec3, DVec3), E),
) -> (Vec<(DVec3, DVec3)>, Vec<E>) {
    (0..count).map(case).unzip()
}

// ---------------------------------------------------------------- random helpers

fn unit(rng: &mut Pcg64) -> DVec3 {
    loop {
        let v = point_in(rng, 1.0);
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

/// A unit vector perpendicular to unit `d`.
fn perpendicular(rng: &mut Pcg64, d: DVec3) -> DVec3 {
    loop {
        let p = unit(rng).reject_from_normalized(d);
        if p.length() > 0.1 {
            return p.normalize();
        }
    }
}

/// A centre for a scene: mostly near the origin, some far from it.
fn center(rng: &mut Pcg64, n: usize) -> DVec3 {
    if n % 5 == 4 {
        point_in(rng, 5.0) + DVec3::new(300.0, -200.0, 100.0)
    } else {
        point_in(rng, 5.0)
    }
}

/// How far a ray moved off tangency is moved: relative to the object's size.
const GRAZE: [f64; 3] = [1e-3, 1e-5, 1e-7];

/// The smallest root > 0 of t² + 2b·t + c = 0 given through the closest
/// approach: t = −b ± h with h² = `h2` (already free of cancellation).
fn first_root(b: f64, h2: f64) -> Option<f64> {
    if h2 < 0.0 {
        return None;
    }
    let h = h2.sqrt();
    [-b - h, -b + h].into_iter().find(|&t| t > 0.0)
}

// ---------------------------------------------------------------- spheres

#[test]
fn probe_spheres_match_closed_form() {
    let mut rng = Pcg64::seed_from_u64(61);
    let mut tally = Tally::default();
    for n in 0..12 {
        let c = center(&mut rng, n);
        let r = log_size(&mut rng, 0.05, 5.0);
        let scene = format!(
            "primitive sphere\n    O= {}\n    R= {r:?}\nend\n",
            scene_vec(c)
        );
        let scale = c.abs().max_element() + r;
        let (rays, expected) = cases(60, |k| {
            let (o, d) = match k % 5 {
                // From outside, aimed at a point within 1.2 R of the centre.
                0 | 1 => {
                    let o = c + unit(&mut rng) * r * rng.random_range(1.5..10.0);
                    let target = c + unit(&mut rng) * r * rng.random_range(0.0..1.2);
                    (o, (target - o).normalize())
                }
                // From inside, any direction; one in three from the centre.
                2 => {
                    let f = if rng.random_bool(0.3) {
                        0.0
                    } else {
                        rng.random_range(0.0..0.95)
                    };
                    (c + unit(&mut rng) * r * f, unit(&mut rng))
                }
                // Tangent, moved in or out by a small fraction of R.
                _ => {
                    let d = unit(&mut rng);
                    let side = perpendicular(&mut rng, d);
                    let g = GRAZE[rng.random_range(0..3usize)];
                    let rho = r * if k % 5 == 3 { 1.0 - g } else { 1.0 + g };
                    (c + side * rho - d * r * rng.random_range(2.0..10.0), d)
                }
            };
            // The closed form, through the closest approach to the centre.
            let oc = o - c;
            let b = oc.dot(d);
            let perp = oc - d * b;
            let e = match first_root(b, (r - perp.length()) * (r + perp.length())) {
                Some(t) => Expect::Hit(t, Some((o + d * t - c) / r)),
                None => Expect::Miss,
            };
            ((o, d), e)
        });
        compare("sphere", &scene, &rays, &expected, scale, &mut tally);
    }
    assert!(
        tally.hits > 350 && tally.normals == tally.hits && tally.misses > 80,
        "{tally:?}"
    );
}

// ---------------------------------------------------------------- planes

#[test]
fn probe_planes_match_closed_form() {
    let mut rng = Pcg64::seed_from_u64(62);
    let mut tally = Tally::default();
    for n in 0..12 {
        // Some planes along world axes, so that rays can be exactly parallel.
        let axis_aligned = n % 3 == 0;
        let big_n = if axis_aligned {
            DVec3::AXES[n % 9 / 3] * rng.random_range(0.5..3.0)
        } else {
            unit(&mut rng) * rng.random_range(0.5..3.0)
        };
        let offset = rng.random_range(-5.0..5.0);
        let scene = format!(
            "primitive plane\n    N= {}\n    R= {offset:?}\nend\n",
            scene_vec(big_n)
        );
        let nn = big_n.normalize();
        let scale = 10.0;
        let (rays, expected) = cases(50, |k| {
            let o = point_in(&mut rng, 10.0);
            let d = match k % 4 {
                0 | 1 => unit(&mut rng),
                // Grazing: n·d = ±10^-j.
                2 => {
                    let j = rng.random_range(1..9);
                    let s = random_sign(&mut rng);
                    let p = perpendicular(&mut rng, nn);
                    (p + nn * (s * 10f64.powi(-j))).normalize()
                }
                // Parallel: exactly so on the axis-aligned planes.
                _ => {
                    let mut d = unit(&mut rng);
                    if axis_aligned {
                        d[n % 9 / 3] = 0.0;
                    }
                    d.normalize()
                }
            };
            let dist = offset - nn.dot(o);
            let e = if dist.abs() < 1e-9 * scale {
                Expect::Skip
            } else if k % 4 == 3 && axis_aligned {
                Expect::Miss
            } else {
                let t = dist / nn.dot(d);
                if t > 0.0 && t.is_finite() {
                    Expect::Hit(t, Some(nn))
                } else {
                    Expect::Miss
                }
            };
            ((o, d), e)
        });
        compare("plane", &scene, &rays, &expected, scale, &mut tally);
    }
    assert!(tally.hits > 200 && tally.misses > 150, "{tally:?}");
}

// ---------------------------------------------------------------- flat shapes

/// The reference for a flat shape: Cramer's rule for the ray against the
/// plane p0 + β·e1 + γ·e2, `inside` deciding from (β, γ) with a signed
/// margin (negative outside); rays within 1e-7 of the outline, nearly in
/// the plane, or starting on it are skipped.
fn flat_reference(
    o: DVec3,
    d: DVec3,
    p0: DVec3,
    e1: DVec3,
    e2: DVec3,
    margin: impl Fn(f64, f64) -> f64,
    scale: f64,
) -> Expect {
    let n = e1.cross(e2).normalize();
    if d.dot(n).abs() < 1e-9 {
        return Expect::Skip;
    }
    let Some((t, be, ga)) = solve_plane(o, d, p0, e1, e2) else {
        return Expect::Skip;
    };
    let m = margin(be, ga);
    if m.abs() < 1e-7 || t.abs() < 1e-9 * scale {
        Expect::Skip
    } else if m > 0.0 && t > 0.0 {
        Expect::Hit(t, Some(n))
    } else {
        Expect::Miss
    }
}

/// A ray at `target` on a flat shape (unit normal `nn`, size `extent`): grazing when `k` % 4 == 3, else from around it.
fn flat_ray(rng: &mut Pcg64, k: usize, target: DVec3, nn: DVec3, extent: f64) -> (DVec3, DVec3) {
    if k % 4 == 3 {
        // Grazing: nearly in the plane.
        let p = perpendicular(rng, nn);
        let j = rng.random_range(1..7);
        let d = (p + nn * (10f64.powi(-j) * if k % 8 == 3 { 1.0 } else { -1.0 })).normalize();
        (target - d * extent * rng.random_range(0.5..5.0), d)
    } else {
        let o = target + unit(rng) * extent * rng.random_range(0.2..5.0);
        (o, (target - o).normalize())
    }
}

#[test]
fn probe_squares_match_cramer_reference() {
    let mut rng = Pcg64::seed_from_u64(63);
    let mut tally = Tally::default();
    for n in 0..12 {
        let c = center(&mut rng, n);
        let (dx, dy) = loop {
            let dx = unit(&mut rng) * log_size(&mut rng, 0.1, 3.0);
            let dy = unit(&mut rng) * log_size(&mut rng, 0.1, 3.0);
            if dx.cross(dy).length() > 0.1 * dx.length() * dy.length() {
                break (dx, dy);
            }
        };
        let scene = format!(
            "primitive square\n    O= {}\n    Dx= {}\n    Dy= {}\nend\n",
            scene_vec(c),
            scene_vec(dx),
            scene_vec(dy)
        );
        let nn = dx.cross(dy).normalize();
        let extent = dx.length() + dy.length();
        let scale = c.abs().max_element() + extent;
        let (rays, expected) = cases(50, |k| {
            let target = c
                + dx * rng.random_range(-1.3..1.3)
                + dy * rng.random_range(-1.3..1.3)
                + nn * (extent * rng.random_range(-0.1..0.1));
            let (o, d) = flat_ray(&mut rng, k, target, nn, extent);
            // Corner c − Dx − Dy, edges 2·Dx and 2·Dy: inside for β, γ in [0, 1].
            let e = flat_reference(
                o,
                d,
                c - dx - dy,
                dx * 2.0,
                dy * 2.0,
                |be, ga| be.min(ga).min(1.0 - be).min(1.0 - ga),
                scale,
            );
            ((o, d), e)
        });
        compare("square", &scene, &rays, &expected, scale, &mut tally);
    }
    assert!(tally.hits > 200 && tally.misses > 100, "{tally:?}");
}

#[test]
fn probe_triangles_match_cramer_reference() {
    let mut rng = Pcg64::seed_from_u64(64);
    let mut tally = Tally::default();
    for n in 0..12 {
        let c = center(&mut rng, n);
        let s = log_size(&mut rng, 0.1, 3.0);
        let (a, b, cc) = loop {
            let (a, b, cc) = (
                c + unit(&mut rng) * s,
                c + unit(&mut rng) * s,
                c + unit(&mut rng) * s,
            );
            let n = (b - a).cross(cc - a);
            if n.length() > 0.1 * (b - a).length() * (cc - a).length() {
                break (a, b, cc);
            }
        };
        let scene = format!(
            "primitive triangle\n    O1= {}\n    O2= {}\n    O3= {}\nend\n",
            scene_vec(a),
            scene_vec(b),
            scene_vec(cc)
        );
        let nn = (b - a).cross(cc - a).normalize();
        let scale = c.abs().max_element() + s;
        let (rays, expected) = cases(50, |k| {
            let w = [
                rng.random_range(-0.2..1.0),
                rng.random_range(-0.2..1.0),
                rng.random_range(-0.2..1.0f64),
            ];
            let sum = w[0] + w[1] + w[2];
            let target =
                (a * w[0] + b * w[1] + cc * w[2]) / sum + nn * (s * rng.random_range(-0.1..0.1));
            let (o, d) = flat_ray(&mut rng, k, target, nn, s);
            let e = flat_reference(
                o,
                d,
                a,
                b - a,
                cc - a,
                |be, ga| be.min(ga).min(1.0 - be - ga),
                scale,
            );
            ((o, d), e)
        });
        compare("triangle", &scene, &rays, &expected, scale, &mut tally);
    }
    assert!(tally.hits > 150 && tally.misses > 100, "{tally:?}");
}

// ---------------------------------------------------------------- cubes

/// The first hit on a box (centre `c`, orthonormal `axes`, half-lengths
/// `h`) by enumerating the six face rectangles: every plane crossing whose
/// point lies on the face (to 1e-12 relative), nearest t > 0. The normal is
/// given when no other face is within 1e-6 of the hit point.
fn box_reference(c: DVec3, axes: [DVec3; 3], h: DVec3, o: DVec3, d: DVec3, scale: f64) -> Expect {
    let l = DVec3::new(axes[0].dot(o - c), axes[1].dot(o - c), axes[2].dot(o - c));
    let dl = DVec3::new(axes[0].dot(d), axes[1].dot(d), axes[2].dot(d));
    // Origins on the surface (to rounding) are ambiguous.
    if ((l.abs() - h).max_element()).abs() < 1e-9 * scale {
        return Expect::Skip;
    }
    let mut best: Option<(f64, DVec3, DVec3)> = None;
    for i in 0..3 {
        if dl[i] == 0.0 {
            continue;
        }
        for s in [1.0, -1.0] {
            let t = (s * h[i] - l[i]) / dl[i];
            let p = l + dl * t;
            let on_face = (0..3).all(|j| j == i || p[j].abs() <= h[j] * (1.0 + 1e-12));
            if t > 0.0 && on_face && best.is_none_or(|b| t < b.0) {
                best = Some((t, axes[i] * s, p));
            }
        }
    }
    match best {
        None => Expect::Miss,
        Some((t, n, p)) => {
            // Near an edge (two faces): the normal is ambiguous.
            let near_edge = (0..3)
                .filter(|&j| (p[j].abs() - h[j]).abs() <= 1e-6 * h.max_element())
                .count()
                > 1;
            Expect::Hit(t, (!near_edge).then_some(n))
        }
    }
}

#[test]
fn probe_cubes_match_face_enumeration() {
    let mut rng = Pcg64::seed_from_u64(65);
    let mut tally = Tally::default();
    for n in 0..12 {
        let c = center(&mut rng, n);
        let rot = rotation(point_in(&mut rng, 3.2));
        let h = half_sizes(&mut rng, 0.05, 3.0);
        // The file's Dx, Dy: unit and perpendicular (no warning), or on one
        // scene in three scaled and skewed, which glint must orthonormalise
        // keeping Dx's direction (with a warning, allowed there).
        let (fx, fy) = if n % 3 == 2 {
            (rot.col(0) * 2.5, rot.col(1) * 0.5 + rot.col(0) * 0.3)
        } else {
            (rot.col(0), rot.col(1))
        };
        let ux = fx.normalize();
        let uy = (fy - ux * ux.dot(fy)).normalize();
        let axes = [ux, uy, ux.cross(uy)];
        let scene = format!(
            "primitive cube\n    O= {}\n    Dx= {}\n    Dy= {}\n    x= {:?}\n    y= {:?}\n    z= {:?}\nend\n",
            scene_vec(c),
            scene_vec(fx),
            scene_vec(fy),
            h.x,
            h.y,
            h.z
        );
        let scale = c.abs().max_element() + h.length();
        let local = |v: DVec3| axes[0] * v.x + axes[1] * v.y + axes[2] * v.z;
        let (rays, expected) = cases(50, |k| {
            let aim = c + local(point_in(&mut rng, 1.2) * h);
            let (o, d) = match k % 5 {
                0 | 1 => {
                    let o = c + unit(&mut rng) * h.length() * rng.random_range(1.2..6.0);
                    (o, (aim - o).normalize())
                }
                // From inside.
                2 => (c + local(point_in(&mut rng, 0.98) * h), unit(&mut rng)),
                // Exactly along a box axis (parallel to four faces).
                3 => {
                    let i = rng.random_range(0..3usize);
                    let s = random_sign(&mut rng);
                    (aim - axes[i] * (s * h.length() * 3.0), axes[i] * s)
                }
                // Along a face, moved off its plane in or out.
                _ => {
                    let i = rng.random_range(0..3usize);
                    let s = random_sign(&mut rng);
                    let g = GRAZE[rng.random_range(0..3usize)] * random_sign(&mut rng);
                    let mut l = point_in(&mut rng, 0.9) * h;
                    l[i] = s * h[i] * (1.0 + g);
                    let d = perpendicular(&mut rng, axes[i]);
                    let p = c + local(l);
                    (p - d * h.length() * rng.random_range(1.5..4.0), d)
                }
            };
            ((o, d), box_reference(c, axes, h, o, d, scale))
        });
        compare_warned(
            "cube",
            &scene,
            n % 3 == 2,
            &rays,
            &expected,
            scale,
            &mut tally,
        );
    }
    assert!(
        tally.hits > 300 && tally.normals > 250 && tally.misses > 100,
        "{tally:?}"
    );
}

// ---------------------------------------------------------------- cylinders

/// The first hit on a closed cylinder by enumerating candidates: the two
/// roots of the side's quadratic (kept where the height is within the caps)
/// and the two cap planes (kept within the radius); nearest t > 0. The
/// normal is left out within 1e-6 of the rim.
fn cylinder_reference(o1: DVec3, o2: DVec3, r: f64, o: DVec3, d: DVec3, scale: f64) -> Expect {
    let len = (o2 - o1).length();
    let a = (o2 - o1) / len;
    let p = o - o1;
    let (pa, da) = (p.dot(a), d.dot(a));
    let (pp, dp) = (p - a * pa, d - a * da);
    let f = (pp.length() - r).max(-pa).max(pa - len);
    if f.abs() < 1e-9 * scale {
        return Expect::Skip; // starts on the surface
    }
    let mut cands: Vec<(f64, DVec3, bool)> = Vec::new();
    let dd = dp.length_squared();
    // Below 1e-24 the ray is parallel to the axis for these tests' purposes
    // (its distance from the axis changes by under 1e-12 per unit): no side crossing.
    if dd > 1e-24 {
        let ts = -pp.dot(dp) / dd;
        let rho = (pp + dp * ts).length();
        let h2 = (r - rho) * (r + rho);
        if h2 >= 0.0 {
            let h = (h2 / dd).sqrt();
            for t in [ts - h, ts + h] {
                let z = pa + da * t;
                if (0.0..=len).contains(&z) {
                    let n = (pp + dp * t).normalize();
                    let rim = z.min(len - z) < 1e-6 * len;
                    cands.push((t, n, rim));
                }
            }
        }
    }
    if da != 0.0 {
        for (zc, n) in [(0.0, -a), (len, a)] {
            let t = (zc - pa) / da;
            let q = (pp + dp * t).length();
            if q <= r {
                cands.push((t, n, q > r * (1.0 - 1e-6)));
            }
        }
    }
    match cands
        .into_iter()
        .filter(|c| c.0 > 0.0)
        .min_by(|x, y| x.0.total_cmp(&y.0))
    {
        None => Expect::Miss,
        Some((t, n, rim)) => Expect::Hit(t, (!rim).then_some(n)),
    }
}

#[test]
fn probe_cylinders_match_candidate_enumeration() {
    let mut rng = Pcg64::seed_from_u64(66);
    let mut tally = Tally::default();
    for n in 0..12 {
        let o1 = center(&mut rng, n);
        let axis = if n % 4 == 1 {
            DVec3::AXES[n % 3]
        } else {
            unit(&mut rng)
        };
        let o2 = o1 + axis * log_size(&mut rng, 0.1, 5.0);
        let r = log_size(&mut rng, 0.05, 2.0);
        let scene = format!(
            "primitive cylinder\n    O1= {}\n    O2= {}\n    R= {r:?}\nend\n",
            scene_vec(o1),
            scene_vec(o2),
        );
        let len = (o2 - o1).length();
        let a = (o2 - o1).normalize();
        let scale = o1.abs().max_element() + len + r;
        let size_ = len + r;
        let (rays, expected) = cases(60, |k| {
            let u = perpendicular(&mut rng, a);
            let w = a.cross(u);
            let g = GRAZE[rng.random_range(0..3usize)];
            let moved = if rng.random_bool(0.5) {
                1.0 - g
            } else {
                1.0 + g
            };
            let (o, d) = match k % 6 {
                // From outside, aimed near the cylinder.
                0 => {
                    let aim = o1
                        + a * (len * rng.random_range(-0.2..1.2))
                        + u * (r * rng.random_range(0.0..1.2));
                    let o = aim + unit(&mut rng) * size_ * rng.random_range(1.0..6.0);
                    (o, (aim - o).normalize())
                }
                // From inside.
                1 => (
                    o1 + a * (len * rng.random_range(0.02..0.98))
                        + u * (r * rng.random_range(0.0..0.98)),
                    unit(&mut rng),
                ),
                // Exactly along the axis (the direction is the axis itself),
                // from the axis or from R·(1 ± g), before, between or beyond the caps.
                2 => {
                    let rho = if rng.random_bool(0.3) { 0.0 } else { r * moved };
                    let s = random_sign(&mut rng);
                    (
                        o1 + a * (len * rng.random_range(-2.0..3.0)) + u * rho,
                        a * s,
                    )
                }
                // Perpendicular to the axis, through it.
                3 => {
                    let z = len * rng.random_range(-0.2..1.2);
                    (o1 + a * z + u * (size_ * rng.random_range(1.0..5.0)), -u)
                }
                // Tangent to the side (slanted or not), moved in or out.
                4 => {
                    let beta: f64 = if rng.random_bool(0.3) {
                        0.0
                    } else {
                        rng.random_range(-1.0..1.0)
                    };
                    let d = (w * beta.cos() + a * beta.sin()).normalize();
                    let p = o1 + a * (len * rng.random_range(0.3..0.7)) + u * (r * moved);
                    (p - d * size_ * rng.random_range(1.0..5.0), d)
                }
                // Tangent to a rim circle, slanted into or out of the slab, moved in or out.
                _ => {
                    let (cap, out) = if rng.random_bool(0.5) {
                        (o2, a)
                    } else {
                        (o1, -a)
                    };
                    let beta: f64 = rng.random_range(0.15..1.3) * random_sign(&mut rng);
                    let d = (w * beta.cos() - out * beta.sin()).normalize();
                    let p = cap + u * (r * moved);
                    (p - d * size_ * rng.random_range(1.0..5.0), d)
                }
            };
            ((o, d), cylinder_reference(o1, o2, r, o, d, scale))
        });
        compare("cylinder", &scene, &rays, &expected, scale, &mut tally);
    }
    assert!(
        tally.hits > 350 && tally.normals > 300 && tally.misses > 100,
        "{tally:?}"
    );
}

// ---------------------------------------------------------------- Bézier surfaces

/// A random profile of degree 1–8: z sorted (a vase) or not (folds,
/// overhangs), r positive or of either sign, sometimes touching the axis.
fn random_model(rng: &mut Pcg64, n: usize) -> Model {
    let count = rng.random_range(2..=9usize);
    let mut pts: Vec<(f64, f64)> = (0..count)
        .map(|_| (rng.random_range(-3.0..3.0), rng.random_range(-2.5..2.5)))
        .collect();
    if n.is_multiple_of(2) {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    if n % 4 != 3 {
        for p in &mut pts {
            p.1 = p.1.abs();
        }
    }
    if n % 5 == 1 {
        pts[0].1 = 0.0;
    }
    let o1 = center(rng, n);
    let axis = if n % 6 == 5 { DVec3::Z } else { unit(rng) };
    Model::new(o1, o1 + axis * rng.random_range(0.5..3.0), &pts)
}

#[test]
fn probe_bezier_surfaces_match_scan_reference() {
    let mut rng = Pcg64::seed_from_u64(67);
    let (mut hits, mut normals, mut misses, mut ambiguous, mut total) = (0, 0, 0, 0, 0);
    for n in 0..16 {
        let m = random_model(&mut rng, n);
        let mut scene = format!(
            "primitive bezier\n    O1= {}\n    O2= {}\n",
            scene_vec(m.o1),
            scene_vec(m.o2)
        );
        for (z, r) in m.z.iter().zip(&m.r) {
            scene += &format!("    P= {z:?} {r:?}\n");
        }
        if n % 2 == 1 {
            scene += "    Cylinder\n";
        }
        scene += "end\n";
        let mid = m.o1 + m.a * 0.5 * (m.z[0] + m.z[m.z.len() - 1]);
        let mut rays = Vec::new();
        for k in 0..50 {
            let s = rng.random_range(0.0..1.0);
            let phi = rng.random_range(0.0..TAU);
            let target = m.point(s, phi)
                + if k % 3 == 0 {
                    unit(&mut rng) * (0.3 * m.scale * rng.random::<f64>())
                } else {
                    DVec3::ZERO
                };
            let ray = match k % 5 {
                // From all around, aimed at the surface (or near it).
                0 | 1 => {
                    let o = mid + unit(&mut rng) * m.scale * rng.random_range(1.5..5.0);
                    (o, (target - o).normalize())
                }
                // From near the middle, inside or not, any direction.
                2 => (
                    mid + unit(&mut rng) * m.scale * rng.random_range(0.0..1.0),
                    unit(&mut rng),
                ),
                // Perpendicular to the axis, or nearly: da = ±10^-j or 0.
                3 => {
                    let j = rng.random_range(0..18);
                    let eps = if j == 17 { 0.0 } else { 10f64.powi(-j) };
                    let perp = perpendicular(&mut rng, m.a);
                    let d = (perp + m.a * (eps * random_sign(&mut rng))).normalize();
                    (target - d * m.scale * rng.random_range(0.2..4.0), d)
                }
                // Along the axis.
                _ => {
                    let d = m.a * random_sign(&mut rng);
                    (target - d * m.scale * rng.random_range(0.2..4.0), d)
                }
            };
            rays.push(ray);
        }
        let answers = probe(&scene, &rays, false);
        for (&(o, d), got) in rays.iter().zip(answers) {
            total += 1;
            let span = m.scale + (o - m.o1).length();
            let tol = |t: f64| 1e-6 * t + 1e-9 * span;
            let refs = m.scan(o, d, 4000);
            if refs.iter().any(|h| h.t.abs() <= 1e-9 * span) {
                continue; // starts on the surface
            }
            let clear = |h: &common::bezier::RefHit| {
                h.cos > common::bezier::GRAZING && h.s > 1e-6 && h.s < 1.0 - 1e-6
            };
            let ahead: Vec<_> = refs.iter().copied().filter(|h| h.t > 0.0).collect();
            let nearest_clear = ahead
                .iter()
                .filter(|h| clear(h))
                .min_by(|x, y| x.t.total_cmp(&y.t));
            let context = || format!("bezier: ray {} {}\n{scene}", scene_vec(o), scene_vec(d));
            let Some(a) = got else {
                assert!(
                    nearest_clear.is_none(),
                    "missed the hit at t = {:?}; {}",
                    nearest_clear,
                    context()
                );
                misses += (ahead.is_empty()) as usize;
                continue;
            };
            // Wherever it is, the hit lies on the surface circle of its s = u.
            assert!((0.0..=1.0).contains(&a.uv.0), "{}", context());
            assert!(
                m.residual(a.uv.0, a.point) <= 1e-9 * span,
                "hit off the surface by {:e}; {}",
                m.residual(a.uv.0, a.point),
                context()
            );
            assert!(
                (a.point - (o + d * a.t)).length() <= tol(a.t),
                "{}",
                context()
            );
            assert_eq!(a.primitive, Some(0), "{}", context());
            match nearest_clear {
                Some(c) if (a.t - c.t).abs() <= tol(c.t) => {
                    let p = o + d * c.t;
                    let (dz, dr) = m.dzr(c.s);
                    if m.axial(p).1 > 1e-6 * m.scale && dz.hypot(dr) > 1e-6 * m.scale {
                        assert_facing_normal(&a, m.normal(c.s, p), d, &context);
                        normals += 1;
                    }
                    hits += 1;
                }
                Some(c) if a.t > c.t => panic!(
                    "hit at t = {} beyond the nearer clear hit t = {} s = {}; {}",
                    a.t,
                    c.t,
                    c.s,
                    context()
                ),
                // Nearer than any clear hit: a grazing or rim hit, or a
                // near-tangent pair of roots closer than the scan's step.
                _ => ambiguous += 1,
            }
        }
    }
    assert!(
        hits > 350 && normals > 300 && misses > 50 && ambiguous * 50 <= total,
        "{hits} hits, {normals} normals, {misses} misses, {ambiguous} ambiguous of {total}"
    );
}

// ---------------------------------------------------------------- a box of six squares

/// The probe on a closed box of six `square` blocks: rays from inside
/// through edges and corners (or a hair beside them) always report a hit,
/// where the ray crosses the edge, on one of the six.
#[test]
fn probe_box_of_squares_from_inside_through_edges_and_corners() {
    let mut rng = Pcg64::seed_from_u64(68);
    for (c, rot, h) in [
        (
            DVec3::new(1.5, 6.2, -0.3),
            glam::DMat3::IDENTITY,
            DVec3::new(0.5, 0.7, 0.9),
        ),
        (
            DVec3::new(0.1, -0.3, 0.7),
            rotation(DVec3::new(0.3, -1.1, 2.0)),
            DVec3::new(0.3, 1.7, 0.05),
        ),
    ] {
        let scene = common::box_of_squares_text(c, rot, h);
        let scale = c.abs().max_element() + h.max_element();
        let (rays, dists) = cases(400, |m| {
            let i = rng.random_range(0..3usize);
            let j = (i + 1 + rng.random_range(0..2usize)) % 3;
            let si = random_sign(&mut rng);
            let sj = random_sign(&mut rng);
            let lambda = if m % 3 == 0 {
                si * sj
            } else {
                rng.random_range(-1.0..1.0)
            };
            let mut target = common::box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
            if m % 4 == 3 {
                target -= rot.col(i)
                    * (si * h.max_element() * 10f64.powf(rng.random_range(-16.0..-10.0)));
            }
            let inside = c + rot * (point_in(&mut rng, 0.99) * h);
            (
                (inside, (target - inside).normalize()),
                (target - inside).length(),
            )
        });
        let answers = probe(&scene, &rays, false);
        for ((&(o, d), dist), a) in rays.iter().zip(dists).zip(answers) {
            let a = a.unwrap_or_else(|| {
                panic!("light leak: ray {} {} missed", scene_vec(o), scene_vec(d))
            });
            assert!((a.t - dist).abs() <= 1e-9 * scale, "t {} vs {dist}", a.t);
            assert!(a.primitive.is_some_and(|p| p < 6));
        }
    }
}
