//! Choosing a file's dialect (`lineages.md` §5): the reader records the
//! markers each lineage leaves (header types, telling keys, spheres resting
//! on planes) as it goes; once the whole file is read, the first rule that
//! matches decides, and the scene is adapted to that lineage's reading of
//! it (camera defaults, plane sign, texel scale).

use crate::geometry::Shape;
use crate::scene::{Camera, Dialect, DialectChoice, Scene};
use glam::DVec3;

/// lazycal's photons a pass (`PHOTONS_PER_ITER`).
const LAZYCAL_EMIT: u64 = 1_000_000;
/// lazycal's passes (`ITERS`).
const LAZYCAL_ITERATIONS: u64 = 100;
/// lazycal's gather radius, the same for every hit point (`getPixelLength`).
const LAZYCAL_RADIUS: f64 = 0.2;

/// The brightest light colour component from which a 1/d² lineage is hinted.
const BRIGHT: f64 = 5.0;
/// A sphere rests on a plane when its centre's distance from it is its
/// radius to within this share of the radius.
const RESTING: f64 = 0.01;

/// What the file shows of its lineage, as read so far (lines 0-based).
#[derive(Debug, Default)]
pub(crate) struct Evidence {
    /// The first key written `key:` (the colon family's blocks).
    colon: Option<usize>,
    /// An `object` header (W's blocks).
    object: Option<usize>,
    /// An `obj` header (abcbdf's blocks).
    obj: Option<usize>,
    /// abcbdf's own kinds or keys (a `tetra`, a triangle's `A0=`, a
    /// bezier's `center=`/`V0=`…): what and where.
    a18_marker: Option<(usize, String)>,
    /// A bezier given by lazycal's keys (`control_points=`, `Dz=`, `S=`).
    l17_marker: Option<(usize, String)>,
    /// A `primitive` header (abcbdf's own reader opens only `obj` blocks).
    primitive: Option<usize>,
    /// A camera `Dx=` (W's camera).
    camera_dx: Option<usize>,
    /// A `primitive polyhedron` (PM3).
    polyhedron: Option<usize>,
    /// V's primitives or keys: what and where.
    v_marker: Option<(usize, String)>,
    /// A camera `algorithm=` (PM3 and V).
    algorithm: Option<usize>,
    /// A `light area` or `primitive rectangle`: what and where.
    area: Option<(usize, &'static str)>,
    /// The first of the framework's own types or keys: what and where.
    f_marker: Option<(usize, String)>,
    /// Sphere centres and radii.
    spheres: Vec<(DVec3, f64)>,
    /// Plane unit normals and `R=` values.
    planes: Vec<(DVec3, f64)>,
    /// The largest colour component of any light.
    brightest: f64,
    /// The camera keys the file sets.
    camera_keys: Vec<&'static str>,
}

impl Evidence {
    /// A block that opens with `head` (`primitive`, `light`, `object`...)
    /// and type `kind` at `line`, with the keys `keys` (as written).
    pub fn block<'k>(
        &mut self,
        line: usize,
        head: &str,
        kind: Option<&str>,
        keys: impl Iterator<Item = &'k str> + Clone,
    ) {
        let has = |k: &str| keys.clone().any(|x| x == k);
        let first = |slot: &mut Option<usize>| {
            slot.get_or_insert(line);
        };
        match head {
            "object" => first(&mut self.object),
            "obj" => first(&mut self.obj),
            "primitive" => first(&mut self.primitive),
            _ => {}
        }
        let kind = kind.unwrap_or("");
        let primitive = matches!(head, "primitive" | "object" | "obj");
        match (head, kind) {
            ("camera", _) => {
                if has("Dx") {
                    first(&mut self.camera_dx);
                }
                if has("algorithm") {
                    first(&mut self.algorithm);
                }
            }
            ("background", _) if has("top") || has("bottom") => {
                self.f_mark(line, "background `top=`/`bottom=`".to_string());
            }
            ("light", "area") => {
                self.area.get_or_insert((line, "light area"));
            }
            ("light", "square" | "sphere") => self.f_mark(line, format!("light {kind}")),
            (_, "rectangle") if primitive => {
                self.area.get_or_insert((line, "primitive rectangle"));
            }
            (_, "polyhedron") if primitive => first(&mut self.polyhedron),
            (_, "Bezier" | "NomalBall" | "NomalPlane") if primitive => {
                self.v_mark(line, format!("primitive {kind}"));
            }
            (_, "bezier") if primitive => {
                // lazycal's marker keys, then abcbdf's.
                let lazycal = ["control_points", "Dz", "S"].into_iter().find(|k| has(k));
                let abcbdf = ["center", "V0", "V1", "V2", "V3"];
                if let Some(key) = lazycal {
                    self.l17_marker
                        .get_or_insert((line, format!("a bezier's `{key}=`")));
                } else if let Some(key) = abcbdf.into_iter().find(|k| has(k)) {
                    self.a18_mark(line, format!("a bezier's `{key}=`"));
                } else if !has("newPoint") {
                    // Z17's tensor-product bezier (`newPoint=`) is not the framework's.
                    self.f_mark(line, format!("primitive {kind}"));
                }
            }
            (_, "triangle") if primitive && has("A0") => {
                self.a18_mark(line, "a triangle's `A0=`".to_string());
            }
            (_, "tetra") if primitive => self.a18_mark(line, format!("{head} tetra")),
            // Z17's triangle is not the framework's.
            (_, "triangle") if primitive && has("P0") => {}
            (_, "square" | "cylinder" | "triangle" | "mesh" | "cube") if primitive => {
                self.f_mark(line, format!("primitive {kind}"));
            }
            _ => {}
        }
        for key in ["NT", "ratio"] {
            if has(key) {
                self.v_mark(line, format!("key `{key}=`"));
            }
        }
    }

