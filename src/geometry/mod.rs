//! Primitives: one file per kind, each answering the same questions
//! (intersect, surface point at a hit, bounds).
//!
//! Conventions shared by every kind:
//! - a [`Ray`] has a unit direction, so `t` is a distance;
//! - `intersect(ray, t_min, t_max)` returns the nearest hit with
//!   `t_min < t < t_max`, or `None`;
//! - [`SurfacePoint::normal`] is the unit *outward* geometric normal (for
//!   two-sided flat shapes: the normal the spec defines, e.g. unit(Dx × Dy));
//!   whether the ray hit the front is decided by its sign against the ray.

mod aabb;
mod bezier;
mod cube;
mod cylinder;
mod frame;
pub(crate) mod normal_map;
mod plane;
mod ray;
mod rectangle;
mod shape;
mod sphere;
mod square;
mod triangle;

pub use aabb::Aabb;
pub use bezier::{Bezier, BezierUv};
pub use cube::Cube;
pub use cylinder::Cylinder;
pub use frame::{angle_around, axis_frame, perpendiculars};
pub use plane::Plane;
pub(crate) use ray::Span;
pub use ray::{Hit, Ray, SurfacePoint, offset_origin};
pub use rectangle::Rectangle;
pub use shape::Shape;
pub(crate) use shape::kind_name_of;
pub use sphere::Sphere;
pub use square::Square;
pub use triangle::Triangle;
