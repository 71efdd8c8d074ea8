//! Closed boxes (centre, rotation, half-lengths) for the square and cube
//! suites, and the rays shot at their edges and corners.

use super::{assert_close, coin_sign, v};
use crate::geometry::{Hit, Ray};
use crate::tests::common::{box_edge_point, point_in, rotation};
use glam::{DMat3, DVec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// Boxes (centre, rotation, half-lengths) to shoot at the edges of: unit, rotated and flat, rotated, tiny and far from the origin.
pub(super) fn edge_box_configs() -> [(DVec3, DMat3, DVec3); 3] {
    [
        (DVec3::ZERO, DMat3::IDENTITY, DVec3::ONE),
        (
            v(0.1, -0.3, 0.7),
            rotation(v(0.3, -1.1, 2.0)),
            v(0.3, 1.7, 0.05),
        ),
        (
            v(1000.1, -999.7, 250.3),
            rotation(v(-0.7, 0.2, 0.9)),
            v(0.011, 0.013, 0.017),
        ),
    ]
}

/// Rays through edges, corners and points a hair from an edge of a closed
/// box, all of which must hit: entering from outside (expected distance
/// known) and leaving from inside. `hit` finds the nearest hit of the solid.
pub(super) fn shoot_at_box_edges(
    c: DVec3,
    rot: DMat3,
    h: DVec3,
    seed: u64,
    rays: usize,
    hit: impl Fn(&Ray) -> Option<Hit>,
) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let size = h.max_element();
    let scale = c.abs().max_element() + size;
    for n in 0..rays {
        // An edge along axis k, on the faces normal to axes i and j.
        let k = rng.random_range(0..3usize);
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (si, sj) = (coin_sign(&mut rng), coin_sign(&mut rng));
        let corner = n % 4 == 0;
        let lambda: f64 = if corner {
            coin_sign(&mut rng)
        } else if n % 4 == 1 {
            0.0
        } else {
            rng.random_range(-0.999..0.999)
        };
        let mut target = box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
        // Slide a hair onto face j (still on the closed box): 0 or 1e-16 .. 1e-10 of the size.
        if n % 3 == 2 {
            let eps = size * 10f64.powf(rng.random_range(-16.0..-10.0));
            target -= rot.col(i) * (si * eps);
        }
        // Outside, beyond both faces (and beyond the end face at a corner): the
        // ray enters the box through `target`.
        let (a, b) = (rng.random_range(0.05..1.0), rng.random_range(0.05..1.0));
        let g = if corner {
            lambda * rng.random_range(0.05..1.0)
        } else {
            rng.random_range(-0.5..0.5)
        };
        let out = (rot.col(i) * (si * a) + rot.col(j) * (sj * b) + rot.col(k) * g).normalize();
        let dist = size * rng.random_range(0.5..20.0);
        let r = Ray::new(target + out * dist, -out);
        let got = hit(&r).unwrap_or_else(|| panic!("crack: ray {r:?} entering at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(got.t, dist, 1e-9 * (scale + dist));
        // From inside towards the same point.
        let l = point_in(&mut rng, 0.99) * h;
        let inside = c + rot * l;
        let r = Ray::new(inside, (target - inside).normalize());
        let got = hit(&r).unwrap_or_else(|| panic!("crack: ray {r:?} leaving at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(got.t, (target - inside).length(), 1e-9 * scale);
    }
}

/// Boxes as scene files build them from six `square` blocks: unit, the
/// framework's kind (axis-aligned, decimal), rotated and flat, far from the
/// origin and tiny, rotated and long, axis-aligned thin and far.
pub(super) fn square_box_configs() -> Vec<(DVec3, DMat3, DVec3)> {
    let [unit, flat, tiny] = edge_box_configs();
    vec![
        unit,
        (v(1.5, 6.2, -0.3), DMat3::IDENTITY, v(0.5, 0.7, 0.9)),
        flat,
        tiny,
        (DVec3::ZERO, rotation(v(0.0, 0.0, 0.785)), v(10.0, 0.1, 0.1)),
        (v(-3.7, 0.25, 12.9), DMat3::IDENTITY, v(2.3, 0.01, 4.4)),
        (
            v(1000.1, -999.7, 250.3),
            DMat3::IDENTITY,
            v(0.011, 0.013, 0.017),
        ),
    ]
}
