//! Turns the `key= values` entries of one block into the camera, the
//! background, a light or a primitive with its material, checking that the
//! values make geometric sense.
//!
//! Defaults chosen where the format leaves them open:
//! - a plane without `Dx=`/`Dy=` gets texture axes (e1, e2) of
//!   [`crate::geometry::axis_frame`] of its unit normal (x and y for N = z);
//!   with only one of them given, the other is that one turned 90° about N
//!   (same length), so Dx × Dy points along N;
//! - a cube without `Dx=`/`Dy=` is axis-aligned (x, y);
//! - background: a gradient end that is not given (`top=` alone, or
//!   `bottom=` alone) is white;
//! - a light without `color=` is black (and a warning says so);
//! - `refr=` > 0 with `rindex=` ≤ 0 uses rindex 1 (the framework divides by
//!   it and produces NaN).

use super::lexer::Word;
use super::parser::{Diags, Site};
use super::suggest::closest;
use super::{Background, Light, LightKind, Material, Scene};
use crate::geometry::{Bezier, Cube, Cylinder, Plane, Shape, Sphere, Square, Triangle, axis_frame};
use crate::shading::Texture;
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The `light TYPE`s.
pub(crate) const LIGHT_TYPES: [&str; 3] = ["point", "square", "sphere"];

/// The `primitive TYPE`s.
pub(crate) const PRIMITIVE_TYPES: [&str; 8] = [
    "sphere", "plane", "square", "cube", "cylinder", "bezier", "triangle", "mesh",
];

/// Largest magnitude accepted for a number: far beyond any scene, and small
/// enough that products of a few coordinates cannot overflow.
const MAX_MAGNITUDE: f64 = 1e100;

/// Largest image side in pixels.
const MAX_IMAGE_SIDE: f64 = 32768.0;

/// Two unit directions closer to parallel than this (sine of the angle)
/// span no area.
const PARALLEL_SINE: f64 = 1e-12;

/// How far a cube's `Dx=`/`Dy=` may be from unit length and perpendicular
/// before a warning says they were adjusted.
const ORTHONORMAL_TOLERANCE: f64 = 1e-9;
/// Above this `shade_quality=` or `drefl_quality=` (16 times the
/// framework's default) a warning says the render will be slow.
const SLOW_QUALITY: u32 = 64;

/// A kind of light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LightType {
    Point,
    Square,
    Sphere,
}

/// A kind of primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PrimitiveType {
    Sphere,
    Plane,
    Square,
    Cube,
    Cylinder,
    Bezier,
    Triangle,
    Mesh,
}

/// What a block describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BlockKind {
    Background,
    Camera,
    Light(LightType),
    Primitive(PrimitiveType),
}

/// The shape of a key's values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// One number.
    Num,
    /// One whole number ≥ 0.
    Count,
    /// Two numbers.
    Vec2,
    /// Three numbers.
    Vec3,
    /// One number (used for all three) or three.
    OneOrThree,
    /// The rest of the line (a file name, a blur name).
    Text,
}

use Kind::{Count, Num, OneOrThree, Text, Vec2, Vec3};

const MATERIAL_KEYS: &[(&str, Kind)] = &[
    ("color", Vec3),
    ("diff", Num),
    ("spec", Num),
    ("refl", Num),
    ("drefl", Num),
    ("blur", Text),
    ("refr", Num),
    ("rindex", Num),
    ("absor", Vec3),
    ("texture", Text),
];

const BACKGROUND_KEYS: &[(&str, Kind)] = &[("color", Vec3), ("top", Vec3), ("bottom", Vec3)];

const CAMERA_KEYS: &[(&str, Kind)] = &[
    ("O", Vec3),
    ("N", Vec3),
    ("lens_W", Num),
    ("lens_H", Num),
    ("image_W", Count),
    ("image_H", Count),
    ("shade_quality", Count),
    ("drefl_quality", Count),
    ("max_photons", Count),
    ("emit_photons", Count),
    ("sample_photons", Count),
    ("sample_dist", Num),
    ("aperture", Num),
    ("focalLen", Num),
    ("dofSample", Count),
    ("max_hitpoints", Count),
    ("iterations", Count),
    ("reduction", Num),
];

const LIGHT_COMMON_KEYS: &[(&str, Kind)] = &[("color", Vec3), ("intensity", OneOrThree)];
const POINT_LIGHT_KEYS: &[(&str, Kind)] = &[("O", Vec3)];
const SQUARE_LIGHT_KEYS: &[(&str, Kind)] = &[("O", Vec3), ("Dx", Vec3), ("Dy", Vec3)];
const SPHERE_LIGHT_KEYS: &[(&str, Kind)] = &[("O", Vec3), ("R", Num)];

const SPHERE_KEYS: &[(&str, Kind)] = &[("O", Vec3), ("R", Num), ("De", Vec3), ("Dc", Vec3)];
const PLANE_KEYS: &[(&str, Kind)] = &[("N", Vec3), ("R", Num), ("Dx", Vec3), ("Dy", Vec3)];
const SQUARE_KEYS: &[(&str, Kind)] = &[("O", Vec3), ("Dx", Vec3), ("Dy", Vec3)];
const CUBE_KEYS: &[(&str, Kind)] = &[
    ("O", Vec3),
    ("Dx", Vec3),
    ("Dy", Vec3),
    ("x", Num),
    ("y", Num),
    ("z", Num),
];
const CYLINDER_KEYS: &[(&str, Kind)] = &[("O1", Vec3), ("O2", Vec3), ("R", Num)];
const BEZIER_KEYS: &[(&str, Kind)] = &[("O1", Vec3), ("O2", Vec3), ("P", Vec2)];
const TRIANGLE_KEYS: &[(&str, Kind)] = &[("O1", Vec3), ("O2", Vec3), ("O3", Vec3)];
const MESH_KEYS: &[(&str, Kind)] = &[
    ("file", Text),
    ("O", Vec3),
    ("scale", OneOrThree),
    ("rotation", Vec3),
];

