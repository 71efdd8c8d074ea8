//! The pinhole cameras of the lineages: the framework's, PM3's and V's
//! (the lens spans the outer pixels' centres), W's (aimed at a corner) and
//! the colon family's (the framework's, turned by its `up:`), with their
//! thin lenses.

use crate::accel::PACKET_MAX;
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
    /// The thin lens: its radius (`aperture=`) over the unit right and up
    /// vectors, and the focus distance along N (`focalLen=`); `None`: a pinhole.
    thin_lens: Option<ThinLens>,
}

/// A thin lens's disc and focus.
#[derive(Clone, Copy, Debug)]
struct ThinLens {
    right: DVec3,
    up: DVec3,
    focal: f64,
    /// Whether the points in focus lie at `focal` along each ray (a
    /// sphere about the eye: the colon family's) rather than on the plane
    /// `focal` along N.
    spherical: bool,
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

/// The unit right and up vectors of `camera` drawn through `lens`.
pub(crate) fn basis(camera: &Camera, lens: Lens) -> (DVec3, DVec3) {
    let n = camera.dir;
    let right = match lens {
        Lens::Corner | Lens::Hta => camera.right.unwrap_or_else(|| right_of(n)),
        Lens::Framework | Lens::Spanned => right_of(n),
    };
    (right, right.cross(n))
}

impl CameraRays {
    /// Sets up the basis of `lens` for a camera rendering `width` × `height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32, lens: Lens) -> Self {
        let n = camera.dir;
        let (right, up) = basis(camera, lens);
        let dof = &camera.dof;
        let thin_lens = (dof.aperture > 0.0).then(|| ThinLens {
            right: right * dof.aperture,
            up: up * dof.aperture,
            focal: dof.focal_len,
            spherical: lens == Lens::Hta,
        });
        CameraRays {
            origin: camera.origin,
            dir: n,
            dx: right * (camera.lens_w / 2.0),
            dy: up * (camera.lens_h / 2.0),
            width: width as f64,
            height: height as f64,
            lens,
            thin_lens,
        }
    }

    /// Whether it has a lens of non-zero aperture.
    pub fn has_lens(&self) -> bool {
        self.thin_lens.is_some()
    }

    /// The ray from point (`lx`, `ly`) of the unit disc on the lens towards
    /// the point where the pinhole ray through image position (`i`, `j`)
    /// meets the plane in focus, or the sphere of the colon family's lens
    /// (the pinhole ray without a lens).
    #[inline]
    pub fn lens_ray(&self, i: f64, j: f64, (lx, ly): (f64, f64)) -> Ray {
        let d = self.direction(i, j);
        match self.thin_lens {
            Some(t) => {
                // d·N = 1: O + d·focal lies on the plane in focus.
                let focus = if t.spherical {
                    self.origin + d.normalize() * t.focal
                } else {
                    self.origin + d * t.focal
                };
                let from = self.origin + t.right * lx + t.up * ly;
                Ray::new(from, (focus - from).normalize())
            }
            None => Ray::new(self.origin, d.normalize()),
        }
    }

    /// The ray through image position (`i` rows from the bottom, `j`
    /// columns from the left), both in pixels (pixel centres at k + ½).
    #[inline]
    pub fn ray(&self, i: f64, j: f64) -> Ray {
        Ray::new(self.origin, self.direction(i, j).normalize())
    }

    /// [`CameraRays::ray`] for each image position (`i`, `j`) of `at` (at
    /// most [`PACKET_MAX`]) into `out`, a lane each: the same operations
    /// (the direction, then `DVec3::normalize`'s), a coordinate at a time
    /// so that the compiler runs the lanes side by side.
    #[inline]
    pub fn rays(&self, at: &[(f64, f64)], out: &mut [Ray]) {
        let n = at.len().min(out.len()).min(PACKET_MAX);
        // The direction's weights of Dy and Dx, each lens's in its own
        // loop (the lens a constant in each).
        let (mut a, mut b) = ([0.0; PACKET_MAX], [0.0; PACKET_MAX]);
        let mut weights = |lens: Lens| {
            for k in 0..n {
                (a[k], b[k]) = self.weights(lens, at[k].0, at[k].1);
            }
        };
        match self.lens {
            Lens::Framework => weights(Lens::Framework),
            Lens::Spanned => weights(Lens::Spanned),
            Lens::Corner => weights(Lens::Corner),
            Lens::Hta => weights(Lens::Hta),
        }
        let (mut x, mut y, mut z) = ([0.0; PACKET_MAX], [0.0; PACKET_MAX], [0.0; PACKET_MAX]);
        let (dir, dy, dx) = (self.dir, self.dy, self.dx);
        for k in 0..n {
            // dir + dy·a + dx·b, then normalised: multiplied by 1/√(d·d).
            let dk = [
                dir.x + dy.x * a[k] + dx.x * b[k],
                dir.y + dy.y * a[k] + dx.y * b[k],
                dir.z + dy.z * a[k] + dx.z * b[k],
            ];
            let recip = 1.0 / (dk[0] * dk[0] + dk[1] * dk[1] + dk[2] * dk[2]).sqrt();
            (x[k], y[k], z[k]) = (dk[0] * recip, dk[1] * recip, dk[2] * recip);
        }
        for k in 0..n {
            out[k] = Ray::new(self.origin, DVec3::new(x[k], y[k], z[k]));
        }
    }

