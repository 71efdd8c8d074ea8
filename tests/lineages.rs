//! The lineages' own primitives through `glint probe --json`, against
//! references written here: the ray–plane closed form with both range tests
//! for `rectangle`; the OBJ text placed by hand (degree rotations built from
//! sines and cosines, fan triangulation) and Möller–Trumbore for
//! `polyhedron`; a fine scan of the implicit surface of V's degree-6 profile
//! with bisection for `Bezier`. Thousands of seeded random rays each; rays
//! the reference cannot decide (near an edge, grazing) are skipped and
//! counted, and each test checks that most rays were decided.

mod common;

use common::{json_field, json_number, json_numbers, json_vec3, scene_vec};
use glam::{DVec2, DVec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::{PI, TAU};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// One hit as the probe prints it.
#[derive(Clone, Copy, Debug)]
struct Answer {
    t: f64,
    normal: DVec3,
    front: bool,
    uv: DVec2,
}

/// A fresh temporary folder for one test's files, removed when dropped (a
/// failing test's too).
fn temp_dir(what: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("glint-lineages-{what}-"))
        .tempdir()
        .unwrap()
}

/// Runs `glint probe SCENE --rays - --json` in `dir` on unit-direction
/// `rays`; its standard error must hold no warning.
fn probe(dir: &Path, scene: &str, rays: &[(DVec3, DVec3)]) -> Vec<Option<Answer>> {
    let path = dir.join("scene.txt");
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
    assert!(!stderr.contains("warning"), "{stderr}\n{scene}");
    let text = String::from_utf8(out.stdout).unwrap();
    let answers: Vec<_> = text
        .lines()
        .map(|line| match json_field(line, "hit") {
            "false" => None,
            _ => Some(Answer {
                t: json_number(json_field(line, "t")),
                normal: json_vec3(json_field(line, "normal")),
                front: json_field(line, "front") == "true",
                uv: {
                    let v = json_numbers(json_field(line, "uv"), 2);
                    DVec2::new(v[0], v[1])
                },
            }),
        })
        .collect();
    assert_eq!(answers.len(), rays.len());
    answers
}

/// What a reference says about one ray.
#[derive(Clone, Copy, Debug)]
enum Expect {
    Miss,
    /// Distance, outward normal, texture coordinates (`None`: not checked).
    Hit(f64, DVec3, Option<DVec2>),
    /// Undecidable here (within a tolerance of an edge, grazing).
    Skip,
}

/// Compares answers with references: t to `tol` relative (plus 1e-12), the
/// normal turned against the ray to `tol`, `front`, the texture coordinates
/// to 1e-7 (v modulo 1 when `wrap_v`). Returns (hits, misses) checked.
fn compare(
    what: &str,
    tol: f64,
    rays: &[(DVec3, DVec3)],
    expected: &[Expect],
    got: &[Option<Answer>],
    wrap_v: bool,
) -> (usize, usize) {
    let (mut hits, mut misses) = (0, 0);
    for ((&(o, d), e), a) in rays.iter().zip(expected).zip(got) {
        let ray = format!("{what}: ray {} {}", scene_vec(o), scene_vec(d));
        match (*e, a) {
            (Expect::Skip, _) => {}
            (Expect::Miss, None) => misses += 1,
            (Expect::Miss, Some(a)) => panic!("false hit {a:?}; {ray}"),
            (Expect::Hit(t, _, _), None) => panic!("missed the hit at t = {t}; {ray}"),
            (Expect::Hit(t, n, uv), Some(a)) => {
                assert!(
                    (a.t - t).abs() <= tol * t + 1e-12,
                    "t {} vs {t}; {ray}",
                    a.t
                );
                let front = n.dot(d) < 0.0;
                let facing = if front { n } else { -n };
                assert!(
                    (a.normal - facing).length() < tol,
                    "normal {} vs {facing}; {ray}",
                    a.normal
                );
                assert_eq!(a.front, front, "{ray}");
                if let Some(uv) = uv {
                    let dv = a.uv.y - uv.y;
                    let dv = if wrap_v { dv - dv.round() } else { dv };
                    assert!(
                        (a.uv.x - uv.x).abs() < 1e-7 && dv.abs() < 1e-7,
                        "uv {} vs {uv}; {ray}",
                        a.uv
                    );
                }
                hits += 1;
            }
        }
    }
    (hits, misses)
}

