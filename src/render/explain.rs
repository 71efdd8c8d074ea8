//! `glint explain`: one pixel's ray trees, traced exactly as a render traces
//! that pixel (the same samples, the anti-aliasing's decision included),
//! with the bytes the render writes there and a verdict on why.

use super::frame::Frame;
use super::passes::differs;
use super::verdict::verdict;
use crate::accel::PACKET_MAX;
use crate::geometry::{Ray, offset_origin};
use crate::integrator::{
    AaHash, AntiAlias, Blocker, PathState, RayNode, RayTree, SceneAccel, ShadowHints,
};
use crate::output::Image;
use crate::sampling::strata;
use crate::scene::{LightKind, Origin, Scene};
use glam::DVec3;

/// Why a pixel is what it is: its samples' ray trees and the bytes a render writes.
#[derive(Clone, Debug, PartialEq)]
pub struct Explanation {
    /// The pixel (column, row from the top).
    pub pixel: (u32, u32),
    /// The 8-bit values the render writes: floor(255·clamp(c)).
    pub bytes: [u8; 3],
    /// The pixel's linear colour as the render stores it, before quantisation.
    pub color: [f32; 3],
    /// How the render sampled it.
    pub sampling: Sampling,
    /// Each camera sample's ray tree, in the order the render sums them.
    pub samples: Vec<RayNode>,
    /// The scene file's name as given (`None`: parsed from text).
    pub file: Option<String>,
    /// The cause that decides the pixel, in a sentence.
    pub verdict: String,
}

/// How the render sampled a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// Adaptive anti-aliasing: one ray through the centre, or the 7×7 grid
    /// when a 4-neighbour's hash differs (`refined`).
    Adaptive {
        /// Whether the pixel took the 7×7 grid.
        refined: bool,
    },
    /// `--spp n`: n stratified samples (one through the centre for 1).
    Stratified(u32),
}

/// Pixel (x, y) of `frame` (inside it) explained: the samples a render
/// with `spp` traces there (adaptive anti-aliasing for `None`), as ray
/// trees, annotated from `scene` (lines) and `accel` (blockers).
pub(crate) fn explain_pixel(
    frame: &Frame,
    scene: &Scene,
    accel: &SceneAccel,
    spp: Option<u32>,
    (x, y): (u32, u32),
) -> Explanation {
    let mut hints = ShadowHints::default();
    let (sampling, color, mut samples) = match spp.map(|n| n.max(1)) {
        Some(n) if n > 1 => {
            let strata = strata(n);
            let (sum, trees) = watched(frame, n as usize, &mut hints, |k| {
                frame.jittered(x, y, k as u32, strata)
            });
            (Sampling::Stratified(n), sum / n as f64, trees)
        }
        Some(_) => {
            let (c, trees) = watched(frame, 1, &mut hints, |_| frame.centre_sample(x, y));
            (Sampling::Stratified(1), c, trees)
        }
        None => {
            let refined = frame.refine_count() > 0 && anti_aliased(frame, x, y, &mut hints);
            let (c, trees) = if refined && frame.anti_alias() == AntiAlias::Cross5 {
                // PM3's: the centre's colour as stored, and four rays more.
                let (first, mut trees) =
                    watched(frame, 1, &mut hints, |_| frame.centre_sample(x, y));
                let first = DVec3::from(first.as_vec3());
                let n = frame.refine_count();
                let (sum, more) = watched(frame, n, &mut hints, |k| frame.grid_sample(x, y, k));
                trees.extend(more);
                (frame.refined(first, sum), trees)
            } else if refined {
                let n = frame.refine_count();
                let (sum, trees) = watched(frame, n, &mut hints, |k| frame.grid_sample(x, y, k));
                (frame.refined(DVec3::ZERO, sum), trees)
            } else {
                watched(frame, 1, &mut hints, |_| frame.centre_sample(x, y))
            };
            (Sampling::Adaptive { refined }, c, trees)
        }
    };
    for node in &mut samples {
        annotate(scene, accel, node);
    }
    let color = color.as_vec3().to_array();
    let rgb = Image::from_pixels(1, 1, vec![color]).to_rgb8();
    let bytes = [rgb[0], rgb[1], rgb[2]];
    let file = scene.path().map(|p| p.display().to_string());
    let verdict = verdict(&samples, bytes, file.as_deref());
    Explanation {
        pixel: (x, y),
        bytes,
        color,
        sampling,
        samples,
        file,
        verdict,
    }
}

