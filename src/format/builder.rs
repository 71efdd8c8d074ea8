//! Assembles the scene block by block: each complete block's `key= values`
//! entries are parsed against its schema row, then handed to the row's
//! build function; what every light or primitive shares (colour, material)
//! is read here.

use super::assets::Assets;
use super::block_keys::BlockKeys;
use super::detect::Evidence;
use super::diags::{Diags, Site};
use super::lexer::Word;
use super::schema::{BlockKind, Build, PrimitiveBuild, is_known_key};
use super::suggest::closest;
use super::values::{Entry, Fields, parse_entry};
use super::{colon, setup};
use crate::scene::{Dialect, DialectChoice, Light, MaterialId, PhotonEmission, Scene};
use glam::DVec3;
use std::path::Path;

/// Builds the scene block by block.
pub(crate) struct Builder<'p> {
    scene: Scene,
    assets: Assets<'p>,
    next_block: u32,
    cameras: u32,
    backgrounds: u32,
    /// The last block's fields, emptied: no allocation per block.
    spare: Fields,
    /// What the file shows of its lineage.
    pub evidence: Evidence,
    /// Notes about the file as a whole.
    notes: Vec<String>,
}

impl<'p> Builder<'p> {
    /// A builder resolving relative paths against `base` first (with
    /// `files`; without, it finds no file: see [`Assets::find_nothing`]).
    pub fn new(base: &'p Path, path: Option<&Path>, files: bool) -> Self {
        let mut scene = Scene::empty();
        scene.set_path(path.map(Path::to_path_buf));
        Builder {
            scene,
            assets: if files {
                Assets::new(base)
            } else {
                Assets::find_nothing(base)
            },
            next_block: 0,
            cameras: 0,
            backgrounds: 0,
            spare: Fields::default(),
            evidence: Evidence::default(),
            notes: Vec::new(),
        }
    }

    /// Adds a note about the file as a whole.
    pub fn note(&mut self, note: String) {
        self.notes.push(note);
    }

    /// The index of the next `primitive` block (counting every one, in file order).
    pub fn next_primitive_block(&mut self) -> u32 {
        let i = self.next_block;
        self.next_block = self.next_block.saturating_add(1);
        i
    }

    /// Makes room for the primitive blocks of the `rest` bytes still to
    /// read, at the rate of the `read` bytes read so far.
    pub fn anticipate(&mut self, read: u64, rest: u64) {
        if read == 0 {
            return;
        }
        let more = u128::from(self.next_block) * u128::from(rest) / u128::from(read);
        let more = usize::try_from(more).unwrap_or(usize::MAX);
        self.scene.reserve_blocks(more);
        self.evidence.reserve_spheres(more);
    }

    /// The scene built so far, adapted to dialect `choice`, with the notes
    /// about it and its files.
    pub fn finish(self, mut choice: DialectChoice) -> Scene {
        let mut scene = self.scene;
        self.evidence.adapt(choice.dialect, &mut scene);
        choice.caveat = caveat(choice.dialect, scene.camera().algorithm.as_deref());
        if choice.dialect == Dialect::F {
            choice.reason.push_str(&fractions(scene.camera()));
        }
        let point = |l: &Light| matches!(l.kind, crate::scene::LightKind::Point { .. });
        if choice.dialect == Dialect::V && scene.lights().iter().any(point) {
            // V's reader has no point light: such a file is likelier PM3's,
            // whose direct light is V's formula too.
            scene.add_note(
                "V's reader reads no `light point`: this file may be PM3's \
                 (its point lights are drawn with PM3's formula, which is V's)"
                    .to_string(),
            );
        }
        for note in self.notes {
            scene.add_note(note);
        }
        for note in self.assets.notes {
            scene.add_note(note);
        }
        scene.set_files(self.assets.files);
        scene.set_dialect(choice);
        scene
    }

