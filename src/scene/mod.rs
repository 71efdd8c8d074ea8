//! The scene: what a file in the framework's format describes, parsed,
//! validated and resolved (textures decoded, meshes loaded), ready to render.
//!
//! A file is a sequence of blocks (`background`, `camera`, `light TYPE`,
//! `primitive TYPE`), each closed by `end`, holding `key= values` lines; see
//! `docs/format.md` for every key.

mod build;
mod diagnostic;
mod escape;
mod lexer;
mod parser;
mod suggest;

pub use diagnostic::{Diagnostic, SceneError, Severity};
pub use escape::escaped;

use crate::geometry::Shape;
use crate::shading::Texture;
use glam::DVec3;
use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};

/// The camera block: a pinhole eye and the framework's quality knobs.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (`O=`).
    pub origin: DVec3,
    /// Unit view direction (`N=`).
    pub dir: DVec3,
    /// Full image-plane width at distance 1 (`lens_W=`).
    pub lens_w: f64,
    /// Full image-plane height at distance 1 (`lens_H=`).
    pub lens_h: f64,
    /// Output width in pixels (`image_W=`).
    pub width: u32,
    /// Output height in pixels (`image_H=`).
    pub height: u32,
    /// Area-light shadow rays per point = 16 × this (`shade_quality=`).
    pub shade_quality: u32,
    /// Glossy-reflection rays = 16 × this (`drefl_quality=`).
    pub drefl_quality: u32,
    /// Photon-mapping settings (rendered by a later feature).
    pub photons: PhotonSettings,
    /// Depth of field (variants; rendered by a later feature).
    pub dof: DepthOfField,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            origin: DVec3::ZERO,
            dir: DVec3::Y,
            lens_w: 0.88,
            lens_h: 0.88,
            width: 420,
            height: 420,
            shade_quality: 4,
            drefl_quality: 4,
            photons: PhotonSettings::default(),
            dof: DepthOfField::default(),
        }
    }
}

/// The photon-map keys of the camera block.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonSettings {
    /// Photon map capacity (`max_photons=`).
    pub max_photons: u64,
    /// Photons emitted (`emit_photons=`).
    pub emit_photons: u64,
    /// Photons gathered per estimate (`sample_photons=`).
    pub sample_photons: u64,
    /// Gather radius (`sample_dist=`).
    pub sample_dist: f64,
    /// Progressive photon mapping hit points (`max_hitpoints=`), if given.
    pub max_hitpoints: Option<u64>,
    /// Progressive photon mapping passes (`iterations=`), if given.
    pub iterations: Option<u64>,
    /// Progressive radius reduction (`reduction=`), if given.
    pub reduction: Option<f64>,
}

impl Default for PhotonSettings {
    fn default() -> Self {
        PhotonSettings {
            max_photons: 2_000_000,
            emit_photons: 1_000_000,
            sample_photons: 100,
            sample_dist: 1.0,
            max_hitpoints: None,
            iterations: None,
            reduction: None,
        }
    }
}

/// Depth-of-field keys of the camera block (0 aperture: pinhole).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DepthOfField {
    /// Lens radius (`aperture=`).
    pub aperture: f64,
    /// Focus distance (`focalLen=`).
    pub focal_len: f64,
    /// Samples per pixel (`dofSample=`).
    pub samples: u32,
}

/// What a ray that hits nothing sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// A uniform colour (`color=`).
    Color(DVec3),
    /// A vertical gradient (`top=` / `bottom=`) on the ray direction's z.
    Gradient {
        /// Colour looking straight up.
        top: DVec3,
        /// Colour looking straight down.
        bottom: DVec3,
    },
}

impl Background {
    /// The colour seen along the unit direction `d`.
    #[inline]
    pub fn color(&self, d: DVec3) -> DVec3 {
        match *self {
            Background::Color(c) => c,
            Background::Gradient { top, bottom } => {
                let t = (d.z + 1.0) * 0.5;
                bottom * (1.0 - t) + top * t
            }
        }
    }
}

