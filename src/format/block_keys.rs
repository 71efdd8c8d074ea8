//! One block being built, with the checked readings of its keys that
//! several block kinds share (radii, half-edge vectors, axes...).

use super::diags::{Diags, Site};
use super::values::{Fields, parallel, unit};
use glam::DVec3;

/// One block being built: its header, parsed keys, and the diagnostics.
pub(crate) struct BlockKeys<'d> {
    /// The header as written (`primitive sphere`), for messages.
    pub title: &'static str,
    /// Where the header is.
    pub header: Site,
    /// The block's keys, parsed.
    pub fields: Fields,
    /// Where its diagnostics go.
    pub diags: &'d mut Diags,
    /// Whether its keys are written `key:` (the colon family's).
    pub colon: bool,
}

impl BlockKeys<'_> {
    /// Key `key` as the block writes it (`R=`, or `R:` in the colon family's), for messages.
    pub fn key(&self, key: &str) -> String {
        format!("{key}{}", if self.colon { ':' } else { '=' })
    }

    /// `O=`, or the origin when absent.
    pub fn origin(&self) -> DVec3 {
        self.fields.v3("O").map_or(DVec3::ZERO, |(v, _)| v)
    }

    /// Whether the block names a texture (found or not): texture directions then matter.
    pub fn textured(&self) -> bool {
        self.fields.get("texture").is_some()
    }

    /// A required vector key; reports its absence at the header.
    pub fn need_v3(&mut self, key: &str, what: &str) -> Option<(DVec3, Site)> {
        let v = self.fields.v3(key);
        if v.is_none() {
            self.missing(key, what);
        }
        v
    }

    /// A required number key; reports its absence at the header.
    pub fn need_num(&mut self, key: &str, what: &str) -> Option<(f64, Site)> {
        let v = self.fields.num(key);
        if v.is_none() {
            self.missing(key, what);
        }
        v
    }

    fn missing(&mut self, key: &str, what: &str) {
        if !self.fields.failed(key) {
            let k = self.key(key);
            self.diags.error(
                self.header,
                format!("a `{}` block needs `{k}` ({what})", self.title),
                None,
            );
        }
    }

    /// A required radius > 0.
    pub fn radius(&mut self, key: &str) -> Option<f64> {
        self.positive(key, "the radius", "the radius")
    }

    /// A required height > 0 (the colon family's cylinders).
    pub fn height(&mut self, key: &str) -> Option<f64> {
        self.positive(key, "the height", "the height")
    }

    /// A required half-length > 0 (cubes).
    pub fn half_length(&mut self, key: &str) -> Option<f64> {
        self.positive(key, "a half-length", "the half-length")
    }

    /// A required number > 0: `what` it is when missing, `the` when wrong.
    fn positive(&mut self, key: &str, what: &str, the: &str) -> Option<f64> {
        let (x, site) = self.need_num(key, what)?;
        if x > 0.0 {
            Some(x)
        } else {
            let k = self.key(key);
            self.diags.error(
                site,
                format!("{the} `{k}` must be greater than 0, found {x}"),
                None,
            );
            None
        }
    }

    /// An optional number that must not be negative.
    pub fn non_negative(&mut self, key: &str) -> Option<f64> {
        let (x, site) = self.fields.num(key)?;
        if x >= 0.0 {
            Some(x)
        } else {
            let k = self.key(key);
            self.diags
                .error(site, format!("`{k}` must not be negative, found {x}"), None);
            None
        }
    }

    /// An optional whole number (already known ≥ 0 and whole) at most
    /// `max`, with its place in the file.
    pub fn count(&mut self, key: &str, max: f64) -> Option<(f64, Site)> {
        let (x, site) = self.fields.num(key)?;
        if x <= max {
            Some((x, site))
        } else {
            let k = self.key(key);
            self.diags.error(
                site,
                format!("`{k}` is too large (at most {max}), found {x}"),
                None,
            );
            None
        }
    }

    /// An optional texture direction (sphere `De=`/`Dc=`), normalised;
    /// zero length is an error only when a texture needs it.
    pub fn direction(&mut self, key: &str, default: DVec3, textured: bool) -> Option<DVec3> {
        let Some((v, site)) = self.fields.v3(key) else {
            return Some(default);
        };
        if let Some(u) = unit(v) {
            return Some(u);
        }
        let k = self.key(key);
        if textured {
            self.diags.error(
                site,
                format!("`{k}` has zero length; the texture mapping needs a direction"),
                None,
            );
            None
        } else {
            self.diags.warn(
                site,
                format!("`{k}` has zero length; ignored (only textures use it)"),
                None,
            );
            Some(default)
        }
    }

    /// An optional plane texture axis: `Some(None)` when absent (or zero
    /// on an untextured plane, with a warning), `None` after an error.
    pub fn texture_axis(&mut self, key: &str, textured: bool) -> Option<Option<DVec3>> {
        let Some((v, site)) = self.fields.v3(key) else {
            return Some(None);
        };
        if unit(v).is_some() {
            return Some(Some(v));
        }
        let k = self.key(key);
        if textured {
            self.diags.error(
                site,
                format!("`{k}` has zero length; the plane's texture needs it"),
                None,
            );
            None
        } else {
            self.diags.warn(
                site,
                format!("`{k}` has zero length; ignored (only textures use it)"),
                None,
            );
            Some(None)
        }
    }

    /// Required non-zero, non-parallel half-edge vectors (squares, square lights).
    pub fn span_pair(&mut self, kx: &str, ky: &str) -> Option<(DVec3, DVec3)> {
        let dx = self.need_v3(kx, "a half-edge vector");
        let dy = self.need_v3(ky, "a half-edge vector");
        let ux = dx.and_then(|(v, site)| self.nonzero(kx, v, site));
        let uy = dy.and_then(|(v, site)| self.nonzero(ky, v, site));
        let (ux, uy, (dx, _), (dy, site)) = (ux?, uy?, dx?, dy?);
        if parallel(ux, uy) {
            let (x, y) = (self.key(kx), self.key(ky));
            self.diags.error(
                site,
                format!(
                    "`{y}` is parallel to `{x}`; a `{}` needs two independent directions",
                    self.title
                ),
                None,
            );
            return None;
        }
        Some((dx, dy))
    }

    /// The unit vector along `v`, reporting zero length.
    pub fn nonzero(&mut self, key: &str, v: DVec3, site: Site) -> Option<DVec3> {
        let u = unit(v);
        if u.is_none() {
            let k = self.key(key);
            self.diags
                .error(site, format!("`{k}` has zero length"), None);
        }
        u
    }

    /// Required `O1=` ≠ `O2=` (cylinders, Bézier surfaces).
    pub fn axis(&mut self) -> Option<(DVec3, DVec3)> {
        let o1 = self.need_v3("O1", "the start of the axis");
        let o2 = self.need_v3("O2", "the end of the axis");
        let ((o1, _), (o2, site)) = (o1?, o2?);
        if unit(o2 - o1).is_none() {
            self.diags
                .error(site, "`O2=` equals `O1=`: the axis has zero length", None);
            return None;
        }
        Some((o1, o2))
    }
}