/// A uniformly random unit vector.
fn unit(rng: &mut Pcg64) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

/// A ray from a random point in a ball of radius `spread` around `from`
/// through a random point in a ball of radius `aim` around `target`.
fn ray_towards(
    rng: &mut Pcg64,
    from: DVec3,
    spread: f64,
    target: DVec3,
    aim: f64,
) -> (DVec3, DVec3) {
    let o = from + unit(rng) * spread * rng.random::<f64>().cbrt();
    let p = target + unit(rng) * aim * rng.random::<f64>().cbrt();
    (o, (p - o).normalize())
}

// ---------------------------------------------------------------- rectangle

/// `primitive rectangle N= R= Dx= Dy=` against the closed form: t from the
/// plane N̂·C = R, then a = C·Dx/|Dx|², b = C·Dy/|Dy|² both in [0, 1]
/// (rays within 1e-7 of a range end skipped); uv = (a, b); normal N̂.
#[test]
fn rectangle_matches_the_plane_and_its_two_ranges() {
    let mut rng = Pcg64::seed_from_u64(1601);
    let tmp = temp_dir("rectangle");
    let dir = tmp.path();
    let (mut hits, mut misses, mut total) = (0, 0, 0);
    for case in 0..8 {
        let n = unit(&mut rng) * rng.random_range(0.5..3.0);
        let nh = n.normalize();
        let r = rng.random_range(-3.0..3.0);
        // Dx, Dy: random, sometimes in the plane, sometimes not.
        let mut dx = unit(&mut rng) * rng.random_range(0.5..4.0);
        let mut dy = unit(&mut rng) * rng.random_range(0.5..4.0);
        if case % 2 == 0 {
            dx -= nh * dx.dot(nh);
            dy -= nh * dy.dot(nh);
        }
        if nh.dot(dx.cross(dy)).abs() < 0.2 * dx.length() * dy.length() {
            continue;
        }
        let scene = format!(
            "primitive rectangle\n N= {}\n R= {r:?}\n Dx= {}\n Dy= {}\n color= 1 1 1\n diff= 1\nend\n",
            scene_vec(n),
            scene_vec(dx),
            scene_vec(dy)
        );
        // The region's centre, solved independently: C·N̂ = R, C·Dx = |Dx|²/2, C·Dy = |Dy|²/2.
        let m = glam::DMat3::from_cols(nh, dx, dy).transpose();
        let centre =
            m.inverse() * DVec3::new(r, dx.length_squared() / 2.0, dy.length_squared() / 2.0);
        let size = (dx.length() + dy.length()) * 2.0;
        // Aimed at points with (a, b) in [−0.3, 1.3]²: about 40 % inside.
        let rays: Vec<_> = (0..500)
            .map(|_| {
                let (a, b) = (rng.random_range(-0.3..1.3), rng.random_range(-0.3..1.3));
                let target =
                    m.inverse() * DVec3::new(r, a * dx.length_squared(), b * dy.length_squared());
                ray_towards(&mut rng, centre, 4.0 * size, target, 0.0)
            })
            .collect();
        let expected: Vec<Expect> = rays
            .iter()
            .map(|&(o, d)| {
                let denom = nh.dot(d);
                if denom.abs() < 1e-6 {
                    return Expect::Skip;
                }
                let t = (r - nh.dot(o)) / denom;
                if t.abs() < 1e-9 {
                    return Expect::Skip;
                }
                if t < 0.0 {
                    return Expect::Miss;
                }
                let c = o + d * t;
                let a = c.dot(dx) / dx.length_squared();
                let b = c.dot(dy) / dy.length_squared();
                let near_end = |x: f64| x.abs() < 1e-7 || (x - 1.0).abs() < 1e-7;
                if near_end(a) || near_end(b) {
                    Expect::Skip
                } else if (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b) {
                    Expect::Hit(t, nh, Some(DVec2::new(a, b)))
                } else {
                    Expect::Miss
                }
            })
            .collect();
        let got = probe(dir, &scene, &rays);
        let (h, m) = compare("rectangle", 1e-9, &rays, &expected, &got, false);
        hits += h;
        misses += m;
        total += rays.len();
    }
    eprintln!("rectangle: {hits} hits, {misses} misses of {total} rays");
    assert!(
        hits > total / 5 && misses > total / 5,
        "{hits} hits, {misses} misses of {total}"
    );
}

