//! OBJ meshes: their triangles, placed as a `primitive mesh` block says.

use super::limits::{Limits, open_regular, read_bounded};
use crate::geometry::Triangle;
use glam::{DMat3, DVec3};
use std::path::Path;

/// Loads every model of an OBJ file as triangles (polygons are triangulated),
/// each vertex P placed at `origin + R·(scale ⊙ P)` with
/// R = Rz(rotation.z)·Ry(rotation.y)·Rx(rotation.x): scaled per axis, then
/// rotated about the fixed x axis, then y, then z (radians), then translated.
///
/// OBJ vertex normals are kept (transformed by the inverse transpose of the
/// scale and rotation, normalised), and a triangle whose winding disagrees
/// with them is flipped so its geometric normal points the same way; a
/// mirroring scale keeps the winding's outward side. Zero-area triangles are
/// skipped. Errors (unreadable file, bad OBJ, no triangle) are returned as
/// a message naming the file (and the line, for bad OBJ).
pub(crate) fn load_obj(
    path: &Path,
    origin: DVec3,
    scale: DVec3,
    rotation: DVec3,
) -> Result<Vec<Triangle>, String> {
    let name = path.display();
    let file = open_regular(path).map_err(|e| format!("cannot open mesh file {name}: {e}"))?;
    let bytes = read_bounded(file, Limits::DEFAULT)
        .map_err(|e| format!("cannot read mesh file {name}: {e}"))?;
    let models = parse_obj(&bytes).map_err(|e| format!("mesh file {name}: {e}"))?;

    let rot = DMat3::from_rotation_z(rotation.z)
        * DMat3::from_rotation_y(rotation.y)
        * DMat3::from_rotation_x(rotation.x);
    // Normals transform by (R·S)⁻ᵀ = R·S⁻¹ ∝ R·cof(S); the cofactor form stays
    // finite for a flattening scale, and sign(det S) keeps the orientation.
    let det = scale.x * scale.y * scale.z;
    let mirrored = det < 0.0;
    let cofactor = DVec3::new(scale.y * scale.z, scale.x * scale.z, scale.x * scale.y)
        * if mirrored { -1.0 } else { 1.0 };
    let place = |p: DVec3| origin + rot * (scale * p);
    let turn = |n: DVec3| (rot * (cofactor * n)).normalize_or_zero();

    let mut triangles = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let position = |i: u32| -> Option<DVec3> {
            let i = i as usize * 3;
            let p = mesh.positions.get(i..i + 3)?;
            Some(DVec3::new(p[0].into(), p[1].into(), p[2].into()))
        };
        let normal = |i: u32| -> Option<DVec3> {
            let i = i as usize * 3;
            let n = mesh.normals.get(i..i + 3)?;
            Some(DVec3::new(n[0].into(), n[1].into(), n[2].into()))
        };
        let has_normals =
            !mesh.normals.is_empty() && mesh.normal_indices.len() == mesh.indices.len();
        triangles.reserve(mesh.indices.len() / 3);
        for (k, face) in mesh.indices.chunks_exact(3).enumerate() {
            let (Some(a), Some(b), Some(c)) =
                (position(face[0]), position(face[1]), position(face[2]))
            else {
                return Err(format!(
                    "mesh file {name}: triangle {} of object '{}' refers to a missing vertex",
                    k + 1,
                    model.name
                ));
            };
            let mut v = [place(a), place(b), place(c)];
            let cross = (v[1] - v[0]).cross(v[2] - v[0]);
            if !(cross.length_squared() > 0.0 && cross.is_finite()) {
                continue;
            }
            let mut normals = if has_normals {
                // invariant: has_normals means normal_indices is as long as indices.
                let ni = &mesh.normal_indices[3 * k..3 * k + 3];
                match (normal(ni[0]), normal(ni[1]), normal(ni[2])) {
                    (Some(na), Some(nb), Some(nc)) => {
                        let n = [turn(na), turn(nb), turn(nc)];
                        n.iter().all(|n| *n != DVec3::ZERO).then_some(n)
                    }
                    _ => None,
                }
            } else {
                None
            };
            let flip = match &normals {
                Some(n) => (n[0] + n[1] + n[2]).dot(cross) < 0.0,
                None => mirrored,
            };
            if flip {
                v.swap(1, 2);
                if let Some(n) = normals.as_mut() {
                    n.swap(1, 2);
                }
            }
            triangles.push(Triangle::new(v[0], v[1], v[2], normals));
        }
    }
    if triangles.is_empty() {
        return Err(format!("mesh file {name} holds no triangle"));
    }
    Ok(triangles)
}

/// The models of OBJ text, or tobj's error with the line it is about.
pub(crate) fn parse_obj(bytes: &[u8]) -> Result<Vec<tobj::Model>, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are not used: never read the MTL files an OBJ names.
    let parse = |mut text: &[u8]| {
        tobj::load_obj_buf(&mut text, &options, |_| {
            Err(tobj::LoadError::GenericFailure)
        })
    };
    match parse(bytes) {
        Ok((models, _)) => Ok(models),
        Err(e) => {
            let line = first_failing_line(bytes, |prefix| parse(prefix).is_err());
            Err(format!("line {line}: {e}"))
        }
    }
}

/// The 1-based line where `fails` starts to fail on the first lines of
/// `bytes` (which fails as a whole): tobj stops at the first bad line, so
/// a prefix fails exactly when it holds that line; found by bisection.
fn first_failing_line(bytes: &[u8], fails: impl Fn(&[u8]) -> bool) -> usize {
    let ends: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .map(|(k, _)| k + 1)
        .chain((bytes.last() != Some(&b'\n')).then_some(bytes.len()))
        .collect();
    // Lines 1..=lo pass, lines 1..=hi fail.
    let (mut lo, mut hi) = (0, ends.len());
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        let end = ends.get(mid - 1).copied().unwrap_or(bytes.len());
        if fails(bytes.get(..end).unwrap_or_default()) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi.max(1)
}
