//! The primitives' blocks: each kind's keys read into its shape, checked
//! for geometric sense (one function per kind, named by its schema row).
//!
//! Defaults chosen where the format leaves them open:
//! - a plane without `Dx=`/`Dy=` gets texture axes (e1, e2) of
//!   [`crate::geometry::axis_frame`] of its unit normal (x and y for N = z);
//!   with only one of them given, the other is that one turned 90° about N
//!   (same length), so Dx × Dy points along N;
//! - a cube without `Dx=`/`Dy=` is axis-aligned (x, y).
//!
//! The lineages' own kinds (`rectangle`, `polyhedron`, `NomalBall`,
//! `NomalPlane`, `Bezier`) follow the lineages spec, §4; blocks that only
//! an unread file format has (Z17's tensor-product `bezier`, scene4's
//! `torus`, `cylinder O= N= R= H=`, `cube O= size=`) build nothing and warn.

use super::assets::Assets;
use super::bezier_forms;
use super::block_keys::BlockKeys;
use super::diags::{Site, When};
use super::obj::{MtlMaterial, Placement};
use super::values::{PARALLEL_SINE, Value, parallel, unit};
use crate::geometry::{
    Bezier, Cube, Cylinder, Plane, Rectangle, Shape, Sphere, Square, Triangle, axis_frame,
};
use crate::scene::{Dialect, Material, Texture};
use glam::{DMat3, DVec2, DVec3};

/// How far a cube's `Dx=`/`Dy=` may be from unit length and perpendicular
/// before a warning says they were adjusted.
const ORTHONORMAL_TOLERANCE: f64 = 1e-9;
/// What one primitive block builds, or `None` after an error (reported).
pub(crate) type Shapes = Option<Built>;

/// Adds a decoded texture to the scene and gives its index.
pub(crate) type AddTexture<'a> = dyn FnMut(Texture) -> u32 + 'a;

/// The shapes of one block, in file order: most blocks make one, held
/// without an allocation (one saved per block).
pub(crate) enum ShapeList {
    /// A block's one shape.
    One(Shape),
    /// Any number of them (a mesh, a tetrahedron, a Bézier's pieces).
    Many(Vec<Shape>),
}

impl Default for ShapeList {
    fn default() -> Self {
        ShapeList::Many(Vec::new())
    }
}

impl ShapeList {
    /// The shapes, in file order.
    pub(crate) fn as_slice(&self) -> &[Shape] {
        match self {
            ShapeList::One(shape) => std::slice::from_ref(shape),
            ShapeList::Many(shapes) => shapes,
        }
    }
}

impl IntoIterator for ShapeList {
    type Item = Shape;
    type IntoIter = std::iter::Chain<std::option::IntoIter<Shape>, std::vec::IntoIter<Shape>>;

    fn into_iter(self) -> Self::IntoIter {
        let (one, many) = match self {
            ShapeList::One(shape) => (Some(shape), Vec::new()),
            ShapeList::Many(shapes) => (None, shapes),
        };
        one.into_iter().chain(many)
    }
}

/// The shapes of one primitive block, and the materials some of them have
/// in place of the block's (a polyhedron's `usemtl` faces).
#[derive(Default)]
pub(crate) struct Built {
    /// The shapes, in file order.
    pub shapes: ShapeList,
    /// Materials of their own, each to be added to the scene once.
    pub materials: Vec<Material>,
    /// Per shape, the index in `materials` of its own material; empty when
    /// every shape has the block's.
    pub material_of: Vec<Option<u32>>,
}

impl Built {
    /// Shapes that all have the block's material.
    pub(crate) fn of(shapes: Vec<Shape>) -> Shapes {
        Built::with(ShapeList::Many(shapes))
    }

    /// One shape with the block's material.
    pub(crate) fn one(shape: Shape) -> Shapes {
        Built::with(ShapeList::One(shape))
    }

    /// `shapes`, all with the block's material.
    fn with(shapes: ShapeList) -> Shapes {
        Some(Built {
            shapes,
            ..Built::default()
        })
    }

    /// Nothing: a block glint skips (after warning).
    fn skipped(b: &mut BlockKeys<'_>, what: &str) -> Shapes {
        b.diags.warn(
            b.header,
            format!("{what}: no lineage reads this; skipped"),
            None,
        );
        Some(Built::default())
    }
}