// ---------------------------------------------------------------- polyhedron

/// A small OBJ file: a quad, a pentagon and a triangle (fans of 2, 3 and 1
/// triangles), texture coordinates on all, vertex normals on the triangle.
/// Coordinates are multiples of 1/8 (exact in the f32 OBJ reader).
const OBJ: &str = "\
# test mesh
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0.5
v 3 0 0.5
v 3.5 1 0.75
v 2.5 2 1
v 1.75 1.25 0.5
v -1 0 1
v -1 1 1.5
v -2 0.5 1.25
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.25
vt 0.75 0.5
vt 0.125 0.875
vn 0 0 1
vn 0.5 0.25 1
vn 1 1 1
f 1/1 2/2 3/3 4/4
f 5/1 6/2 7/3 8/4 9/5
f 10/5/1 11/6/2 12/7/3
";

/// The OBJ text's triangles as the lineages spec places them, computed
/// here: R_z·R_y·R_x from the degrees' sines and cosines, then size ⊙, then
/// + O; fans (0, k − 1, k); with each corner's `vt` as (v, u).
fn placed_triangles(o: DVec3, size: DVec3, degrees: DVec3) -> Vec<([DVec3; 3], [DVec2; 3])> {
    let (mut v, mut vt) = (Vec::new(), Vec::new());
    let mut faces: Vec<Vec<(usize, usize)>> = Vec::new();
    for line in OBJ.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| w[i].parse::<f64>().unwrap();
        match w.first() {
            Some(&"v") => v.push(DVec3::new(num(1), num(2), num(3))),
            Some(&"vt") => vt.push(DVec2::new(num(2), num(1))),
            Some(&"f") => faces.push(
                w[1..]
                    .iter()
                    .map(|c| {
                        let mut p = c.split('/');
                        let i = p.next().unwrap().parse::<usize>().unwrap() - 1;
                        let t = p.next().unwrap().parse::<usize>().unwrap() - 1;
                        (i, t)
                    })
                    .collect(),
            ),
            _ => {}
        }
    }
    let rad = degrees * (PI / 180.0);
    let rx = |p: DVec3| {
        let (s, c) = rad.x.sin_cos();
        DVec3::new(p.x, c * p.y - s * p.z, s * p.y + c * p.z)
    };
    let ry = |p: DVec3| {
        let (s, c) = rad.y.sin_cos();
        DVec3::new(c * p.x + s * p.z, p.y, -s * p.x + c * p.z)
    };
    let rz = |p: DVec3| {
        let (s, c) = rad.z.sin_cos();
        DVec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z)
    };
    let place = |p: DVec3| o + size * rz(ry(rx(p)));
    let mut out = Vec::new();
    for f in &faces {
        for k in 2..f.len() {
            let c = [f[0], f[k - 1], f[k]];
            out.push((c.map(|(i, _)| place(v[i])), c.map(|(_, t)| vt[t])));
        }
    }
    out
}

/// Möller–Trumbore: (t, β, γ) of the ray and triangle, two-sided.
fn ray_triangle(o: DVec3, d: DVec3, p: &[DVec3; 3]) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - p[0];
    let beta = s.dot(h) / det;
    let q = s.cross(e1);
    let gamma = d.dot(q) / det;
    Some((e2.dot(q) / det, beta, gamma))
}