/// Fills in what the shading code does not know: lines, light kinds,
/// and the blockers of point lights' shadow rays.
fn annotate(scene: &Scene, accel: &SceneAccel, node: &mut RayNode) {
    if let Some(hit) = &mut node.hit {
        hit.line = match (hit.primitive, hit.light) {
            (Some(b), _) => scene.block_line(b),
            (None, Some(l)) => scene.light_line(l),
            (None, None) => None,
        };
    }
    for term in &mut node.lights {
        term.line = scene.light_line(term.light);
        let Some(light) = scene.lights().get(term.light as usize) else {
            continue;
        };
        term.kind = match light.kind {
            LightKind::Point { .. } => "point",
            LightKind::Square { .. } => "square",
            LightKind::Sphere { .. } => "sphere",
        };
        if let LightKind::Point { pos } = light.kind
            && term.rays > 0
            && term.reached == 0
        {
            // The shadow ray Light::shade traced, asked for its nearest blocker.
            let origin = offset_origin(term.from.0, term.from.1);
            let to = pos - origin;
            let dist = to.length();
            let ray = Ray::off_surface(origin, to / dist);
            term.blocker = accel.intersect(&ray, dist).map(|(i, hit)| {
                let object = &accel.objects()[i as usize];
                let (primitive, light) = match object.origin() {
                    Origin::Block(b) => (Some(b), None),
                    Origin::Light(l) => (None, Some(l)),
                };
                Blocker {
                    primitive,
                    light,
                    kind: object.shape().kind_name(),
                    line: match object.origin() {
                        Origin::Block(b) => scene.block_line(b),
                        Origin::Light(l) => scene.light_line(l),
                    },
                    t: hit.t,
                }
            });
        }
    }
    for child in &mut node.children {
        annotate(scene, accel, child);
    }
}

/// Whether the adaptive anti-aliasing refines pixel (x, y): its centre
/// ray's hash and its 4-neighbours', traced as pass 1 traces them.
fn anti_aliased(frame: &Frame, x: u32, y: u32, hints: &mut ShadowHints) -> bool {
    let (w, h) = (frame.width, frame.height);
    let around: Vec<(u32, u32)> = [
        (x, y),
        (x.wrapping_sub(1), y),
        (x + 1, y),
        (x, y.wrapping_sub(1)),
        (x, y + 1),
    ]
    .into_iter()
    .filter(|&(i, j)| i < w && j < h)
    .collect();
    let mut hashes = vec![0u32; around.len()];
    frame.packet(
        around.len(),
        |k| frame.centre_sample(around[k].0, around[k].1),
        &AaHash::default(),
        |k, _, hash: &mut AaHash, _| hashes[k] = hash.folded(),
        hints,
    );
    let hash = |i: u32, j: u32| {
        around
            .iter()
            .position(|&p| p == (i, j))
            .map_or(0, |k| hashes[k])
    };
    differs(hash, x, y, w, h)
}

/// The sum of `n` camera samples `sample_of(k)`, traced in packets as the
/// render traces them and summed in the same order, with their trees.
fn watched(
    frame: &Frame,
    n: usize,
    hints: &mut ShadowHints,
    sample_of: impl Fn(usize) -> (Ray, PathState),
) -> (DVec3, Vec<RayNode>) {
    let mut sum = DVec3::ZERO;
    let mut trees = Vec::with_capacity(n);
    let mut start = 0;
    while start < n {
        let len = (n - start).min(PACKET_MAX);
        frame.packet(
            len,
            |k| sample_of(start + k),
            &RayTree::default(),
            |_, c, tree: &mut RayTree, _| {
                sum += c;
                trees.extend(std::mem::take(tree).into_roots());
            },
            hints,
        );
        start += len;
    }
    (sum, trees)
}
