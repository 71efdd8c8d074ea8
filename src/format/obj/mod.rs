//! OBJ meshes: their triangles, placed as a `primitive mesh` or
//! `primitive polyhedron` block says, with the polyhedron's texture
//! coordinates and MTL materials.

use super::limits::{Limits, open_regular, read_bounded};
use crate::geometry::Triangle;
use glam::{DMat3, DVec2, DVec3};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::Path;

/// How a block places its OBJ file's vertices, P ↦ origin + post ⊙ (R·(pre ⊙ P)),
/// and what else it reads from the file.
pub(crate) struct Placement {
    /// The translation (`O=`).
    pub origin: DVec3,
    /// The per-axis scale before the rotation (`primitive mesh`'s `scale=`).
    pub pre_scale: DVec3,
    /// The rotation.
    pub rotation: DMat3,
    /// The per-axis scale after the rotation (`primitive polyhedron`'s `size=`).
    pub post_scale: DVec3,
    /// Whether vertex normals follow the scales (the inverse transpose) or,
    /// as PM3 has it, only the rotation.
    pub scale_normals: bool,
    /// Whether the `vt` texture coordinates (and `usemtl` materials) are read.
    pub lineage: bool,
}

impl Placement {
    /// `primitive mesh`: scaled per axis, then rotated about the fixed x
    /// axis, then y, then z (`rotation=`, radians), then translated.
    pub fn mesh(origin: DVec3, scale: DVec3, rotation: DVec3) -> Self {
        Placement {
            origin,
            pre_scale: scale,
            rotation: rotation_xyz(rotation),
            post_scale: DVec3::ONE,
            scale_normals: true,
            lineage: false,
        }
    }

    /// `primitive polyhedron` (PM3): rotated about the world x axis, then
    /// y, then z (`angles=`, degrees), then scaled per world axis
    /// (`size=`), then translated; normals only rotated.
    pub fn polyhedron(origin: DVec3, size: DVec3, degrees: DVec3) -> Self {
        Placement {
            origin,
            pre_scale: DVec3::ONE,
            rotation: rotation_xyz(degrees * (std::f64::consts::PI / 180.0)),
            post_scale: size,
            scale_normals: false,
            lineage: true,
        }
    }
}

/// R = Rz(a.z)·Ry(a.y)·Rx(a.x) (radians, right-handed, fixed axes).
fn rotation_xyz(a: DVec3) -> DMat3 {
    DMat3::from_rotation_z(a.z) * DMat3::from_rotation_y(a.y) * DMat3::from_rotation_x(a.x)
}

/// An OBJ file's triangles, with the materials its faces name.
pub(crate) struct LoadedObj {
    /// The triangles, in file order.
    pub triangles: Vec<Triangle>,
    /// Per triangle: the index in `materials` of its `usemtl` material, if any.
    pub face_materials: Vec<Option<usize>>,
    /// The materials of the MTL files named by `mtllib` (only when read).
    pub materials: Vec<MtlMaterial>,
    /// The `usemtl` names no MTL file defines, with their 1-based lines.
    pub unknown_materials: Vec<(usize, String)>,
}

/// Reads an MTL file named by `mtllib`: its bytes, or a message naming it.
pub(crate) type MtlReader<'a> = &'a dyn Fn(&str) -> Result<Vec<u8>, String>;

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
#[cfg(test)]
pub(crate) fn load_obj(
    path: &Path,
    origin: DVec3,
    scale: DVec3,
    rotation: DVec3,
) -> Result<Vec<Triangle>, String> {
    load_placed(path, &Placement::mesh(origin, scale, rotation), None).map(|o| o.triangles)
}

