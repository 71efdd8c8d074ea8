//! The primitives' blocks: each kind's keys read into its shape, checked
//! for geometric sense (one function per kind, named by its schema row).
//!
//! Defaults chosen where the format leaves them open:
//! - a plane without `Dx=`/`Dy=` gets texture axes (e1, e2) of
//!   [`crate::geometry::axis_frame`] of its unit normal (x and y for N = z);
//!   with only one of them given, the other is that one turned 90° about N
//!   (same length), so Dx × Dy points along N;
//! - a cube without `Dx=`/`Dy=` is axis-aligned (x, y).

use super::assets::{Assets, Placement};
use super::block::Block;
use super::diags::Site;
use super::values::{PARALLEL_SINE, Value, parallel, unit};
use crate::geometry::{Bezier, Cube, Cylinder, Plane, Shape, Sphere, Square, Triangle, axis_frame};
use glam::{DVec2, DVec3};

/// How far a cube's `Dx=`/`Dy=` may be from unit length and perpendicular
/// before a warning says they were adjusted.
const ORTHONORMAL_TOLERANCE: f64 = 1e-9;
/// The shapes of one primitive block, or `None` after an error (reported).
pub(crate) type Shapes = Option<Vec<Shape>>;

/// `primitive sphere`: `O= R=`, texture directions `De= Dc=`.
pub(crate) fn sphere(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let (origin, textured) = (b.origin(), b.textured());
    let r = b.radius("R");
    let de = b.direction("De", DVec3::Z, textured);
    let dc = b.direction("Dc", DVec3::Y, textured);
    let (r, de, dc) = (r?, de?, dc?);
    Some(vec![Shape::Sphere(Sphere::with_orientation(
        origin, r, de, dc,
    ))])
}

/// `primitive square`: `O=` and half-edge vectors `Dx= Dy=`.
pub(crate) fn square(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let origin = b.origin();
    let (dx, dy) = b.span_pair("Dx", "Dy")?;
    Some(vec![Shape::Square(Box::new(Square::new(origin, dx, dy)))])
}

/// `primitive cylinder`: axis `O1= O2=`, radius `R=`.
pub(crate) fn cylinder(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let axis = b.axis();
    let r = b.radius("R");
    let ((o1, o2), r) = (axis?, r?);
    Some(vec![Shape::Cylinder(Box::new(Cylinder::new(o1, o2, r)))])
}

/// `primitive mesh`: the triangles of OBJ file `file=`, placed by `O= scale= rotation=`.
pub(crate) fn mesh(assets: &mut Assets, b: &mut Block<'_>) -> Shapes {
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
    let at = Placement {
        origin,
        scale,
        rotation,
    };
    let triangles = assets.mesh(&name, site, &at, b.diags)?;
    Some(
        triangles
            .into_iter()
            .map(|t| Shape::Triangle(Box::new(t)))
            .collect(),
    )
}

/// `primitive plane`: normal `N=`, offset `R=`, texture axes (defaults in the module docs).
pub(crate) fn plane(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let textured = b.textured();
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
    Some(vec![Shape::Plane(Box::new(Plane::new(n, r, dx, dy)))])
}

/// `primitive cube`: `O=`, half-lengths `x= y= z=` along `Dx=`, `Dy=` and
/// their cross product, Dx and Dy made orthonormal (Gram–Schmidt, keeping
/// Dx's direction) with a warning where the input was not already so.
pub(crate) fn cube(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
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
    Some(vec![Shape::Cube(Box::new(Cube::new(
        origin, ux, uy_perp, size,
    )))])
}

/// `primitive bezier`: a surface of revolution about `O1= O2=`, profile
/// `P= z r` (at least two control points).
pub(crate) fn bezier(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let axis = b.axis();
    let points: Vec<(DVec2, Site)> = b
        .fields
        .list
        .iter()
        .filter_map(|f| match f.value {
            Value::V2(p) if f.name == "P" => Some((p, f.site)),
            _ => None,
        })
        .collect();
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
    Some(vec![Shape::Bezier(Box::new(Bezier::new(o1, o2, profile)))])
}

/// `primitive triangle`: corners `O1= O2= O3=`, not collinear.
pub(crate) fn triangle(_: &mut Assets, b: &mut Block<'_>) -> Shapes {
    let p0 = b.need_v3("O1", "the first corner");
    let p1 = b.need_v3("O2", "the second corner");
    let p2 = b.need_v3("O3", "the third corner");
    let ((p0, _), (p1, _), (p2, _)) = (p0?, p1?, p2?);
    let degenerate = match (unit(p1 - p0), unit(p2 - p0)) {
        (Some(a), Some(c)) => parallel(a, c),
        _ => true,
    };
    if degenerate {
        b.diags.error(
            b.header,
            "degenerate triangle: its corners `O1=`, `O2=`, `O3=` are collinear",
            None,
        );
        return None;
    }
    Some(vec![Shape::Triangle(Box::new(Triangle::new(
        p0, p1, p2, None,
    )))])
}