/// `primitive sphere`: `O= R=`, texture directions `De= Dc=`.
pub(crate) fn sphere(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let (origin, textured) = (b.origin(), b.textured() || b.fields.get("NT").is_some());
    let r = b.radius("R");
    let de = b.direction("De", DVec3::Z, textured);
    let dc = b.direction("Dc", DVec3::Y, textured);
    let (r, de, dc) = (r?, de?, dc?);
    Built::one(Shape::Sphere(Sphere::with_orientation(origin, r, de, dc)))
}

/// `primitive square`: `O=` and half-edge vectors `Dx= Dy=`.
pub(crate) fn square(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let origin = b.origin();
    let (dx, dy) = b.span_pair("Dx", "Dy")?;
    Built::one(Shape::Square(Box::new(Square::new(origin, dx, dy))))
}

/// `primitive cylinder`: axis `O1= O2=`, radius `R=`.
pub(crate) fn cylinder(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    if b.fields.get("O1").is_none() && (b.fields.get("N").is_some() || b.fields.get("H").is_some())
    {
        return Built::skipped(
            b,
            "a `primitive cylinder` with `N=`/`H=` and no `O1=` (F's scene4)",
        );
    }
    let axis = b.axis();
    let r = b.radius("R");
    let ((o1, o2), r) = (axis?, r?);
    Built::one(Shape::Cylinder(Box::new(Cylinder::new(o1, o2, r))))
}

/// `primitive mesh`: the triangles of OBJ file `file=`, placed by `O= scale= rotation=`.
pub(crate) fn mesh(assets: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let (name, site) = match b.fields.text("file") {
        Some((n, s)) => (n.to_string(), s),
        None => {
            if !b.fields.failed("file") {
                b.diags.error(
                    b.header,
                    "a `primitive mesh` block needs `file=` (the OBJ file)",
                    None,
                );
            }
            return None;
        }
    };
    let origin = b.origin();
    let rotation = b.fields.v3("rotation").map_or(DVec3::ZERO, |(v, _)| v);
    let scale = match b.fields.v3("scale") {
        Some((s, site)) if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 => {
            b.diags.error(
                site,
                "`scale=` is 0 along some axis; the mesh would be flat",
                None,
            );
            return None;
        }
        Some((s, _)) => s,
        None => DVec3::ONE,
    };
    let at = Placement::mesh(origin, scale, rotation);
    let loaded = assets.mesh(&name, site, &at, b.diags)?;
    Built::of(
        loaded
            .triangles
            .into_iter()
            .map(|t| Shape::Triangle(Box::new(t)))
            .collect(),
    )
}

/// `primitive plane`: normal `N=`, offset `R=`, texture axes (defaults in the module docs).
pub(crate) fn plane(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    Built::one(Shape::Plane(Box::new(read_plane(b)?)))
}

/// The plane of a `plane` or `NomalPlane` block.
fn read_plane(b: &mut BlockKeys<'_>) -> Option<Plane> {
    let textured = b.textured() || b.fields.get("NT").is_some();
    let (n, site) = b.need_v3("N", "its normal")?;
    let Some(n) = unit(n) else {
        b.diags
            .error(site, "`N=` has zero length; a plane needs a normal", None);
        return None;
    };
    let r = b.fields.num("R").map_or(0.0, |(x, _)| x);
    let dx = b.texture_axis("Dx", textured);
    let dy = b.texture_axis("Dy", textured);
    let (dx, dy) = match (dx?, dy?) {
        (Some(dx), Some(dy)) => (dx, dy),
        (Some(dx), None) => (dx, n.cross(dx)),
        (None, Some(dy)) => (dy.cross(n), dy),
        (None, None) => axis_frame(n),
    };
    Some(Plane::new(n, r, dx, dy))
}