/// Every key table, for telling "a key of another block" from "unknown".
const ALL_TABLES: [&[(&str, Kind)]; 15] = [
    MATERIAL_KEYS,
    BACKGROUND_KEYS,
    CAMERA_KEYS,
    LIGHT_COMMON_KEYS,
    POINT_LIGHT_KEYS,
    SQUARE_LIGHT_KEYS,
    SPHERE_LIGHT_KEYS,
    SPHERE_KEYS,
    PLANE_KEYS,
    SQUARE_KEYS,
    CUBE_KEYS,
    CYLINDER_KEYS,
    BEZIER_KEYS,
    TRIANGLE_KEYS,
    MESH_KEYS,
];

impl BlockKind {
    /// The light block for a `light TYPE` header.
    pub fn light(t: &str) -> Option<BlockKind> {
        Some(BlockKind::Light(match t {
            "point" => LightType::Point,
            "square" => LightType::Square,
            "sphere" => LightType::Sphere,
            _ => return None,
        }))
    }

    /// The primitive block for a `primitive TYPE` header.
    pub fn primitive(t: &str) -> Option<BlockKind> {
        use PrimitiveType as P;
        Some(BlockKind::Primitive(match t {
            "sphere" => P::Sphere,
            "plane" => P::Plane,
            "square" => P::Square,
            "cube" => P::Cube,
            "cylinder" => P::Cylinder,
            "bezier" => P::Bezier,
            "triangle" => P::Triangle,
            "mesh" => P::Mesh,
            _ => return None,
        }))
    }

    /// The header as written (`primitive sphere`).
    pub fn name(&self) -> String {
        match self {
            BlockKind::Background => "background".to_string(),
            BlockKind::Camera => "camera".to_string(),
            BlockKind::Light(t) => format!("light {}", LIGHT_TYPES[*t as usize]),
            BlockKind::Primitive(t) => format!("primitive {}", PRIMITIVE_TYPES[*t as usize]),
        }
    }

    /// The key tables that apply to this block.
    fn tables(&self) -> [&'static [(&'static str, Kind)]; 2] {
        use PrimitiveType as P;
        match self {
            BlockKind::Background => [BACKGROUND_KEYS, &[]],
            BlockKind::Camera => [CAMERA_KEYS, &[]],
            BlockKind::Light(t) => [
                match t {
                    LightType::Point => POINT_LIGHT_KEYS,
                    LightType::Square => SQUARE_LIGHT_KEYS,
                    LightType::Sphere => SPHERE_LIGHT_KEYS,
                },
                LIGHT_COMMON_KEYS,
            ],
            BlockKind::Primitive(t) => [
                match t {
                    P::Sphere => SPHERE_KEYS,
                    P::Plane => PLANE_KEYS,
                    P::Square => SQUARE_KEYS,
                    P::Cube => CUBE_KEYS,
                    P::Cylinder => CYLINDER_KEYS,
                    P::Bezier => BEZIER_KEYS,
                    P::Triangle => TRIANGLE_KEYS,
                    P::Mesh => MESH_KEYS,
                },
                MATERIAL_KEYS,
            ],
        }
    }

    /// The key's canonical name and kind, if this block uses it.
    fn lookup(&self, key: &str) -> Option<(&'static str, Kind)> {
        self.tables()
            .into_iter()
            .flatten()
            .find(|(k, _)| *k == key)
            .copied()
    }

    /// The keys this block uses (without `=`).
    pub fn key_names(&self) -> Vec<&'static str> {
        self.tables()
            .into_iter()
            .flatten()
            .map(|(k, _)| *k)
            .collect()
    }
}

/// Whether some block type uses `key`.
fn is_known_key(key: &str) -> bool {
    ALL_TABLES.iter().any(|t| t.iter().any(|(k, _)| *k == key))
}

/// One `key= values` line of a block, as read.
#[derive(Clone, Debug)]
pub(crate) struct Entry<'a> {
    /// The key without `=`.
    pub key: &'a str,
    /// Where the key (with its `=`) is.
    pub key_site: Site,
    /// Where the words after `=` lie in the block's list of values.
    pub values: Range<usize>,
    /// 0-based line index.
    pub line: usize,
    /// The line's text (for values that are the rest of the line).
    pub raw: &'a str,
}

/// A parsed value.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Num(f64),
    V2(DVec2),
    V3(DVec3),
    Text(String),
}

/// A key with its parsed value and where it was.
#[derive(Clone, Debug)]
struct Field {
    name: &'static str,
    value: Value,
    /// From the key to the last value.
    site: Site,
}

/// The parsed keys of one block, in file order.
#[derive(Default)]
struct Fields {
    list: Vec<Field>,
    /// Keys that were present but whose values were wrong (already reported).
    failed: Vec<&'static str>,
}

impl Fields {
    /// The last (overriding) occurrence of `name`.
    fn get(&self, name: &str) -> Option<&Field> {
        self.list.iter().rev().find(|f| f.name == name)
    }

    fn num(&self, name: &str) -> Option<(f64, Site)> {
        self.get(name).and_then(|f| match f.value {
            Value::Num(x) => Some((x, f.site)),
            _ => None,
        })
    }

    fn v3(&self, name: &str) -> Option<(DVec3, Site)> {
        self.get(name).and_then(|f| match f.value {
            Value::V3(v) => Some((v, f.site)),
            _ => None,
        })
    }

