//! Infinite planes against Cramer's rule, rays toward and away from them,
//! in windows that start at, past and before 0.

use super::{INF, ray, vec3};
use crate::geometry::{Plane, axis_frame};
use crate::tests::common::solve_plane;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Random planes and rays (from either side, toward the plane or away,
    /// windows from 0, from 1 and from −5) against a plane solve by
    /// Cramer's rule: the same hits and misses, and the same t to 1e-9.
    #[test]
    fn plane_matches_cramer_reference(
        n in vec3(2.0), offset in -5.0..5.0f64, o in vec3(10.0), d in vec3(1.0),
        window in 0usize..4,
    ) {
        prop_assume!(n.length() > 0.1 && d.length() > 0.1);
        let plane = Plane::new(n, offset, n, n);
        let r = ray(o, d);
        let unit = n.normalize();
        // Near-parallel rays leave the reference's solve ill-conditioned.
        prop_assume!(unit.dot(r.dir).abs() > 1e-3);
        let (e1, e2) = axis_frame(unit);
        let (t_lo, t_hi) = [(0.0, INF), (0.0, 4.0), (1.0, 30.0), (-5.0, INF)][window];
        let scale = 1.0 + o.length() + offset.abs();
        let reference = solve_plane(r.origin, r.dir, unit * offset, e1, e2).map(|s| s.0);
        let near_window = reference.is_some_and(|t| (t - t_lo).abs() < 1e-9 * scale || (t - t_hi).abs() < 1e-9 * scale);
        prop_assume!(!near_window);
        let got = plane.intersect(&r, t_lo, t_hi);
        match (got, reference.filter(|t| *t > t_lo && *t < t_hi)) {
            (None, None) => {}
            (Some(h), Some(t)) => prop_assert!((h.t - t).abs() < 1e-9 * scale, "t {} vs reference {}", h.t, t),
            (got, reference) => prop_assert!(false, "plane {:?} vs reference {:?}", got, reference),
        }
    }
}
