//! The pinhole cameras of the lineages: the framework's, PM3's and V's
//! (the lens spans the outer pixels' centres), and W's (aimed at a corner).

use crate::geometry::Ray;
use crate::integrator::Lens;
use crate::scene::Camera;
use glam::DVec3;

/// Generates primary rays for image positions.
#[derive(Clone, Debug)]
pub struct CameraRays {
    origin: DVec3,
    dir: DVec3,
    /// Right vector scaled by lens_W / 2.
    dx: DVec3,
    /// Up vector scaled by lens_H / 2 (W: down the image).
    dy: DVec3,
    width: f64,
    height: f64,
    lens: Lens,
}

/// unit(N × ẑ), or x̂ when N is vertical: the framework's right-hand direction.
fn right_of(n: DVec3) -> DVec3 {
    let right = n.cross(DVec3::Z);
    if right.length_squared() < 1e-24 {
        DVec3::X
    } else {
        right.normalize()
    }
}

impl CameraRays {
    /// Sets up the basis of `lens` for a camera rendering `width` × `height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32, lens: Lens) -> Self {
        let n = camera.dir;
        let right = match lens {
            Lens::Corner => camera.right.unwrap_or_else(|| right_of(n)),
            Lens::Framework | Lens::Spanned => right_of(n),
        };
        let up = right.cross(n);
        CameraRays {
            origin: camera.origin,
            dir: n,
            dx: right * (camera.lens_w / 2.0),
            dy: up * (camera.lens_h / 2.0),
            width: width as f64,
            height: height as f64,
            lens,
        }
    }

    /// The ray through image position (`i` rows from the bottom, `j`
    /// columns from the left), both in pixels (pixel centres at k + ½).
    #[inline]
    pub fn ray(&self, i: f64, j: f64) -> Ray {
        let d = match self.lens {
            Lens::Framework => {
                self.dir
                    + self.dy * (2.0 * i / self.height - 1.0)
                    + self.dx * (2.0 * j / self.width - 1.0)
            }
            // Pixel k's centre is the lineage's integer k: N + Dy·lens_H·(k/(H−1) − ½)...
            Lens::Spanned => {
                let span = |k: f64, n: f64| 2.0 * ((k - 0.5) / (n - 1.0).max(1.0) - 0.5);
                self.dir + self.dy * span(i, self.height) + self.dx * span(j, self.width)
            }
            // W's row index counts from the top, and N is aimed at pixel (0, 0).
            Lens::Corner => {
                self.dir
                    + self.dy * (2.0 * (self.height - i) / self.height)
                    + self.dx * (2.0 * j / self.width)
            }
        };
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
        let c = CameraRays::new(&cam, 100, 60, Lens::Framework);
        assert!((c.ray(30.0, 50.0).dir - DVec3::Y).length() < 1e-15);
        // Top-right corner: N + Dy + Dx with Dx = (1,0,0)·0.5 (N × z = x), Dy = (0,0,1)·0.3.
        let want = DVec3::new(0.5, 1.0, 0.3).normalize();
        assert!((c.ray(60.0, 100.0).dir - want).length() < 1e-15);
        // Looking straight down: Dx falls back to x.
        let cam = Camera {
            dir: -DVec3::Z,
            ..cam
        };
        let c = CameraRays::new(&cam, 100, 60, Lens::Framework);
        let want = DVec3::new(0.5, 0.0, -1.0).normalize();
        assert!((c.ray(30.0, 100.0).dir - want).length() < 1e-15);
    }
}
