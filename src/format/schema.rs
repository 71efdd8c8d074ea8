//! The schema of the format: one row per block kind, holding its header,
//! its keys with the shape of their values, and the function that builds
//! it. A new primitive kind is one row here (and its build function).

use super::assets::Assets;
use super::block_keys::BlockKeys;
use super::values::Kind::{self, Count, List, Num, OneOrThree, Text, TwoOrThree, Vec3};
use super::{colon, setup, shapes};
use crate::scene::{Background, Camera, LightKind};

/// A key's name (without `=`) and the shape of its values.
type Keys = &'static [(&'static str, Kind)];

const MATERIAL_KEYS: Keys = &[
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
    ("NT", Text),
];

const BACKGROUND_KEYS: Keys = &[("color", Vec3), ("top", Vec3), ("bottom", Vec3)];

const CAMERA_KEYS: Keys = &[
    ("O", Vec3),
    ("N", Vec3),
    ("lens_W", Num),
    ("lens_H", Num),
    ("image_W", Count),
    ("image_H", Count),
    ("shade_quality", Num),
    ("drefl_quality", Num),
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
    ("Dx", Vec3),
    ("algorithm", Text),
];

const LIGHT_COMMON_KEYS: Keys = &[("color", Vec3), ("intensity", OneOrThree)];
const POINT_LIGHT_KEYS: Keys = &[("O", Vec3)];
const SQUARE_LIGHT_KEYS: Keys = &[("O", Vec3), ("Dx", Vec3), ("Dy", Vec3)];
const SPHERE_LIGHT_KEYS: Keys = &[("O", Vec3), ("R", Num)];

const SPHERE_KEYS: Keys = &[("O", Vec3), ("R", Num), ("De", Vec3), ("Dc", Vec3)];
const PLANE_KEYS: Keys = &[("N", Vec3), ("R", Num), ("Dx", Vec3), ("Dy", Vec3)];
const SQUARE_KEYS: Keys = &[("O", Vec3), ("Dx", Vec3), ("Dy", Vec3)];
// `size=` (F's scene4 cube), `N= H=` (its cylinder), `N= M= newPoint=`
// (Z17's patch) and `R_major= R_minor=` (scene4's torus) are read only to
// skip those blocks, so their values are taken as text.
const CUBE_KEYS: Keys = &[
    ("O", Vec3),
    ("Dx", Vec3),
    ("Dy", Vec3),
    ("x", Num),
    ("y", Num),
    ("z", Num),
    ("size", Text),
];
const CYLINDER_KEYS: Keys = &[
    ("O1", Vec3),
    ("O2", Vec3),
    ("R", Num),
    ("O", Text),
    ("N", Text),
    ("H", Text),
];
// `P=` is the framework's `z r` or lazycal's base point; `Dz= S=
// control_points=` are lazycal's form, `center= V0= ... V3=` abcbdf's.
const BEZIER_KEYS: Keys = &[
    ("O1", Vec3),
    ("O2", Vec3),
    ("P", TwoOrThree),
    ("N", Text),
    ("M", Text),
    ("newPoint", Text),
    ("Dz", Vec3),
    ("S", Num),
    ("control_points", List),
    ("center", Vec3),
    ("V0", Vec3),
    ("V1", Vec3),
    ("V2", Vec3),
    ("V3", Vec3),
];
const TORUS_KEYS: Keys = &[
    ("O", Text),
    ("N", Text),
    ("R_major", Text),
    ("R_minor", Text),
];
const RECTANGLE_KEYS: Keys = &[("N", Vec3), ("R", Num), ("Dx", Vec3), ("Dy", Vec3)];
const POLYHEDRON_KEYS: Keys = &[
    ("mesh", Text),
    ("O", Vec3),
    ("size", Vec3),
    ("angles", Vec3),
];
const NOMAL_BALL_KEYS: Keys = SPHERE_KEYS;
const NOMAL_PLANE_KEYS: Keys = PLANE_KEYS;
const LINEAGE_BEZIER_KEYS: Keys = &[("O", Vec3), ("R", Num), ("ratio", Num)];
// `A0= A1= A2= N=`: abcbdf's triangle.
const TRIANGLE_KEYS: Keys = &[
    ("O1", Vec3),
    ("O2", Vec3),
    ("O3", Vec3),
    ("A0", Vec3),
    ("A1", Vec3),
    ("A2", Vec3),
    ("N", Vec3),
];
const TETRA_KEYS: Keys = &[("V0", Vec3), ("V1", Vec3), ("V2", Vec3), ("V3", Vec3)];
const MESH_KEYS: Keys = &[
    ("file", Text),
    ("O", Vec3),
    ("scale", OneOrThree),
    ("rotation", Vec3),
];

