//! Oriented boxes: `primitive cube` (`O= Dx= Dy= x= y= z=`).

use super::{Aabb, Hit, Ray, Span, SurfacePoint};
use glam::{DVec2, DVec3};

/// A box centred at `center` with orthonormal axes and half-lengths.
///
/// A hit's `part` is the face: `2·axis` for the face whose outward normal is
/// `+axes[axis]`, `2·axis + 1` for `−axes[axis]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Cube {
    /// Centre.
    pub center: DVec3,
    /// Orthonormal axes Dx, Dy, Dz = Dx × Dy.
    pub axes: [DVec3; 3],
    /// Half-lengths along the axes.
    pub half: DVec3,
}

impl Cube {
    /// A box from orthonormal `dx`, `dy` (the caller orthonormalises) and
    /// half-lengths (their absolute values are used).
    pub fn new(center: DVec3, dx: DVec3, dy: DVec3, half: DVec3) -> Self {
        Cube {
            center,
            axes: [dx, dy, dx.cross(dy)],
            half: half.abs(),
        }
    }

    /// `v` in the box's frame (coordinates along Dx, Dy, Dz).
    #[inline]
    fn to_local(&self, v: DVec3) -> [f64; 3] {
        [
            v.dot(self.axes[0]),
            v.dot(self.axes[1]),
            v.dot(self.axes[2]),
        ]
    }

    /// The nearest hit with `t_min < t < t_max`: the entry face from
    /// outside, the exit face from inside; `part` is the face.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let o = self.to_local(ray.origin - self.center);
        let d = self.to_local(ray.dir);
        let h = self.half.to_array();
        // Slab test, keeping which face bounds the interval on each side.
        let mut span = Span::all();
        for i in 0..3 {
            if d[i] == 0.0 {
                // Parallel to this slab: no constraint inside it, a miss outside
                // (tested explicitly, as 0·∞ would give NaN).
                if o[i].abs() > h[i] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d[i];
            let (ta, tb) = ((-h[i] - o[i]) * inv, (h[i] - o[i]) * inv);
            let face = 2 * i as u32;
            // Entering through the face that faces the ray, leaving through the other.
            if d[i] > 0.0 {
                span.clip(ta, tb, face + 1, face);
            } else {
                span.clip(tb, ta, face, face + 1);
            }
        }
        span.hit(t_min, t_max)
    }

    /// Point (on the face), outward normal and the face's texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let axis = (hit.part as usize / 2).min(2);
        let sign = if hit.part.is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        let h = self.half.to_array();
        let mut l = self.to_local(ray.at(hit.t) - self.center);
        for i in 0..3 {
            // max/min rather than clamp: never panics, even on a malformed box.
            l[i] = l[i].max(-h[i]).min(h[i]);
        }
        // Snap onto the face plane: removes the rounding of o + t·d.
        l[axis] = sign * h[axis];
        let point = self.center + self.axes[0] * l[0] + self.axes[1] * l[1] + self.axes[2] * l[2];
        let normal = self.axes[axis] * sign;
        // The spec's per-face (Dx, Dy) pairs: ±Dz faces use (x, y), ±Dx faces
        // (y, z), ±Dy faces (z, x); each face is mapped like a square.
        let (iu, iv) = match axis {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        };
        SurfacePoint {
            point,
            normal,
            shading_normal: normal,
            uv: DVec2::new(square_coord(l[iu], h[iu]), square_coord(l[iv], h[iv])),
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let e = (self.axes[0] * self.half.x).abs()
            + (self.axes[1] * self.half.y).abs()
            + (self.axes[2] * self.half.z).abs();
        Aabb::from_points(self.center - e, self.center + e)
    }
}

/// The square texture coordinate of local coordinate `l` on an edge of
/// half-length `h`: 0 at −h, 1 at +h (1/2 on a flat, zero-length edge).
fn square_coord(l: f64, h: f64) -> f64 {
    if h > 0.0 { l / h / 2.0 + 0.5 } else { 0.5 }
}
