//! Materials: `rindex=` below 1 with `refr=`, all-zero materials, and
//! `diff + refl + refr` above 1. (`rindex=` 0 or below with `refr=` is the
//! reader's warning: it renders with rindex 1 in the framework's dialect,
//! as a mirror in the relatives'.)

use super::finding::{Code, Findings};
use super::primitive_blocks::{PrimitiveBlock, name};
use crate::scene::Dialect;
use glam::DVec3;

/// How far above 1 `diff + refl + refr` may be before it is said (rounding).
const ENERGY_SLACK: f64 = 1e-9;

/// The material lints over every block.
pub(crate) fn check(blocks: &[PrimitiveBlock], out: &mut Findings) {
    for b in blocks {
        let m = &b.material;
        let what = name(b);
        if m.refr > 0.0 && m.rindex > 0.0 && m.rindex < 1.0 {
            out.block(
                Code::RindexBelowOne,
                b.index,
                format!(
                    "{what} has `refr= {}` with `rindex= {}`: below 1, it bends light as air inside glass would, which is rarely what is meant",
                    m.refr, m.rindex
                ),
                "glass is about 1.5, water 1.33, diamond 2.42; set `rindex=` to the material's index".to_string(),
            );
        }
        // The colour scales diffuse, specular and reflection; refraction not.
        // In W and lazycal's a texture replaces the colour.
        let coloured = m.diff > 0.0 || m.spec > 0.0 || m.refl > 0.0;
        let replaced =
            m.texture.is_some() && matches!(out.scene.dialect().dialect, Dialect::W | Dialect::L17);
        if m.refr <= 0.0 && ((m.color == DVec3::ZERO && !replaced) || !coloured) {
            let why = if coloured {
                "its `color=` is 0 0 0 and it has no `refr=`"
            } else {
                "none of `diff=`, `spec=`, `refl=`, `refr=` is above 0"
            };
            out.block(
                Code::ZeroMaterial,
                b.index,
                format!("{what} is black wherever it is seen: {why}"),
                "give it a colour and a `diff=` (e.g. `color= 1 1 1` and `diff= 0.8`)".to_string(),
            );
        }
        let sum = m.diff + m.refl + m.refr;
        if sum > 1.0 + ENERGY_SLACK {
            out.block(
                Code::EnergyAboveOne,
                b.index,
                format!(
                    "{what} has `diff= {}` + `refl= {}` + `refr= {}` = {sum}: above 1, it gives back more light than it receives, so it glows and its reflections clamp to white",
                    m.diff, m.refl, m.refr
                ),
                format!("scale them so they sum to at most 1 (divide each by {sum})"),
            );
        }
    }
}