/// `primitive cube`: `O=`, half-lengths `x= y= z=` along `Dx=`, `Dy=` and
/// their cross product, Dx and Dy made orthonormal (Gram–Schmidt, keeping
/// Dx's direction) with a warning where the input was not already so.
pub(crate) fn cube(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    if b.fields.get("size").is_some() {
        return Built::skipped(b, "a `primitive cube` with `size=` (F's scene4)");
    }
    let origin = b.origin();
    let dx = b.fields.v3("Dx");
    let dy = b.fields.v3("Dy");
    let hx = b.half_length("x");
    let hy = b.half_length("y");
    let hz = b.half_length("z");
    let ux = match dx {
        Some((v, site)) => b.nonzero("Dx", v, site),
        None => Some(DVec3::X),
    };
    let uy = match dy {
        Some((v, site)) => b.nonzero("Dy", v, site),
        None => Some(DVec3::Y),
    };
    let (ux, uy) = (ux?, uy?);
    let perp = uy - ux * uy.dot(ux);
    let Some(uy_perp) = unit(perp).filter(|_| perp.length() > PARALLEL_SINE) else {
        let site = dy.or(dx).map_or(b.header, |(_, s)| s);
        b.diags.error(
            site,
            "`Dy=` is parallel to `Dx=`; a cube needs two independent directions",
            None,
        );
        return None;
    };
    if let Some((v, site)) = dx
        && (v.length() - 1.0).abs() > ORTHONORMAL_TOLERANCE
    {
        b.diags.warn(
            site,
            format!(
                "`Dx=` is not a unit vector (length {}); normalised",
                v.length()
            ),
            None,
        );
    }
    if let Some((v, site)) = dy {
        let not_unit = (v.length() - 1.0).abs() > ORTHONORMAL_TOLERANCE;
        let not_perp = v.dot(ux).abs() > ORTHONORMAL_TOLERANCE * v.length().max(1.0);
        if not_unit || not_perp {
            b.diags.warn(
                site,
                "`Dy=` is not a unit vector perpendicular to `Dx=`; made so, keeping `Dx=`'s direction",
                None,
            );
        }
    }
    let size = DVec3::new(hx?, hy?, hz?);
    Built::one(Shape::Cube(Box::new(Cube::new(origin, ux, uy_perp, size))))
}

/// `primitive bezier`: a surface of revolution about `O1= O2=`, profile
/// `P= z r` (at least two control points); or written in lazycal's or
/// abcbdf's form (see [`bezier_forms`]).
pub(crate) fn bezier(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    if b.fields.get("newPoint").is_some() && b.fields.get("P").is_none() {
        return Built::skipped(
            b,
            "a `primitive bezier` with `newPoint=` and no `P=` (Z17's tensor-product patch)",
        );
    }
    let has = |keys: &[&str]| {
        keys.iter()
            .any(|k| b.fields.get(k).is_some() || b.fields.failed(k))
    };
    if has(&bezier_forms::AXIS_KEYS) {
        return Built::one(bezier_forms::axis_form(b)?);
    }
    if has(&bezier_forms::CUBIC_KEYS) {
        return Built::one(bezier_forms::cubic_form(b)?);
    }
    let axis = b.axis();
    let mut points: Vec<(DVec2, Site)> = Vec::new();
    for f in b.fields.list() {
        match f.value {
            Value::V2(p) if f.name == "P" => points.push((p, f.site)),
            Value::V3(p) if f.name == "P" => {
                b.diags.warn(
                    f.site,
                    "`P=` takes 2 numbers (z r) in a bezier about `O1= O2=`: the third is ignored",
                    None,
                );
                points.push((p.truncate(), f.site));
            }
            _ => {}
        }
    }
    if points.len() < 2 && !b.fields.failed("P") {
        let site = points.first().map_or(b.header, |(_, s)| *s);
        b.diags.error(
            site,
            format!(
                "a `primitive bezier` block needs at least 2 `P= z r` control points, found {}",
                points.len()
            ),
            None,
        );
        return None;
    }
    // Any degree is valid in the format; glint intersects up to degree 64,
    // far beyond what a hand-made profile needs.
    let max = Bezier::MAX_DEGREE + 1;
    if points.len() > max {
        b.diags.error(
            points[max].1,
            format!(
                "a `primitive bezier` profile has at most {max} control points (degree {}) in glint, found {}",
                Bezier::MAX_DEGREE,
                points.len()
            ),
            Some(
                "split the profile into several `primitive bezier` blocks of lower degree"
                    .to_string(),
            ),
        );
        return None;
    }
    let (o1, o2) = axis?;
    let profile = points.into_iter().map(|(p, _)| p).collect();
    Built::one(Shape::Bezier(Box::new(Bezier::new(o1, o2, profile))))
}

