//! The verdict of `glint explain`: the one cause that decides a pixel,
//! named in a sentence a student understands.

use crate::integrator::{HitInfo, RayKind, RayNode};
use crate::scene::Material;

/// `file:line` of a block (`line N` without a file, `?` without a line).
pub(crate) fn place(file: Option<&str>, line: Option<u32>) -> String {
    match (file, line) {
        (Some(f), Some(l)) => format!("{f}:{l}"),
        (None, Some(l)) => format!("line {l}"),
        _ => "?".to_string(),
    }
}

/// What a hit is called: `sphere #2 (scene.txt:14)` or `light #1's surface (scene.txt:5)`.
pub(crate) fn named(hit: &HitInfo, file: Option<&str>) -> String {
    match (hit.primitive, hit.light) {
        (Some(b), _) => format!("{} #{b} ({})", hit.kind, place(file, hit.line)),
        (None, Some(l)) => format!("light #{l}'s surface ({})", place(file, hit.line)),
        (None, None) => hit.kind.to_string(),
    }
}

/// The verdict for a pixel whose samples are `samples` and bytes `bytes`.
/// Samples that see the same thing for the same reason say one thing;
/// samples that disagree (an edge) are named with their counts, and the
/// most common one is explained.
pub(crate) fn verdict(samples: &[RayNode], bytes: [u8; 3], file: Option<&str>) -> String {
    let mut groups = sides(samples, bytes, file);
    // The most samples first; of equal counts, the one seen first.
    groups.sort_by_key(|g| std::cmp::Reverse(g.count));
    let Some(main) = groups.first() else {
        return "no sample was traced".to_string();
    };
    let mut said = Vec::new();
    if let [_, second, ..] = &groups[..] {
        let n = samples.len();
        let labels: Vec<String> = groups
            .iter()
            .map(|g| match g.kind {
                Cause::Background => format!("the background ({} of {n} samples)", g.count),
                _ => format!("{} ({}: {} of {n} samples)", g.what, g.kind.name(), g.count),
            })
            .collect();
        let most = if main.count > second.count {
            "Most samples"
        } else {
            "The first of the largest sides"
        };
        said.push(format!(
            "edge between {}: the pixel is their mean. {most}: {}",
            labels.join(" and "),
            main.said
        ));
    } else {
        said.push(main.said.clone());
    }
    let mut tir = None;
    let mut cut = false;
    walk(main.root, &mut |n| {
        cut |= !n.cut.is_empty();
        if n.kind == RayKind::TotalInternalReflection && tir.is_none() {
            tir = Some(n.depth);
        }
    });
    if let Some(d) = tir {
        said.push(format!(
            "A refraction ray at depth {d} meets total internal reflection: it bounces back inside the glass."
        ));
    }
    if cut {
        said.push(
            "The depth limit (10) stops a reflection or refraction ray: what it would see counts as black."
                .to_string(),
        );
    }
    said.join(" ")
}

/// The samples of a pixel that see the same thing for the same reason.
struct Side<'a> {
    /// What their camera rays hit: (primitive, light), both `None` for the background.
    seen: (Option<u32>, Option<u32>),
    /// Its name, `sphere #2 (scene.txt:14)`.
    what: String,
    /// Why they are what they are.
    kind: Cause,
    /// The first one's sentence.
    said: String,
    /// The first one.
    root: &'a RayNode,
    /// How many samples.
    count: usize,
}

/// `samples` gathered into sides, in the order first seen.
fn sides<'a>(samples: &'a [RayNode], bytes: [u8; 3], file: Option<&str>) -> Vec<Side<'a>> {
    let mut sides: Vec<Side> = Vec::new();
    for root in samples {
        let (kind, said) = cause(root, bytes, file);
        let seen = root
            .hit
            .as_ref()
            .map_or((None, None), |h| (h.primitive, h.light));
        match sides.iter_mut().find(|s| s.seen == seen && s.kind == kind) {
            Some(side) => side.count += 1,
            None => sides.push(Side {
                seen,
                what: root
                    .hit
                    .as_ref()
                    .map_or("the background".to_string(), |h| named(h, file)),
                kind,
                said,
                root,
                count: 1,
            }),
        }
    }
    sides
}