// The colon family's keys (hta1996/Raytracing `object.h`, `object.cpp`),
// written `key:`.
const COLON_MATERIAL_KEYS: Keys = &[
    ("color", Vec3),
    ("absor", Vec3),
    ("refl", Num),
    ("refr", Num),
    ("diff", Num),
    ("spec", Num),
    ("rindex", Num),
    ("texture", Text),
];
const COLON_BACKGROUND_KEYS: Keys = &[("ambientcolor", Vec3)];
const COLON_CAMERA_KEYS: Keys = &[
    ("eye", Vec3),
    ("lookat", Vec3),
    ("up", Vec3),
    ("fovy", Num),
    ("w", Count),
    ("h", Count),
    ("aperture", Num),
    ("focal", Num),
];
const COLON_LIGHT_COMMON_KEYS: Keys = &[("color", Vec3), ("power", Num)];
const COLON_AREA_LIGHT_KEYS: Keys = &[("O", Vec3), ("N", Vec3), ("Dx", Vec3), ("Dy", Vec3)];
const COLON_SPHERE_KEYS: Keys = &[("O", Vec3), ("R", Num), ("Dx", Vec3), ("Dz", Vec3)];
const COLON_PLANE_KEYS: Keys = &[
    ("N", Vec3),
    ("d", Num),
    ("Do", Vec3),
    ("Dx", Vec3),
    ("Dy", Vec3),
];
const COLON_CYLINDER_KEYS: Keys = &[("O", Vec3), ("R", Num), ("H", Num), ("ang", Num)];
const COLON_ROTATION_BODY_KEYS: Keys = &[
    ("O", Vec3),
    ("scale", Num),
    ("ang", Num),
    ("curve", List),
    ("ratio", List),
];