/// `primitive triangle`: corners `O1= O2= O3=`, not collinear; or
/// abcbdf's `A0= A1= A2=` with the shading normal `N=` (the triangle's own
/// where it is missing or zero).
pub(crate) fn triangle(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let abcbdf = ["A0", "A1", "A2"]
        .iter()
        .any(|k| b.fields.get(k).is_some() || b.fields.failed(k));
    let keys = if abcbdf {
        ["A0", "A1", "A2"]
    } else {
        ["O1", "O2", "O3"]
    };
    let p0 = b.need_v3(keys[0], "the first corner");
    let p1 = b.need_v3(keys[1], "the second corner");
    let p2 = b.need_v3(keys[2], "the third corner");
    let ((p0, _), (p1, _), (p2, _)) = (p0?, p1?, p2?);
    if collinear(p0, p1, p2) {
        b.diags.error(
            b.header,
            format!(
                "degenerate triangle: its corners `{}=`, `{}=`, `{}=` are collinear",
                keys[0], keys[1], keys[2]
            ),
            None,
        );
        return None;
    }
    let normals = b
        .fields
        .v3("N")
        .filter(|_| abcbdf)
        .and_then(|(n, _)| unit(n))
        .map(|n| [n; 3]);
    Built::one(Shape::Triangle(Box::new(Triangle::new(
        p0, p1, p2, normals,
    ))))
}

/// Whether three points lie on one line (or two coincide).
fn collinear(p0: DVec3, p1: DVec3, p2: DVec3) -> bool {
    match (unit(p1 - p0), unit(p2 - p0)) {
        (Some(a), Some(c)) => parallel(a, c),
        _ => true,
    }
}

/// `primitive tetra` (abcbdf): the tetrahedron of corners `V0=` … `V3=`,
/// four triangles facing out. (abcbdf's own reader hands the block's keys
/// to its last face, which reads none of them: it draws nothing.)
pub(crate) fn tetra(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let v0 = b.need_v3("V0", "a corner");
    let v1 = b.need_v3("V1", "a corner");
    let v2 = b.need_v3("V2", "a corner");
    let v3 = b.need_v3("V3", "a corner");
    let v = [v0?.0, v1?.0, v2?.0, v3?.0];
    let volume = (v[1] - v[0]).cross(v[2] - v[0]).dot(v[3] - v[0]);
    let size = (v[1] - v[0])
        .length()
        .max((v[2] - v[0]).length())
        .max((v[3] - v[0]).length());
    if volume.abs() <= PARALLEL_SINE * size * size * size {
        b.diags.error(
            b.header,
            "degenerate tetrahedron: its corners `V0=` ... `V3=` lie in one plane",
            None,
        );
        return None;
    }
    b.diags.warn_when(
        When::In(Dialect::A18),
        b.header,
        "abcbdf's reader draws no tetrahedron (its keys reach none of the four faces); \
         glint draws it",
        None,
    );
    // Each face, its corners turned so that (b − a) × (c − a) points away
    // from the fourth corner.
    let faces = [[0, 1, 2, 3], [0, 1, 3, 2], [0, 2, 3, 1], [1, 2, 3, 0]];
    let shapes = faces
        .iter()
        .map(|&[a, p, q, away]| {
            let outward = (v[p] - v[a]).cross(v[q] - v[a]).dot(v[away] - v[a]) < 0.0;
            let (p, q) = if outward { (p, q) } else { (q, p) };
            Shape::Triangle(Box::new(Triangle::new(v[a], v[p], v[q], None)))
        })
        .collect();
    Built::of(shapes)
}