/// `primitive polyhedron mesh= O= size= angles=` against the placed OBJ
/// triangles: nearest t, the flat normal of the triangle hit (up to sign:
/// the probe turns it against the ray; `front` is not compared, as the
/// winding may be flipped to agree with `vn`), and the interpolated `vt`.
#[test]
fn polyhedron_matches_the_placed_obj_triangles() {
    let mut rng = Pcg64::seed_from_u64(1602);
    let tmp = temp_dir("polyhedron");
    let dir = tmp.path();
    std::fs::write(dir.join("m.obj"), OBJ).unwrap();
    let (mut hits, mut misses, mut total) = (0, 0, 0);
    for _ in 0..8 {
        let o = DVec3::new(
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
        );
        let size = DVec3::new(
            rng.random_range(0.5..3.0),
            rng.random_range(0.5..3.0),
            rng.random_range(0.5..3.0),
        );
        let degrees = DVec3::new(
            rng.random_range(-180.0..180.0),
            rng.random_range(-180.0..180.0),
            rng.random_range(-180.0..180.0),
        );
        let scene = format!(
            "primitive polyhedron\n mesh= m.obj\n O= {}\n size= {}\n angles= {}\n color= 1 1 1\n diff= 1\nend\n",
            scene_vec(o),
            scene_vec(size),
            scene_vec(degrees)
        );
        let tris = placed_triangles(o, size, degrees);
        let centre =
            tris.iter().flat_map(|(p, _)| p.iter()).sum::<DVec3>() / (3 * tris.len()) as f64;
        let extent = 4.0 * size.max_element();
        // Aimed near a random point of a random triangle.
        let rays: Vec<_> = (0..500)
            .map(|_| {
                let (p, _) = &tris[rng.random_range(0..tris.len())];
                let (b, g) = (rng.random::<f64>(), rng.random::<f64>());
                let (b, g) = if b + g > 1.0 {
                    (1.0 - b, 1.0 - g)
                } else {
                    (b, g)
                };
                let target = p[0] + (p[1] - p[0]) * b + (p[2] - p[0]) * g;
                ray_towards(
                    &mut rng,
                    centre,
                    3.0 * extent,
                    target,
                    0.3 * size.min_element(),
                )
            })
            .collect();
        let expected: Vec<Expect> = rays
            .iter()
            .map(|&(o, d)| {
                let mut best: Option<(f64, usize, f64, f64)> = None;
                let mut unsure = false;
                for (k, (p, _)) in tris.iter().enumerate() {
                    let Some((t, b, g)) = ray_triangle(o, d, p) else {
                        continue;
                    };
                    let margin = 1e-7;
                    let inside = b > margin && g > margin && b + g < 1.0 - margin;
                    let outside = b < -margin || g < -margin || b + g > 1.0 + margin;
                    if t <= 1e-9 || outside {
                        continue;
                    }
                    if !inside {
                        unsure = true;
                        continue;
                    }
                    if best.is_none_or(|(bt, ..)| t < bt) {
                        best = Some((t, k, b, g));
                    }
                }
                match best {
                    _ if unsure => Expect::Skip,
                    None => Expect::Miss,
                    Some((t, k, b, g)) => {
                        let (p, uv) = &tris[k];
                        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                        let uv = uv[0] * (1.0 - b - g) + uv[1] * b + uv[2] * g;
                        // The probe's normal faces the ray; compare it so.
                        let n = if n.dot(d) < 0.0 { n } else { -n };
                        Expect::Hit(t, n, Some(uv))
                    }
                }
            })
            .collect();
        let got = probe(dir, &scene, &rays);
        // `front` depends on the winding glint keeps; align it with the answer.
        let got: Vec<_> = got
            .into_iter()
            .map(|a| a.map(|a| Answer { front: true, ..a }))
            .collect();
        let (h, m) = compare("polyhedron", 1e-9, &rays, &expected, &got, false);
        hits += h;
        misses += m;
        total += rays.len();
    }
    eprintln!("polyhedron: {hits} hits, {misses} misses of {total} rays");
    assert!(
        hits > total / 2 && misses > total / 10,
        "{hits} hits, {misses} misses of {total}"
    );
}

