//! The scene model: what a file describes, validated and resolved
//! (textures decoded, meshes loaded), ready to render. Its collections are
//! private; the `add_*` methods keep their invariants (every object's
//! material and light exist), so a scene built in code is as sound as one
//! read from a file.

mod background;
mod camera;
mod diagnostic;
mod dialect;
mod escape;
mod light;
mod material;
mod object;
mod room;
mod texture;

pub use background::Background;
pub use camera::{Camera, DepthOfField, MAX_IMAGE_SIDE, PhotonSettings};
pub use diagnostic::{Diagnostic, SceneError, Severity};
pub use dialect::{Dialect, DialectChoice};
pub use escape::escaped;
pub use light::{Light, LightKind, PhotonEmission};
pub use material::Material;
pub use object::{Object, Origin};
pub(crate) use room::make_room;
pub use texture::Texture;

use crate::geometry::{Shape, Sphere, Square};
use glam::DVec3;
use material::MaterialTable;
use std::path::{Path, PathBuf};

/// A material's index in its scene, as [`Scene::add_material`] returns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialId(u32);

impl MaterialId {
    /// The index, for [`Scene::material`].
    pub fn index(self) -> u32 {
        self.0
    }
}

/// A parsed and validated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    path: Option<PathBuf>,
    camera: Camera,
    background: Background,
    materials: MaterialTable,
    textures: Vec<Texture>,
    lights: Vec<Light>,
    objects: Vec<Object>,
    warnings: Vec<Diagnostic>,
    notes: Vec<String>,
    /// The files besides the scene file it read (textures, meshes, MTL files).
    files: Vec<PathBuf>,
    /// The 1-based line of each primitive block's header, by block index (0: unknown).
    block_lines: Vec<u32>,
    /// The 1-based line of each light's header, by light index (0: unknown).
    light_lines: Vec<u32>,
    /// The 1-based line of each camera key that set its value (the last
    /// one read), when read from text.
    camera_key_lines: Vec<(&'static str, u32)>,
    /// The lineage whose renderer's model draws it, and why.
    dialect: DialectChoice,
}