    fn text(&self, name: &str) -> Option<(&str, Site)> {
        self.get(name).and_then(|f| match &f.value {
            Value::Text(s) => Some((s.as_str(), f.site)),
            _ => None,
        })
    }

    fn failed(&self, name: &str) -> bool {
        self.failed.contains(&name)
    }
}

/// Why a word is not a usable number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NumberError {
    /// Not a decimal number at all.
    Malformed,
    /// `inf`, `nan` and the like.
    NotFinite,
    /// Beyond ±1e100 (including overflow such as `1e999`).
    TooLarge,
}

/// Parses a decimal number: optional sign, digits with an optional `.`
/// (either side may be empty, not both), optional exponent.
pub(crate) fn parse_number(s: &str) -> Result<f64, NumberError> {
    let b = s.as_bytes();
    let mut i = 0;
    if matches!(b.first(), Some(b'+' | b'-')) {
        i += 1;
    }
    let unsigned = &s[i..];
    if ["inf", "infinity", "nan"]
        .iter()
        .any(|w| unsigned.eq_ignore_ascii_case(w))
    {
        return Err(NumberError::NotFinite);
    }
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut mantissa = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        mantissa += digits(&mut i);
    }
    if mantissa == 0 {
        return Err(NumberError::Malformed);
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return Err(NumberError::Malformed);
        }
    }
    if i != b.len() {
        return Err(NumberError::Malformed);
    }
    let x: f64 = s.parse().map_err(|_| NumberError::Malformed)?;
    if !x.is_finite() || x.abs() > MAX_MAGNITUDE {
        return Err(NumberError::TooLarge);
    }
    Ok(x)
}

/// What a kind of value looks like, for messages.
fn describe(name: &str, kind: Kind) -> &'static str {
    match kind {
        Num => "a number",
        Count => "a whole number",
        Vec2 => "2 numbers (z r)",
        Vec3 => "3 numbers",
        OneOrThree => "1 or 3 numbers",
        Text if name == "blur" => "a blur name (`exp`)",
        Text => "a file name",
    }
}

/// Parses an entry's values as `kind`, reporting what is wrong.
fn parse_entry(
    e: &Entry<'_>,
    values: &[Word<'_>],
    name: &'static str,
    kind: Kind,
    diags: &mut Diags,
) -> Option<Field> {
    let values = values.get(e.values.clone()).unwrap_or_default();
    let line = e.line;
    let site = match values.last() {
        Some(last) => Site {
            line,
            col: e.key_site.col,
            len: (last.col + last.len).saturating_sub(e.key_site.col).max(1),
        },
        None => e.key_site,
    };
    let what = describe(name, kind);
    let (Some(first), Some(last)) = (values.first(), values.last()) else {
        diags.error(
            e.key_site,
            format!("`{}=` expects {what}, found nothing", e.key),
            None,
        );
        return None;
    };
    if kind == Text {
        let text = e
            .raw
            .get(first.start..last.start + last.text.len())
            .unwrap_or(first.text);
        return Some(Field {
            name,
            value: Value::Text(text.to_string()),
            site,
        });
    }
    // No kind takes more than 3 numbers; with more, the count is an error.
    let mut numbers = [0.0; 3];
    let mut ok = true;
    for (k, w) in values.iter().enumerate() {
        match parse_number(w.text) {
            Ok(x) => {
                if let Some(slot) = numbers.get_mut(k) {
                    *slot = x;
                }
            }
            Err(err) => {
                ok = false;
                let message = match err {
                    NumberError::Malformed => {
                        format!("expected a number after `{}=`, found `{}`", e.key, w.text)
                    }
                    NumberError::NotFinite => format!("`{}` is not a finite number", w.text),
                    NumberError::TooLarge => {
                        format!("`{}` is too large (numbers must lie within ±1e100)", w.text)
                    }
                };
                diags.error(Site::word(line, w), message, None);
            }
        }
    }
    let n = values.len();
    let counts: &[usize] = match kind {
        Num | Count => &[1],
        Vec2 => &[2],
        Vec3 => &[3],
        OneOrThree => &[1, 3],
        Text => &[],
    };
    let max = counts.iter().copied().max().unwrap_or(1);
    if n > max {
        let extra = &values[max];
        diags.error(
            Site::span(line, extra, last),
            format!("`{}=` expects {what}, found {n}", e.key),
            None,
        );
        return None;
    }
    if !counts.contains(&n) {
        diags.error(
            site,
            format!("`{}=` expects {what}, found {n}", e.key),
            None,
        );
        return None;
    }
    if !ok {
        return None;
    }
    let value = match kind {
        Num => Value::Num(numbers[0]),
        Count => {
            let x = numbers[0];
            if x < 0.0 {
                diags.error(
                    Site::word(line, first),
                    format!("`{}=` must not be negative, found {x}", e.key),
                    None,
                );
                return None;
            }
            if x.fract() != 0.0 {
                diags.error(
                    Site::word(line, first),
                    format!(
                        "`{}=` expects a whole number, found `{}`",
                        e.key, first.text
                    ),
                    None,
                );
                return None;
            }
            Value::Num(x)
        }
        Vec2 => Value::V2(DVec2::new(numbers[0], numbers[1])),
        Vec3 => Value::V3(DVec3::new(numbers[0], numbers[1], numbers[2])),
        OneOrThree if n == 1 => Value::V3(DVec3::splat(numbers[0])),
        OneOrThree => Value::V3(DVec3::new(numbers[0], numbers[1], numbers[2])),
        Text => return None,
    };
    Some(Field { name, value, site })
}

/// The unit vector along `v`, or `None` when `v` has zero length (scaled
/// first so tiny or huge components neither underflow nor overflow).
fn unit(v: DVec3) -> Option<DVec3> {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        return None;
    }
    let w = v / m;
    Some(w / w.length())
}

