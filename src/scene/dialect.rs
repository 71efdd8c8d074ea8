//! Dialects: which lineage of the format a file belongs to, and so which
//! renderer's model (shading, camera, plane sign, defaults) draws it.

use std::fmt;

/// A lineage of the scene format, as glint renders it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// The teaching framework (kevinpruvost/Ray_Tracing and CUDA_RayTracing).
    F,
    /// The 2014 photon engine (zsyzgu/new_photon_mapping), its 2017
    /// rewrite and Pilgrimss/RayTracing: photon-lit diffuse light.
    Z14,
    /// daibiaoxuwu/PM3: 1/d² direct light, photon maps, polyhedra.
    Pm3,
    /// LuChengTHU/RayTracing-PPM-NormalMap: PM3's model, normal maps,
    /// a Bézier vase, progressive photon mapping.
    V,
    /// wangxr14/raytrace: the framework's model with ambient light, a
    /// mirrored camera and `object` blocks.
    W,
    /// abcbdf/photon_mapping-bezier: the framework's ray tracer with ambient
    /// light, `obj` blocks and a cubic Bézier profile of 3-D points.
    A18,
    /// lazycal/Progressive-Photon-Mapping: progressive photon mapping whose
    /// picture is the photon estimate alone; Béziers by axis, scale and
    /// control points.
    L17,
    /// hta1996/Raytracing: `key:` lines, an eye–look-at camera with depth of
    /// field, Phong highlights, Fresnel glass, surfaces of revolution.
    Colon,
}

impl Dialect {
    /// Every dialect, in the order of the lineage table.
    pub const ALL: [Dialect; 8] = [
        Dialect::F,
        Dialect::Z14,
        Dialect::Pm3,
        Dialect::V,
        Dialect::W,
        Dialect::A18,
        Dialect::L17,
        Dialect::Colon,
    ];

    /// Its short name (`f`, `z14`, `pm3`, `v`, `w`, `a18`, `l17`, `colon`).
    pub fn name(self) -> &'static str {
        match self {
            Dialect::F => "f",
            Dialect::Z14 => "z14",
            Dialect::Pm3 => "pm3",
            Dialect::V => "v",
            Dialect::W => "w",
            Dialect::A18 => "a18",
            Dialect::L17 => "l17",
            Dialect::Colon => "colon",
        }
    }

    /// The repositories whose names also select it (`--dialect raytrace`).
    pub fn aliases(self) -> &'static [&'static str] {
        match self {
            Dialect::F => &["ray_tracing", "cuda_raytracing", "framework"],
            Dialect::Z14 => &["new_photon_mapping", "photon-mapping", "z17", "p"],
            Dialect::Pm3 => &[],
            Dialect::V => &["raytracing-ppm-normalmap"],
            Dialect::W => &["raytrace"],
            Dialect::A18 => &["abcbdf", "photon_mapping-bezier"],
            Dialect::L17 => &["lazycal", "progressive-photon-mapping"],
            Dialect::Colon => &["hta1996", "hta"],
        }
    }

    /// The dialect named `s` (its short name or a repository's, any case).
    pub fn from_name(s: &str) -> Option<Dialect> {
        let s = s.to_ascii_lowercase();
        Dialect::ALL
            .into_iter()
            .find(|d| d.name() == s || d.aliases().contains(&s.as_str()))
    }
}

impl std::str::FromStr for Dialect {
    type Err = String;

    /// `--dialect NAME`: [`Dialect::from_name`], or a message listing the names.
    fn from_str(s: &str) -> Result<Dialect, String> {
        Dialect::from_name(s).ok_or_else(|| {
            let names: Vec<&str> = Dialect::ALL.iter().map(|d| d.name()).collect();
            format!(
                "unknown dialect `{s}`: expected one of {}",
                names.join(", ")
            )
        })
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The dialect a scene is drawn in and the rule that chose it.
#[derive(Clone, Debug, PartialEq)]
pub struct DialectChoice {
    /// The dialect.
    pub dialect: Dialect,
    /// Why: the rule and where it matched (`primitive polyhedron at line 72`).
    pub reason: String,
    /// What of the lineage's picture glint does not draw yet, if anything.
    pub caveat: Option<String>,
}

impl Default for DialectChoice {
    fn default() -> Self {
        DialectChoice {
            dialect: Dialect::F,
            reason: "the default".to_string(),
            caveat: None,
        }
    }
}

impl fmt::Display for DialectChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "dialect {}: {}", self.dialect, self.reason)?;
        match &self.caveat {
            Some(c) => write!(f, "; {c}"),
            None => Ok(()),
        }
    }
}
