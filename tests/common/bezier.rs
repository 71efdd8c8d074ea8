//! An independent model of a Bézier surface of revolution (de Casteljau,
//! its own axis frame) and the dense-scan reference for ray hits: the exact
//! two-equation system in the curve parameter is sampled densely and every
//! sign change bisected to the last bit.
//!
//! (The same model as `tests/bezier.rs`, which can use this module instead
//! of its own copy.)

use glam::DVec3;

/// A surface of revolution about the axis `o1` → `o2` (unit `a`, with
/// `u`, `w` completing a frame) of the profile with control points (z, r).
#[derive(Clone, Debug)]
pub struct Model {
    pub o1: DVec3,
    pub o2: DVec3,
    pub a: DVec3,
    pub u: DVec3,
    pub w: DVec3,
    pub z: Vec<f64>,
    pub r: Vec<f64>,
    /// Size of the profile and its distance from O1 (for tolerances).
    pub scale: f64,
}

pub fn casteljau(c: &[f64], s: f64) -> f64 {
    let mut b = c.to_vec();
    for k in 1..b.len() {
        for i in 0..b.len() - k {
            b[i] = b[i] * (1.0 - s) + b[i + 1] * s;
        }
    }
    b[0]
}

pub fn hodograph(c: &[f64]) -> Vec<f64> {
    let n = (c.len() - 1) as f64;
    c.windows(2).map(|p| n * (p[1] - p[0])).collect()
}

pub fn elevate(c: &[f64]) -> Vec<f64> {
    let n = c.len() - 1;
    let m = (n + 1) as f64;
    (0..=n + 1)
        .map(|i| {
            let k = i as f64 / m;
            let lo = if i > 0 { c[i - 1] } else { 0.0 };
            let hi = if i <= n { c[i] } else { 0.0 };
            k * lo + (1.0 - k) * hi
        })
        .collect()
}

impl Model {
    pub fn new(o1: DVec3, o2: DVec3, pts: &[(f64, f64)]) -> Model {
        let a = (o2 - o1).normalize();
        let helper = if a.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
        let u = a.cross(helper).normalize();
        let w = a.cross(u);
        let z: Vec<f64> = pts.iter().map(|p| p.0).collect();
        let r: Vec<f64> = pts.iter().map(|p| p.1).collect();
        let scale = pts
            .iter()
            .fold(1e-3f64, |m, p| m.max(p.0.abs()).max(p.1.abs()));
        Model {
            o1,
            o2,
            a,
            u,
            w,
            z,
            r,
            scale,
        }
    }

    pub fn elevated(&self) -> Model {
        let mut m = self.clone();
        m.z = elevate(&self.z);
        m.r = elevate(&self.r);
        m
    }

    pub fn zr(&self, s: f64) -> (f64, f64) {
        (casteljau(&self.z, s), casteljau(&self.r, s))
    }

    pub fn dzr(&self, s: f64) -> (f64, f64) {
        (
            casteljau(&hodograph(&self.z), s),
            casteljau(&hodograph(&self.r), s),
        )
    }

    pub fn point(&self, s: f64, phi: f64) -> DVec3 {
        let (z, r) = self.zr(s);
        self.o1 + self.a * z + (self.u * phi.cos() + self.w * phi.sin()) * r
    }

    /// Height along the axis and distance from it.
    pub fn axial(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.o1;
        let h = q.dot(self.a);
        (h, (q - self.a * h).length())
    }

    /// Outward normal of the |r| profile: radial·z' − a·|r|'.
    pub fn normal(&self, s: f64, p: DVec3) -> DVec3 {
        let q = p - self.o1;
        let radial = (q - self.a * q.dot(self.a)).normalize_or_zero();
        let (_, r) = self.zr(s);
        let (dz, dr) = self.dzr(s);
        (radial * dz - self.a * dr * r.signum()).normalize_or_zero()
    }

    /// How far `p` is from the surface circle at parameter `s`.
    pub fn residual(&self, s: f64, p: DVec3) -> f64 {
        let (z, r) = self.zr(s);
        let (h, rho) = self.axial(p);
        (z - h).abs().max((r.abs() - rho).abs())
    }

    /// The ray's origin (from O1) and direction split along and across the axis: (pa, da, pp, dp).
    pub fn split(&self, origin: DVec3, dir: DVec3) -> (f64, f64, DVec3, DVec3) {
        let p = origin - self.o1;
        let d = dir;
        let (pa, da) = (p.dot(self.a), d.dot(self.a));
        (pa, da, p - self.a * pa, d - self.a * da)
    }

    /// Every hit of the ray with the surface, found by scanning the exact
    /// equations at `n` values of s and bisecting each sign change.
    pub fn scan(&self, origin: DVec3, dir: DVec3, n: usize) -> Vec<RefHit> {
        let d = dir;
        let (pa, da, pp, dp) = self.split(origin, dir);
        let aa = dp.length_squared();
        let mut out = Vec::new();
        let mut push = |s: f64, t: f64| {
            let pt = origin + dir * t;
            out.push(RefHit {
                t,
                s,
                cos: self.normal(s, pt).dot(d).abs(),
            });
        };
        if da.abs() > 0.3 {
            // The ray crosses height z(s) once, at t(s); compare radii there.
            let e = |s: f64| {
                let (z, r) = self.zr(s);
                let t = (z - pa) / da;
                (pp + dp * t).length_squared() - r * r
            };
            for s in scan_roots(&e, n) {
                push(s, (self.zr(s).0 - pa) / da);
            }
        } else {
            // Each half of the ray (split at its closest approach to the axis)
            // reaches radius |r(s)| once; compare heights there.
            let ts = -pp.dot(dp) / aa;
            let rs2 = (pp + dp * ts).length_squared();
            let hs = pa + da * ts;
            for sigma in [-1.0, 1.0] {
                let e = |s: f64| {
                    let (z, r) = self.zr(s);
                    let q = r * r - rs2;
                    if q < 0.0 {
                        f64::NAN
                    } else {
                        hs + da * sigma * (q / aa).sqrt() - z
                    }
                };
                for s in scan_roots(&e, n) {
                    let (_, r) = self.zr(s);
                    push(s, ts + sigma * ((r * r - rs2).max(0.0) / aa).sqrt());
                }
            }
        }
        out
    }
}

/// One hit the reference found: distance, curve parameter, and how
/// squarely the ray meets the surface there.
#[derive(Clone, Copy, Debug)]
pub struct RefHit {
    pub t: f64,
    pub s: f64,
    /// |cos| of the angle between the ray and the surface normal.
    pub cos: f64,
}

/// Roots of `e` on [0, 1] from sign changes between `n` + 1 samples
/// (NaN samples skipped), each bisected to the last bit.
pub fn scan_roots(e: &impl Fn(f64) -> f64, n: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let mut prev = (0.0, e(0.0));
    for i in 1..=n {
        let s = i as f64 / n as f64;
        let v = e(s);
        let (s0, v0) = prev;
        if v0 == 0.0 {
            out.push(s0);
        } else if v0.is_finite() && v.is_finite() && v0 * v < 0.0 {
            let (mut lo, mut hi) = (s0, s);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                let vm = e(mid);
                if vm.is_nan() || (vm > 0.0) == (v0 > 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            out.push(0.5 * (lo + hi));
        }
        prev = (s, v);
    }
    if prev.1 == 0.0 {
        out.push(1.0);
    }
    out
}

/// Hits closer to grazing than this are ambiguous for every method.
pub const GRAZING: f64 = 1e-5;
