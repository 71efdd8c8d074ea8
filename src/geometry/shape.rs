//! The one enum the renderer branches on: every kind of primitive.

use super::normal_map::{
    TangentFrame, perturbed_normal, plane_frame, sphere_frame, triangle_frame,
};
use super::{
    Aabb, Bezier, Cube, Cylinder, Hit, Plane, Ray, Rectangle, Sphere, Square, SurfacePoint,
    Triangle,
};
use glam::DVec3;

/// Every kind of primitive, as one enum so the hot path branches instead of
/// calling through pointers. Large kinds are boxed to keep the enum small.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// An infinite plane.
    Plane(Box<Plane>),
    /// A parallelogram.
    Square(Box<Square>),
    /// An oriented box.
    Cube(Box<Cube>),
    /// A closed cylinder.
    Cylinder(Box<Cylinder>),
    /// A Bézier surface of revolution.
    Bezier(Box<Bezier>),
    /// A triangle (alone or from a mesh).
    Triangle(Box<Triangle>),
    /// The lineages' rectangle (a plane cut by its texture coordinates).
    Rectangle(Box<Rectangle>),
}

impl Shape {
    /// The nearest hit with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Plane(s) => s.intersect(ray, t_min, t_max),
            Shape::Square(s) => s.intersect(ray, t_min, t_max),
            Shape::Cube(s) => s.intersect(ray, t_min, t_max),
            Shape::Cylinder(s) => s.intersect(ray, t_min, t_max),
            Shape::Bezier(s) => s.intersect(ray, t_min, t_max),
            Shape::Triangle(s) => s.intersect(ray, t_min, t_max),
            Shape::Rectangle(s) => s.intersect(ray, t_min, t_max),
        }
    }

    /// [`Shape::intersect`] with a plane's test inlined at the call: the
    /// unbounded kind, which every query tests, where a call costs as much
    /// as the test.
    #[inline(always)]
    pub fn intersect_unbounded(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match self {
            Shape::Plane(p) => p.intersect(ray, t_min, t_max),
            _ => self.intersect(ray, t_min, t_max),
        }
    }

    /// Whether [`Shape::intersect_bounded`] finds a hit: a Bézier surface's
    /// search ends at the first it finds, not the nearest.
    #[inline(always)]
    pub fn blocks_bounded(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        match self {
            Shape::Bezier(b) => b.blocks(ray, t_min, t_max),
            _ => self.intersect_bounded(ray, t_min, t_max).is_some(),
        }
    }

    /// [`Shape::intersect`] with a sphere's test inlined at the call.
    #[inline(always)]
    pub fn intersect_bounded(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            _ => self.intersect(ray, t_min, t_max),
        }
    }

    /// Finishes a hit returned by [`Shape::intersect`] for the same ray.
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface(ray, hit),
            Shape::Plane(s) => s.surface(ray, hit),
            Shape::Square(s) => s.surface(ray, hit),
            Shape::Cube(s) => s.surface(ray, hit),
            Shape::Cylinder(s) => s.surface(ray, hit),
            Shape::Bezier(s) => s.surface(ray, hit),
            Shape::Triangle(s) => s.surface(ray, hit),
            Shape::Rectangle(s) => s.surface(ray, hit),
        }
    }

    /// [`Shape::surface`] without the texture coordinates (left at zero), for
    /// untextured materials: spares spheres their trigonometry.
    #[inline]
    pub fn surface_untextured(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface_untextured(ray, hit),
            _ => self.surface(ray, hit),
        }
    }

    /// The kind's name, as the scene format spells it (`sphere`, `cube`...).
    pub fn kind_name(&self) -> &'static str {
        // The names are those of `KINDS`.
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Plane(_) => "plane",
            Shape::Square(_) => "square",
            Shape::Cube(_) => "cube",
            Shape::Cylinder(_) => "cylinder",
            Shape::Bezier(_) => "bezier",
            Shape::Triangle(_) => "triangle",
            Shape::Rectangle(_) => "rectangle",
        }
    }

    /// World-space bounds, or `None` for unbounded shapes (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Plane(_) => None,
            Shape::Square(s) => Some(s.bounds()),
            Shape::Cube(s) => Some(s.bounds()),
            Shape::Cylinder(s) => Some(s.bounds()),
            Shape::Bezier(s) => Some(s.bounds()),
            Shape::Triangle(s) => Some(s.bounds()),
            Shape::Rectangle(s) => Some(s.bounds()),
        }
    }

    /// Whether a normal map can be read on this kind (it has a
    /// [`Shape::tangent_frame`]): spheres, planes, squares, rectangles and
    /// triangles.
    pub fn takes_normal_map(&self) -> bool {
        matches!(
            self,
            Shape::Sphere(_)
                | Shape::Plane(_)
                | Shape::Square(_)
                | Shape::Rectangle(_)
                | Shape::Triangle(_)
        )
    }

    /// The frame a normal map is read in at surface point `s` (from
    /// [`Shape::surface`]): V's sphere frame about the centre, V's plane frame
    /// (fixed) for the flat kinds, the texture-coordinate frame for triangles;
    /// `None` for the other kinds and degenerate mappings.
    pub fn tangent_frame(&self, s: &SurfacePoint) -> Option<TangentFrame> {
        match self {
            Shape::Sphere(sp) => Some(sphere_frame(s.point - sp.center)),
            Shape::Plane(_) | Shape::Square(_) | Shape::Rectangle(_) => Some(plane_frame(s.normal)),
            Shape::Triangle(t) => triangle_frame(s.shading_normal, t.vertices, t.vertex_uvs()),
            Shape::Cube(_) | Shape::Cylinder(_) | Shape::Bezier(_) => None,
        }
    }

    /// The outward shading normal at `s` perturbed by the normal-map texel
    /// `texel` (sampled at `s.uv`); `s.shading_normal` where there is no frame.
    pub fn mapped_normal(&self, s: &SurfacePoint, texel: DVec3) -> DVec3 {
        self.tangent_frame(s)
            .map_or(s.shading_normal, |f| perturbed_normal(&f, texel))
    }
}

/// Every name [`Shape::kind_name`] gives.
const KINDS: [&str; 8] = [
    "sphere",
    "plane",
    "square",
    "cube",
    "cylinder",
    "bezier",
    "triangle",
    "rectangle",
];

/// The kind name `name` as [`Shape::kind_name`] gives it (`?` for none).
pub(crate) fn kind_name_of(name: &str) -> &'static str {
    KINDS.iter().find(|k| **k == name).copied().unwrap_or("?")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A million-sphere scene keeps its objects small: the enum stays at the
    /// sphere's size because the larger kinds are boxed.
    #[test]
    fn shape_stays_small() {
        assert!(
            std::mem::size_of::<Shape>() <= 48,
            "{}",
            std::mem::size_of::<Shape>()
        );
    }
}
