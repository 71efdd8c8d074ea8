//! Lights: their kinds and the geometry of each (where their shadow rays go).

use crate::geometry::perpendiculars;
use crate::sampling::{RandomSource, strata};
use glam::DVec3;
use rand::Rng;
use std::f64::consts::TAU;

/// One light source.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Its shape and position.
    pub kind: LightKind,
    /// Emitted colour, `intensity=` already multiplied in.
    pub color: DVec3,
    /// How its photons leave it, where its lineage says more than the colour.
    pub emission: PhotonEmission,
}

/// What the colon family's lights say of their photons (hta1996/Raytracing
/// `ppm.cpp` `Photontracer::emit`, `object.h` `Arealight::emit`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhotonEmission {
    /// `power:`: the light's share of the photons, which carry
    /// colour × power / (its photons); else the share follows the colour's
    /// mean and each carries colour × 4π / (its photons).
    pub power: Option<f64>,
    /// `N:` of an area light: its photons leave on that side only,
    /// cosine-weighted; else in every direction.
    pub normal: Option<DVec3>,
}

impl Light {
    /// The light's centre (where L points in the shading model).
    pub fn center(&self) -> DVec3 {
        match self.kind {
            LightKind::Point { pos } => pos,
            LightKind::Square { center, .. } | LightKind::Sphere { center, .. } => center,
        }
    }
}

/// The kinds of light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// `light point`: one shadow ray, hard shadows.
    Point {
        /// Position.
        pos: DVec3,
    },
    /// `light square`: area light over centre ± dx ± dy.
    Square {
        /// Centre.
        center: DVec3,
        /// Half-edge vector.
        dx: DVec3,
        /// Half-edge vector.
        dy: DVec3,
    },
    /// `light sphere`: area light over a sphere.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
}

impl Light {
    /// The box that every shadow ray towards this light ends in (`None`
    /// for a point light, whose one ray needs none).
    pub(crate) fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match self.kind {
            LightKind::Point { .. } => None,
            LightKind::Square { center, dx, dy } => {
                let half = dx.abs() + dy.abs();
                Some((center - half, center + half))
            }
            LightKind::Sphere { center, radius } => Some((center - radius, center + radius)),
        }
    }

    /// The shade factor s in [0, 1] at `origin`: the fraction of the shadow
    /// rays towards this light that `reaches(unit direction, distance to
    /// the light)` lets through. A point light takes one ray; an area light
    /// `samples` (see [`Light::for_each_sample`]). Returns s and the number of rays.
    /// (Inlined, with a point light's one ray; area lights in [`Light::shade_area`].)
    #[inline(always)]
    pub(crate) fn shade(
        &self,
        origin: DVec3,
        samples: u32,
        rng: &mut impl RandomSource,
        mut reaches: impl FnMut(DVec3, f64) -> bool,
    ) -> (f64, u64) {
        match self.kind {
            LightKind::Point { pos } => {
                let to = pos - origin;
                let dist = to.length();
                let blocked = dist > 0.0 && !reaches(to / dist, dist);
                (if blocked { 0.0 } else { 1.0 }, 1)
            }
            _ => self.shade_area(origin, samples, rng, reaches),
        }
    }

    /// [`Light::shade`] for an area light (never a point light).
    fn shade_area(
        &self,
        origin: DVec3,
        samples: u32,
        rng: &mut impl RandomSource,
        mut reaches: impl FnMut(DVec3, f64) -> bool,
    ) -> (f64, u64) {
        match self.kind {
            LightKind::Sphere { center, radius }
                if (center - origin).length_squared() <= radius * radius =>
            {
                (1.0, 0) // inside the light: nothing can block it
            }
            _ => {
                let mut lit = 0u32;
                let n = self.for_each_sample(origin, samples, rng, |dir, dist| {
                    if dist > 0.0 && reaches(dir, dist) {
                        lit += 1;
                    }
                });
                (lit as f64 / n.max(1) as f64, n as u64)
            }
        }
    }

    /// The mean over this light's shadow samples from `origin` of
    /// `weight(unit direction, distance)` where `reaches` lets the sample
    /// through (a sample of weight 0 is not traced): the 1/d² lineages'
    /// direct light. Returns the mean and the number of rays traced.
    pub(crate) fn shade_weighted(
        &self,
        origin: DVec3,
        samples: u32,
        rng: &mut impl RandomSource,
        mut reaches: impl FnMut(DVec3, f64) -> bool,
        mut weight: impl FnMut(DVec3, f64) -> f64,
    ) -> (f64, u64) {
        let mut sum = 0.0;
        let mut rays = 0u64;
        let n = self.for_each_sample(origin, samples, rng, |dir, dist| {
            if dist <= 0.0 {
                return;
            }
            let w = weight(dir, dist);
            if w > 0.0 {
                rays += 1;
                if reaches(dir, dist) {
                    sum += w;
                }
            }
        });
        (sum / n.max(1) as f64, rays)
    }

    /// Calls `each(unit direction, distance)` for each shadow sample from
    /// `origin` (a zero distance comes with an arbitrary direction);
    /// returns their number. A point light has one; an area light
    /// `samples`, stratified: a jittered grid over a square light,
    /// directions stratified in the cone a sphere light subtends (none from
    /// inside it).
    pub(crate) fn for_each_sample(
        &self,
        origin: DVec3,
        samples: u32,
        rng: &mut impl RandomSource,
        mut each: impl FnMut(DVec3, f64),
    ) -> u32 {
        match self.kind {
            LightKind::Point { pos } => {
                let (dir, dist) = toward(origin, pos);
                each(dir, dist);
                1
            }
            LightKind::Square { center, dx, dy } => {
                let rng = rng.generator();
                let (rows, cols) = strata(samples);
                let (cell_a, cell_b) = (2.0 / cols as f64, 2.0 / rows as f64);
                in_batches(
                    rows,
                    cols,
                    &mut each,
                    |r, c| {
                        let a = (c as f64 + rng.random::<f64>()) * cell_a - 1.0;
                        let b = (r as f64 + rng.random::<f64>()) * cell_b - 1.0;
                        center + dx * a + dy * b
                    },
                    |points, out| toward_each(origin, points, out),
                )
            }
            LightKind::Sphere { center, radius } => {
                let Some((cone, cos_max)) = Cone::of(origin, center, radius) else {
                    return 0;
                };
                let rng = rng.generator();
                let (rows, cols) = strata(samples);
                in_batches(
                    rows,
                    cols,
                    &mut each,
                    |r, c| {
                        // Uniform in solid angle over the cone: cos θ uniform in [cos_max, 1].
                        let cos_t =
                            1.0 - (r as f64 + rng.random::<f64>()) / rows as f64 * (1.0 - cos_max);
                        let phi = TAU * (c as f64 + rng.random::<f64>()) / cols as f64;
                        [cos_t, phi.cos(), phi.sin()]
                    },
                    |drawn, out| cone.rays(drawn, out),
                )
            }
        }
    }
}