impl Scene {
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
            files: Vec::new(),
            block_lines: Vec::new(),
            light_lines: Vec::new(),
            camera_key_lines: Vec::new(),
            dialect: DialectChoice::default(),
        }
    }

    /// The dialect it is drawn in, and the rule that chose it.
    pub fn dialect(&self) -> &DialectChoice {
        &self.dialect
    }

    /// Sets the dialect it is drawn in (a scene built in code is the framework's).
    pub fn set_dialect(&mut self, dialect: DialectChoice) {
        self.dialect = dialect;
    }

    /// Every object's shape, to adapt a file read by the framework's rules to its lineage.
    pub(crate) fn shapes_mut(&mut self) -> impl Iterator<Item = &mut Shape> {
        self.objects.iter_mut().map(|o| &mut o.shape)
    }

    /// The textures, to adapt to a lineage's way of reading images.
    pub(crate) fn textures_mut(&mut self) -> &mut [Texture] {
        &mut self.textures
    }

    /// The file it was read from (`None` when parsed from a string or built in code).
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The background.
    pub fn background(&self) -> Background {
        self.background
    }

    /// Decoded textures, indexed by [`Material::texture`].
    pub fn textures(&self) -> &[Texture] {
        &self.textures
    }

    /// Lights, in file order.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Every surface: primitives in file order (a mesh expanded into its
    /// triangles) and the visible surfaces of area lights.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Warnings found while reading (unused keys, adjusted values).
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// Notes for verbose output (e.g. which folder a texture was found in).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The material of `object`.
    #[inline]
    pub fn material_of(&self, object: &Object) -> Material {
        self.materials.get(object.material)
    }

    /// A number read from `object`'s material entry, meaningless: reading
    /// it ahead of [`Scene::material_of`] brings the entry into the cache.
    #[inline]
    pub(crate) fn read_material_ahead(&self, object: &Object) -> u32 {
        self.materials.read_ahead(object.material)
    }

    /// The material at `index` (in the order added, shared ones once);
    /// panics if out of range.
    pub fn material(&self, index: u32) -> Material {
        self.materials.get(index)
    }

    /// Every material, in index order.
    pub fn materials(&self) -> impl ExactSizeIterator<Item = Material> + '_ {
        (0..self.materials.len() as u32).map(|i| self.materials.get(i))
    }

    /// How many materials are stored (shared ones once).
    pub fn material_count(&self) -> usize {
        self.materials.len()
    }

    /// How many distinct sets of the keys other than `color=` are stored.
    pub fn finish_count(&self) -> usize {
        self.materials.finish_count()
    }

    /// Sets the camera.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// Sets the background.
    pub fn set_background(&mut self, background: Background) {
        self.background = background;
    }

    /// The files besides the scene file it read: textures, meshes and their
    /// MTL files, as found (next to the scene file or in the working directory).
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Makes room for `more` primitive blocks' objects, materials and
    /// lines beyond those held (one shape each): a reader that can tell how
    /// many are still to come saves the copies of growing a million-entry
    /// list by doubling (objects, aligned to cache lines, are copied whole
    /// on every growth). See [`make_room`].
    pub(crate) fn reserve_blocks(&mut self, more: usize) {
        make_room(&mut self.objects, more);
        self.materials.make_room(more);
        make_room(&mut self.block_lines, more);
    }

    /// Sets the files besides the scene file that it read.
    pub(crate) fn set_files(&mut self, files: Vec<PathBuf>) {
        self.files = files;
    }

    /// Sets the file the scene was read from.
    pub(crate) fn set_path(&mut self, path: Option<PathBuf>) {
        self.path = path;
    }

    /// The 1-based line of the header of primitive block `block` (0-based,
    /// in file order), when the scene was read from text.
    pub fn block_line(&self, block: u32) -> Option<u32> {
        self.block_lines
            .get(block as usize)
            .copied()
            .filter(|&l| l > 0)
    }

    /// The 1-based line of the header of light `light`, when the scene was read from text.
    pub fn light_line(&self, light: u32) -> Option<u32> {
        self.light_lines
            .get(light as usize)
            .copied()
            .filter(|&l| l > 0)
    }

    /// The 1-based line of the camera key `key` (`shade_quality`,
    /// `image_W`...) that set the camera's value, when the scene was read
    /// from text (a second `camera` block's key overrides the first's).
    pub fn camera_key_line(&self, key: &str) -> Option<u32> {
        self.camera_key_lines
            .iter()
            .find(|(k, _)| *k == key)
            .map(|&(_, l)| l)
            .filter(|&l| l > 0)
    }

    /// Records that the camera key `key` was set at 1-based line `line`.
    pub(crate) fn set_camera_key_line(&mut self, key: &'static str, line: u32) {
        match self.camera_key_lines.iter_mut().find(|(k, _)| *k == key) {
            Some(entry) => entry.1 = line,
            None => self.camera_key_lines.push((key, line)),
        }
    }

    /// Records that primitive block `block` starts at 1-based line `line`.
    pub(crate) fn set_block_line(&mut self, block: u32, line: u32) {
        set_line(&mut self.block_lines, block, line);
    }

    /// Records that light `light` starts at 1-based line `line`.
    pub(crate) fn set_light_line(&mut self, light: u32, line: u32) {
        set_line(&mut self.light_lines, light, line);
    }

    /// Sets the warnings found while reading.
    pub(crate) fn set_warnings(&mut self, warnings: Vec<Diagnostic>) {
        self.warnings = warnings;
    }

    /// Adds a note for verbose output.
    pub(crate) fn add_note(&mut self, note: String) {
        self.notes.push(note);
    }

    /// Adds a texture; its index (for [`Material::texture`]) is returned.
    pub fn add_texture(&mut self, texture: Texture) -> u32 {
        self.textures.push(texture);
        (self.textures.len() - 1) as u32
    }

    /// Adds a light, and its visible surface for area lights.
    pub fn add_light(&mut self, light: Light) -> u32 {
        let index = self.lights.len() as u32;
        let shape = match light.kind {
            LightKind::Point { .. } => None,
            LightKind::Square { center, dx, dy } => {
                Some(Shape::Square(Box::new(Square::new(center, dx, dy))))
            }
            LightKind::Sphere { center, radius } => {
                Some(Shape::Sphere(Sphere::new(center, radius)))
            }
        };
        if let Some(shape) = shape {
            let material = self.add_material(Material {
                color: light.color,
                ..Material::default()
            });
            self.objects.push(Object {
                shape,
                material: material.0,
                origin: Origin::Light(index),
            });
        }
        self.lights.push(light);
        index
    }

    /// Adds a material and returns its id. One identical (bit for bit) to
    /// the last added, or to a recent one (a table of recent entries, so
    /// most repeats), is shared; otherwise it costs 32 bytes, plus its keys
    /// other than `color=` when no earlier material had them all identical.
    /// A texture index (also a normal map's) that names no texture of this
    /// scene is dropped.
    pub fn add_material(&mut self, mut material: Material) -> MaterialId {
        let count = self.textures.len();
        for t in [&mut material.texture, &mut material.normal_map] {
            if t.is_some_and(|t| t as usize >= count) {
                *t = None;
            }
        }
        MaterialId(self.materials.add(&material))
    }

    /// Adds a primitive surface: the `block`-th primitive block (0-based,
    /// in file order), with material `material` of this scene.
    pub fn add_object(&mut self, shape: Shape, material: MaterialId, block: u32) {
        self.objects.push(Object {
            shape,
            material: material.0,
            origin: Origin::Block(block),
        });
    }

    /// Removes the lights' visible surfaces (a lineage whose lights are no
    /// primitives: lazycal's).
    pub(crate) fn hide_light_surfaces(&mut self) {
        self.objects.retain(|o| o.light().is_none());
    }

    /// Keeps the last light only (lazycal's reader keeps the last `light`
    /// block), with its line; call before any light has a visible surface
    /// left ([`Scene::hide_light_surfaces`]).
    pub(crate) fn keep_last_light(&mut self) {
        let last = self.lights.len().saturating_sub(1);
        self.lights.drain(..last);
        let line = self.light_lines.get(last).copied();
        self.light_lines = line.into_iter().collect();
    }

    /// Takes the objects out (for the acceleration structure that will own them).
    pub(crate) fn take_objects(&mut self) -> Vec<Object> {
        std::mem::take(&mut self.objects)
    }
}

/// Sets `lines[index]` to `line`, growing the table with unknowns (0).
fn set_line(lines: &mut Vec<u32>, index: u32, line: u32) {
    let i = index as usize;
    if lines.len() <= i {
        lines.resize(i + 1, 0);
    }
    lines[i] = line;
}