/// `primitive rectangle` (Z14, Z17, P): the plane `N= R=` where both
/// texture coordinates of `Dx= Dy=` (measured from the world origin) lie in
/// [0, 1]; N, Dx and Dy must be independent.
pub(crate) fn rectangle(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    let n = b.need_v3("N", "its normal");
    let dx = b.need_v3("Dx", "an edge vector");
    let dy = b.need_v3("Dy", "an edge vector");
    let (n, (dx, dx_site), (dy, dy_site)) = (n?, dx?, dy?);
    let un = b.nonzero("N", n.0, n.1);
    let ux = b.nonzero("Dx", dx, dx_site);
    let uy = b.nonzero("Dy", dy, dy_site);
    let (un, ux, uy) = (un?, ux?, uy?);
    // The volume of the unit vectors: 0 when the region is a strip (or empty).
    if DMat3::from_cols(un, ux, uy).determinant().abs() <= PARALLEL_SINE {
        b.diags.error(
            dy_site,
            "`N=`, `Dx=` and `Dy=` lie in one plane; a `primitive rectangle` needs them independent",
            None,
        );
        return None;
    }
    let r = b.fields.num("R").map_or(0.0, |(x, _)| x);
    Built::one(Shape::Rectangle(Box::new(Rectangle::new(un, r, dx, dy))))
}

/// Warns that a V normal-map block without `NT=` draws its plain shape.
fn plain_without_normal_map(b: &mut BlockKeys<'_>, plain: &str) {
    if b.fields.get("NT").is_none() && !b.fields.failed("NT") {
        b.diags.warn(
            b.header,
            format!(
                "a `{}` without `NT=` (its normal map): drawn as a plain {plain}",
                b.title
            ),
            Some("add `NT= FILE.bmp`, or write `primitive {plain}`".to_string()),
        );
    }
}

/// `primitive NomalBall` (V): a sphere (`O= R= De= Dc=`) with the normal map
/// `NT=` (a material key, read with the others).
pub(crate) fn nomal_ball(a: &mut Assets, b: &mut BlockKeys<'_>, t: &mut AddTexture<'_>) -> Shapes {
    plain_without_normal_map(b, "sphere");
    sphere(a, b, t)
}

/// `primitive NomalPlane` (V): a plane (`N= R= Dx= Dy=`) with the normal map `NT=`.
pub(crate) fn nomal_plane(a: &mut Assets, b: &mut BlockKeys<'_>, t: &mut AddTexture<'_>) -> Shapes {
    plain_without_normal_map(b, "plane");
    plane(a, b, t)
}

/// The control points (x, y) of V's `Bezier` profile, before `ratio=`.
const V_PROFILE: [(f64, f64); 7] = [
    (1.5, 0.0),
    (2.9, 13.0),
    (-3.5, 15.0),
    (-5.5, 21.0),
    (-1.1, 22.5),
    (-5.5, 25.0),
    (0.0, 38.0),
];

/// `primitive Bezier` (V): V's fixed degree-6 vase profile, scaled by
/// `ratio=` and widened by `R=`, standing on its base centre `O=`: the
/// `bezier` surface with O1 = O + 38·ratio·ẑ, O2 = O and control points
/// (ratio·y, R + ratio·x); open; its texture angle runs counter-clockwise
/// about +z from +x, as V's does.
pub(crate) fn lineage_bezier(
    _: &mut Assets,
    b: &mut BlockKeys<'_>,
    _: &mut AddTexture<'_>,
) -> Shapes {
    let origin = b.origin();
    let r = b.need_num("R", "the radius added to the profile");
    let ratio = b.need_num("ratio", "the profile's scale");
    let ((r, _), (ratio, site)) = (r?, ratio?);
    if ratio == 0.0 {
        b.diags
            .error(site, "`ratio=` is 0: the vase would have no height", None);
        return None;
    }
    let top = origin + DVec3::Z * (38.0 * ratio);
    let profile = V_PROFILE
        .iter()
        .map(|&(x, y)| DVec2::new(ratio * y, r + ratio * x))
        .collect();
    let shape = Bezier::new(top, origin, profile).with_angle_frame(DVec3::X, DVec3::Y);
    Built::one(Shape::Bezier(Box::new(shape)))
}

/// `primitive torus` (F's scene4): no lineage reads it; skipped.
pub(crate) fn torus(_: &mut Assets, b: &mut BlockKeys<'_>, _: &mut AddTexture<'_>) -> Shapes {
    Built::skipped(b, "a `primitive torus` (F's scene4)")
}