/// Surface material (the same keys on every primitive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Base colour (`color=`).
    pub color: DVec3,
    /// Diffuse coefficient (`diff=`).
    pub diff: f64,
    /// Specular coefficient (`spec=`).
    pub spec: f64,
    /// Mirror reflection coefficient (`refl=`).
    pub refl: f64,
    /// Glossiness of the reflection (`drefl=`, 0: perfect mirror).
    pub drefl: f64,
    /// Transmission coefficient (`refr=`).
    pub refr: f64,
    /// Index of refraction (`rindex=`).
    pub rindex: f64,
    /// Beer absorption per unit length inside, per channel (`absor=`).
    pub absor: DVec3,
    /// Index into [`Scene::textures`] (`texture=`).
    pub texture: Option<u32>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            color: DVec3::ZERO,
            diff: 0.0,
            spec: 0.0,
            refl: 0.0,
            drefl: 0.0,
            refr: 0.0,
            rindex: 0.0,
            absor: DVec3::ZERO,
            texture: None,
        }
    }
}

/// The exact bit patterns of a material's keys other than its colour (its
/// "finish"): what "equal" means for sharing (-0.0 is not 0.0, and a NaN
/// equals the same NaN), so a shared value is always the very value the
/// file gave.
fn finish_bits(m: &Material) -> [u64; 10] {
    [
        m.diff.to_bits(),
        m.spec.to_bits(),
        m.refl.to_bits(),
        m.drefl.to_bits(),
        m.refr.to_bits(),
        m.rindex.to_bits(),
        m.absor.x.to_bits(),
        m.absor.y.to_bits(),
        m.absor.z.to_bits(),
        // Never a u32: untextured differs from every texture index.
        m.texture.map_or(u64::MAX, u64::from),
    ]
}

/// A stored material: its colour and the index of its finish (32 bytes).
#[derive(Clone, Copy, Debug)]
struct MaterialEntry {
    color: DVec3,
    finish: u32,
}

fn color_bits(c: DVec3) -> [u64; 3] {
    [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()]
}

/// The scene's materials, compact: a million spheres that differ only in
/// colour cost 32 bytes each, not a full [`Material`] (104).
#[derive(Clone, Debug, Default)]
struct MaterialTable {
    /// Indexed by [`Object::material`].
    entries: Vec<MaterialEntry>,
    /// Distinct finishes (bit for bit), in order of first use: materials
    /// whose colour is unused (black).
    finishes: Vec<Material>,
    /// Finish index by a hash of its bits. Keyed by the hash alone to cost
    /// 16 bytes a finish, not 80 of bits: the bits are checked on a hit, and a
    /// different finish with the same hash (never seen in practice) is
    /// stored unshared.
    by_hash: HashMap<u64, u32>,
}

impl MaterialTable {
    #[inline]
    fn get(&self, index: u32) -> Material {
        let e = self.entries[index as usize];
        Material {
            color: e.color,
            ..self.finishes[e.finish as usize]
        }
    }

    fn add(&mut self, material: &Material) -> u32 {
        let bits = finish_bits(material);
        let last = self
            .entries
            .last()
            .map(|e| (e, finish_bits(&self.finishes[e.finish as usize])));
        let finish = match last {
            // Generated files repeat the same material block after block.
            Some((e, last_bits)) if last_bits == bits => {
                if color_bits(e.color) == color_bits(material.color) {
                    return (self.entries.len() - 1) as u32;
                }
                // Only the colour is new: no hashing needed.
                e.finish
            }
            _ => {
                let finish = Material {
                    color: DVec3::ZERO,
                    ..*material
                };
                self.intern(finish, bits, hash_bits(&bits))
            }
        };
        self.entries.push(MaterialEntry {
            color: material.color,
            finish,
        });
        (self.entries.len() - 1) as u32
    }

    /// The index of a finish equal to `finish` bit for bit, added if new;
    /// `hash` is [`hash_bits`] of `bits` (a parameter so a test can collide).
    fn intern(&mut self, finish: Material, bits: [u64; 10], hash: u64) -> u32 {
        if let Some(&i) = self.by_hash.get(&hash)
            && finish_bits(&self.finishes[i as usize]) == bits
        {
            return i;
        }
        let i = self.finishes.len() as u32;
        self.finishes.push(finish);
        self.by_hash.entry(hash).or_insert(i);
        i
    }
}

