//! The one enum the renderer branches on: every kind of primitive.

use super::{
    Aabb, Bezier, Cube, Cylinder, Hit, Plane, Ray, Sphere, Square, SurfacePoint, Triangle,
};

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
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Plane(_) => "plane",
            Shape::Square(_) => "square",
            Shape::Cube(_) => "cube",
            Shape::Cylinder(_) => "cylinder",
            Shape::Bezier(_) => "bezier",
            Shape::Triangle(_) => "triangle",
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
        }
    }
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