/// Whether two unit vectors are (numerically) parallel.
fn parallel(a: DVec3, b: DVec3) -> bool {
    a.cross(b).length() <= PARALLEL_SINE
}

/// Builds the scene block by block.
pub(crate) struct Builder<'p> {
    scene: Scene,
    base: &'p Path,
    /// Loaded textures by resolved path, so each file is decoded once.
    textures: HashMap<PathBuf, u32>,
    next_block: u32,
    cameras: u32,
    backgrounds: u32,
    /// The last block's fields, emptied: no allocation per block.
    spare: Fields,
}

impl<'p> Builder<'p> {
    /// A builder resolving relative paths against `base` first.
    pub fn new(base: &'p Path, path: Option<&Path>) -> Self {
        let mut scene = Scene::empty();
        scene.path = path.map(Path::to_path_buf);
        Builder {
            scene,
            base,
            textures: HashMap::new(),
            next_block: 0,
            cameras: 0,
            backgrounds: 0,
            spare: Fields::default(),
        }
    }

    /// The index of the next `primitive` block (counting every one, in file order).
    pub fn next_primitive_block(&mut self) -> u32 {
        let i = self.next_block;
        self.next_block = self.next_block.saturating_add(1);
        i
    }

    /// The scene built so far.
    pub fn finish(self) -> Scene {
        self.scene
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
        fields.list.clear();
        fields.failed.clear();
        for e in entries {
            match kind.lookup(e.key) {
                Some((name, k)) => match parse_entry(e, values, name, k, diags) {
                    Some(f) => fields.list.push(f),
                    None => fields.failed.push(name),
                },
                None if is_known_key(e.key) => diags.warn(
                    e.key_site,
                    format!(
                        "`{}=` is not used by a `{}` block; ignored",
                        e.key,
                        kind.name()
                    ),
                    None,
                ),
                None => diags.warn(
                    e.key_site,
                    format!(
                        "unknown key `{}=` in a `{}` block; ignored",
                        e.key,
                        kind.name()
                    ),
                    closest(e.key, &kind.key_names()).map(|c| format!("did you mean `{c}=`?")),
                ),
            }
        }
        let mut b = Block {
            kind,
            header,
            fields,
            diags,
        };
        match kind {
            BlockKind::Background => self.background(&mut b),
            BlockKind::Camera => self.camera(&mut b),
            BlockKind::Light(t) => self.light(t, &mut b),
            BlockKind::Primitive(t) => self.primitive(t, index, &mut b),
        }
        self.spare = b.fields;
    }

    fn background(&mut self, b: &mut Block<'_>) {
        self.backgrounds += 1;
        if self.backgrounds == 2 {
            b.diags.warn(
                b.header,
                "a second `background` block; its keys override the first's",
                None,
            );
        }
        let mut bg = self.scene.background;
        for f in &b.fields.list {
            let Value::V3(c) = f.value else { continue };
            bg = match (f.name, bg) {
                ("color", _) => Background::Color(c),
                ("top", Background::Gradient { bottom, .. }) => {
                    Background::Gradient { top: c, bottom }
                }
                ("top", Background::Color(_)) => Background::Gradient {
                    top: c,
                    bottom: DVec3::ONE,
                },
                ("bottom", Background::Gradient { top, .. }) => {
                    Background::Gradient { top, bottom: c }
                }
                ("bottom", Background::Color(_)) => Background::Gradient {
                    top: DVec3::ONE,
                    bottom: c,
                },
                _ => bg,
            };
        }
        self.scene.background = bg;
    }

    fn camera(&mut self, b: &mut Block<'_>) {
        self.cameras += 1;
        if self.cameras == 2 {
            b.diags.warn(
                b.header,
                "a second `camera` block; its keys override the first's",
                None,
            );
        }
        let mut cam = self.scene.camera.clone();
        if let Some((o, _)) = b.fields.v3("O") {
            cam.origin = o;
        }
        if let Some((n, site)) = b.fields.v3("N") {
            match unit(n) {
                Some(n) => cam.dir = n,
                None => b.diags.error(
                    site,
                    "`N=` has zero length; the camera needs a view direction",
                    None,
                ),
            }
        }
        for (key, target) in [("lens_W", &mut cam.lens_w), ("lens_H", &mut cam.lens_h)] {
            if let Some((x, site)) = b.fields.num(key) {
                if x > 0.0 {
                    *target = x;
                } else {
                    b.diags.error(
                        site,
                        format!("`{key}=` must be greater than 0, found {x}"),
                        None,
                    );
                }
            }
        }
        for (key, target) in [("image_W", &mut cam.width), ("image_H", &mut cam.height)] {
            if let Some((x, site)) = b.fields.num(key) {
                if (1.0..=MAX_IMAGE_SIDE).contains(&x) {
                    *target = x as u32;
                } else {
                    b.diags.error(
                        site,
                        format!("`{key}=` must be between 1 and {MAX_IMAGE_SIDE}, found {x}"),
                        None,
                    );
                }
            }
        }
        // 16 × quality rays must fit in a u32; above SLOW_QUALITY a warning
        // says what they cost (the rays, what they slow).
        let max_quality = f64::from(u32::MAX / 16);
        for (key, target, rays, what) in [
            (
                "shade_quality",
                &mut cam.shade_quality,
                "shadow rays per shading point towards each area light",
                "area lights",
            ),
            (
                "drefl_quality",
                &mut cam.drefl_quality,
                "rays per glossy reflection",
                "glossy reflections",
            ),
        ] {
            let Some((x, site)) = b.count(key, max_quality) else {
                continue;
            };
            let quality = x as u32;
            *target = quality;
            if quality > SLOW_QUALITY {
                let message = format!(
                    "`{key}={quality}` means {} {rays} (the default, 4, means 64): \
                     a scene with {what} will render very slowly",
                    16 * u64::from(quality)
                );
                b.diags.warn(site, message, None);
            }
        }
        if let Some((x, _)) = b.count("dofSample", f64::from(u32::MAX)) {
            cam.dof.samples = x as u32;
        }
        // Exactly 2^64: the first whole number that does not fit.
        let max64 = 18_446_744_073_709_551_615.0;
        let photons = &mut cam.photons;
        for (key, target) in [
            ("max_photons", &mut photons.max_photons),
            ("emit_photons", &mut photons.emit_photons),
            ("sample_photons", &mut photons.sample_photons),
        ] {
            if let Some((x, _)) = b.count(key, max64) {
                *target = x as u64;
            }
        }
        for (key, target) in [
            ("max_hitpoints", &mut photons.max_hitpoints),
            ("iterations", &mut photons.iterations),
        ] {
            if let Some((x, _)) = b.count(key, max64) {
                *target = Some(x as u64);
            }
        }
        if let Some(x) = b.non_negative("sample_dist") {
            photons.sample_dist = x;
        }
        if let Some(x) = b.non_negative("reduction") {
            photons.reduction = Some(x);
        }
        if let Some(x) = b.non_negative("aperture") {
            cam.dof.aperture = x;
        }
        if let Some(x) = b.non_negative("focalLen") {
            cam.dof.focal_len = x;
        }
        self.scene.camera = cam;
    }