// ---------------------------------------------------------------- V's Bezier

/// V's profile control points (x, y), before `ratio=`.
const V_POINTS: [(f64, f64); 7] = [
    (1.5, 0.0),
    (2.9, 13.0),
    (-3.5, 15.0),
    (-5.5, 21.0),
    (-1.1, 22.5),
    (-5.5, 25.0),
    (0.0, 38.0),
];

/// The degree-6 Bernstein sum of `c` at `t` (written out, binomials 1 6 15 20 15 6 1).
fn bernstein6(c: [f64; 7], t: f64) -> f64 {
    const BINOM: [f64; 7] = [1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0];
    (0..7)
        .map(|k| BINOM[k] * t.powi(k as i32) * (1.0 - t).powi(6 - k as i32) * c[k])
        .sum()
}

/// V's `Bezier` at `O= R= ratio=` as an implicit surface: the profile's
/// height y(t) rises monotonically (its control heights do), so a point at
/// height z inside the band meets the profile at one t, and the surface is
/// where its distance from the axis equals R + ratio·x(t).
struct Vase {
    o: DVec3,
    r: f64,
    ratio: f64,
}

impl Vase {
    fn x(&self, t: f64) -> f64 {
        bernstein6(V_POINTS.map(|p| p.0), t)
    }

    fn y(&self, t: f64) -> f64 {
        bernstein6(V_POINTS.map(|p| p.1), t)
    }

    /// The profile parameter at world height `z`, if inside the band.
    fn t_at(&self, z: f64) -> Option<f64> {
        // z = O_z + 38·ratio − ratio·y(t).
        let y = (self.o.z + 38.0 * self.ratio - z) / self.ratio;
        if !(0.0..=38.0).contains(&y) {
            return None;
        }
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.y(mid) < y {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }

    /// Distance from the axis minus the profile's radius at that height.
    fn g(&self, p: DVec3) -> Option<f64> {
        let t = self.t_at(p.z)?;
        let rho = (p.x - self.o.x).hypot(p.y - self.o.y);
        Some(rho - (self.r + self.ratio * self.x(t)))
    }

    /// The first root along the ray by a scan of `n` steps over [0, far]
    /// and bisection; `Skip` when the ray grazes the surface first (|g|
    /// has a local minimum below 1e-3 of the size without a sign change),
    /// when it enters or leaves the band near a rim, or when the root is
    /// within 1e-6 of an end of the profile.
    fn first_hit(&self, o: DVec3, d: DVec3, far: f64, n: usize) -> Expect {
        let step = far / n as f64;
        let near = 1e-3 * (self.r + 6.0 * self.ratio);
        // The last two samples (None: outside the band).
        let (mut before, mut prev): (Option<f64>, Option<f64>) = (None, None);
        for k in 0..=n {
            let s = k as f64 * step;
            let g = self.g(o + d * s);
            if let (Some(g0), Some(g1)) = (prev, g) {
                if (g0 < 0.0) != (g1 < 0.0) {
                    return self.root(o, d, s - step, s, g0);
                }
                if let Some(gb) = before
                    && g0.abs() < near
                    && g0.abs() <= gb.abs()
                    && g0.abs() <= g1.abs()
                {
                    return Expect::Skip;
                }
            }
            if k > 0 && prev.is_some() != g.is_some() && self.near_rims(o, d, s - step, s) {
                return Expect::Skip;
            }
            (before, prev) = (prev, g);
        }
        Expect::Miss
    }

    /// The root of g in [a, b] (g(a) has the sign of `g0`), by bisection.
    fn root(&self, o: DVec3, d: DVec3, mut a: f64, mut b: f64, g0: f64) -> Expect {
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            match self.g(o + d * m) {
                Some(gm) if (gm < 0.0) == (g0 < 0.0) => a = m,
                Some(_) => b = m,
                None => return Expect::Skip,
            }
        }
        let t = 0.5 * (a + b);
        let p = o + d * t;
        let u = self.t_at(p.z).unwrap_or(f64::NAN);
        if !(1e-6..=1.0 - 1e-6).contains(&u) || t < 1e-6 {
            return Expect::Skip;
        }
        let v = (p.y - self.o.y).atan2(p.x - self.o.x).rem_euclid(TAU) / TAU;
        Expect::Hit(t, self.normal(p, u), Some(DVec2::new(u, v)))
    }