/// The kinds of main cause a verdict names (the `why` pass's colours).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cause {
    /// The camera ray misses everything.
    Background,
    /// It sees an area light's surface.
    Light,
    /// An all-zero material.
    ZeroMaterial,
    /// No diffuse or specular term: the colour is reflected or refracted light.
    Carried,
    /// The scene has no light.
    NoLights,
    /// The hit faces away from every light.
    FacesAway,
    /// Every light it faces is blocked.
    Shadow,
    /// Lit by one light while others face away or are blocked.
    OneLightAlone,
    /// Lit by every light it faces, or by several.
    Lit,
}

impl Cause {
    /// Every kind, in the order of the legend.
    pub const ALL: [Cause; 9] = [
        Cause::Background,
        Cause::Light,
        Cause::ZeroMaterial,
        Cause::Carried,
        Cause::NoLights,
        Cause::FacesAway,
        Cause::Shadow,
        Cause::OneLightAlone,
        Cause::Lit,
    ];

    /// Its name in the legend.
    pub fn name(self) -> &'static str {
        match self {
            Cause::Background => "background",
            Cause::Light => "light",
            Cause::ZeroMaterial => "zero material",
            Cause::Carried => "reflection or refraction only",
            Cause::NoLights => "no light in the scene",
            Cause::FacesAway => "faces away from every light",
            Cause::Shadow => "in shadow",
            Cause::OneLightAlone => "lit by one light alone",
            Cause::Lit => "lit",
        }
    }

    /// Its colour in the `why` pass (8-bit sRGB-free bytes, as written).
    pub fn colour(self) -> [u8; 3] {
        match self {
            Cause::Background => [40, 40, 40],
            Cause::Light => [255, 255, 255],
            Cause::ZeroMaterial => [255, 0, 255],
            Cause::Carried => [0, 160, 255],
            Cause::NoLights => [128, 0, 0],
            Cause::FacesAway => [255, 60, 0],
            Cause::Shadow => [140, 70, 255],
            Cause::OneLightAlone => [255, 210, 0],
            Cause::Lit => [60, 200, 60],
        }
    }
}

/// What the camera ray met, as the verdict's kind reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum FirstHit<'m> {
    /// Nothing: the background.
    Nothing,
    /// An area light's visible surface.
    Light,
    /// A primitive's surface, and its material where known.
    Surface(Option<&'m Material>),
}

/// The lights at the camera ray's hit, counted as the verdict reads them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct LightCounts {
    /// Lights whose term was computed (every light, where the material has
    /// a diffuse or specular term the model lights).
    pub all: u32,
    /// Of those, the ones the hit faces (L·N > 0).
    pub facing: u32,
    /// Of those, the ones some shadow ray reached (s > 0).
    pub lit: u32,
}

impl LightCounts {
    /// Counts one light's term: its L·N and its shade factor.
    pub fn add(&mut self, l_dot_n: f64, s: f64) {
        self.all += 1;
        if l_dot_n > 0.0 {
            self.facing += 1;
            self.lit += u32::from(s > 0.0);
        }
    }
}

/// The kind of main cause of a camera ray that met `first`, with the
/// lights there counted in `lights` (what [`cause`] names in a sentence,
/// and the `why` pass shows).
pub(crate) fn kind(first: FirstHit, lights: LightCounts) -> Cause {
    let m = match first {
        FirstHit::Nothing => return Cause::Background,
        FirstHit::Light => return Cause::Light,
        FirstHit::Surface(None) => return Cause::Lit,
        FirstHit::Surface(Some(m)) => m,
    };
    // The colour scales diffuse, specular and reflection; refraction not.
    let coloured = m.diff > 0.0 || m.spec > 0.0 || m.refl > 0.0;
    if m.refr <= 0.0 && (m.color == glam::DVec3::ZERO || !coloured) {
        Cause::ZeroMaterial
    } else if !(m.diff > 0.0 || m.spec > 0.0) {
        Cause::Carried
    } else if lights.all == 0 {
        Cause::NoLights
    } else if lights.facing == 0 {
        Cause::FacesAway
    } else if lights.lit == 0 {
        Cause::Shadow
    } else if lights.lit == 1 && lights.all > 1 {
        Cause::OneLightAlone
    } else {
        Cause::Lit
    }
}

/// What `root`'s camera ray met, and the lights there, as [`kind`] reads them.
fn facts(root: &RayNode) -> (FirstHit<'_>, LightCounts) {
    let first = match &root.hit {
        None => FirstHit::Nothing,
        Some(hit) if hit.light.is_some() => FirstHit::Light,
        Some(_) => FirstHit::Surface(root.material.as_ref()),
    };
    let mut lights = LightCounts::default();
    for l in &root.lights {
        lights.add(l.l_dot_n, l.s);
    }
    (first, lights)
}