/// Loads an OBJ file's triangles placed by `at` ([`load_obj`] describes the
/// normals, flips and skips). With `at.lineage`, `vt` coordinates become the
/// triangles' texture coordinates ((v, u): `vt u v` samples row v, column u),
/// and `mtllib` files are read through `mtl` (a missing or bad one is an
/// error naming it and the OBJ line).
pub(crate) fn load_placed(
    path: &Path,
    at: &Placement,
    mtl: Option<MtlReader<'_>>,
) -> Result<LoadedObj, String> {
    let name = path.display();
    let file = open_regular(path).map_err(|e| format!("cannot open mesh file {name}: {e}"))?;
    let bytes = read_bounded(file, Limits::DEFAULT)
        .map_err(|e| format!("cannot read mesh file {name}: {e}"))?;
    let (models, materials) = parse_obj_with(&bytes, if at.lineage { mtl } else { None })
        .map_err(|e| format!("mesh file {name}: {e}"))?;

    let rot = at.rotation;
    // Normals transform by M⁻ᵀ ∝ cof(post)·R·cof(pre) for M = post·R·pre; the
    // cofactor form stays finite for a flattening scale, and sign(det M)
    // keeps the orientation.
    let (pre, post) = (at.pre_scale, at.post_scale);
    let det = pre.x * pre.y * pre.z * post.x * post.y * post.z;
    let mirrored = det < 0.0;
    let cof = |s: DVec3| DVec3::new(s.y * s.z, s.x * s.z, s.x * s.y);
    let sign = if mirrored { -1.0 } else { 1.0 };
    let (cof_pre, cof_post) = (cof(pre) * sign, cof(post));
    let place = |p: DVec3| at.origin + post * (rot * (pre * p));
    let turn = |n: DVec3| {
        if at.scale_normals {
            (cof_post * (rot * (cof_pre * n))).normalize_or_zero()
        } else {
            (rot * n).normalize_or_zero()
        }
    };

    let mut triangles = Vec::new();
    let mut face_materials = Vec::new();
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
        let texcoord = |i: u32| -> Option<DVec2> {
            let i = i as usize * 2;
            let t = mesh.texcoords.get(i..i + 2)?;
            Some(DVec2::new(t[1].into(), t[0].into()))
        };
        let has_normals =
            !mesh.normals.is_empty() && mesh.normal_indices.len() == mesh.indices.len();
        let has_uvs = at.lineage
            && !mesh.texcoords.is_empty()
            && mesh.texcoord_indices.len() == mesh.indices.len();
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
            let mut uvs = if has_uvs {
                // invariant: has_uvs means texcoord_indices is as long as indices.
                let ti = &mesh.texcoord_indices[3 * k..3 * k + 3];
                match (texcoord(ti[0]), texcoord(ti[1]), texcoord(ti[2])) {
                    (Some(ta), Some(tb), Some(tc)) => Some([ta, tb, tc]),
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
                if let Some(t) = uvs.as_mut() {
                    t.swap(1, 2);
                }
            }
            let t = Triangle::new(v[0], v[1], v[2], normals);
            triangles.push(match uvs {
                Some(uvs) => t.with_uvs(uvs),
                None => t,
            });
            face_materials.push(mesh.material_id.filter(|&m| m < materials.len()));
        }
    }
    if triangles.is_empty() {
        return Err(format!("mesh file {name} holds no triangle"));
    }
    let unknown_materials = if at.lineage {
        unknown_usemtl(&bytes, &materials)
    } else {
        Vec::new()
    };
    Ok(LoadedObj {
        triangles,
        face_materials,
        materials,
        unknown_materials,
    })
}

/// The `usemtl` lines (1-based) whose name no loaded material has.
fn unknown_usemtl(bytes: &[u8], materials: &[MtlMaterial]) -> Vec<(usize, String)> {
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("usemtl") {
            continue;
        }
        let name = line.trim().split_once(' ').map_or("", |(_, n)| n.trim());
        if !materials.iter().any(|m| m.name == name) {
            out.push((k + 1, name.to_string()));
        }
    }
    out
}

/// The 1-based line of the first `mtllib` naming `file` (1 if none does).
fn mtllib_line(bytes: &[u8], file: &str) -> usize {
    let text = String::from_utf8_lossy(bytes);
    text.lines()
        .position(|l| {
            let l = l.trim();
            l.starts_with("mtllib") && l.split_once(' ').is_some_and(|(_, n)| n.trim() == file)
        })
        .map_or(1, |k| k + 1)
}

/// One `newmtl` of an MTL file: the keys PM3 reads (`Kd`, `Ks`, `Tf`,
/// `Ni`, `map_Kd`, `map_bump`), as written.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MtlMaterial {
    /// Its name.
    pub name: String,
    /// `Kd r g b`.
    pub kd: Option<DVec3>,
    /// `Ks`: its first number (PM3 reads one, as `refl`).
    pub ks: Option<f64>,
    /// `Tf r g b`.
    pub tf: Option<DVec3>,
    /// `Ni`.
    pub ni: Option<f64>,
    /// `map_Kd`'s file (the word after the key, as PM3 reads it).
    pub map_kd: Option<String>,
    /// `map_bump`'s (or `map_Bump`'s, `bump`'s) file.
    pub map_bump: Option<String>,
}