    /// Takes the markers of `marks` (what [`Evidence::block`] and
    /// [`Evidence::colon`] found, on the reader's side), keeping the values
    /// found here (spheres, planes, lights, camera keys, on the builder's).
    pub fn absorb(&mut self, marks: Evidence) {
        *self = Evidence {
            spheres: std::mem::take(&mut self.spheres),
            planes: std::mem::take(&mut self.planes),
            brightest: self.brightest,
            camera_keys: std::mem::take(&mut self.camera_keys),
            ..marks
        };
    }

    /// A block whose keys are written `key:`, the first at `line`.
    pub fn colon(&mut self, line: usize) {
        self.colon.get_or_insert(line);
    }

    fn f_mark(&mut self, line: usize, what: String) {
        self.f_marker.get_or_insert((line, what));
    }

    fn v_mark(&mut self, line: usize, what: String) {
        self.v_marker.get_or_insert((line, what));
    }

    fn a18_mark(&mut self, line: usize, what: String) {
        self.a18_marker.get_or_insert((line, what));
    }

    /// Whether the blocks read so far are lazycal's (its reader stops at a
    /// word `end` outside a block).
    pub fn lazycal(&self) -> bool {
        self.l17_marker.is_some()
    }

    /// Makes room for `more` spheres ([`crate::scene::make_room`]).
    pub fn reserve_spheres(&mut self, more: usize) {
        crate::scene::make_room(&mut self.spheres, more);
    }

    /// A sphere with centre `o` and radius `r`.
    pub fn sphere(&mut self, o: DVec3, r: f64) {
        self.spheres.push((o, r));
    }

    /// A plane with unit normal `n` and `R=` value `r`.
    pub fn plane(&mut self, n: DVec3, r: f64) {
        self.planes.push((n, r));
    }

    /// A light of colour `c`.
    pub fn light(&mut self, c: DVec3) {
        self.brightest = self.brightest.max(c.max_element());
    }

    /// The camera sets key `key`.
    pub fn camera_key(&mut self, key: &'static str) {
        if !self.camera_keys.contains(&key) {
            self.camera_keys.push(key);
        }
    }

    /// Spheres resting on planes read as N·P + R = 0 (PM3) and as N·P = R (V).
    fn resting(&self) -> (usize, usize) {
        let count = |sign: f64| {
            let mut n = 0;
            for &(o, rs) in &self.spheres {
                for &(pn, r) in &self.planes {
                    if ((pn.dot(o) + sign * r).abs() - rs).abs() <= RESTING * rs {
                        n += 1;
                    }
                }
            }
            n
        };
        (count(1.0), count(-1.0))
    }