    fn light(&mut self, t: LightType, b: &mut Block<'_>) {
        let errors = b.diags.error_count();
        let color = match b.fields.v3("color") {
            Some((c, _)) => c,
            None => {
                if !b.fields.failed("color") {
                    b.diags.warn(
                        b.header,
                        "this light has no `color=`; it gives no light",
                        Some("add e.g. `color= 1 1 1`".to_string()),
                    );
                }
                DVec3::ZERO
            }
        };
        let intensity = b.fields.v3("intensity").map_or(DVec3::ONE, |(v, _)| v);
        let center = b.fields.v3("O").map_or(DVec3::ZERO, |(v, _)| v);
        let kind = match t {
            LightType::Point => Some(LightKind::Point { pos: center }),
            LightType::Square => {
                b.span_pair("Dx", "Dy")
                    .map(|(dx, dy)| LightKind::Square { center, dx, dy })
            }
            LightType::Sphere => b
                .radius("R")
                .map(|radius| LightKind::Sphere { center, radius }),
        };
        if let Some(kind) = kind
            && b.diags.error_count() == errors
        {
            self.scene.add_light(Light {
                kind,
                color: color * intensity,
            });
        }
    }

    fn primitive(&mut self, t: PrimitiveType, index: u32, b: &mut Block<'_>) {
        use PrimitiveType as P;
        let errors = b.diags.error_count();
        let material = self.material(b);
        // Texture directions matter once a texture is named, found or not.
        let textured = b.fields.get("texture").is_some();
        let origin = b.fields.v3("O").map_or(DVec3::ZERO, |(v, _)| v);
        let shapes: Option<Vec<Shape>> = match t {
            P::Sphere => {
                let r = b.radius("R");
                let de = b.direction("De", DVec3::Z, textured);
                let dc = b.direction("Dc", DVec3::Y, textured);
                match (r, de, dc) {
                    (Some(r), Some(de), Some(dc)) => Some(vec![Shape::Sphere(
                        Sphere::with_orientation(origin, r, de, dc),
                    )]),
                    _ => None,
                }
            }
            P::Plane => plane(b, textured).map(|p| vec![Shape::Plane(Box::new(p))]),
            P::Square => b
                .span_pair("Dx", "Dy")
                .map(|(dx, dy)| vec![Shape::Square(Box::new(Square::new(origin, dx, dy)))]),
            P::Cube => cube(b, origin).map(|c| vec![Shape::Cube(Box::new(c))]),
            P::Cylinder => {
                let axis = b.axis();
                let r = b.radius("R");
                match (axis, r) {
                    (Some((o1, o2)), Some(r)) => {
                        Some(vec![Shape::Cylinder(Box::new(Cylinder::new(o1, o2, r)))])
                    }
                    _ => None,
                }
            }
            P::Bezier => bezier(b).map(|z| vec![Shape::Bezier(Box::new(z))]),
            P::Triangle => triangle(b).map(|tri| vec![Shape::Triangle(Box::new(tri))]),
            P::Mesh => self.mesh(b),
        };
        if b.diags.error_count() != errors {
            return;
        }
        if let (Some(m), Some(shapes)) = (material, shapes) {
            let m = self.scene.add_material(m);
            for s in shapes {
                self.scene.add_object(s, m, index);
            }
        }
    }

    fn material(&mut self, b: &mut Block<'_>) -> Option<Material> {
        let f = &b.fields;
        let num = |k: &str, d: f64| f.num(k).map_or(d, |(x, _)| x);
        let mut m = Material {
            color: f.v3("color").map_or(DVec3::ZERO, |(v, _)| v),
            diff: num("diff", 0.0),
            spec: num("spec", 0.0),
            refl: num("refl", 0.0),
            drefl: num("drefl", 0.0),
            refr: num("refr", 0.0),
            rindex: num("rindex", 0.0),
            absor: f.v3("absor").map_or(DVec3::ZERO, |(v, _)| v),
            texture: None,
        };
        if let Some((blur, site)) = f.text("blur")
            && blur != "exp"
        {
            b.diags.warn(
                site,
                format!("unknown blur `{blur}`; using `exp`, the only one"),
                closest(blur, &["exp"]).map(|c| format!("did you mean `{c}`?")),
            );
        }
        if m.refr > 0.0 && m.rindex <= 0.0 {
            let site = f
                .num("rindex")
                .or_else(|| f.num("refr"))
                .map_or(b.header, |(_, s)| s);
            b.diags.warn(
                site,
                format!(
                    "`refr=` is {} but `rindex=` is {}; using rindex 1 (the framework would produce NaN)",
                    m.refr, m.rindex
                ),
                None,
            );
            m.rindex = 1.0;
        }
        if let Some((name, site)) = b.fields.text("texture") {
            let name = name.to_string();
            m.texture = Some(self.texture(&name, site, b.diags)?);
        }
        Some(m)
    }

