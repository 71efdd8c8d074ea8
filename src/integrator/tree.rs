//! The ray tree of one camera sample: a [`PathObserver`] that records every
//! ray the shading code traces, what it hit, each light's term and the
//! colour it returned (for `glint explain`).

use super::observer::{LightSeen, PathObserver, RayKind, SurfaceSeen};
use super::photons::Gathered;
use crate::geometry::{Hit, Ray, Shape};
use crate::scene::{Material, Origin};
use glam::{DVec2, DVec3};

/// What a ray hit.
#[derive(Clone, Debug, PartialEq)]
pub struct HitInfo {
    /// The primitive block (0-based, file order), `None` for a light's surface.
    pub primitive: Option<u32>,
    /// The area light whose visible surface was hit.
    pub light: Option<u32>,
    /// The shape's kind (`sphere`, `cube`...).
    pub kind: &'static str,
    /// The 1-based line of the block's header (filled in by the renderer).
    pub line: Option<u32>,
    /// Distance along the ray.
    pub t: f64,
    /// The hit point.
    pub point: DVec3,
    /// Unit geometric normal, turned to face against the ray.
    pub normal: DVec3,
    /// Whether the ray hit the outside (front) of the surface.
    pub front: bool,
    /// Texture coordinates.
    pub uv: DVec2,
}

/// What stopped a point light's shadow ray.
#[derive(Clone, Debug, PartialEq)]
pub struct Blocker {
    /// The primitive block, `None` for a light's surface.
    pub primitive: Option<u32>,
    /// The area light whose surface blocked it.
    pub light: Option<u32>,
    /// The shape's kind.
    pub kind: &'static str,
    /// The 1-based line of its block's header.
    pub line: Option<u32>,
    /// Distance from the shaded point along the shadow ray.
    pub t: f64,
}

/// One light's term at a hit.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTerm {
    /// The light's index, in file order.
    pub light: u32,
    /// `point`, `square` or `sphere`.
    pub kind: &'static str,
    /// The 1-based line of its header.
    pub line: Option<u32>,
    /// L·N: the light only counts where it is positive.
    pub l_dot_n: f64,
    /// Shadow rays that reached the light.
    pub reached: u64,
    /// Shadow rays traced (0 when L·N ≤ 0: none are).
    pub rays: u64,
    /// The shade factor: `reached / rays`.
    pub s: f64,
    /// The diffuse weight diff·(L·N)·s.
    pub diffuse: f64,
    /// The specular weight spec·(L·N)^20·s.
    pub specular: f64,
    /// What blocked a point light's shadow ray (filled in by the renderer).
    pub blocker: Option<Blocker>,
    /// Where the shadow rays started: the point and the side's unit normal.
    pub(crate) from: (DVec3, DVec3),
}

/// The photon estimate at a hit (PM).
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonTerm {
    /// Photons gathered (fewer than 8 give no estimate).
    pub gathered: usize,
    /// The gather radius r (the K-th nearest photon's distance, or R).
    pub radius: f64,
    /// What it adds to the hit's colour, k·(the estimate).
    pub term: DVec3,
}

/// One ray of a sample's tree.
#[derive(Clone, Debug, PartialEq)]
pub struct RayNode {
    /// What made it.
    pub kind: RayKind,
    /// Its depth (the camera ray has 1).
    pub depth: u32,
    /// Where it starts.
    pub origin: DVec3,
    /// Its unit direction.
    pub direction: DVec3,
    /// What it hit (`None`: the background).
    pub hit: Option<HitInfo>,
    /// The material at the hit.
    pub material: Option<Material>,
    /// Each light's term at the hit.
    pub lights: Vec<LightTerm>,
    /// The rays it spawned, in order.
    pub children: Vec<RayNode>,
    /// Child rays not traced because they would pass the depth limit.
    pub cut: Vec<RayKind>,
    /// The photon estimate at the hit (PM).
    pub photons: Option<PhotonTerm>,
    /// The sum before the clamp to 1 per channel (`None` on a miss or a light's surface).
    pub unclamped: Option<DVec3>,
    /// Its colour, clamped.
    pub color: DVec3,
    /// Its weight in its parent's sum (1 for the camera ray).
    pub weight: DVec3,
}