/// `primitive polyhedron` (PM3, Z17): the OBJ file `mesh=`, rotated by
/// `angles=` (degrees: about world x, then y, then z), scaled per axis by
/// `size=`, moved to `O=`; its `vt` texture the triangles, and the faces
/// after a `usemtl` get that MTL material instead of the block's.
pub(crate) fn polyhedron(
    assets: &mut Assets,
    b: &mut BlockKeys<'_>,
    add_texture: &mut AddTexture<'_>,
) -> Shapes {
    let (name, site) = match b.fields.text("mesh") {
        Some((n, s)) => (n.to_string(), s),
        None => {
            if !b.fields.failed("mesh") {
                b.diags.error(
                    b.header,
                    "a `primitive polyhedron` block needs `mesh=` (the OBJ file)",
                    None,
                );
            }
            return None;
        }
    };
    let origin = b.origin();
    let angles = b.fields.v3("angles").map_or(DVec3::ZERO, |(v, _)| v);
    let size = match b.fields.v3("size") {
        Some((s, site)) if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 => {
            b.diags.error(
                site,
                "`size=` is 0 along some axis; the polyhedron would be flat",
                None,
            );
            return None;
        }
        Some((s, _)) => s,
        None => DVec3::ONE,
    };
    let at = Placement::polyhedron(origin, size, angles);
    let loaded = assets.mesh(&name, site, &at, b.diags)?;
    for (line, m) in &loaded.unknown_materials {
        b.diags.warn(
            site,
            format!(
                "line {line} of `{name}`: `usemtl {m}` names no material of its MTL files; \
                 those faces keep the block's material"
            ),
            None,
        );
    }
    let mut materials = Vec::with_capacity(loaded.materials.len());
    for m in &loaded.materials {
        materials.push(mtl_material(m, assets, b, site, add_texture)?);
    }
    let material_of = if loaded.face_materials.iter().any(Option::is_some) {
        loaded
            .face_materials
            .iter()
            .map(|m| m.and_then(|i| u32::try_from(i).ok()))
            .collect()
    } else {
        Vec::new()
    };
    Some(Built {
        shapes: ShapeList::Many(
            loaded
                .triangles
                .into_iter()
                .map(|t| Shape::Triangle(Box::new(t)))
                .collect(),
        ),
        materials,
        material_of,
    })
}

/// PM3's reading of an MTL material (replacing the block's): `Kd` gives
/// diff = max(Kd) and color = Kd/diff; `Ks` (one number) refl; `Tf` absor,
/// and a `Tf` of mean below 1 makes it clear glass (refr = 1, no diff, spec
/// or refl); `Ni` rindex; `map_Kd` its texture. `map_bump` is not rendered.
fn mtl_material(
    m: &MtlMaterial,
    assets: &mut Assets,
    b: &mut BlockKeys<'_>,
    site: Site,
    add_texture: &mut AddTexture<'_>,
) -> Option<Material> {
    let mut out = Material::default();
    if let Some(kd) = m.kd {
        let diff = kd.max_element();
        out.diff = diff.max(0.0);
        out.color = if diff > 0.0 { kd / diff } else { DVec3::ZERO };
    }
    if let Some(ks) = m.ks {
        out.refl = ks;
    }
    if let Some(tf) = m.tf {
        out.absor = tf;
        if tf.element_sum() / 3.0 < 1.0 {
            out.refr = 1.0;
            (out.diff, out.spec, out.refl) = (0.0, 0.0, 0.0);
        }
    }
    if let Some(ni) = m.ni {
        out.rindex = ni;
    }
    if out.refr > 0.0 && out.rindex <= 0.0 {
        b.diags.warn(
            site,
            format!(
                "material `{}` is transparent (`Tf`) but has no `Ni` > 0; using rindex 1",
                m.name
            ),
            None,
        );
        out.rindex = 1.0;
    }
    if let Some(file) = &m.map_kd {
        out.texture = Some(assets.texture(file, site, b.diags, add_texture)?);
    }
    if let Some(file) = &m.map_bump {
        b.diags.warn(
            site,
            format!(
                "material `{}`: bump map `{file}` (`map_bump`) not rendered yet",
                m.name
            ),
            None,
        );
    }
    Some(out)
}
