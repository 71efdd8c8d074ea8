//! Orthonormal frames around an axis, and angles about it.

use glam::DVec3;

/// The reference direction e1 ⟂ `axis` used by the spec's angular texture
/// mappings (cylinder, Bézier): unit(axis × z), or x when axis ∥ z.
/// Returns (e1, e2 = axis × e1); `axis` must be unit length.
pub fn axis_frame(axis: DVec3) -> (DVec3, DVec3) {
    let c = axis.cross(DVec3::Z);
    let e1 = if c.length_squared() < 1e-24 {
        DVec3::X
    } else {
        c.normalize()
    };
    (e1, axis.cross(e1))
}

/// Two unit vectors perpendicular to the unit vector `w` and to each other.
pub fn perpendiculars(w: DVec3) -> (DVec3, DVec3) {
    let a = if w.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let u = w.cross(a).normalize();
    (u, w.cross(u))
}

/// The angle of `q` around an axis with frame (e1, e2), in [0, 2π).
pub fn angle_around(q: DVec3, e1: DVec3, e2: DVec3) -> f64 {
    let a = q.dot(e2).atan2(q.dot(e1));
    if a < 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perpendiculars_are_orthonormal() {
        for w in [
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (u, v) = perpendiculars(w);
            assert!(u.dot(w).abs() < 1e-15 && v.dot(w).abs() < 1e-15 && u.dot(v).abs() < 1e-15);
            assert!((u.length() - 1.0).abs() < 1e-15 && (v.length() - 1.0).abs() < 1e-15);
        }
    }
}