    /// The dialect rules 2–7 pick, with the reason, and a hint when the
    /// default decided although the lights look like a 1/d² lineage's.
    fn rules(&self) -> (DialectChoice, Option<String>) {
        let at = |line: usize| format!("at line {}", line + 1);
        let choice = |dialect, reason: String| {
            (
                DialectChoice {
                    dialect,
                    reason,
                    caveat: None,
                },
                None,
            )
        };
        if let Some(l) = self.colon {
            return choice(
                Dialect::Colon,
                format!(
                    "keys written `key:` (hta1996/Raytracing's reader) {}",
                    at(l)
                ),
            );
        }
        if let Some((l, what)) = &self.l17_marker {
            return choice(Dialect::L17, format!("{what} {}", at(*l)));
        }
        if let Some(l) = self.obj {
            return choice(Dialect::A18, format!("an `obj` block {}", at(l)));
        }
        if let Some((l, what)) = &self.a18_marker {
            return choice(Dialect::A18, format!("{what} {}", at(*l)));
        }
        if let Some(l) = self.object {
            return choice(Dialect::W, format!("an `object` block {}", at(l)));
        }
        if let Some(l) = self.camera_dx {
            return choice(Dialect::W, format!("camera `Dx=` {}", at(l)));
        }
        if let Some(l) = self.polyhedron {
            return choice(Dialect::Pm3, format!("primitive polyhedron {}", at(l)));
        }
        if let Some((l, what)) = &self.v_marker {
            return choice(Dialect::V, format!("{what} {}", at(*l)));
        }
        if let Some(l) = self.algorithm {
            let (pm3, v) = self.resting();
            let counted = format!(
                "camera `algorithm=` {}, spheres resting on planes: {pm3} as N·P + R = 0 (pm3), {v} as N·P = R (v)",
                at(l)
            );
            return if pm3 > v {
                choice(Dialect::Pm3, counted)
            } else if v > pm3 {
                choice(Dialect::V, counted)
            } else {
                choice(Dialect::V, format!("{counted}; plane sign undecided"))
            };
        }
        if let (Some((l, what)), None) = (self.area, &self.f_marker) {
            return choice(Dialect::Z14, format!("{what} {}", at(l)));
        }
        if let Some((l, what)) = &self.f_marker {
            return choice(Dialect::F, format!("{what} {}", at(*l)));
        }
        let hint = (self.brightest >= BRIGHT)
            .then(|| "bright lights suggest a 1/d² lineage; try --dialect z14".to_string());
        (
            DialectChoice {
                dialect: Dialect::F,
                reason: "no lineage's marker, the framework by default".to_string(),
                caveat: None,
            },
            hint,
        )
    }

    /// The dialect of the file (`forced` by the user, or by the rules),
    /// and a warning to give: the rules disagree with the user, or a hint.
    pub fn choose(&self, forced: Option<Dialect>) -> (DialectChoice, Option<String>) {
        let (ruled, hint) = self.rules();
        match forced {
            None => (ruled, hint),
            Some(d) => {
                let warning = (d != ruled.dialect).then(|| {
                    format!(
                        "--dialect {d} overrides the file's markers, which read as {}",
                        ruled
                    )
                });
                (
                    DialectChoice {
                        dialect: d,
                        reason: "chosen by --dialect".to_string(),
                        caveat: None,
                    },
                    warning,
                )
            }
        }
    }

    /// lazycal's photon settings, fixed in its code (`PPMRenderer.cpp`,
    /// `Camera::getPixelLength`): its reader reads none of the camera's
    /// photon keys. Returns a note naming those the file sets.
    fn lazycal_photons(&self, cam: &mut Camera) -> Option<String> {
        let p = &mut cam.photons;
        let set: Vec<String> = p.keys.iter().map(|k| format!("`{k}=`")).collect();
        (p.emit_photons, p.iterations, p.sample_dist, p.reduction) = (
            LAZYCAL_EMIT,
            Some(LAZYCAL_ITERATIONS),
            LAZYCAL_RADIUS,
            Some(0.7),
        );
        // lazycal keeps every photon of a pass; glint thins beyond this.
        p.max_photons = LAZYCAL_EMIT * 4;
        (!set.is_empty()).then(|| {
            format!(
                "lazycal's reader reads no photon key ({} here): it renders {LAZYCAL_ITERATIONS}                  passes of {LAZYCAL_EMIT} photons, gathered within R = {LAZYCAL_RADIUS}                  (--iterations and --emit change them)",
                set.join(" ")
            )
        })
    }