impl Light {
    /// Calls `each(unit direction, distance)` from `origin` to each point of
    /// lazycal's fixed grid over the light: centre + (j/q)·dx − (i/q)·dy for
    /// i, j from −q to q (q = `half`), the edges included; a point or
    /// sphere light is its centre alone. Returns the number of points.
    pub(crate) fn for_each_grid_point(
        &self,
        origin: DVec3,
        half: u32,
        mut each: impl FnMut(DVec3, f64),
    ) -> u32 {
        match self.kind {
            LightKind::Square { center, dx, dy } if half > 0 => {
                let q = f64::from(half);
                let side = 2 * half as i64 + 1;
                for i in -(half as i64)..=half as i64 {
                    for j in -(half as i64)..=half as i64 {
                        let p = center + dx * (j as f64 / q) - dy * (i as f64 / q);
                        let (dir, dist) = toward(origin, p);
                        each(dir, dist);
                    }
                }
                (side * side) as u32
            }
            _ => {
                let (dir, dist) = toward(origin, self.center());
                each(dir, dist);
                1
            }
        }
    }
}

/// The unit direction and distance from `origin` to `p` (+z when they
/// coincide).
#[inline(always)]
fn toward(origin: DVec3, p: DVec3) -> (DVec3, f64) {
    let to = p - origin;
    let dist = to.length();
    let dir = if dist > 0.0 {
        to * (1.0 / dist)
    } else {
        DVec3::Z
    };
    (dir, dist)
}

/// [`toward`] for each of `points` (at most [`BATCH`]) into `out`, a lane
/// each: the same operations, a coordinate at a time so that the compiler
/// runs the lanes side by side.
#[inline(always)]
fn toward_each(origin: DVec3, points: &[DVec3], out: &mut [(DVec3, f64)]) {
    let n = points.len().min(out.len()).min(BATCH);
    let mut x = [0.0; BATCH];
    let mut y = [0.0; BATCH];
    let mut z = [0.0; BATCH];
    let mut dist = [0.0; BATCH];
    for k in 0..n {
        let (tx, ty, tz) = (
            points[k].x - origin.x,
            points[k].y - origin.y,
            points[k].z - origin.z,
        );
        let d = (tx * tx + ty * ty + tz * tz).sqrt();
        let recip = 1.0 / d;
        (x[k], y[k], z[k]) = if d > 0.0 {
            (tx * recip, ty * recip, tz * recip)
        } else {
            (0.0, 0.0, 1.0)
        };
        dist[k] = d;
    }
    for k in 0..n {
        out[k] = (DVec3::new(x[k], y[k], z[k]), dist[k]);
    }
}

