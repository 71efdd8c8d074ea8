//! Infinite planes: `primitive plane` (`N= R= Dx= Dy=`).

use super::{Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// The points P with P·normal = offset.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal.
    pub normal: DVec3,
    /// Signed distance from the origin along the normal.
    pub offset: f64,
    /// Texture axis: u = P·dx/|dx|².
    pub dx: DVec3,
    /// Texture axis: v = P·dy/|dy|².
    pub dy: DVec3,
    /// Added to the texture coordinates (PM3 shifts its tiles by half; the
    /// colon family measures them from a corner `Do:`).
    pub uv_shift: DVec2,
}

impl Plane {
    /// A plane from the spec's keys (N need not be unit; it must not be zero).
    pub fn new(n: DVec3, r: f64, dx: DVec3, dy: DVec3) -> Self {
        Plane {
            normal: n.normalize(),
            offset: r,
            dx,
            dy,
            uv_shift: DVec2::ZERO,
        }
    }

    /// The hit with `t_min < t < t_max`, if any.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let num = self.offset - self.normal.dot(ray.origin);
        if behind(num, denom, t_min) {
            return None;
        }
        let t = num / denom;
        (t > t_min && t < t_max).then(|| Hit::at(t))
    }

    /// Point, normal (the plane's N) and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let mut point = ray.at(hit.t);
        // Project back onto the plane: removes the rounding of o + t·d.
        point -= self.normal * (point.dot(self.normal) - self.offset);
        SurfacePoint {
            point,
            normal: self.normal,
            shading_normal: self.normal,
            uv: self.uv(point),
        }
    }

    /// The spec's plane mapping (tiles every |Dx| along Dx).
    pub fn uv(&self, p: DVec3) -> DVec2 {
        DVec2::new(
            p.dot(self.dx) / self.dx.length_squared(),
            p.dot(self.dy) / self.dy.length_squared(),
        ) + self.uv_shift
    }
}

/// Whether `t = num / denom` cannot pass `t > t_min`, told without the
/// division: `t_min` ≥ 0 and the sign bits of `num` and `denom` differ,
/// so `t` is negative, −0, −∞ or NaN. A ray leaving the plane behind it
/// (most shadow rays above a floor) is a miss at once.
#[inline(always)]
pub(crate) fn behind(num: f64, denom: f64, t_min: f64) -> bool {
    t_min >= 0.0 && (num.to_bits() ^ denom.to_bits()) >> 63 == 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_plane_hit_and_tiling() -> Result<(), &'static str> {
        let p = Plane::new(
            DVec3::new(0.0, 0.0, 2.0),
            -2.0,
            DVec3::new(8.0, 0.0, 0.0),
            DVec3::new(0.0, 8.0, 0.0),
        );
        let r = Ray::new(DVec3::new(4.0, 12.0, 1.0), -DVec3::Z);
        let h = p
            .intersect(&r, 0.0, f64::INFINITY)
            .ok_or("the ray straight down misses the plane")?;
        assert_eq!(h.t, 3.0);
        let s = p.surface(&r, &h);
        assert_eq!(s.point, DVec3::new(4.0, 12.0, -2.0));
        assert_eq!(s.uv, DVec2::new(0.5, 1.5));
        // Parallel and behind miss.
        assert!(
            p.intersect(&Ray::new(DVec3::ZERO, DVec3::X), 0.0, 1e9)
                .is_none()
        );
        assert!(
            p.intersect(&Ray::new(DVec3::ZERO, DVec3::Z), 0.0, 1e9)
                .is_none()
        );
        Ok(())
    }
}