fn hash_bits(bits: &[u64; 10]) -> u64 {
    let mut h = DefaultHasher::new();
    bits.hash(&mut h);
    h.finish()
}

/// One light source.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Its shape and position.
    pub kind: LightKind,
    /// Emitted colour, `intensity=` already multiplied in.
    pub color: DVec3,
}

impl Light {
    /// The light's centre (where L points in the shading model).
    pub fn center(&self) -> DVec3 {
        match self.kind {
            LightKind::Point { pos } => pos,
            LightKind::Square { center, .. } | LightKind::Sphere { center, .. } => center,
        }
    }
}

/// The kinds of light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// `light point`: one shadow ray, hard shadows.
    Point {
        /// Position.
        pos: DVec3,
    },
    /// `light square`: area light over centre ± dx ± dy.
    Square {
        /// Centre.
        center: DVec3,
        /// Half-edge vector.
        dx: DVec3,
        /// Half-edge vector.
        dy: DVec3,
    },
    /// `light sphere`: area light over a sphere.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
}

/// One renderable surface: a shape with its material. Exactly one cache
/// line, so a primitive test touches one line.
#[derive(Clone, Debug)]
#[repr(align(64))]
pub struct Object {
    /// The geometry.
    pub shape: Shape,
    /// Material index, for [`Scene::material`].
    pub material: u32,
    /// The block or light it came from.
    pub origin: Origin,
}

// A million spheres touch a million lines, not two million.
const _: () = assert!(size_of::<Object>() == 64);

/// Where an [`Object`] came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// A `primitive` block: its 0-based index in file order.
    Block(u32),
    /// The visible surface of area light `n` (an index into [`Scene::lights`]).
    Light(u32),
}

impl Object {
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

/// A parsed and validated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file it was read from (`None` when parsed from a string).
    pub path: Option<PathBuf>,
    /// The camera.
    pub camera: Camera,
    /// The background.
    pub background: Background,
    /// Materials, indexed by [`Object::material`]: read them with
    /// [`Scene::material`], add them with [`Scene::add_material`].
    materials: MaterialTable,
    /// Decoded textures, indexed by [`Material::texture`].
    pub textures: Vec<Texture>,
    /// Lights, in file order.
    pub lights: Vec<Light>,
    /// Every surface: primitives in file order (a mesh expanded into its
    /// triangles) and the visible surfaces of area lights.
    pub objects: Vec<Object>,
    /// Warnings found while reading (unused keys, adjusted values).
    pub warnings: Vec<Diagnostic>,
    /// Notes for verbose output (e.g. which folder a texture was found in).
    pub notes: Vec<String>,
}

