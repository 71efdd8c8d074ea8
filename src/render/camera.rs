//! The framework's pinhole camera.

use crate::geometry::Ray;
use crate::scene::Camera;
use glam::DVec3;

/// Generates primary rays for image positions.
#[derive(Clone, Debug)]
pub struct CameraRays {
    origin: DVec3,
    dir: DVec3,
    /// Right vector scaled by lens_W / 2.
    dx: DVec3,
    /// Up vector scaled by lens_H / 2.
    dy: DVec3,
    width: f64,
    height: f64,
}

impl CameraRays {
    /// Sets up the basis of the spec for a camera rendering `width` × `height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let n = camera.dir;
        let right = n.cross(DVec3::Z);
        let right = if right.length_squared() < 1e-24 {
            DVec3::X
        } else {
            right.normalize()
        };
        let up = right.cross(n);
        CameraRays {
            origin: camera.origin,
            dir: n,
            dx: right * (camera.lens_w / 2.0),
            dy: up * (camera.lens_h / 2.0),
            width: width as f64,
            height: height as f64,
        }
    }

    /// The ray through image position (`i` rows from the bottom, `j`
    /// columns from the left), both in pixels (pixel centres at k + ½).
    #[inline]
    pub fn ray(&self, i: f64, j: f64) -> Ray {
        let d = self.dir
            + self.dy * (2.0 * i / self.height - 1.0)
            + self.dx * (2.0 * j / self.width - 1.0);
        Ray::new(self.origin, d.normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_and_corners_follow_the_spec() {
        let cam = Camera {
            dir: DVec3::Y,
            lens_w: 1.0,
            lens_h: 0.6,
            ..Camera::default()
        };
        let c = CameraRays::new(&cam, 100, 60);
        assert!((c.ray(30.0, 50.0).dir - DVec3::Y).length() < 1e-15);
        // Top-right corner: N + Dy + Dx with Dx = (1,0,0)·0.5 (N × z = x), Dy = (0,0,1)·0.3.
        let want = DVec3::new(0.5, 1.0, 0.3).normalize();
        assert!((c.ray(60.0, 100.0).dir - want).length() < 1e-15);
        // Looking straight down: Dx falls back to x.
        let cam = Camera {
            dir: -DVec3::Z,
            ..cam
        };
        let c = CameraRays::new(&cam, 100, 60);
        let want = DVec3::new(0.5, 0.0, -1.0).normalize();
        assert!((c.ray(30.0, 100.0).dir - want).length() < 1e-15);
    }
}
