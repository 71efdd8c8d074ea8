//! The relatives' ways of writing a `bezier` block, turned into the
//! framework's surface of revolution (`lineages.md`, A18 and L17):
//!
//! - lazycal's axis form, `Dz= S= P= control_points= N r1 h1 … rN hN`:
//!   the axis through the base point P along Dz (any length), the profile's
//!   control points (r, h)/S, r the radius (negative allowed), h the height
//!   along the axis;
//! - abcbdf's cubic form, `center= V0= V1= V2= V3=`: a cubic profile of
//!   3-D points, radius x − center.x and height z, turned about the
//!   vertical line through (center.x, center.y); their y is not read.

use super::block_keys::BlockKeys;
use super::values::{Value, parallel, unit};
use crate::geometry::{Bezier, BezierUv, Shape};
use glam::{DVec2, DVec3};

/// The keys that make a `bezier` block lazycal's.
pub(crate) const AXIS_KEYS: [&str; 3] = ["Dz", "S", "control_points"];
/// The keys that make a `bezier` block abcbdf's.
pub(crate) const CUBIC_KEYS: [&str; 5] = ["center", "V0", "V1", "V2", "V3"];

/// Warns at the framework's keys in a block written in another form.
fn framework_keys_unread(b: &mut BlockKeys<'_>, form: &str) {
    for key in ["O1", "O2"] {
        if let Some(f) = b.fields.get(key) {
            let site = f.site;
            b.diags.warn(
                site,
                format!("`{key}=` is not read by a bezier in {form}; ignored"),
                None,
            );
        }
    }
}

/// lazycal's bezier: `Dz=` (default ẑ, as its zero vector normalises to),
/// `S=` (not 0), `P=` (default the origin), `control_points=` (a count
/// n ≥ 2, then n pairs r h). Its texture coordinates are lazycal's
/// (`BezierUv::Lazycal`), the angle measured from −Dx towards −Dy where
/// Dx = unit(ŷ × Dz) (x̂ when Dz is along ŷ) and Dy = Dz × Dx.
pub(crate) fn axis_form(b: &mut BlockKeys<'_>) -> Option<Shape> {
    framework_keys_unread(b, "lazycal's form (`Dz= S= P= control_points=`)");
    let axis = match b.fields.v3("Dz") {
        Some((v, site)) => match unit(v) {
            Some(a) => a,
            None => {
                b.diags.warn(
                    site,
                    "`Dz=` has zero length: lazycal normalises it to 0 0 1",
                    None,
                );
                DVec3::Z
            }
        },
        None => DVec3::Z,
    };
    let scale = match b.fields.num("S") {
        Some((0.0, site)) => {
            b.diags.error(
                site,
                "`S=` is 0: the control points are divided by it",
                None,
            );
            return None;
        }
        Some((s, _)) => s,
        None => {
            if !b.fields.failed("S") {
                b.diags.warn(
                    b.header,
                    "this bezier has no `S=` (lazycal leaves it undefined); read as 1",
                    Some("add `S= 1`".to_string()),
                );
            }
            1.0
        }
    };
    let base = match b.fields.get("P").map(|f| (&f.value, f.site)) {
        Some((Value::V3(p), _)) => *p,
        Some((Value::V2(p), site)) => {
            b.diags.warn(
                site,
                "`P=` is lazycal's base point here (x y z): its z reads as 0",
                None,
            );
            p.extend(0.0)
        }
        _ => DVec3::ZERO,
    };
    let profile = control_points(b, scale)?;
    let dx = match unit(DVec3::Y.cross(axis)) {
        Some(dx) if !parallel(axis, DVec3::Y) => dx,
        _ => DVec3::X,
    };
    let dy = axis.cross(dx);
    let shape = Bezier::new(base, base + axis, profile)
        .with_angle_frame(-dx, -dy)
        .with_uv(BezierUv::Lazycal);
    Some(Shape::Bezier(Box::new(shape)))
}

/// lazycal's `control_points= n r1 h1 … rn hn` as the framework's (z, r)
/// profile, divided by `scale`.
fn control_points(b: &mut BlockKeys<'_>, scale: f64) -> Option<Vec<DVec2>> {
    let (list, site) = match b.fields.get("control_points") {
        Some(f) => match &f.value {
            Value::List(list) => (list.clone(), f.site),
            _ => return None,
        },
        None => {
            if !b.fields.failed("control_points") {
                b.diags.error(
                    b.header,
                    "a bezier with `Dz=`/`S=` needs `control_points= N r1 h1 ...`",
                    None,
                );
            }
            return None;
        }
    };
    let max = Bezier::MAX_DEGREE + 1;
    let count = list.first().copied().unwrap_or_default();
    if count.fract() != 0.0 || count < 2.0 || count > max as f64 {
        b.diags.error(
            site,
            format!(
                "`control_points=` starts with the count of points, a whole number from 2 to \
                 {max}; found {count}"
            ),
            None,
        );
        return None;
    }
    let n = count as usize;
    let pairs = &list[1..];
    if pairs.len() < 2 * n {
        b.diags.error(
            site,
            format!(
                "`control_points= {n}` needs {} numbers after the count (r h for each point), \
                 found {}",
                2 * n,
                pairs.len()
            ),
            None,
        );
        return None;
    }
    if pairs.len() > 2 * n {
        b.diags.warn(
            site,
            format!(
                "`control_points= {n}` reads {} numbers after the count; the {} after them are ignored",
                2 * n,
                pairs.len() - 2 * n
            ),
            None,
        );
    }
    Some(
        pairs
            .chunks_exact(2)
            .take(n)
            .map(|rh| DVec2::new(rh[1] / scale, rh[0] / scale))
            .collect(),
    )
}

/// abcbdf's bezier: `center=` (default the origin) and the four points
/// `V0=` … `V3=` (all needed). The profile is built from V3 back to V0,
/// so that the curve parameter runs as abcbdf's texture row 1 − t does;
/// the texture angle is measured from ŷ towards −x̂ (abcbdf's column
/// θ/2π + ¾, θ counter-clockwise from x̂).
pub(crate) fn cubic_form(b: &mut BlockKeys<'_>) -> Option<Shape> {
    framework_keys_unread(b, "abcbdf's form (`center= V0= ... V3=`)");
    let center = b.fields.v3("center").map_or(DVec3::ZERO, |(c, _)| c);
    let mut points = Vec::with_capacity(4);
    let mut missing = Vec::new();
    for key in ["V0", "V1", "V2", "V3"] {
        match b.fields.v3(key) {
            Some((v, _)) => points.push(DVec2::new(v.z - center.z, v.x - center.x)),
            None if b.fields.failed(key) => return None,
            None => missing.push(format!("`{key}=`")),
        }
    }
    if !missing.is_empty() {
        b.diags.error(
            b.header,
            format!(
                "a bezier with `center=` needs the four points `V0=` ... `V3=`; missing {}",
                missing.join(", ")
            ),
            None,
        );
        return None;
    }
    points.reverse();
    let o1 = center;
    let shape = Bezier::new(o1, o1 + DVec3::Z, points).with_angle_frame(DVec3::Y, -DVec3::X);
    Some(Shape::Bezier(Box::new(shape)))
}