impl Scene {
    /// Reads and validates a scene file; relative texture and mesh paths
    /// are looked up next to the file first, then in the working directory.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        parser::parse_file(path.as_ref())
    }

    /// Parses scene text; relative paths are looked up in `base_dir`, then
    /// in the working directory.
    pub fn parse(text: &str, base_dir: impl AsRef<Path>) -> Result<Scene, SceneError> {
        parser::parse_str(text, None, base_dir.as_ref())
    }

    /// An empty scene (black background, default camera), for building scenes in code.
    pub fn empty() -> Scene {
        Scene {
            path: None,
            camera: Camera::default(),
            background: Background::Color(DVec3::ZERO),
            materials: MaterialTable::default(),
            textures: Vec::new(),
            lights: Vec::new(),
            objects: Vec::new(),
            warnings: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Adds a light, and its visible surface for area lights.
    pub fn add_light(&mut self, light: Light) -> u32 {
        let index = self.lights.len() as u32;
        let shape = match light.kind {
            LightKind::Point { .. } => None,
            LightKind::Square { center, dx, dy } => Some(Shape::Square(Box::new(
                crate::geometry::Square::new(center, dx, dy),
            ))),
            LightKind::Sphere { center, radius } => {
                Some(Shape::Sphere(crate::geometry::Sphere::new(center, radius)))
            }
        };
        if let Some(shape) = shape {
            let material = self.add_material(Material {
                color: light.color,
                ..Material::default()
            });
            self.objects.push(Object {
                shape,
                material,
                origin: Origin::Light(index),
            });
        }
        self.lights.push(light);
        index
    }

    /// Adds a material and returns its index. One identical (bit for bit) to
    /// the last added is shared; otherwise it costs 32 bytes, plus its keys
    /// other than `color=` when no earlier material had them all identical.
    pub fn add_material(&mut self, material: Material) -> u32 {
        self.materials.add(&material)
    }

    /// The material at `index` (an [`Object::material`]); panics if out of range.
    #[inline]
    pub fn material(&self, index: u32) -> Material {
        self.materials.get(index)
    }

    /// Every material, in index order.
    pub fn materials(&self) -> impl ExactSizeIterator<Item = Material> + '_ {
        (0..self.materials.entries.len() as u32).map(|i| self.materials.get(i))
    }

    /// How many materials are stored (shared ones once).
    pub fn material_count(&self) -> usize {
        self.materials.entries.len()
    }

    /// How many distinct sets of the keys other than `color=` are stored.
    pub fn finish_count(&self) -> usize {
        self.materials.finishes.len()
    }

    /// Adds a primitive surface with the given block index and material.
    pub fn add_object(&mut self, shape: Shape, material: u32, block: u32) {
        self.objects.push(Object {
            shape,
            material,
            origin: Origin::Block(block),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glossy(color: DVec3) -> Material {
        Material {
            color,
            diff: 0.3,
            refl: 0.6,
            drefl: 0.2,
            ..Material::default()
        }
    }

    #[test]
    fn a_material_that_only_brings_a_colour_costs_32_bytes() {
        assert_eq!(std::mem::size_of::<MaterialEntry>(), 32);
        let mut scene = Scene::empty();
        for i in 0..1000 {
            let index = scene.add_material(glossy(DVec3::splat(i as f64)));
            assert_eq!(index, i);
        }
        assert_eq!((scene.material_count(), scene.finish_count()), (1000, 1));
        assert_eq!(scene.material(999), glossy(DVec3::splat(999.0)));
    }

    #[test]
    fn materials_read_back_exactly_as_added() {
        let mut scene = Scene::empty();
        let all = [
            glossy(DVec3::X),
            Material {
                texture: Some(3),
                ..glossy(DVec3::X)
            },
            Material::default(),
            Material {
                rindex: f64::NAN,
                refr: 1.0,
                absor: DVec3::new(-0.0, 1e-300, 7.0),
                ..glossy(DVec3::Y)
            },
            glossy(DVec3::Z),
        ];
        let indices: Vec<_> = all.iter().map(|m| scene.add_material(*m)).collect();
        assert_eq!(indices, vec![0, 1, 2, 3, 4]);
        assert_eq!(scene.finish_count(), 4);
        for (i, m) in indices.iter().zip(&all) {
            let got = scene.material(*i);
            assert_eq!(finish_bits(&got), finish_bits(m));
            assert_eq!(color_bits(got.color), color_bits(m.color));
        }
        // A NaN is the same NaN: equal bits are shared even where == is false.
        let nan = all[3];
        assert_eq!(scene.add_material(nan), 5);
        assert_eq!(scene.add_material(nan), 5);
        assert_eq!(scene.finish_count(), 4);
    }

    #[test]
    fn a_hash_collision_stores_the_finish_unshared() {
        let mut table = MaterialTable::default();
        let a = glossy(DVec3::ZERO);
        let b = Material::default();
        assert_eq!(table.intern(a, finish_bits(&a), 7), 0);
        // Same hash, different bits: never taken for `a`.
        assert_eq!(table.intern(b, finish_bits(&b), 7), 1);
        assert_eq!(table.intern(a, finish_bits(&a), 7), 0);
        assert_eq!(table.finishes.len(), 2);
        assert_eq!(finish_bits(&table.finishes[1]), finish_bits(&b));
    }
}
