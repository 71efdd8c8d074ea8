//! Normal maps (`NT=`): the tangent frame a normal-map texel is read in at
//! a surface point, and the shading normal that texel gives.
//!
//! A texel (r, g, b) in [0, 1]³ means n = 2·(r, g, b) − 1, and the new
//! shading normal is unit(n_b·N + n_r·R + n_g·G) for the frame (N, R, G)
//! of the surface point. The frames are V's (`NomalBall`, `NomalPlane`) with
//! the fixes of the lineages spec (§7.9), and for triangles one built from
//! the texture coordinates' derivatives.

use glam::{DVec2, DVec3};

/// The directions a normal-map texel's channels weigh: blue the surface
/// normal, red and green two tangents (unit; V's frames are not all
/// right-handed, so neither is this type).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// The unperturbed outward normal (blue).
    pub normal: DVec3,
    /// The tangent the red channel weighs.
    pub red: DVec3,
    /// The tangent the green channel weighs.
    pub green: DVec3,
}

/// The shading normal for a normal-map `texel` (channels in [0, 1]) read in
/// `frame`: unit(n_b·N + n_r·R + n_g·G) with n = 2·texel − 1; the frame's
/// normal when that sum vanishes (a texel of (½, ½, ½)).
pub fn perturbed_normal(frame: &TangentFrame, texel: DVec3) -> DVec3 {
    let n = texel * 2.0 - DVec3::ONE;
    let m = frame.normal * n.z + frame.red * n.x + frame.green * n.y;
    m.try_normalize().unwrap_or(frame.normal)
}

/// V's `NomalBall` frame at a point q = C − O from the sphere's centre
/// (not from the world origin as V has it): N = unit(q), green
/// h = unit(q_y, −q_x, 0) (ŷ on the polar axis), red unit(N × h).
pub fn sphere_frame(q: DVec3) -> TangentFrame {
    let normal = q.normalize();
    let green = if q.x * q.x + q.y * q.y <= 1e-24 * q.length_squared() {
        DVec3::Y
    } else {
        DVec3::new(q.y, -q.x, 0.0).normalize()
    };
    TangentFrame {
        normal,
        red: normal.cross(green).normalize(),
        green,
    }
}

/// V's `NomalPlane` frame for the unit normal `n`: red along the part of
/// h = (n_x, n_y, 0) perpendicular to n (h = x̂ when both are 0), or along
/// unit(n × ẑ) when there is none (vertical planes, where V's frame
/// collapses); green unit(n × red).
pub fn plane_frame(n: DVec3) -> TangentFrame {
    let h = if n.x == 0.0 && n.y == 0.0 {
        DVec3::X
    } else {
        DVec3::new(n.x, n.y, 0.0)
    };
    let perp = h - n * h.dot(n);
    let red = if perp.length_squared() > 1e-24 * h.length_squared() {
        perp.normalize()
    } else {
        n.cross(DVec3::Z).normalize()
    };
    TangentFrame {
        normal: n,
        red,
        green: n.cross(red).normalize(),
    }
}

/// A frame from texture-coordinate derivatives on a triangle with corners
/// `p` and texture coordinates `uv` (glint's: x picks the texture's row, y
/// its column), around the unit normal `n`: red along ∂P/∂uv.y (across the
/// picture, left to right), green along ∂P/∂uv.x (up the picture), both made
/// perpendicular to `n`. `None` where the mapping is degenerate.
pub fn triangle_frame(n: DVec3, p: [DVec3; 3], uv: [DVec2; 3]) -> Option<TangentFrame> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let dp_dx = (e1 * d2.y - e2 * d1.y) / det;
    let dp_dy = (e2 * d1.x - e1 * d2.x) / det;
    let red = (dp_dy - n * dp_dy.dot(n)).try_normalize()?;
    let up = n.cross(red);
    let green = if up.dot(dp_dx) < 0.0 { -up } else { up };
    Some(TangentFrame {
        normal: n,
        red,
        green,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_texel_keeps_the_normal() {
        let f = plane_frame(DVec3::Z);
        let n = perturbed_normal(&f, DVec3::new(0.5, 0.5, 1.0));
        assert!((n - DVec3::Z).length() < 1e-15);
    }
}
