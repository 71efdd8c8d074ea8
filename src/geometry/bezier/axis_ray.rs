//! The ray in the surface's axis coordinates: along the axis and
//! perpendicular to it, restarted near the surface so that the solvers'
//! arithmetic is at object scale.

use super::super::Ray;
use glam::DVec3;

/// The ray in axis coordinates, restarted at `t0`.
pub struct AxisRay {
    /// Where the ray is restarted (global t); local t is global t − t0.
    pub t0: f64,
    /// Axial coordinate of the (restarted) origin relative to O1.
    pub pa: f64,
    /// Axial coordinate of the direction.
    pub da: f64,
    /// Perpendicular part of the origin.
    pub pp: DVec3,
    /// Perpendicular part of the direction.
    pub dp: DVec3,
    /// |d⊥|²: the squared distance from the axis is a·t² + 2b·t + c.
    pub a: f64,
    /// p⊥·d⊥.
    pub b: f64,
    /// |p⊥|².
    pub c: f64,
    /// 1/da.
    pub inv_da: f64,
    /// Where the ray comes closest to the axis (local t; 0 if parallel).
    pub t_axis: f64,
    /// Start of the valid window in global t.
    pub t_min: f64,
}

impl AxisRay {
    /// `ray` about the unit axis through `o1`, restarted at its closest
    /// approach to `center`, valid beyond global `t_min`.
    #[inline]
    pub fn new(ray: &Ray, o1: DVec3, axis: DVec3, center: DVec3, t_min: f64) -> Self {
        let t0 = (center - ray.origin).dot(ray.dir);
        let p = ray.origin + ray.dir * t0 - o1;
        let d = ray.dir;
        let pa = p.dot(axis);
        let da = d.dot(axis);
        let pp = p - axis * pa;
        let dp = d - axis * da;
        AxisRay {
            t0,
            pa,
            da,
            pp,
            dp,
            a: dp.length_squared(),
            b: pp.dot(dp),
            c: pp.length_squared(),
            inv_da: 1.0 / da,
            t_axis: if dp == DVec3::ZERO {
                0.0
            } else {
                -pp.dot(dp) / dp.length_squared()
            },
            t_min,
        }
    }
}