    /// Finds a file named in the scene: next to the scene file first, then
    /// in the working directory (and, for names written with Windows
    /// separators, the same with `/`). Returns the path and where it was
    /// found, or the places tried.
    fn resolve(&self, name: &str) -> Result<(PathBuf, &'static str), Vec<PathBuf>> {
        let mut tried: Vec<PathBuf> = Vec::new();
        let slashed = name.replace('\\', "/");
        let names: &[&str] = if slashed != name {
            &[name, &slashed]
        } else {
            &[name]
        };
        for &n in names {
            let p = Path::new(n);
            let candidates = if p.is_absolute() {
                [
                    (p.to_path_buf(), "as an absolute path"),
                    (p.to_path_buf(), ""),
                ]
            } else {
                [
                    (self.base.join(p), "in the scene file's folder"),
                    (p.to_path_buf(), "in the working directory"),
                ]
            };
            for (path, found) in candidates {
                if found.is_empty() || tried.contains(&path) {
                    continue;
                }
                if path.is_file() {
                    return Ok((path, found));
                }
                tried.push(path);
            }
        }
        Err(tried)
    }

    /// Reports a file that was not found.
    fn not_found(what: &str, name: &str, tried: &[PathBuf], site: Site, diags: &mut Diags) {
        let tried = tried
            .iter()
            .map(|p| format!("`{}`", p.display()))
            .collect::<Vec<_>>()
            .join(" and ");
        diags.error(
            site,
            format!("{what} file `{name}` not found"),
            Some(format!(
                "looked for {tried} (next to the scene file, then in the working directory)"
            )),
        );
    }

    fn texture(&mut self, name: &str, site: Site, diags: &mut Diags) -> Option<u32> {
        let (path, found) = match self.resolve(name) {
            Ok(p) => p,
            Err(tried) => {
                Self::not_found("texture", name, &tried, site, diags);
                return None;
            }
        };
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if let Some(&i) = self.textures.get(&key) {
            return Some(i);
        }
        match Texture::load(&path) {
            Ok(t) => {
                let i = self.scene.textures.len() as u32;
                self.scene.textures.push(t);
                self.textures.insert(key, i);
                self.scene.notes.push(format!(
                    "line {}: texture `{name}` found {found}: {}",
                    site.line + 1,
                    path.display()
                ));
                Some(i)
            }
            Err(e) => {
                diags.error(
                    site,
                    format!("cannot read texture `{name}` ({}): {e}", path.display()),
                    None,
                );
                None
            }
        }
    }

    fn mesh(&mut self, b: &mut Block<'_>) -> Option<Vec<Shape>> {
        let (name, site) = match b.fields.text("file") {
            Some((n, s)) => (n.to_string(), s),
            None => {
                if !b.fields.failed("file") {
                    b.diags.error(
                        b.header,
                        "a `primitive mesh` block needs `file=` (the OBJ file)",
                        None,
                    );
                }
                return None;
            }
        };
        let origin = b.fields.v3("O").map_or(DVec3::ZERO, |(v, _)| v);
        let rotation = b.fields.v3("rotation").map_or(DVec3::ZERO, |(v, _)| v);
        let scale = match b.fields.v3("scale") {
            Some((s, site)) if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 => {
                b.diags.error(
                    site,
                    "`scale=` is 0 along some axis; the mesh would be flat",
                    None,
                );
                return None;
            }
            Some((s, _)) => s,
            None => DVec3::ONE,
        };
        let (path, found) = match self.resolve(&name) {
            Ok(p) => p,
            Err(tried) => {
                Self::not_found("mesh", &name, &tried, site, b.diags);
                return None;
            }
        };
        match crate::geometry::load_obj(&path, origin, scale, rotation) {
            Ok(triangles) => {
                self.scene.notes.push(format!(
                    "line {}: mesh `{name}` found {found}: {} ({} triangles)",
                    site.line + 1,
                    path.display(),
                    triangles.len()
                ));
                if triangles.is_empty() {
                    b.diags
                        .warn(site, format!("mesh `{name}` has no triangles"), None);
                }
                Some(
                    triangles
                        .into_iter()
                        .map(|t| Shape::Triangle(Box::new(t)))
                        .collect(),
                )
            }
            Err(e) => {
                b.diags.error(
                    site,
                    format!("cannot load mesh `{name}` ({}): {e}", path.display()),
                    None,
                );
                None
            }
        }
    }
}

/// One block being built: its kind, header, parsed keys, and the diagnostics.
struct Block<'d> {
    kind: BlockKind,
    header: Site,
    fields: Fields,
    diags: &'d mut Diags,
}