    /// Whether the ray's segment [s0, s1] passes near either rim circle.
    fn near_rims(&self, o: DVec3, d: DVec3, s0: f64, s1: f64) -> bool {
        let tol = 0.05 * (self.r + self.ratio);
        let rim = |t: f64| {
            let z = self.o.z + 38.0 * self.ratio - self.ratio * self.y(t);
            (z, self.r + self.ratio * self.x(t))
        };
        [rim(0.0), rim(1.0)].iter().any(|&(z, rho)| {
            (0..=100).any(|k| {
                let p = o + d * (s0 + (s1 - s0) * k as f64 / 100.0);
                let radial = (p.x - self.o.x).hypot(p.y - self.o.y) - rho;
                radial.abs() < tol && (p.z - z).abs() < tol
            })
        })
    }

    /// The outward normal at `p` (profile parameter `u`): the profile's
    /// tangent (ρ′, z′) in the (radius, height) half-plane turned to
    /// (z′, −ρ′), up to sign.
    fn normal(&self, p: DVec3, u: f64) -> DVec3 {
        let drho = self.ratio * bernstein6_derivative(V_POINTS.map(|p| p.0), u);
        let dz = -self.ratio * bernstein6_derivative(V_POINTS.map(|p| p.1), u);
        let radial = DVec3::new(p.x - self.o.x, p.y - self.o.y, 0.0).normalize();
        (radial * dz - DVec3::Z * drho).normalize()
    }
}

/// The derivative of [`bernstein6`]: 6·Σ (c_{k+1} − c_k)·B_{k,5}(t).
fn bernstein6_derivative(c: [f64; 7], t: f64) -> f64 {
    const BINOM: [f64; 6] = [1.0, 5.0, 10.0, 10.0, 5.0, 1.0];
    (0..6)
        .map(|k| {
            6.0 * BINOM[k] * t.powi(k as i32) * (1.0 - t).powi(5 - k as i32) * (c[k + 1] - c[k])
        })
        .sum()
}

/// `primitive Bezier O= R= ratio=` against the scanned implicit surface:
/// first hit distance, normal up to orientation (the probe's faces the
/// ray), u = t and v = θ/2π counter-clockwise about +z from +x; the open
/// ends let rays through.
#[test]
fn v_bezier_matches_a_scan_of_its_profile() {
    let mut rng = Pcg64::seed_from_u64(1603);
    let tmp = temp_dir("vase");
    let dir = tmp.path();
    let (mut hits, mut misses, mut total) = (0, 0, 0);
    for _ in 0..4 {
        let vase = Vase {
            o: DVec3::new(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            ),
            r: rng.random_range(0.1..0.4),
            ratio: rng.random_range(0.01..0.05),
        };
        let scene = format!(
            "primitive Bezier\n O= {}\n R= {:?}\n ratio= {:?}\n color= 1 1 1\n diff= 1\nend\n",
            scene_vec(vase.o),
            vase.r,
            vase.ratio
        );
        let height = 38.0 * vase.ratio;
        let centre = vase.o + DVec3::Z * (height / 2.0);
        let size = height + vase.r;
        // Aimed near a random point of the surface.
        let rays: Vec<_> = (0..500)
            .map(|_| {
                let (t, th) = (rng.random::<f64>(), rng.random_range(0.0..TAU));
                let rho = vase.r + vase.ratio * vase.x(t);
                let z = vase.o.z + height - vase.ratio * vase.y(t);
                let target = DVec3::new(vase.o.x + rho * th.cos(), vase.o.y + rho * th.sin(), z);
                ray_towards(&mut rng, centre, 3.0 * size, target, 0.2 * vase.r)
            })
            .collect();
        let far = 8.0 * size;
        let expected: Vec<Expect> = rays
            .iter()
            .map(|&(o, d)| match vase.first_hit(o, d, far, 20_000) {
                // The probe's normal faces the ray: orient the reference so.
                Expect::Hit(t, n, uv) => Expect::Hit(t, if n.dot(d) < 0.0 { n } else { -n }, uv),
                e => e,
            })
            .collect();
        let got = probe(dir, &scene, &rays);
        let got: Vec<_> = got
            .into_iter()
            .map(|a| a.map(|a| Answer { front: true, ..a }))
            .collect();
        // 1e-6: the exact bezier's contract in tests/probe.rs (its roots are
        // polished Bernstein roots); the scan's are exact to rounding.
        let (h, m) = compare("Bezier", 1e-6, &rays, &expected, &got, true);
        hits += h;
        misses += m;
        total += rays.len();
    }
    eprintln!("Bezier: {hits} hits, {misses} misses of {total} rays");
    assert!(
        hits > total / 2 && misses > total / 10,
        "{hits} hits, {misses} misses of {total}"
    );
}

