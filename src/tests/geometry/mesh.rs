//! Closed triangle meshes (an octahedron, icospheres) leave no crack at
//! their vertices and edges, and a mesh's triangles stay small.

use super::{INF, assert_close, nearest, v};
use crate::geometry::{Ray, Triangle};
use crate::tests::common::{point_in, rotation};
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

/// A unit icosphere subdivided `level` times, as vertex list + outward CCW faces.
fn icosphere(level: usize) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let p = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<DVec3> = [
        v(-1.0, p, 0.0),
        v(1.0, p, 0.0),
        v(-1.0, -p, 0.0),
        v(1.0, -p, 0.0),
        v(0.0, -1.0, p),
        v(0.0, 1.0, p),
        v(0.0, -1.0, -p),
        v(0.0, 1.0, -p),
        v(p, 0.0, -1.0),
        v(p, 0.0, 1.0),
        v(-p, 0.0, -1.0),
        v(-p, 0.0, 1.0),
    ]
    .iter()
    .map(|x| x.normalize())
    .collect();
    let mut faces = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |i: usize, j: usize, verts: &mut Vec<DVec3>| {
            *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                verts.push(((verts[i] + verts[j]) * 0.5).normalize());
                verts.len() - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                midpoint(a, b, &mut verts),
                midpoint(b, c, &mut verts),
                midpoint(c, a, &mut verts),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    (verts, faces)
}

/// Rays at the vertices and edges of a closed convex mesh: from inside (a
/// point within `inner` of `center`) they must all hit; from outside,
/// entering through the point, they must hit it.
fn shoot_at_mesh_edges(
    verts: &[DVec3],
    faces: &[[usize; 3]],
    center: DVec3,
    inner: f64,
    size: f64,
    seed: u64,
    rays: usize,
) {
    let tris: Vec<Triangle> = faces
        .iter()
        .map(|f| Triangle::new(verts[f[0]], verts[f[1]], verts[f[2]], None))
        .collect();
    let scale = center.abs().max_element() + size;
    let mut rng = Pcg64::seed_from_u64(seed);
    for n in 0..rays {
        let f = faces[rng.random_range(0..faces.len())];
        let e = rng.random_range(0..3usize);
        let (p, q) = (verts[f[e]], verts[f[(e + 1) % 3]]);
        let target = match n % 3 {
            0 => p,
            1 => (p + q) * 0.5,
            _ => p + (q - p) * rng.random_range(0.0..1.0),
        };
        let inside = center + point_in(&mut rng, 1.0) * (inner / 3f64.sqrt());
        let r = Ray::new(inside, (target - inside).normalize());
        let (_, h) = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b))
            .unwrap_or_else(|| panic!("crack: ray {r:?} from inside at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(h.t, (target - inside).length(), 1e-9 * scale);
        // From outside through the same point towards the inside point.
        let dist = size * rng.random_range(0.1..10.0);
        let r = Ray::new(target + r.dir * dist, -r.dir);
        let (_, h) = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b))
            .unwrap_or_else(|| panic!("crack: ray {r:?} entering at {target} missed")); // invariant: the test's own fixed input (a failure fails the test)
        assert_close(h.t, dist, 1e-9 * (scale + dist));
    }
}

#[test]
fn octahedron_and_icosphere_meshes_leave_no_crack() {
    let rot = rotation(v(0.3, 1.2, -0.4));
    let c = v(0.1, -2.3, 0.7);
    let h = v(0.7, 1.3, 0.3);
    let octa: Vec<DVec3> = (0..6)
        .map(|k| c + rot.col(k / 2) * (h[k / 2] * if k % 2 == 0 { 1.0 } else { -1.0 }))
        .collect();
    // Faces: one per octant (x±, y±, z±).
    let mut faces = Vec::new();
    for xs in [0, 1] {
        for ys in [2, 3] {
            for zs in [4, 5] {
                faces.push([xs, ys, zs]);
            }
        }
    }
    // The octahedron's inscribed sphere has radius 1/√(Σ 1/h²).
    let inscribed = 1.0 / (1.0 / (h * h)).element_sum().sqrt();
    shoot_at_mesh_edges(&octa, &faces, c, 0.9 * inscribed, 1.3, 1, 20_000);
    let (verts, faces) = icosphere(3);
    for (center, radius) in [(v(0.1, -2.3, 0.7), 1.7), (v(300.7, 120.1, -55.3), 0.05)] {
        let verts: Vec<DVec3> = verts.iter().map(|p| center + rot * (*p * radius)).collect();
        // The subdivided icosahedron's inscribed sphere is larger than 0.9·R.
        shoot_at_mesh_edges(&verts, &faces, center, 0.9 * radius, radius, 2, 10_000);
        // The geometric normal is the winding's, outward for this mesh.
        for f in &faces {
            let t = Triangle::new(verts[f[0]], verts[f[1]], verts[f[2]], None);
            let centroid = (verts[f[0]] + verts[f[1]] + verts[f[2]]) / 3.0;
            let r = Ray::new(center, (centroid - center).normalize());
            let hit = t.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
            assert!(t.surface(&r, &hit).normal.dot(centroid - center) > 0.0);
        }
    }
}

#[test]
fn mesh_triangles_stay_compact() {
    // Meshes hold up to a million triangles, each boxed in a Shape.
    assert!(
        std::mem::size_of::<Triangle>() <= 80,
        "{}",
        std::mem::size_of::<Triangle>()
    );
}