/// What a block's function builds from its keys.
#[derive(Clone, Copy)]
pub(crate) enum Build {
    /// The background, over the one so far.
    Background(fn(Background, &mut BlockKeys<'_>) -> Background),
    /// The camera, over the one so far.
    Camera(fn(Camera, &mut BlockKeys<'_>) -> Camera),
    /// A light's shape and position (its colour is common to every light).
    Light(fn(&mut BlockKeys<'_>) -> Option<LightKind>),
    /// A primitive's shapes (its material is common to every primitive),
    /// adding the textures its own materials name.
    Primitive(PrimitiveBuild),
}

/// One kind of block.
pub(crate) struct Row {
    /// The type word after `light` or `primitive` (the header itself for
    /// `background` and `camera`).
    pub name: &'static str,
    /// The header as written (`primitive sphere`).
    pub title: &'static str,
    /// The keys of this kind.
    keys: Keys,
    /// The keys every block of its class shares (material, light colour).
    common: Keys,
    /// What builds it.
    pub build: Build,
    /// Whether it is the colon family's block (`key:` lines, its defaults).
    pub colon: bool,
}

/// What a block describes: its row of the schema.
pub(crate) type BlockKind = &'static Row;

/// The `background` block.
pub(crate) static BACKGROUND: Row = Row {
    name: "background",
    title: "background",
    keys: BACKGROUND_KEYS,
    common: &[],
    build: Build::Background(setup::background),
    colon: false,
};

/// The `camera` block.
pub(crate) static CAMERA: Row = Row {
    name: "camera",
    title: "camera",
    keys: CAMERA_KEYS,
    common: &[],
    build: Build::Camera(setup::camera),
    colon: false,
};

/// The `light TYPE` blocks.
pub(crate) static LIGHTS: [Row; 4] = [
    Row {
        name: "point",
        title: "light point",
        keys: POINT_LIGHT_KEYS,
        common: LIGHT_COMMON_KEYS,
        build: Build::Light(setup::point_light),
        colon: false,
    },
    Row {
        name: "square",
        title: "light square",
        keys: SQUARE_LIGHT_KEYS,
        common: LIGHT_COMMON_KEYS,
        build: Build::Light(setup::square_light),
        colon: false,
    },
    Row {
        name: "sphere",
        title: "light sphere",
        keys: SPHERE_LIGHT_KEYS,
        common: LIGHT_COMMON_KEYS,
        build: Build::Light(setup::sphere_light),
        colon: false,
    },
    // The lineages' name for the square light.
    Row {
        name: "area",
        title: "light area",
        keys: SQUARE_LIGHT_KEYS,
        common: LIGHT_COMMON_KEYS,
        build: Build::Light(setup::square_light),
        colon: false,
    },
];

/// A primitive kind's build function.
pub(crate) type PrimitiveBuild =
    fn(&mut Assets, &mut BlockKeys<'_>, &mut shapes::AddTexture<'_>) -> shapes::Shapes;

/// A `primitive TYPE` row.
const fn primitive(
    name: &'static str,
    title: &'static str,
    keys: Keys,
    build: PrimitiveBuild,
) -> Row {
    Row {
        name,
        title,
        keys,
        common: MATERIAL_KEYS,
        build: Build::Primitive(build),
        colon: false,
    }
}

/// A colon-family `primitive TYPE` row.
const fn colon_primitive(
    name: &'static str,
    title: &'static str,
    keys: Keys,
    build: PrimitiveBuild,
) -> Row {
    Row {
        name,
        title,
        keys,
        common: COLON_MATERIAL_KEYS,
        build: Build::Primitive(build),
        colon: true,
    }
}

/// The `primitive TYPE` blocks.
pub(crate) static PRIMITIVES: [Row; 15] = [
    primitive("sphere", "primitive sphere", SPHERE_KEYS, shapes::sphere),
    primitive("plane", "primitive plane", PLANE_KEYS, shapes::plane),
    primitive("square", "primitive square", SQUARE_KEYS, shapes::square),
    primitive("cube", "primitive cube", CUBE_KEYS, shapes::cube),
    primitive(
        "cylinder",
        "primitive cylinder",
        CYLINDER_KEYS,
        shapes::cylinder,
    ),
    primitive("bezier", "primitive bezier", BEZIER_KEYS, shapes::bezier),
    primitive(
        "triangle",
        "primitive triangle",
        TRIANGLE_KEYS,
        shapes::triangle,
    ),
    primitive("mesh", "primitive mesh", MESH_KEYS, shapes::mesh),
    primitive(
        "rectangle",
        "primitive rectangle",
        RECTANGLE_KEYS,
        shapes::rectangle,
    ),
    primitive(
        "polyhedron",
        "primitive polyhedron",
        POLYHEDRON_KEYS,
        shapes::polyhedron,
    ),
    primitive(
        "NomalBall",
        "primitive NomalBall",
        NOMAL_BALL_KEYS,
        shapes::nomal_ball,
    ),
    primitive(
        "NomalPlane",
        "primitive NomalPlane",
        NOMAL_PLANE_KEYS,
        shapes::nomal_plane,
    ),
    primitive(
        "Bezier",
        "primitive Bezier",
        LINEAGE_BEZIER_KEYS,
        shapes::lineage_bezier,
    ),
    primitive("torus", "primitive torus", TORUS_KEYS, shapes::torus),
    primitive("tetra", "primitive tetra", TETRA_KEYS, shapes::tetra),
];

/// The colon family's `background` block.
static COLON_BACKGROUND: Row = Row {
    name: "background",
    title: "background",
    keys: COLON_BACKGROUND_KEYS,
    common: &[],
    build: Build::Background(colon::background),
    colon: true,
};

/// The colon family's `camera` block.
static COLON_CAMERA: Row = Row {
    name: "camera",
    title: "camera",
    keys: COLON_CAMERA_KEYS,
    common: &[],
    build: Build::Camera(colon::camera),
    colon: true,
};

/// The colon family's `light TYPE` blocks.
static COLON_LIGHTS: [Row; 2] = [
    Row {
        name: "point",
        title: "light point",
        keys: POINT_LIGHT_KEYS,
        common: COLON_LIGHT_COMMON_KEYS,
        build: Build::Light(setup::point_light),
        colon: true,
    },
    Row {
        name: "area",
        title: "light area",
        keys: COLON_AREA_LIGHT_KEYS,
        common: COLON_LIGHT_COMMON_KEYS,
        build: Build::Light(colon::area_light),
        colon: true,
    },
];

/// The colon family's `primitive TYPE` blocks.
static COLON_PRIMITIVES: [Row; 4] = [
    colon_primitive(
        "sphere",
        "primitive sphere",
        COLON_SPHERE_KEYS,
        colon::sphere,
    ),
    colon_primitive("plane", "primitive plane", COLON_PLANE_KEYS, colon::plane),
    colon_primitive(
        "cylinder",
        "primitive cylinder",
        COLON_CYLINDER_KEYS,
        colon::cylinder,
    ),
    colon_primitive(
        "rotationbody",
        "primitive rotationbody",
        COLON_ROTATION_BODY_KEYS,
        colon::rotation_body,
    ),
];

/// The colon family's row for a block opened by `head` (and type `kind`).
pub(crate) fn colon_row(head: &str, kind: Option<&str>) -> Option<BlockKind> {
    match (head, kind) {
        ("background", _) => Some(&COLON_BACKGROUND),
        ("camera", _) => Some(&COLON_CAMERA),
        ("light", Some(t)) => find(&COLON_LIGHTS, t),
        ("primitive", Some(t)) => find(&COLON_PRIMITIVES, t),
        _ => None,
    }
}

/// The colon family's block headers, for messages.
pub(crate) fn colon_titles() -> Vec<&'static str> {
    [&COLON_BACKGROUND, &COLON_CAMERA]
        .into_iter()
        .chain(&COLON_LIGHTS)
        .chain(&COLON_PRIMITIVES)
        .map(|r| r.title)
        .collect()
}

/// The row of type `name` among `rows`.
pub(crate) fn find(rows: &'static [Row], name: &str) -> Option<BlockKind> {
    rows.iter().find(|r| r.name == name)
}

/// The type names of `rows`, in order (for suggestions and messages).
pub(crate) fn names(rows: &'static [Row]) -> Vec<&'static str> {
    rows.iter().map(|r| r.name).collect()
}

impl Row {
    /// The key's canonical name and kind, if this block uses it.
    pub fn lookup(&self, key: &str) -> Option<(&'static str, Kind)> {
        self.keys
            .iter()
            .chain(self.common)
            .find(|(k, _)| *k == key)
            .copied()
    }

    /// The keys this block uses (without `=`).
    pub fn key_names(&self) -> Vec<&'static str> {
        self.keys
            .iter()
            .chain(self.common)
            .map(|(k, _)| *k)
            .collect()
    }
}

/// Whether some block kind uses `key`.
pub(crate) fn is_known_key(key: &str) -> bool {
    all_kinds().any(|r| r.lookup(key).is_some())
}

/// Every block kind, of both families.
pub(crate) fn all_kinds() -> impl Iterator<Item = BlockKind> {
    let rows = [&BACKGROUND, &CAMERA, &COLON_BACKGROUND, &COLON_CAMERA].into_iter();
    rows.chain(&LIGHTS)
        .chain(&PRIMITIVES)
        .chain(&COLON_LIGHTS)
        .chain(&COLON_PRIMITIVES)
}