impl Block<'_> {
    /// A required vector key; reports its absence at the header.
    fn need_v3(&mut self, key: &str, what: &str) -> Option<(DVec3, Site)> {
        let v = self.fields.v3(key);
        if v.is_none() {
            self.missing(key, what);
        }
        v
    }

    /// A required number key; reports its absence at the header.
    fn need_num(&mut self, key: &str, what: &str) -> Option<(f64, Site)> {
        let v = self.fields.num(key);
        if v.is_none() {
            self.missing(key, what);
        }
        v
    }

    fn missing(&mut self, key: &str, what: &str) {
        if !self.fields.failed(key) {
            self.diags.error(
                self.header,
                format!("a `{}` block needs `{key}=` ({what})", self.kind.name()),
                None,
            );
        }
    }

    /// A required radius > 0.
    fn radius(&mut self, key: &str) -> Option<f64> {
        let (r, site) = self.need_num(key, "the radius")?;
        if r > 0.0 {
            Some(r)
        } else {
            self.diags.error(
                site,
                format!("the radius `{key}=` must be greater than 0, found {r}"),
                None,
            );
            None
        }
    }

    /// A required half-length > 0 (cubes).
    fn half_length(&mut self, key: &str) -> Option<f64> {
        let (x, site) = self.need_num(key, "a half-length")?;
        if x > 0.0 {
            Some(x)
        } else {
            self.diags.error(
                site,
                format!("the half-length `{key}=` must be greater than 0, found {x}"),
                None,
            );
            None
        }
    }

    /// An optional number that must not be negative.
    fn non_negative(&mut self, key: &str) -> Option<f64> {
        let (x, site) = self.fields.num(key)?;
        if x >= 0.0 {
            Some(x)
        } else {
            self.diags.error(
                site,
                format!("`{key}=` must not be negative, found {x}"),
                None,
            );
            None
        }
    }

    /// An optional whole number (already known ≥ 0 and whole) at most
    /// `max`, with its place in the file.
    fn count(&mut self, key: &str, max: f64) -> Option<(f64, Site)> {
        let (x, site) = self.fields.num(key)?;
        if x <= max {
            Some((x, site))
        } else {
            self.diags
                .error(site, format!("`{key}=` is too large, found {x}"), None);
            None
        }
    }

    /// An optional texture direction (sphere `De=`/`Dc=`), normalised;
    /// zero length is an error only when a texture needs it.
    fn direction(&mut self, key: &str, default: DVec3, textured: bool) -> Option<DVec3> {
        let Some((v, site)) = self.fields.v3(key) else {
            return Some(default);
        };
        if let Some(u) = unit(v) {
            return Some(u);
        }
        if textured {
            self.diags.error(
                site,
                format!("`{key}=` has zero length; the texture mapping needs a direction"),
                None,
            );
            None
        } else {
            self.diags.warn(
                site,
                format!("`{key}=` has zero length; ignored (only textures use it)"),
                None,
            );
            Some(default)
        }
    }

    /// An optional plane texture axis: `Some(None)` when absent (or zero
    /// on an untextured plane, with a warning), `None` after an error.
    fn texture_axis(&mut self, key: &str, textured: bool) -> Option<Option<DVec3>> {
        let Some((v, site)) = self.fields.v3(key) else {
            return Some(None);
        };
        if unit(v).is_some() {
            return Some(Some(v));
        }
        if textured {
            self.diags.error(
                site,
                format!("`{key}=` has zero length; the plane's texture needs it"),
                None,
            );
            None
        } else {
            self.diags.warn(
                site,
                format!("`{key}=` has zero length; ignored (only textures use it)"),
                None,
            );
            Some(None)
        }
    }

    /// Required non-zero, non-parallel half-edge vectors (squares, square lights).
    fn span_pair(&mut self, kx: &str, ky: &str) -> Option<(DVec3, DVec3)> {
        let dx = self.need_v3(kx, "a half-edge vector");
        let dy = self.need_v3(ky, "a half-edge vector");
        let ux = dx.and_then(|(v, site)| self.nonzero(kx, v, site));
        let uy = dy.and_then(|(v, site)| self.nonzero(ky, v, site));
        let (ux, uy, (dx, _), (dy, site)) = (ux?, uy?, dx?, dy?);
        if parallel(ux, uy) {
            self.diags.error(
                site,
                format!(
                    "`{ky}=` is parallel to `{kx}=`; a `{}` needs two independent directions",
                    self.kind.name()
                ),
                None,
            );
            return None;
        }
        Some((dx, dy))
    }

    /// The unit vector along `v`, reporting zero length.
    fn nonzero(&mut self, key: &str, v: DVec3, site: Site) -> Option<DVec3> {
        let u = unit(v);
        if u.is_none() {
            self.diags
                .error(site, format!("`{key}=` has zero length"), None);
        }
        u
    }

    /// Required `O1=` ≠ `O2=` (cylinders, Bézier surfaces).
    fn axis(&mut self) -> Option<(DVec3, DVec3)> {
        let o1 = self.need_v3("O1", "the start of the axis");
        let o2 = self.need_v3("O2", "the end of the axis");
        let ((o1, _), (o2, site)) = (o1?, o2?);
        if unit(o2 - o1).is_none() {
            self.diags
                .error(site, "`O2=` equals `O1=`: the axis has zero length", None);
            return None;
        }
        Some((o1, o2))
    }
}

/// A plane: a non-zero normal, and texture axes (defaults in the module docs).
fn plane(b: &mut Block<'_>, textured: bool) -> Option<Plane> {
    let (n, site) = b.need_v3("N", "its normal")?;
    let Some(n) = unit(n) else {
        b.diags
            .error(site, "`N=` has zero length; a plane needs a normal", None);
        return None;
    };
    let r = b.fields.num("R").map_or(0.0, |(x, _)| x);
    let dx = b.texture_axis("Dx", textured);
    let dy = b.texture_axis("Dy", textured);
    let (dx, dy) = match (dx?, dy?) {
        (Some(dx), Some(dy)) => (dx, dy),
        (Some(dx), None) => (dx, n.cross(dx)),
        (None, Some(dy)) => (dy.cross(n), dy),
        (None, None) => axis_frame(n),
    };
    Some(Plane::new(n, r, dx, dy))
}