/// Shadow samples made ahead of their rays, at most this many at a time.
const BATCH: usize = 16;

/// Calls `each(unit direction, distance)` for each cell of a
/// `rows`×`cols` grid, row by row, and returns their number: `draw(row,
/// column)` makes a cell's draws, and `rays` turns a batch of draws into
/// their rays. Up to [`BATCH`] samples are made
/// before their rays are traced, so that their square roots and divisions
/// overlap in the CPU, lane by lane, rather than wait on each ray's walk;
/// the order of the draws and of the rays is the same.
#[inline(always)]
fn in_batches<D: Copy + Default>(
    rows: u32,
    cols: u32,
    each: &mut impl FnMut(DVec3, f64),
    mut draw: impl FnMut(u32, u32) -> D,
    rays: impl Fn(&[D], &mut [(DVec3, f64)]),
) -> u32 {
    let mut drawn = [D::default(); BATCH];
    let mut batch = [(DVec3::ZERO, 0.0); BATCH];
    let (mut r, mut c) = (0, 0);
    let mut left = rows * cols;
    while left > 0 {
        let len = left.min(BATCH as u32);
        for slot in &mut drawn[..len as usize] {
            *slot = draw(r, c);
            c += 1;
            if c == cols {
                (r, c) = (r + 1, 0);
            }
        }
        rays(&drawn[..len as usize], &mut batch[..len as usize]);
        for &(dir, dist) in &batch[..len as usize] {
            each(dir, dist);
        }
        left -= len;
    }
    rows * cols
}

/// The cone of directions from a point to a sphere light, about `w`.
struct Cone {
    /// The point less the light's centre.
    f: DVec3,
    /// The radius squared.
    r2: f64,
    /// |f|² − r2 (the roots' product, as `Sphere::roots` has it).
    c: f64,
    /// The unit direction to the centre, and two unit perpendiculars.
    w: DVec3,
    u_axis: DVec3,
    v_axis: DVec3,
    /// The distance to the sphere's rim.
    tangent: f64,
}

impl Cone {
    /// The cone from `origin` to the sphere light of `center` and
    /// `radius`, and the cosine of its half-angle; `None` from inside the
    /// light.
    fn of(origin: DVec3, center: DVec3, radius: f64) -> Option<(Cone, f64)> {
        let to = center - origin;
        let d2 = to.length_squared();
        let r2 = radius * radius;
        if d2 <= r2 {
            return None;
        }
        let w = to / d2.sqrt();
        let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
        let (u_axis, v_axis) = perpendiculars(w);
        // origin − centre is −to exactly, with the same |·|²: d2.
        let c = d2 - r2;
        let cone = Cone {
            f: origin - center,
            r2,
            c,
            w,
            u_axis,
            v_axis,
            tangent: c.max(0.0).sqrt(),
        };
        Some((cone, cos_max))
    }