    /// The lineage's (unnormalised) direction through image position (`i`, `j`).
    #[inline]
    fn direction(&self, i: f64, j: f64) -> DVec3 {
        let (a, b) = self.weights(self.lens, i, j);
        self.dir + self.dy * a + self.dx * b
    }

    /// The weights of Dy and Dx in `lens`'s direction through image
    /// position (`i`, `j`).
    #[inline(always)]
    fn weights(&self, lens: Lens, i: f64, j: f64) -> (f64, f64) {
        let (h, w) = (self.height, self.width);
        match lens {
            Lens::Framework => (2.0 * i / h - 1.0, 2.0 * j / w - 1.0),
            // Its pixel k's centre is its integer k, rows from the top: half
            // a pixel left of and above the framework's.
            Lens::Hta => (2.0 * (i + 0.5) / h - 1.0, 2.0 * (j - 0.5) / w - 1.0),
            // Pixel k's centre is the lineage's integer k: N + Dy·lens_H·(k/(H−1) − ½)...
            Lens::Spanned => {
                let span = |k: f64, n: f64| 2.0 * ((k - 0.5) / (n - 1.0).max(1.0) - 0.5);
                (span(i, h), span(j, w))
            }
            // W's row index counts from the top, and N is aimed at pixel (0, 0).
            Lens::Corner => (2.0 * (h - i) / h, 2.0 * j / w),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thin_lens_rays_meet_on_the_plane_in_focus() {
        use crate::scene::DepthOfField;
        let cam = Camera {
            origin: DVec3::new(1.0, -2.0, 0.5),
            dir: DVec3::new(0.0, 1.0, -0.2).normalize(),
            lens_w: 1.0,
            lens_h: 0.6,
            dof: DepthOfField {
                aperture: 0.1,
                focal_len: 3.0,
                samples: 8,
            },
            ..Camera::default()
        };
        let pinhole = CameraRays::new(
            &Camera {
                dof: DepthOfField::default(),
                ..cam.clone()
            },
            100,
            60,
            Lens::Spanned,
        );
        let c = CameraRays::new(&cam, 100, 60, Lens::Spanned);
        assert!(c.has_lens() && !pinhole.has_lens());
        for (i, j) in [(30.0, 50.0), (3.5, 90.25), (59.0, 0.5)] {
            // Where the pinhole ray meets the plane 3 along N from the eye.
            let p = pinhole.ray(i, j);
            let focus = p.origin + p.dir * (3.0 / p.dir.dot(cam.dir));
            for disc in [(0.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.6, 0.7)] {
                let r = c.lens_ray(i, j, disc);
                // It leaves the lens: within the aperture, in the plane ⟂ N.
                let off = r.origin - cam.origin;
                assert!(off.dot(cam.dir).abs() < 1e-15 && off.length() <= 0.1 + 1e-15);
                // And passes through the point in focus.
                let t = (focus - r.origin).dot(r.dir);
                assert!((r.origin + r.dir * t - focus).length() < 1e-12);
            }
        }
    }

    #[test]
    fn rays_made_in_lanes_are_the_single_rays_bit_for_bit() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut unit = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for lens in [Lens::Framework, Lens::Spanned, Lens::Corner, Lens::Hta] {
            for _ in 0..50 {
                let v =
                    |unit: &mut dyn FnMut() -> f64| DVec3::new(unit(), unit(), unit()) * 2.0 - 1.0;
                let cam = Camera {
                    origin: v(&mut unit) * 10.0,
                    dir: v(&mut unit).normalize(),
                    lens_w: 0.1 + unit() * 2.0,
                    lens_h: 0.1 + unit() * 2.0,
                    right: Some(v(&mut unit).normalize()),
                    ..Camera::default()
                };
                let (w, h) = (1 + (unit() * 2000.0) as u32, 1 + (unit() * 2000.0) as u32);
                let c = CameraRays::new(&cam, w, h, lens);
                // Inside the frame and past its edges, its corners exactly,
                // and a packet of every length up to the most.
                let n = (unit() * (PACKET_MAX + 1) as f64) as usize;
                let at: Vec<(f64, f64)> = (0..n)
                    .map(|k| match k % 4 {
                        0 => (unit() * h as f64, unit() * w as f64),
                        1 => (
                            (unit() - 0.5) * 4.0 * h as f64,
                            (unit() - 0.5) * 4.0 * w as f64,
                        ),
                        2 => (h as f64, 0.0),
                        _ => (0.0, w as f64 - 0.5),
                    })
                    .collect();
                let mut out = vec![Ray::new(DVec3::ZERO, DVec3::Z); n];
                c.rays(&at, &mut out);
                for (&(i, j), got) in at.iter().zip(&out) {
                    let want = c.ray(i, j);
                    let bits = |r: &Ray| (r.origin.to_array(), r.dir.to_array().map(f64::to_bits));
                    assert_eq!(bits(got), bits(&want), "{lens:?} {w}x{h} at ({i}, {j})");
                }
            }
        }
    }

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

    #[test]
    fn pm3_and_v_lenses_span_the_outer_pixel_centres() {
        let cam = Camera {
            dir: DVec3::Y,
            lens_w: 1.0,
            lens_h: 0.6,
            ..Camera::default()
        };
        // PM3's `Emit(i, j)` = N + Dx·lens_W·(j/(W−1) − ½) + Dy·lens_H·(i/(H−1) − ½)
        // at the integer pixel k, glint's pixel centre k + ½.
        let c = CameraRays::new(&cam, 101, 61, Lens::Spanned);
        let emit = |i: f64, j: f64| {
            (DVec3::Y + DVec3::X * (j / 100.0 - 0.5) + DVec3::Z * 0.6 * (i / 60.0 - 0.5))
                .normalize()
        };
        for (i, j) in [(0.0, 0.0), (60.0, 100.0), (30.0, 50.0), (7.0, 93.0)] {
            let got = c.ray(i + 0.5, j + 0.5).dir;
            assert!((got - emit(i, j)).length() < 1e-15, "{i} {j}: {got}");
        }
    }

    #[test]
    fn w_camera_is_aimed_at_a_corner_and_mirrored_by_its_dx() {
        // W's scene.txt camera: its sphere at (2, 6, −1.5), radius 0.5, lands
        // at about (j, i) = (425, 96) of picture.bmp (rows from the top).
        let cam = Camera {
            origin: DVec3::new(0.5, -1.0, 0.2),
            dir: DVec3::new(0.6, 1.0, -0.2).normalize(),
            lens_w: 1.0,
            lens_h: 0.6,
            right: Some(DVec3::new(-1.0, 0.6, 0.0).normalize()),
            ..Camera::default()
        };
        let (w, h) = (1280.0, 760.0);
        let c = CameraRays::new(&cam, 1280, 760, Lens::Corner);
        // W's formula: N + Dy·2i/H + Dx·2j/W, Dx = unit(Dx=)·lens_W/2, Dy = unit(Dx=) × N·lens_H/2.
        let dx = DVec3::new(-1.0, 0.6, 0.0).normalize();
        let dy = dx.cross(cam.dir);
        let emit = |i: f64, j: f64| {
            (cam.dir + dy * 0.3 * (2.0 * i / h) + dx * 0.5 * (2.0 * j / w)).normalize()
        };
        for (top, j) in [(96.0, 425.0), (0.0, 0.0), (759.0, 1279.0)] {
            // Glint's rows count from the bottom: pixel row `top` is i = H − top − ½.
            let got = c.ray(h - top - 0.5, j + 0.5);
            assert!((got.dir - emit(top + 0.5, j + 0.5)).length() < 1e-15);
        }
        let centre = DVec3::new(2.0, 6.0, -1.5);
        let ray = c.ray(h - 96.5, 425.5);
        let to = centre - ray.origin;
        let miss = (to - ray.dir * to.dot(ray.dir)).length();
        assert!(
            miss < 0.5 * 0.25,
            "the sphere's centre is {miss} off the ray"
        );
    }
}