/// A cube: Dx, Dy made orthonormal (Gram–Schmidt, keeping Dx's direction),
/// with a warning where the input was not already so.
fn cube(b: &mut Block<'_>, origin: DVec3) -> Option<Cube> {
    let dx = b.fields.v3("Dx");
    let dy = b.fields.v3("Dy");
    let hx = b.half_length("x");
    let hy = b.half_length("y");
    let hz = b.half_length("z");
    let ux = match dx {
        Some((v, site)) => b.nonzero("Dx", v, site),
        None => Some(DVec3::X),
    };
    let uy = match dy {
        Some((v, site)) => b.nonzero("Dy", v, site),
        None => Some(DVec3::Y),
    };
    let (ux, uy) = (ux?, uy?);
    let perp = uy - ux * uy.dot(ux);
    let Some(uy_perp) = unit(perp).filter(|_| perp.length() > PARALLEL_SINE) else {
        let site = dy.or(dx).map_or(b.header, |(_, s)| s);
        b.diags.error(
            site,
            "`Dy=` is parallel to `Dx=`; a cube needs two independent directions",
            None,
        );
        return None;
    };
    if let Some((v, site)) = dx
        && (v.length() - 1.0).abs() > ORTHONORMAL_TOLERANCE
    {
        b.diags.warn(
            site,
            format!(
                "`Dx=` is not a unit vector (length {}); normalised",
                v.length()
            ),
            None,
        );
    }
    if let Some((v, site)) = dy {
        let not_unit = (v.length() - 1.0).abs() > ORTHONORMAL_TOLERANCE;
        let not_perp = v.dot(ux).abs() > ORTHONORMAL_TOLERANCE * v.length().max(1.0);
        if not_unit || not_perp {
            b.diags.warn(
                site,
                "`Dy=` is not a unit vector perpendicular to `Dx=`; made so, keeping `Dx=`'s direction",
                None,
            );
        }
    }
    Some(Cube::new(origin, ux, uy_perp, DVec3::new(hx?, hy?, hz?)))
}

/// A Bézier surface of revolution: an axis and at least two control points.
fn bezier(b: &mut Block<'_>) -> Option<Bezier> {
    let axis = b.axis();
    let points: Vec<(DVec2, Site)> = b
        .fields
        .list
        .iter()
        .filter_map(|f| match f.value {
            Value::V2(p) if f.name == "P" => Some((p, f.site)),
            _ => None,
        })
        .collect();
    if points.len() < 2 && !b.fields.failed("P") {
        let site = points.first().map_or(b.header, |(_, s)| *s);
        b.diags.error(
            site,
            format!(
                "a `primitive bezier` block needs at least 2 `P= z r` control points, found {}",
                points.len()
            ),
            None,
        );
        return None;
    }
    // Any degree is valid in the format; glint intersects up to degree 64,
    // far beyond what a hand-made profile needs.
    let max = Bezier::MAX_DEGREE + 1;
    if points.len() > max {
        b.diags.error(
            points[max].1,
            format!(
                "a `primitive bezier` profile has at most {max} control points (degree {}) in glint, found {}",
                Bezier::MAX_DEGREE,
                points.len()
            ),
            Some(
                "split the profile into several `primitive bezier` blocks of lower degree"
                    .to_string(),
            ),
        );
        return None;
    }
    let (o1, o2) = axis?;
    Some(Bezier::new(
        o1,
        o2,
        points.into_iter().map(|(p, _)| p).collect(),
    ))
}

/// A triangle whose corners are not collinear.
fn triangle(b: &mut Block<'_>) -> Option<Triangle> {
    let p0 = b.need_v3("O1", "the first corner");
    let p1 = b.need_v3("O2", "the second corner");
    let p2 = b.need_v3("O3", "the third corner");
    let ((p0, _), (p1, _), (p2, _)) = (p0?, p1?, p2?);
    let degenerate = match (unit(p1 - p0), unit(p2 - p0)) {
        (Some(a), Some(c)) => parallel(a, c),
        _ => true,
    };
    if degenerate {
        b.diags.error(
            b.header,
            "degenerate triangle: its corners `O1=`, `O2=`, `O3=` are collinear",
            None,
        );
        return None;
    }
    Some(Triangle::new(p0, p1, p2, None))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number(".5"), Ok(0.5));
        assert_eq!(parse_number("-1e-3"), Ok(-1e-3));
        assert_eq!(parse_number("+2"), Ok(2.0));
        assert_eq!(parse_number("1."), Ok(1.0));
        assert_eq!(parse_number("1E+2"), Ok(100.0));
        assert_eq!(parse_number("."), Err(NumberError::Malformed));
        assert_eq!(parse_number("1e"), Err(NumberError::Malformed));
        assert_eq!(parse_number("1.2.3"), Err(NumberError::Malformed));
        assert_eq!(parse_number("0x10"), Err(NumberError::Malformed));
        assert_eq!(parse_number("1,5"), Err(NumberError::Malformed));
        assert_eq!(parse_number(""), Err(NumberError::Malformed));
        assert_eq!(parse_number("-"), Err(NumberError::Malformed));
        assert_eq!(parse_number("inf"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("-NaN"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("1e999"), Err(NumberError::TooLarge));
        assert_eq!(parse_number("-1e101"), Err(NumberError::TooLarge));
        assert_eq!(parse_number("1e-999"), Ok(0.0));
    }

    #[test]
    fn unit_vectors() {
        assert_eq!(unit(DVec3::ZERO), None);
        let u = unit(DVec3::new(1e-200, 0.0, 0.0));
        assert_eq!(u, Some(DVec3::X));
        let u = unit(DVec3::new(3e100, 4e100, 0.0));
        assert!(u.is_some_and(|u| (u - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-15));
    }
}