/// The main cause, from one sample's tree: its kind and sentence.
pub(crate) fn cause(root: &RayNode, bytes: [u8; 3], file: Option<&str>) -> (Cause, String) {
    let (first, counts) = facts(root);
    let kind = kind(first, counts);
    let (hit, m) = match (&root.hit, root.material) {
        (Some(hit), Some(m)) if kind != Cause::Light => (hit, m),
        (None, _) => return (kind, "background: the camera ray misses every object, so the pixel is the background's colour.".to_string()),
        (Some(hit), _) if kind == Cause::Light => {
            let what = named(hit, file);
            return (
                kind,
                format!("light: the camera ray sees {what} directly, which shows the light's colour."),
            );
        }
        (Some(hit), _) => return (kind, format!("the camera ray hits {}.", named(hit, file))),
    };
    let what = named(hit, file);
    let side = if hit.front {
        ""
    } else {
        " from behind (its back face)"
    };
    let facing: Vec<_> = root.lights.iter().filter(|l| l.l_dot_n > 0.0).collect();
    let lit: Vec<_> = facing.iter().filter(|l| l.s > 0.0).collect();
    let clamped = root
        .unclamped
        .is_some_and(|u| u.max_element() > 1.0 && bytes.contains(&255));
    let light_name = |i: u32, line| format!("light #{i} ({})", place(file, line));
    let main = match kind {
        Cause::ZeroMaterial => {
            return (
                kind,
                format!(
                    "black: the material of {what} is all zero (colour or every one of diff, spec, refl, refr), so it neither reflects light nor lets any through."
                ),
            );
        }
        Cause::Carried => format!(
            "{what}{side} has no diffuse or specular term: its colour comes only from what it reflects or lets through."
        ),
        Cause::NoLights => format!(
            "{what}{side} is seen, but the scene has no light, and the model has no ambient term."
        ),
        Cause::FacesAway => format!(
            "black: the camera ray hits {what}{side}, which faces away from every light, and the model has no ambient term (the framework renders it black too)."
        ),
        Cause::Shadow => {
            let blocked = facing.iter().find_map(|l| {
                l.blocker.as_ref().map(|b| {
                    let by = match (b.primitive, b.light) {
                        (Some(p), _) => format!("{} #{p} at {}", b.kind, place(file, b.line)),
                        (None, Some(i)) => {
                            format!("light #{i}'s surface at {}", place(file, b.line))
                        }
                        (None, None) => b.kind.to_string(),
                    };
                    format!(
                        "in shadow: {what}{side} is in the shadow of {by}, which blocks the ray to {} at t {:.4}.",
                        light_name(l.light, l.line),
                        b.t
                    )
                })
            });
            blocked.unwrap_or_else(|| {
                format!(
                    "in shadow: {what}{side} faces the lights, but every shadow ray towards them is blocked."
                )
            })
        }
        _ => match lit[..] {
            [l] => {
                let by = format!(
                    "{} (shade {}/{})",
                    light_name(l.light, l.line),
                    l.reached,
                    l.rays
                );
                if kind == Cause::OneLightAlone {
                    format!(
                        "lit by {by} alone: the other lights face away from {what}{side} or are blocked."
                    )
                } else {
                    format!("{what}{side} is lit by the scene's one light, {by}.")
                }
            }
            _ => format!(
                "{what}{side} is lit by {} of the scene's {} lights.",
                lit.len(),
                root.lights.len()
            ),
        },
    };
    // No direct light, but a mirror or glass term still carries colour.
    let carried = m.refl > 0.0 || m.refr > 0.0;
    let main = if carried && matches!(kind, Cause::FacesAway | Cause::Shadow | Cause::NoLights) {
        let direct = main
            .trim_start_matches("black: ")
            .replace(" (the framework renders it black too)", "");
        format!(
            "{direct} No light reaches it directly: its colour comes only from what it reflects or lets through."
        )
    } else {
        main
    };
    if clamped {
        (
            kind,
            format!("{main} Clamped: the sum exceeds 1 in a channel and is cut to 1 (byte 255)."),
        )
    } else {
        (kind, main)
    }
}

/// Calls `f` on every node of the tree, parents first.
pub(crate) fn walk<'a>(node: &'a RayNode, f: &mut impl FnMut(&'a RayNode)) {
    f(node);
    for c in &node.children {
        walk(c, f);
    }
}