/// The materials of MTL text (PM3's keys; others are ignored), or the line
/// of a key whose values do not read.
pub(crate) fn parse_mtl(bytes: &[u8]) -> Result<Vec<MtlMaterial>, String> {
    let text = String::from_utf8_lossy(bytes);
    let mut out: Vec<MtlMaterial> = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let bad = |what: &str| format!("line {}: `{key}` needs {what}", k + 1);
        let nums = |n: usize| -> Result<Vec<f64>, String> {
            let v: Vec<f64> = words
                .clone()
                .take(n)
                .map(|w| w.parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect::<Option<_>>()
                .ok_or_else(|| bad(if n == 1 { "a number" } else { "3 numbers" }))?;
            if v.len() < n {
                return Err(bad(if n == 1 { "a number" } else { "3 numbers" }));
            }
            Ok(v)
        };
        if key == "newmtl" {
            let name = line
                .trim()
                .split_once(char::is_whitespace)
                .map_or("", |(_, n)| n.trim());
            out.push(MtlMaterial {
                name: name.to_string(),
                ..MtlMaterial::default()
            });
            continue;
        }
        // Keys before the first `newmtl` belong to no material.
        let Some(m) = out.last_mut() else { continue };
        let v3 = |v: Vec<f64>| DVec3::new(v[0], v[1], v[2]);
        match key {
            "Kd" => m.kd = Some(v3(nums(3)?)),
            "Ks" => m.ks = Some(nums(1)?[0]),
            "Tf" => m.tf = Some(v3(nums(3)?)),
            "Ni" => m.ni = Some(nums(1)?[0]),
            "map_Kd" | "map_bump" | "map_Bump" | "bump" => {
                let file = words.next().ok_or_else(|| bad("a file name"))?.to_string();
                if key == "map_Kd" {
                    m.map_kd = Some(file);
                } else {
                    m.map_bump = Some(file);
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The models of OBJ text, or tobj's error with the line it is about
/// (materials are not read).
#[cfg(feature = "fuzzing")]
pub(crate) fn parse_obj(bytes: &[u8]) -> Result<Vec<tobj::Model>, String> {
    parse_obj_with(bytes, None).map(|(models, _)| models)
}

/// The models of OBJ text and, when `mtl` reads them, the materials of its
/// `mtllib` files (in the order tobj numbers them); or the error with the
/// line it is about.
fn parse_obj_with(
    bytes: &[u8],
    mtl: Option<MtlReader<'_>>,
) -> Result<(Vec<tobj::Model>, Vec<MtlMaterial>), String> {
    // Exporters write comments in local encodings (PM3's dragon2.obj: GBK);
    // tobj reads lines as UTF-8, so bytes that are not become U+FFFD (they
    // only ever matter in comments and names). Same line breaks, same lines.
    let lossy = String::from_utf8_lossy(bytes);
    let bytes = lossy.as_bytes();
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj ignores a material library that fails to load: remember why.
    // MTL text is read here, not by tobj (whose reader panics on a short `Ks`).
    let failure: RefCell<Option<String>> = RefCell::new(None);
    let found: RefCell<Vec<MtlMaterial>> = RefCell::new(Vec::new());
    let loader = |p: &Path| -> tobj::MTLLoadResult {
        let Some(read) = mtl else {
            return Err(tobj::LoadError::GenericFailure);
        };
        let file = p.to_string_lossy();
        let parsed = read(&file)
            .and_then(|text| parse_mtl(&text).map_err(|e| format!("material file `{file}`: {e}")));
        match parsed {
            Ok(list) => {
                let mut names = HashMap::new();
                let mut stubs = Vec::new();
                for m in &list {
                    names.insert(m.name.clone(), stubs.len());
                    stubs.push(tobj::Material {
                        name: m.name.clone(),
                        ..tobj::Material::default()
                    });
                }
                found.borrow_mut().extend(list);
                Ok((stubs, names))
            }
            Err(e) => {
                let line = mtllib_line(bytes, &file);
                failure
                    .borrow_mut()
                    .get_or_insert(format!("line {line} (`mtllib`): {e}"));
                Err(tobj::LoadError::GenericFailure)
            }
        }
    };
    let parse = |mut text: &[u8]| {
        found.borrow_mut().clear();
        tobj::load_obj_buf(&mut text, &options, loader)
    };
    match parse(bytes) {
        Ok((models, _)) => match failure.take() {
            Some(e) => Err(e),
            None => Ok((models, found.take())),
        },
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

#[cfg(test)]
mod tests;