    /// The rays of a batch of draws (cos θ, cos φ, sin φ), at most
    /// [`BATCH`], into `out`: the unit
    /// direction at polar angle θ, azimuth φ, and the distance to the
    /// sphere along it (its nearest root, the tangent distance where
    /// rounding misses the rim). Each lane does the operations of
    /// `DVec3::normalize` and `Sphere::roots` for one sample, in their
    /// order, so the values are theirs, bit for bit; written a coordinate
    /// at a time so that the compiler runs the lanes side by side.
    #[inline(always)]
    fn rays(&self, drawn: &[[f64; 3]], out: &mut [(DVec3, f64)]) {
        let n = drawn.len().min(out.len()).min(BATCH);
        let (w, u, v) = (self.w, self.u_axis, self.v_axis);
        let (f, r2, c) = (self.f, self.r2, self.c);
        let mut x = [0.0; BATCH];
        let mut y = [0.0; BATCH];
        let mut z = [0.0; BATCH];
        let mut t = [0.0; BATCH];
        for k in 0..n {
            let [cos_t, cos_p, sin_p] = drawn[k];
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let dx = w.x * cos_t + (u.x * cos_p + v.x * sin_p) * sin_t;
            let dy = w.y * cos_t + (u.y * cos_p + v.y * sin_p) * sin_t;
            let dz = w.z * cos_t + (u.z * cos_p + v.z * sin_p) * sin_t;
            let recip = 1.0 / (dx * dx + dy * dy + dz * dz).sqrt();
            let (dx, dy, dz) = (dx * recip, dy * recip, dz * recip);
            let b = f.x * dx + f.y * dy + f.z * dz;
            let (px, py, pz) = (f.x - dx * b, f.y - dy * b, f.z - dz * b);
            let disc = r2 - (px * px + py * py + pz * pz);
            let q = -b - disc.sqrt().copysign(b);
            let t0 = c / q;
            let near = if t0 <= q { t0 } else { q };
            // (q is 0 only for a ray from the sphere's surface, which a
            // cone's origin, outside it, never is; kept as `roots` has it.)
            t[k] = if disc < 0.0 {
                self.tangent
            } else if q == 0.0 {
                0.0
            } else {
                near
            };
            (x[k], y[k], z[k]) = (dx, dy, dz);
        }
        for k in 0..n {
            out[k] = (DVec3::new(x[k], y[k], z[k]), t[k]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Ray, Sphere};
    use rand::SeedableRng;

    /// A random point in (−s, s)³, its scale itself random over twelve
    /// orders of magnitude.
    fn point(rng: &mut rand_pcg::Pcg64) -> DVec3 {
        let s = 10f64.powf(rng.random_range(-6.0..6.0));
        DVec3::new(
            rng.random_range(-s..s),
            rng.random_range(-s..s),
            rng.random_range(-s..s),
        )
    }

    #[test]
    fn a_cones_lanes_give_the_bits_of_normalize_and_the_spheres_roots() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        for _ in 0..4000 {
            let (origin, center) = (point(&mut rng), point(&mut rng));
            let to = center - origin;
            // Radii from a sliver of the distance to nearly all of it.
            let radius = to.length() * 10f64.powf(rng.random_range(-9.0..-1e-9));
            let Some((cone, cos_max)) = Cone::of(origin, center, radius) else {
                panic!("{origin} inside the sphere of {center}, {radius}"); // invariant: the test's radius is below the distance (a failure fails the test)
            };
            let (w, u_axis, v_axis) = (cone.w, cone.u_axis, cone.v_axis);
            // Directions across the cone, its rim (cos θ = cos_max) included.
            let drawn: [[f64; 3]; BATCH] = std::array::from_fn(|k| {
                let cos_t = if k == 0 {
                    cos_max
                } else {
                    1.0 - rng.random::<f64>() * (1.0 - cos_max)
                };
                let phi = TAU * rng.random::<f64>();
                [cos_t, phi.cos(), phi.sin()]
            });
            let mut out = [(DVec3::ZERO, 0.0); BATCH];
            cone.rays(&drawn, &mut out);
            let sphere = Sphere::new(center, radius);
            for (k, &[cos_t, cos_p, sin_p]) in drawn.iter().enumerate() {
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let dir = (w * cos_t + (u_axis * cos_p + v_axis * sin_p) * sin_t).normalize();
                let t = sphere
                    .roots(&Ray::new(origin, dir))
                    .map_or(cone.tangent, |(t0, _)| t0);
                let bits = |(d, t): (DVec3, f64)| (d.to_array().map(f64::to_bits), t.to_bits());
                assert_eq!(
                    bits(out[k]),
                    bits((dir, t)),
                    "lane {k} of {origin} → {center} r {radius}"
                );
            }
        }
    }

    #[test]
    fn lanes_toward_points_give_the_bits_of_toward() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(4);
        for _ in 0..4000 {
            let origin = point(&mut rng);
            let points: [DVec3; BATCH] = std::array::from_fn(|k| match k {
                0 => origin,
                1 => origin + DVec3::new(0.0, 5e-324, 0.0),
                _ => point(&mut rng),
            });
            let mut out = [(DVec3::ZERO, 0.0); BATCH];
            toward_each(origin, &points, &mut out);
            for (k, &p) in points.iter().enumerate() {
                let bits = |(d, t): (DVec3, f64)| (d.to_array().map(f64::to_bits), t.to_bits());
                assert_eq!(bits(out[k]), bits(toward(origin, p)), "{origin} → {p}");
            }
        }
    }

    #[test]
    fn batches_make_and_hand_on_every_cell_row_by_row() {
        for rows in 1..=6 {
            for cols in 1..=39 {
                // A cell is told by its sample: direction (r, c, k), k the
                // k-th call of `make`; `each` must see them in grid order.
                let mut made = 0.0;
                let mut seen = Vec::new();
                let n = in_batches(
                    rows,
                    cols,
                    &mut |d: DVec3, dist: f64| seen.push((d, dist)),
                    |r, c| {
                        made += 1.0;
                        (DVec3::new(f64::from(r), f64::from(c), made), made)
                    },
                    |made, out| out.copy_from_slice(made),
                );
                assert_eq!(n, rows * cols);
                let expected: Vec<(DVec3, f64)> = (0..rows)
                    .flat_map(|r| (0..cols).map(move |c| (r, c)))
                    .enumerate()
                    .map(|(k, (r, c))| {
                        let k = (k + 1) as f64;
                        (DVec3::new(f64::from(r), f64::from(c), k), k)
                    })
                    .collect();
                assert_eq!(seen, expected, "{rows}×{cols}");
            }
        }
    }
}
