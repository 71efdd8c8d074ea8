//! `glint explain`: one pixel's ray trees, traced exactly as a render traces
//! that pixel (the same samples, the anti-aliasing's decision included),
//! with the bytes the render writes there and a verdict on why.

use crate::accel::PACKET_MAX;
use crate::geometry::{Ray, offset_origin};
use crate::image::Image;
use crate::integrator::photons::PhotonMode;
use crate::integrator::{
    AaHash, AntiAlias, Blocker, PathState, RayNode, RayTree, SceneAccel, ShadowHints,
};
use crate::render::frame::Frame;
use crate::render::refine::differs;
use crate::render::verdict::verdict;
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
    /// Under PPM or SPPM, the pixel's photon term after the render's iterations.
    pub progressive: Option<ProgressiveTerm>,
}

/// A pixel's photon term under PPM or SPPM: its hit points after the
/// render's iterations (the same photons, gathered the same way).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgressiveTerm {
    /// PPM or SPPM.
    pub algorithm: PhotonMode,
    /// Iterations done.
    pub iterations: u64,
    /// Photons emitted in each.
    pub emitted: u64,
    /// The pixel's ray-traced part (linear): PPM's render of it, SPPM's mean
    /// of its iterations' samples.
    pub direct: [f32; 3],
    /// PPM's hit points in the pixel, or SPPM's one running estimate.
    pub points: Vec<HitPointTerm>,
}

/// One hit point's estimate after the iterations.
#[derive(Clone, Debug, PartialEq)]
pub struct HitPointTerm {
    /// Where it is (`None` for SPPM's, whose point is fresh each iteration).
    pub point: Option<DVec3>,
    /// What its estimate is multiplied by: the path's weight times k.
    pub weight: DVec3,
    /// Its radius R now.
    pub radius: f64,
    /// N: the photons it has accumulated (after the reduction α).
    pub photons: f64,
    /// What it adds to the pixel: weight·τ/(π·R²·iterations).
    pub term: DVec3,
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
    /// SPPM: one sample jittered over the pixel in each of n iterations.
    Fresh(u32),
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
    let (sampling, color, samples) = match spp.map(|n| n.max(1)) {
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
    explained(
        scene,
        accel,
        (x, y),
        sampling,
        color.as_vec3().to_array(),
        samples,
    )
}

/// Pixel (x, y) of `frame` explained as SPPM samples it: one sample
/// jittered over the pixel in each of its `iterations`.
pub(crate) fn explain_fresh(
    frame: &Frame,
    scene: &Scene,
    accel: &SceneAccel,
    iterations: u32,
    (x, y): (u32, u32),
) -> Explanation {
    let mut hints = ShadowHints::default();
    let n = iterations.max(1);
    let (sum, samples) = watched(frame, n as usize, &mut hints, |k| {
        frame.fresh(x, y, k as u32 + 1)
    });
    let color = (sum / f64::from(n)).as_vec3().to_array();
    explained(scene, accel, (x, y), Sampling::Fresh(n), color, samples)
}

/// The explanation of a pixel of colour `color` from its annotated samples.
fn explained(
    scene: &Scene,
    accel: &SceneAccel,
    pixel: (u32, u32),
    sampling: Sampling,
    color: [f32; 3],
    mut samples: Vec<RayNode>,
) -> Explanation {
    for node in &mut samples {
        annotate(scene, accel, node);
    }
    let file = scene.path().map(|p| p.display().to_string());
    let mut e = Explanation {
        pixel,
        bytes: [0; 3],
        color,
        sampling,
        samples,
        file,
        verdict: String::new(),
        progressive: None,
    };
    e.set_color(color);
    e
}

impl Explanation {
    /// Makes `color` the pixel's colour: its bytes and verdict follow.
    fn set_color(&mut self, color: [f32; 3]) {
        let rgb = Image::from_pixels(1, 1, vec![color]).to_rgb8();
        self.color = color;
        self.bytes = [rgb[0], rgb[1], rgb[2]];
        self.verdict = verdict(&self.samples, self.bytes, self.file.as_deref());
    }

    /// Adds PPM's or SPPM's photon term `term`, which makes the pixel
    /// `color`; the verdict says what share of its light the photons give.
    pub(crate) fn set_progressive(&mut self, term: ProgressiveTerm, color: [f32; 3]) {
        self.set_color(color);
        let photons: DVec3 = term.points.iter().map(|h| h.term).sum();
        let all = photons + DVec3::from(term.direct.map(f64::from));
        if photons.element_sum() > 0.0 {
            let share = 100.0 * photons.element_sum() / all.element_sum();
            self.verdict.push_str(&format!(
                " {}'s photons give {share:.0} % of its light.",
                term.algorithm.name().to_uppercase()
            ));
        } else {
            self.verdict.push_str(&format!(
                " {}'s photons add nothing here.",
                term.algorithm.name().to_uppercase()
            ));
        }
        self.progressive = Some(term);
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
