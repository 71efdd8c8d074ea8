//! Cubes and cylinders read from scene text: a ray that enters through an
//! edge or a rim and goes straight on next hits where it really leaves.

use super::boxes::square_box_configs;
use super::{INF, coin_sign, v};
use crate::Scene;
use crate::accel::Accel;
use crate::geometry::{Ray, offset_origin};
use crate::scene::Object;
use crate::tests::common::{box_edge_point, box_exit, scene_vec};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::TAU;

/// A ray that enters a `cube` exactly through an edge, or a `cylinder`
/// exactly through a rim, and goes straight on from the point the renderer
/// would start it from, next hits the solid where it really leaves it (slab
/// exits; for the cylinder the cap planes and the side's far root), not the
/// neighbouring face or the side again at t ≈ 1e-16.
#[test]
fn cube_edges_and_cylinder_rims_do_not_double_hit() {
    let mut rng = Pcg64::seed_from_u64(57);
    // Continues the first hit of `r` straight on; returns (t, exit reference check).
    let continued = |accel: &Accel<Object>, objects: &[crate::scene::Object], r: &Ray| {
        let (i, hit) = accel.intersect(r, INF)?;
        let sp = objects[i as usize].shape.surface(r, &hit);
        let side = if sp.normal.dot(r.dir) < 0.0 {
            sp.normal
        } else {
            -sp.normal
        };
        let next = Ray::off_surface(offset_origin(sp.point, -side), r.dir);
        let (_, h2) = accel.intersect(&next, INF)?;
        Some((next, h2.t))
    };
    for (c, rot, h) in square_box_configs() {
        let text = format!(
            "primitive cube\n O= {}\n Dx= {}\n Dy= {}\n x= {:?}\n y= {:?}\n z= {:?}\nend\n",
            scene_vec(c),
            scene_vec(rot.col(0)),
            scene_vec(rot.col(1)),
            h.x,
            h.y,
            h.z
        );
        let scene = Scene::parse(&text, ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let accel = Accel::build(scene.objects().to_vec());
        let scale = c.abs().max_element() + h.max_element();
        for m in 0..2000 {
            let i = rng.random_range(0..3usize);
            let j = (i + 1 + rng.random_range(0..2usize)) % 3;
            let (si, sj) = (coin_sign(&mut rng), coin_sign(&mut rng));
            let lambda = if m % 4 == 0 {
                si * sj
            } else {
                rng.random_range(-1.0..1.0)
            };
            let target = box_edge_point(c, rot, h, (i, si), (j, sj), lambda);
            // Outside both faces of the edge (all three at a corner): the ray
            // enters through it.
            let k = 3 - i - j;
            let along = if lambda.abs() == 1.0 {
                lambda * rng.random_range(0.05..1.0)
            } else {
                rng.random_range(-0.5..0.5)
            };
            let out = (rot.col(i) * (si * rng.random_range(0.05..1.0))
                + rot.col(j) * (sj * rng.random_range(0.05..1.0))
                + rot.col(k) * along)
                .normalize();
            let r = Ray::new(target + out * (h.max_element() * 3.0), -out);
            let (next, t2) = continued(&accel, scene.objects(), &r)
                .unwrap_or_else(|| panic!("no exit after entering the cube at {target}")); // invariant: the test's own fixed input (a failure fails the test)
            let (exit, cos) = box_exit(c, rot, h, next.origin, next.dir);
            assert!(
                (t2 - exit).abs() <= 1e-9 * scale / cos,
                "cube: entering at {target}, went on {next:?}, hit t={t2:e}, exit at {exit}"
            );
        }
    }
    let cylinders = [
        (DVec3::ZERO, v(0.0, 0.0, 2.0), 1.0),
        (v(0.3, -1.2, 0.5), v(1.7, 0.4, 2.9), 0.45),
        (v(100.0, 250.0, -30.0), v(100.2, 250.1, -29.5), 0.03),
    ];
    for (o1, o2, radius) in cylinders {
        let text = format!(
            "primitive cylinder\n O1= {}\n O2= {}\n R= {radius:?}\nend\n",
            scene_vec(o1),
            scene_vec(o2)
        );
        let scene = Scene::parse(&text, ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let accel = Accel::build(scene.objects().to_vec());
        let axis = (o2 - o1).normalize();
        let length = (o2 - o1).length();
        let (e1, e2) = crate::geometry::perpendiculars(axis);
        let scale = o1.abs().max(o2.abs()).max_element() + length + radius;
        for m in 0..2000 {
            let phi = rng.random_range(0.0..TAU);
            let radial = e1 * phi.cos() + e2 * phi.sin();
            let top = m % 2 == 0;
            let target = if top { o2 } else { o1 } + radial * radius;
            let cap_out = if top { axis } else { -axis };
            let tangent = axis.cross(radial);
            let out = (cap_out * rng.random_range(0.05..1.0)
                + radial * rng.random_range(0.05..1.0)
                + tangent * rng.random_range(-0.5..0.5))
            .normalize();
            let r = Ray::new(target + out * (length + radius) * 3.0, -out);
            let (next, t2) = continued(&accel, scene.objects(), &r)
                .unwrap_or_else(|| panic!("no exit after entering the cylinder at {target}")); // invariant: the test's own fixed input (a failure fails the test)
            // Exit from inside: the cap plane ahead, or the side's far root.
            let (s, d) = (next.origin - o1, next.dir);
            let (sa, da) = (s.dot(axis), d.dot(axis));
            let cap = if da > 0.0 {
                (length - sa) / da
            } else {
                -sa / da
            };
            let (sp, dp) = (s - axis * sa, d - axis * da);
            let (a, b, cc) = (
                dp.length_squared(),
                sp.dot(dp),
                sp.length_squared() - radius * radius,
            );
            let side = (-b + (b * b - a * cc).max(0.0).sqrt()) / a;
            let exit = cap.min(side);
            let cos = if cap < side {
                da.abs()
            } else {
                (sp + dp * side).normalize().dot(d).abs()
            };
            assert!(
                (t2 - exit).abs() <= 1e-9 * scale / cos,
                "cylinder: entering at {target}, went on {next:?}, hit t={t2:e}, exit at {exit}"
            );
        }
    }
}
