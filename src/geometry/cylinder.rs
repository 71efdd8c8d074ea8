//! Closed cylinders: `primitive cylinder` (`O1= O2= R=`).

use super::{Aabb, Hit, Ray, Span, SurfacePoint, angle_around, axis_frame};
use glam::{DVec2, DVec3};
use std::f64::consts::TAU;

/// `Hit::part` of a hit on the side surface.
const SIDE: u32 = 0;
/// `Hit::part` of a hit on the cap at O1.
const CAP1: u32 = 1;
/// `Hit::part` of a hit on the cap at O2.
const CAP2: u32 = 2;

/// Below this |d⊥|² the ray counts as parallel to the axis: its distance
/// from the axis then changes by less than 1e-15 per unit travelled.
const PARALLEL_D2: f64 = 1e-30;

/// A closed cylinder: side surface plus discs at both ends.
///
/// A hit's `part` is 0 for the side, 1 for the cap at O1, 2 for the cap at O2.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first cap.
    pub o1: DVec3,
    /// Centre of the second cap.
    pub o2: DVec3,
    /// Radius (> 0).
    pub radius: f64,
    /// Unit axis O1 → O2.
    axis: DVec3,
    /// |O2 − O1|.
    length: f64,
    /// The spec's angular frame around the axis ([`axis_frame`]).
    e1: DVec3,
    e2: DVec3,
}

impl Cylinder {
    /// A cylinder from the spec's keys (O1 ≠ O2, R > 0; a degenerate one is
    /// never hit).
    pub fn new(o1: DVec3, o2: DVec3, radius: f64) -> Self {
        let length = (o2 - o1).length();
        let axis = if length > 0.0 {
            (o2 - o1) / length
        } else {
            DVec3::Z
        };
        let (e1, e2) = axis_frame(axis);
        Cylinder {
            o1,
            o2,
            radius,
            axis,
            length,
            e1,
            e2,
        }
    }

    /// The nearest hit with `t_min < t < t_max`: the entry point from
    /// outside, the exit point from inside; `part` says side or which cap.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if !(self.length > 0.0 && self.radius > 0.0) {
            return None;
        }
        // The solid is the intersection of the slab between the cap planes and
        // the infinite cylinder: intersect their two intervals along the ray
        // (like a box's slabs), so the rim has no crack between side and cap.
        let s = ray.origin - self.o1;
        let (sa, da) = (s.dot(self.axis), ray.dir.dot(self.axis));
        let mut span = if da == 0.0 {
            if sa < 0.0 || sa > self.length {
                return None;
            }
            Span::all()
        } else {
            let inv = 1.0 / da;
            let (t1, t2) = (-sa * inv, (self.length - sa) * inv);
            if da > 0.0 {
                Span::new(t1, t2, CAP1, CAP2)
            } else {
                Span::new(t2, t1, CAP2, CAP1)
            }
        };
        // The side only narrows the caps' span: wholly before t_min or
        // past t_max, it holds no hit (and the side's roots are not needed).
        if span.outside(t_min, t_max) {
            return None;
        }
        // Side: |s⊥ + t·d⊥|² = R², solved in the form of Sphere::roots that
        // stays exact for rays far from or nearly along the axis.
        let r2 = self.radius * self.radius;
        let sp = s - self.axis * sa;
        let dp = ray.dir - self.axis * da;
        let a = dp.length_squared();
        if a <= PARALLEL_D2 {
            if sp.length_squared() > r2 {
                return None;
            }
        } else {
            let b = sp.dot(dp);
            let perp = sp - dp * (b / a);
            let disc = r2 - perp.length_squared();
            if disc < 0.0 || disc.is_nan() {
                return None;
            }
            let c = sp.length_squared() - r2;
            let q = -b - (a * disc).sqrt().copysign(b);
            let (r0, r1) = if q == 0.0 {
                (0.0, 0.0)
            } else {
                let (x, y) = (c / q, q / a);
                if x <= y { (x, y) } else { (y, x) }
            };
            span.clip(r0, r1, SIDE, SIDE);
        }
        span.hit(t_min, t_max)
    }

    /// Point (on the surface), outward normal and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let q = ray.at(hit.t) - self.o1;
        let z = q.dot(self.axis);
        let radial = q - self.axis * z;
        let (point, normal, uv) = match hit.part {
            SIDE => {
                let rl = radial.length();
                let n = if rl > 0.0 { radial / rl } else { self.e1 };
                let z = z.max(0.0).min(self.length);
                // Snap onto the side: removes the rounding of o + t·d.
                let point = self.o1 + self.axis * z + n * self.radius;
                let uv = DVec2::new(z / self.length, angle_around(n, self.e1, self.e2) / TAU);
                (point, n, uv)
            }
            part => {
                let (center, n) = if part == CAP1 {
                    (self.o1, -self.axis)
                } else {
                    (self.o2, self.axis)
                };
                let rl = radial.length();
                let r = if rl > self.radius {
                    radial * (self.radius / rl)
                } else {
                    radial
                };
                let uv = DVec2::new(
                    0.5 + r.dot(self.e1) / (2.0 * self.radius),
                    0.5 + r.dot(self.e2) / (2.0 * self.radius),
                );
                (center + r, n, uv)
            }
        };
        SurfacePoint {
            point,
            normal,
            shading_normal: normal,
            uv,
        }
    }

    /// Bounds (tight: the caps' discs extend R·√(1 − a_i²) along world axis i).
    pub fn bounds(&self) -> Aabb {
        let a2 = self.axis * self.axis;
        // The 1e-9 pad keeps the box conservative despite the rounding of the root.
        let e = (DVec3::ONE - a2).max(DVec3::ZERO).powf(0.5) * (self.radius * (1.0 + 1e-9));
        Aabb::from_points(self.o1 - e, self.o1 + e)
            .union(&Aabb::from_points(self.o2 - e, self.o2 + e))
    }
}