    /// Reads one complete block.
    pub fn block(
        &mut self,
        kind: BlockKind,
        header: Site,
        entries: &[Entry<'_>],
        values: &[Word<'_>],
        index: u32,
        diags: &mut Diags,
    ) {
        let mut fields = std::mem::take(&mut self.spare);
        fields.clear();
        for e in entries {
            match kind.lookup(e.key) {
                Some((name, k)) => match parse_entry(e, values, name, k, diags) {
                    Some(f) => fields.push(f),
                    None => fields.failed.push(name),
                },
                None if is_known_key(e.key) => diags.warn(
                    e.key_site,
                    format!(
                        "`{}` is not used by a `{}` block; ignored",
                        e.written(),
                        kind.title
                    ),
                    None,
                ),
                None => {
                    let sep = if e.colon { ':' } else { '=' };
                    diags.warn(
                        e.key_site,
                        format!(
                            "unknown key `{}` in a `{}` block; ignored",
                            e.written(),
                            kind.title
                        ),
                        closest(e.key, &kind.key_names())
                            .map(|c| format!("did you mean `{c}{sep}`?")),
                    )
                }
            }
        }
        match kind.title {
            "camera" => fields
                .list()
                .iter()
                .for_each(|f| self.evidence.camera_key(f.name)),
            "primitive sphere" => {
                if let (Some((o, _)), Some((r, _))) = (fields.v3("O"), fields.num("R")) {
                    self.evidence.sphere(o, r);
                }
            }
            "primitive plane" => {
                if let (Some((n, _)), Some((r, _))) = (fields.v3("N"), fields.num("R"))
                    && let Some(n) = super::values::unit(n)
                {
                    self.evidence.plane(n, r);
                }
            }
            _ => {}
        }
        let mut b = BlockKeys {
            title: kind.title,
            header,
            fields,
            diags,
            colon: kind.colon,
        };
        match kind.build {
            Build::Background(build) => {
                self.backgrounds += 1;
                second_block(self.backgrounds, "background", &mut b);
                let bg = build(self.scene.background(), &mut b);
                self.scene.set_background(bg);
            }
            Build::Camera(build) => {
                self.cameras += 1;
                second_block(self.cameras, "camera", &mut b);
                let cam = build(self.scene.camera().clone(), &mut b);
                self.scene.set_camera(cam);
                for f in b.fields.list() {
                    self.scene.set_camera_key_line(f.name, header_line(f.site));
                }
            }
            Build::Light(build) => self.light(build, &mut b),
            Build::Primitive(build) => self.primitive(build, index, &mut b),
        }
        self.spare = b.fields;
    }

    /// A light: its kind's keys, and the colour every light has.
    fn light(
        &mut self,
        build: fn(&mut BlockKeys<'_>) -> Option<crate::scene::LightKind>,
        b: &mut BlockKeys<'_>,
    ) {
        let errors = b.diags.error_count();
        let color = match b.fields.v3("color") {
            Some((c, _)) => c,
            None => {
                if !b.fields.failed("color") {
                    let k = b.key("color");
                    b.diags.warn(
                        b.header,
                        format!("this light has no `{k}`; it gives no light"),
                        Some(format!("add e.g. `{k} 1 1 1`")),
                    );
                }
                DVec3::ZERO
            }
        };
        let intensity = b.fields.v3("intensity").map_or(DVec3::ONE, |(v, _)| v);
        self.evidence.light(color * intensity);
        let emission = if b.colon {
            colon::emission(b)
        } else {
            PhotonEmission::default()
        };
        if let Some(kind) = build(b)
            && b.diags.error_count() == errors
        {
            let index = self.scene.add_light(Light {
                kind,
                color: color * intensity,
                emission,
            });
            self.scene.set_light_line(index, header_line(b.header));
        }
    }

    /// A primitive: its material, then its kind's shapes (some with
    /// materials of their own), added as block `index`.
    fn primitive(&mut self, build: PrimitiveBuild, index: u32, b: &mut BlockKeys<'_>) {
        let errors = b.diags.error_count();
        let scene = &mut self.scene;
        let material = if b.colon {
            colon::material(&mut self.assets, b, &mut |t| scene.add_texture(t))
        } else {
            setup::material(&mut self.assets, b, &mut |t| scene.add_texture(t))
        };
        let built = build(&mut self.assets, b, &mut |t| scene.add_texture(t));
        if b.diags.error_count() != errors {
            return;
        }
        let (Some(mut m), Some(built)) = (material, built) else {
            return;
        };
        if m.normal_map.is_some()
            && let Some(shape) = built
                .shapes
                .as_slice()
                .iter()
                .find(|s| !s.takes_normal_map())
        {
            let site = b.fields.text("NT").map_or(b.header, |(_, s)| s);
            let kind = shape.kind_name();
            b.diags.warn(
                site,
                format!("a {kind} has no tangent frame to read a normal map (`NT=`) in; ignored"),
                None,
            );
            m.normal_map = None;
        }
        let m = self.scene.add_material(m);
        let own: Vec<MaterialId> = built
            .materials
            .iter()
            .map(|o| self.scene.add_material(*o))
            .collect();
        for (k, s) in built.shapes.into_iter().enumerate() {
            let of = built.material_of.get(k).copied().flatten();
            let id = of.and_then(|i| own.get(i as usize)).copied().unwrap_or(m);
            self.scene.add_object(s, id, index);
        }
        self.scene.set_block_line(index, header_line(b.header));
    }
}

/// What a reader of dialect `d`'s file should know about its picture
/// (PM3 ignores its `algorithm=`).
fn caveat(d: Dialect, algorithm: Option<&str>) -> Option<String> {
    match (d, algorithm) {
        (Dialect::Pm3, Some(a)) if a != "PM" => Some(format!(
            "PM3 renders PM whatever `algorithm=` says (here {a})"
        )),
        _ => None,
    }
}

/// What the framework's readers make of fractional qualities (they hold
/// reals and count int(16·q) rays: F `src/camera.h`, `src/raytracer.cpp`;
/// CUDA `Scene_Material.cu`), for its dialect line: empty when both are whole.
fn fractions(cam: &crate::scene::Camera) -> String {
    let mut said = String::new();
    for (key, q, rays) in [
        (
            "shade_quality",
            cam.shade_quality,
            "shadow rays an area light",
        ),
        ("drefl_quality", cam.drefl_quality, "glossy rays"),
    ] {
        if q.fract() != 0.0 && q > 0.0 {
            let n = ((16.0 * q) as u64).max(1);
            said.push_str(&format!(
                "; `{key}= {q}` read as a fraction, as the framework's readers do: {n} {rays} (int(16 × {q}))"
            ));
        }
    }
    said
}

/// The 1-based line of a site (a block's header, a key).
fn header_line(header: Site) -> u32 {
    u32::try_from(header.line + 1).unwrap_or(u32::MAX)
}

/// Warns at the second block of a kind that should appear once.
fn second_block(count: u32, what: &str, b: &mut BlockKeys<'_>) {
    if count == 2 {
        b.diags.warn(
            b.header,
            format!("a second `{what}` block; its keys override the first's"),
            None,
        );
    }
}