/// Records the trees of the camera rays it watches.
#[derive(Clone, Default)]
pub(crate) struct RayTree {
    open: Vec<RayNode>,
    done: Vec<RayNode>,
}

impl RayTree {
    /// The finished trees (one per camera ray watched).
    pub fn into_roots(self) -> Vec<RayNode> {
        self.done
    }

    fn top(&mut self) -> Option<&mut RayNode> {
        self.open.last_mut()
    }
}

/// What `ray` hit on `shape` at `hit`, with the full surface (uv included).
fn hit_info(origin: Origin, shape: &Shape, ray: &Ray, hit: &Hit) -> HitInfo {
    let s = shape.surface(ray, hit);
    let front = s.normal.dot(ray.dir) < 0.0;
    let (primitive, light) = match origin {
        Origin::Block(b) => (Some(b), None),
        Origin::Light(l) => (None, Some(l)),
    };
    HitInfo {
        primitive,
        light,
        kind: shape.kind_name(),
        line: None,
        t: hit.t,
        point: s.point,
        normal: if front { s.normal } else { -s.normal },
        front,
        uv: s.uv,
    }
}

impl PathObserver for RayTree {
    type Fan<'s> = &'s mut RayTree;

    fn fan(&mut self) -> &mut RayTree {
        self
    }

    type Queries<'q> = ();

    fn queries(&mut self) {}

    fn hit(&mut self, _: Origin) {}

    fn point_light(&mut self, _: u32) {}

    fn ray(&mut self, kind: RayKind, depth: u32, ray: &Ray) {
        self.open.push(RayNode {
            kind,
            depth,
            origin: ray.origin,
            direction: ray.dir,
            hit: None,
            material: None,
            lights: Vec::new(),
            children: Vec::new(),
            cut: Vec::new(),
            photons: None,
            unclamped: None,
            color: DVec3::ZERO,
            weight: DVec3::ONE,
        });
    }

    fn surface(&mut self, seen: &SurfaceSeen<'_>) {
        let info = hit_info(seen.origin, seen.shape, seen.ray, seen.hit);
        if let Some(node) = self.top() {
            node.hit = Some(info);
            node.material = Some(*seen.material);
        }
    }

    fn emitter(&mut self, light: u32, shape: &Shape, ray: &Ray, hit: &Hit) {
        let info = hit_info(Origin::Light(light), shape, ray, hit);
        if let Some(node) = self.top() {
            node.hit = Some(info);
        }
    }

    fn light(&mut self, seen: &LightSeen) {
        let term = LightTerm {
            light: seen.light,
            kind: "",
            line: None,
            l_dot_n: seen.l_dot_n,
            reached: (seen.s * seen.rays as f64).round() as u64,
            rays: seen.rays,
            s: seen.s,
            diffuse: seen.diffuse,
            specular: seen.specular,
            blocker: None,
            from: (seen.point, seen.side),
        };
        if let Some(node) = self.top() {
            node.lights.push(term);
        }
    }

    fn cut(&mut self, kind: RayKind) {
        if let Some(node) = self.top() {
            node.cut.push(kind);
        }
    }

    fn photons(&mut self, gathered: &Gathered, term: DVec3) {
        if let Some(node) = self.top() {
            node.photons = Some(PhotonTerm {
                gathered: gathered.count,
                radius: gathered.r2.sqrt(),
                term,
            });
        }
    }

    fn shaded(&mut self, sum: DVec3) {
        if let Some(node) = self.top() {
            node.unclamped = Some(sum);
        }
    }

    fn done(&mut self, color: DVec3, weight: DVec3) {
        let Some(mut node) = self.open.pop() else {
            return;
        };
        node.color = color;
        node.weight = weight;
        match self.open.last_mut() {
            Some(parent) => parent.children.push(node),
            None => self.done.push(node),
        }
    }
}