    /// Gives the camera keys the file leaves unset dialect `d`'s defaults.
    fn camera_defaults(&self, d: Dialect, cam: &mut Camera) {
        let unset = |k: &str| !self.camera_keys.contains(&k);
        if d == Dialect::Colon {
            colon_photons(cam);
            return;
        }
        if !matches!(d, Dialect::Pm3 | Dialect::V) {
            return;
        }
        if unset("drefl_quality") {
            cam.drefl_quality = 20.0;
        }
        let p = &mut cam.photons;
        for (key, slot, value) in [
            ("max_photons", &mut p.max_photons, 500_000),
            ("emit_photons", &mut p.emit_photons, 100_000),
            ("sample_photons", &mut p.sample_photons, 10),
        ] {
            if unset(key) {
                *slot = value;
            }
        }
        if unset("sample_dist") {
            p.sample_dist = 0.1;
        }
        p.max_hitpoints.get_or_insert(4_000_000);
        p.iterations.get_or_insert(5000);
        p.reduction.get_or_insert(0.7);
        if unset("dofSample") {
            cam.dof.samples = 64;
        }
        if unset("focalLen") {
            cam.dof.focal_len = 1.0;
        }
    }

    /// Adapts `scene`, read by the framework's rules, to dialect `d`.
    pub fn adapt(&self, d: Dialect, scene: &mut Scene) {
        let mut cam = scene.camera().clone();
        self.camera_defaults(d, &mut cam);
        let lazycal_note = (d == Dialect::L17)
            .then(|| self.lazycal_photons(&mut cam))
            .flatten();
        scene.set_camera(cam);
        if let Some(note) = lazycal_note {
            scene.add_note(note);
        }
        if d == Dialect::L17 {
            // lazycal's plane texture: the column along Dx, the row along Dy.
            for shape in scene.shapes_mut() {
                if let Shape::Plane(p) = shape {
                    std::mem::swap(&mut p.dx, &mut p.dy);
                }
            }
            // lazycal's light is no primitive: nothing sees it; it keeps the last.
            scene.hide_light_surfaces();
            if scene.lights().len() > 1 {
                scene.keep_last_light();
                scene.add_note(
                    "lazycal's reader keeps the last `light` block only: the others are not drawn"
                        .to_string(),
                );
            }
        }
        if let (Dialect::A18, Some(l)) = (d, self.primitive) {
            scene.add_note(format!(
                "abcbdf's own reader opens only `obj` blocks: it would draw none of the \
                 `primitive` blocks (the first at line {}); glint reads them",
                l + 1
            ));
        }
        if d == Dialect::Pm3 {
            // PM3's planes are N·P + R = 0; its textures are offset by half a tile.
            for shape in scene.shapes_mut() {
                if let Shape::Plane(p) = shape {
                    p.offset = -p.offset;
                    p.uv_shift = glam::DVec2::splat(0.5);
                }
            }
        }
        let (divisor, flipped) = match d {
            Dialect::F | Dialect::Z14 | Dialect::A18 => (256.0, false),
            Dialect::Pm3 | Dialect::V | Dialect::L17 | Dialect::Colon => (255.0, false),
            Dialect::W => (255.0, true),
        };
        for t in scene.textures_mut() {
            t.set_byte_divisor(divisor);
            if flipped {
                t.flip_clamped();
            }
        }
    }
}

/// The colon family's PPM hit points at most: its program keeps them all,
/// and its 960×540 `bar.txt` with its open lens (16 rays a pixel) makes
/// more than the 4 million glint allows the others.
const COLON_HIT_POINTS: u64 = 32_000_000;

/// The colon family's progressive photon mapping, fixed in its program
/// (hta1996/Raytracing `const.h`): a million photons a round, every hit
/// point's first radius² 0.2, α = 2/3, 15000 rounds; it stores every
/// photon's every hit (at most 10 each: glint's cap is that), and every
/// hit point of its eye pass, 16 lens rays a pixel (glint's cap:
/// [`COLON_HIT_POINTS`]).
fn colon_photons(cam: &mut Camera) {
    let p = &mut cam.photons;
    p.max_hitpoints = Some(COLON_HIT_POINTS);
    p.emit_photons = 1_000_000;
    p.max_photons = 10_000_000;
    p.sample_dist = 0.2f64.sqrt();
    p.iterations = Some(15_000);
    p.reduction = Some(2.0 / 3.0);
}