// ---------------------------------------------------------------- normal maps, rendered

/// A `NomalPlane` facing the camera under a point light, its normal map one
/// colour: the file is V's (§5 rule 4), so the centre pixel is V's
/// diff·(L·N′)/d² (§3.2, black background) with N′ worked out by hand. The
/// plane N = −ŷ is vertical, so its frame is the spec's fix: red
/// unit(N × ẑ) = −x̂, green N × red = −ẑ; texel bytes (64, 200, 230) give
/// n = 2·b/255 − 1 and N′ = unit(n_b·N − n_r·x̂ − n_g·ẑ). Without the map the
/// pixel would be L·N = 1/√2.
#[test]
fn normal_mapped_plane_shades_with_the_perturbed_normal() {
    let tmp = temp_dir("render");
    let dir = tmp.path();
    let bytes = [64u8, 200, 230];
    image::RgbImage::from_pixel(2, 2, image::Rgb(bytes))
        .save(dir.join("n.bmp"))
        .unwrap();
    let text = "camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
                light point\n O= 0 0 5\n color= 1 1 1\nend\n\
                primitive NomalPlane\n N= 0 -1 0\n R= -5\n color= 1 1 1\n diff= 1\n NT= n.bmp\nend\n";
    let scene = glint::Scene::parse(text, dir).unwrap();
    let renderer = glint::Renderer::new(scene);
    // Photons off: the ray-traced formula (V's default algorithm is SPPM).
    let options = glint::RenderOptions {
        spp: Some(1),
        photons: glint::PhotonOptions {
            mode: Some(glint::PhotonMode::Off),
            ..glint::PhotonOptions::default()
        },
        ..glint::RenderOptions::default()
    };
    let image = renderer.render(&options).unwrap().into_image();
    let n = DVec3::from_array(bytes.map(|b| 2.0 * f64::from(b) / 255.0 - 1.0));
    let shading = (DVec3::new(0.0, -1.0, 0.0) * n.z - DVec3::X * n.x - DVec3::Z * n.y).normalize();
    // The centre pixel's ray meets the plane at (0, 5, 0); L = unit((0, −5, 5)).
    let l = DVec3::new(0.0, -1.0, 1.0).normalize();
    assert!(
        l.dot(shading) > 0.0 && (l.dot(shading) - l.dot(-DVec3::Y)).abs() > 0.05,
        "{shading}"
    );
    // The light is d² = 5² + 5² away.
    let want = l.dot(shading) / 50.0;
    let got = image.pixel(10, 10);
    for c in got {
        assert!((f64::from(c) - want).abs() < 1e-6, "{got:?} vs {want}");
    }
}
