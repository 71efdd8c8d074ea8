//! The surfaces a scene is made of: a shape, its material, where it came from.

use crate::geometry::Shape;

/// One renderable surface: a shape with its material. Exactly one cache
/// line, so a primitive test touches one line.
#[derive(Clone, Debug)]
#[repr(align(64))]
pub struct Object {
    /// The geometry.
    pub(crate) shape: Shape,
    /// Index into the scene's materials.
    pub(crate) material: u32,
    /// The block or light it came from.
    pub(crate) origin: Origin,
}

// A million spheres touch a million lines, not two million.
const _: () = assert!(size_of::<Object>() == 64);

/// Where an [`Object`] came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// A `primitive` block: its 0-based index in file order.
    Block(u32),
    /// The visible surface of area light `n` (an index into [`Scene::lights`](super::Scene::lights)).
    Light(u32),
}

impl Object {
    /// The geometry.
    #[inline]
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The block or light it came from.
    #[inline]
    pub fn origin(&self) -> Origin {
        self.origin
    }

    /// 0-based index of the `primitive` block it came from, in file order
    /// (`None` for the visible surface of an area light).
    #[inline]
    pub fn block(&self) -> Option<u32> {
        match self.origin {
            Origin::Block(b) => Some(b),
            Origin::Light(_) => None,
        }
    }

    /// The light this surface emits for, if it is an area light's surface.
    #[inline]
    pub fn light(&self) -> Option<u32> {
        match self.origin {
            Origin::Light(l) => Some(l),
            Origin::Block(_) => None,
        }
    }
}
