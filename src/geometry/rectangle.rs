//! Rectangles of the lineages (Z14, Z17, P): `primitive rectangle`
//! (`N= R= Dx= Dy=`), the part of a plane whose texture coordinates, measured
//! from the world origin, both lie in [0, 1].

use super::{Aabb, Hit, Plane, Ray, SurfacePoint};
use glam::{DMat3, DVec3};

/// The points C of the plane N̂·C = R with 0 ≤ C·Dx/|Dx|² ≤ 1 and
/// 0 ≤ C·Dy/|Dy|² ≤ 1; two-sided, normal N̂, texture coordinates those two
/// numbers (the plane's own mapping, untiled).
#[derive(Clone, Debug, PartialEq)]
pub struct Rectangle {
    /// The plane it lies in, whose texture axes are Dx and Dy.
    pub plane: Plane,
    bounds: Aabb,
}

impl Rectangle {
    /// A rectangle from the lineages' keys. N must not be zero, and N, Dx
    /// and Dy must be linearly independent (else the region is unbounded or
    /// empty); the parser checks both.
    pub fn new(n: DVec3, r: f64, dx: DVec3, dy: DVec3) -> Self {
        let plane = Plane::new(n, r, dx, dy);
        // The corners solve N̂·C = R, C·Dx = a|Dx|², C·Dy = b|Dy|², a, b ∈ {0, 1}.
        let rows = DMat3::from_cols(plane.normal, dx, dy).transpose();
        let inv = rows.inverse();
        let corner =
            |a: f64, b: f64| inv * DVec3::new(r, a * dx.length_squared(), b * dy.length_squared());
        let corners = Aabb::from_points(corner(0.0, 0.0), corner(1.0, 1.0))
            .grow(corner(1.0, 0.0))
            .grow(corner(0.0, 1.0));
        // The range test rounds differently from the inverse: pad by a few ulps of the size.
        let size = corners.min.abs().max(corners.max.abs()).max_element();
        let bounds = corners.padded(1e-12 * size);
        Rectangle { plane, bounds }
    }

    /// The hit with `t_min < t < t_max`: the plane's, kept when both texture
    /// coordinates of the hit point lie in [0, 1].
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let hit = self.plane.intersect(ray, t_min, t_max)?;
        let uv = self.plane.uv(ray.at(hit.t));
        let inside = |x: f64| (0.0..=1.0).contains(&x);
        (inside(uv.x) && inside(uv.y)).then_some(hit)
    }

    /// Point, normal (N̂) and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        self.plane.surface(ray, hit)
    }

    /// Bounds (the four corners).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_on_the_floor() {
        let r = Rectangle::new(DVec3::Z, 0.0, DVec3::new(2.0, 0.0, 0.0), DVec3::Y);
        let down = |x: f64, y: f64| Ray::new(DVec3::new(x, y, 1.0), -DVec3::Z);
        let hit = r.intersect(&down(1.0, 0.5), 0.0, 10.0);
        assert_eq!(hit.map(|h| h.t), Some(1.0));
        let s = r.surface(&down(1.0, 0.5), &Hit::at(1.0));
        assert_eq!((s.uv.x, s.uv.y), (0.5, 0.5));
        assert!(r.intersect(&down(2.5, 0.5), 0.0, 10.0).is_none());
        assert!(r.intersect(&down(-0.1, 0.5), 0.0, 10.0).is_none());
        assert!(r.intersect(&down(1.0, 1.1), 0.0, 10.0).is_none());
        let b = r.bounds();
        assert!((b.min - DVec3::ZERO).abs().max_element() < 1e-11);
        assert!((b.max - DVec3::new(2.0, 1.0, 0.0)).abs().max_element() < 1e-11);
    }
}
