//! `glint compare`: a student's own render against glint's, pixel by pixel:
//! a heat map of the differences, and the differing pixels grouped by the
//! primitive glint sees there (its `primitive` pass), worst first.

use crate::image::Image;
use crate::integrator::photons::PhotonFilter;
use crate::render::{Aov, RenderError, RenderOptions, Renderer, place};
use crate::scene::Dialect;
use serde_json::{Value, json};
use std::fmt::Write;
use std::path::Path;

/// A pixel differs when a channel is off by more than this many 8-bit
/// steps (anti-aliasing, texture filtering and rounding stay below it).
pub const DEFAULT_THRESHOLD: u8 = 8;

/// Why two pictures could not be compared.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CompareError {
    /// Their picture is not the size the scene renders at.
    #[error(
        "{theirs_w}x{theirs_h} is not the scene's size: it renders {ours_w}x{ours_h} (image_W= and image_H= of its camera)"
    )]
    Size {
        /// Their width.
        theirs_w: u32,
        /// Their height.
        theirs_h: u32,
        /// The scene's width.
        ours_w: u32,
        /// The scene's height.
        ours_h: u32,
    },
    /// The render failed.
    #[error("{0}")]
    Render(#[from] RenderError),
}

/// The differing pixels on one primitive.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// The primitive block (`None`: the background, or a light's surface).
    pub primitive: Option<u32>,
    /// The light whose surface it is.
    pub light: Option<u32>,
    /// What it is: `sphere`, `background`, `light`...
    pub kind: &'static str,
    /// The 1-based line of its block's header.
    pub line: Option<u32>,
    /// Pixels glint sees it at.
    pub pixels: u64,
    /// Of those, the ones that differ by more than the threshold.
    pub differing: u64,
    /// Of the differing ones, those that are black in theirs.
    pub black_in_theirs: u64,
    /// The differing pixel that differs most (the first such, row by row).
    pub example: (u32, u32),
    /// Glint's bytes there.
    pub ours: [u8; 3],
    /// Theirs.
    pub theirs: [u8; 3],
}

/// A comparison of their picture with glint's.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The scene file's name as given.
    pub file: Option<String>,
    /// The pictures' size.
    pub size: (u32, u32),
    /// The threshold used (see [`DEFAULT_THRESHOLD`]).
    pub threshold: u8,
    /// Pixels that differ by more than it.
    pub differing: u64,
    /// The mean absolute difference over every channel of every pixel, in
    /// 8-bit steps (x/255).
    pub mae: f64,
    /// The groups with differing pixels, most differing pixels first.
    pub groups: Vec<Group>,
    /// The heat map: glint's picture dimmed, differences from red (just
    /// over the threshold) to yellow and white (255 apart).
    pub heat: Image,
    /// Glint's render that was compared.
    pub picture: Image,
    /// The options of `glint explain` that trace glint's pixels as this
    /// comparison rendered them: the size and samples as given, the seed
    /// when not 0, and the dialect the scene was drawn in.
    pub explain_options: Vec<String>,
}

/// Compares `theirs` (8-bit RGB, rows from the top, `w` × `h`) with
/// glint's render of `renderer`'s scene as `options` say (sizes, samples,
/// seed; its passes and region are not used: the whole frame is compared).
pub fn compare(
    renderer: &Renderer,
    theirs: &[u8],
    (w, h): (u32, u32),
    threshold: u8,
    options: &RenderOptions,
) -> Result<Comparison, CompareError> {
    let options = RenderOptions {
        aovs: vec![Aov::Primitive],
        region: None,
        ..options.clone()
    };
    let (ours_w, ours_h) = renderer.frame_size(&options)?;
    if (w, h) != (ours_w, ours_h) || theirs.len() != (w as usize * h as usize * 3) {
        return Err(CompareError::Size {
            theirs_w: w,
            theirs_h: h,
            ours_w,
            ours_h,
        });
    }
    let film = renderer.render(&options)?;
    let ours = film.image().to_rgb8();
    let prim = film
        .aov(Aov::Primitive)
        .map(|p| p.data.clone())
        .unwrap_or_default();
    let table = renderer.primitive_table();
    let mut groups: std::collections::BTreeMap<i64, Group> = std::collections::BTreeMap::new();
    let mut worst: std::collections::BTreeMap<i64, u8> = std::collections::BTreeMap::new();
    let mut heat = Vec::with_capacity((w * h) as usize);
    let (mut differing, mut absolute) = (0, 0u64);
    for i in 0..(w * h) as usize {
        let (a, b) = (&ours[3 * i..3 * i + 3], &theirs[3 * i..3 * i + 3]);
        let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        absolute += (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>();
        let v = prim.get(i).copied().unwrap_or(-1.0);
        let key = v as i64;
        let g = groups.entry(key).or_insert_with(|| {
            let (primitive, light, kind, line) = if v >= 0.0 {
                let (kind, line) = table.get(&(v as u32)).copied().unwrap_or(("?", None));
                (Some(v as u32), None, kind, line)
            } else if v <= -2.0 {
                let l = (-2.0 - v) as u32;
                (None, Some(l), "light", renderer.scene().light_line(l))
            } else {
                (None, None, "background", None)
            };
            Group {
                primitive,
                light,
                kind,
                line,
                pixels: 0,
                differing: 0,
                black_in_theirs: 0,
                example: (0, 0),
                ours: [0; 3],
                theirs: [0; 3],
            }
        });
        g.pixels += 1;
        let dim = |c: u8| c as f32 / 255.0 * 0.25;
        if d > threshold {
            differing += 1;
            g.differing += 1;
            g.black_in_theirs += u64::from(b == [0, 0, 0]);
            let most = worst.entry(key).or_insert(0);
            if d > *most {
                *most = d;
                g.example = ((i as u32) % w, (i as u32) / w);
                g.ours = [a[0], a[1], a[2]];
                g.theirs = [b[0], b[1], b[2]];
            }
            // Red from the threshold, through yellow, to white at 255.
            let t = d as f32 / 255.0;
            heat.push([
                1.0,
                (2.0 * t - 0.2).clamp(0.0, 1.0),
                (2.0 * t - 1.0).clamp(0.0, 1.0),
            ]);
        } else {
            heat.push([dim(a[0]), dim(a[1]), dim(a[2])]);
        }
    }
    let mut groups: Vec<Group> = groups.into_values().filter(|g| g.differing > 0).collect();
    groups.sort_by(|a, b| {
        b.differing
            .cmp(&a.differing)
            .then(a.primitive.cmp(&b.primitive))
    });
    Ok(Comparison {
        file: renderer.scene_file(),
        size: (w, h),
        threshold,
        differing,
        mae: absolute as f64 / (3 * w as u64 * h as u64).max(1) as f64,
        groups,
        heat: Image::from_pixels(w, h, heat),
        picture: film.image().clone(),
        explain_options: explain_options(&options, renderer.scene().dialect().dialect),
    })
}

/// The options of `glint explain` that draw a pixel as a render with
/// `options` in `dialect` does.
fn explain_options(options: &RenderOptions, dialect: Dialect) -> Vec<String> {
    let given = [
        ("--width", options.width.map(u64::from)),
        ("--height", options.height.map(u64::from)),
        ("--spp", options.spp.map(u64::from)),
        ("--seed", Some(options.seed).filter(|&s| s != 0)),
        ("--iterations", options.photons.iterations),
        ("--emit", options.photons.emit),
    ];
    let mut out: Vec<String> = given
        .into_iter()
        .filter_map(|(flag, v)| v.map(|v| [flag.to_string(), v.to_string()]))
        .flatten()
        .collect();
    let photons = &options.photons;
    if let Some(mode) = photons.mode {
        out.extend(["--photons".to_string(), mode.name().to_string()]);
    }
    if photons.filter != PhotonFilter::default() {
        out.extend([
            "--photon-filter".to_string(),
            photons.filter.name().to_string(),
        ]);
    }
    out.extend(["--dialect".to_string(), dialect.name().to_string()]);
    out
}

/// `word` as one word of a POSIX shell's command line: as it is when it
/// holds only safe characters, else in single quotes.
fn shell_word(word: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "-_./,:=+@%".contains(c);
    if !word.is_empty() && word.chars().all(safe) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

impl Group {
    /// `sphere #3` / `light #0's surface` / `background`.
    fn name(&self) -> String {
        match (self.primitive, self.light) {
            (Some(p), _) => format!("{} #{p}", self.kind),
            (None, Some(l)) => format!("light #{l}'s surface"),
            _ => "background".to_string(),
        }
    }
}

impl Comparison {
    /// The `glint explain` command for pixel (x, y) of this scene, with
    /// the options that draw it as this comparison did (a shell's words).
    pub fn explain_command(&self, (x, y): (u32, u32)) -> String {
        let file = self.file.as_deref().map_or("SCENE".to_string(), shell_word);
        let mut command = format!("glint explain {file} --pixel {x},{y}");
        for word in &self.explain_options {
            command.push(' ');
            command.push_str(&shell_word(word));
        }
        command
    }

    /// The share of the pixels that differ by more than the threshold.
    pub fn share(&self) -> f64 {
        let (w, h) = self.size;
        self.differing as f64 / (w as u64 * h as u64).max(1) as f64
    }

    /// A summary, then one paragraph per group, worst first.
    pub fn to_text(&self) -> String {
        let (w, h) = self.size;
        let mut s = format!(
            "{} of {} pixels ({:.1} %) differ by more than {}/255; mean absolute difference {:.2}/255\n",
            self.differing,
            w as u64 * h as u64,
            100.0 * self.share(),
            self.threshold,
            self.mae
        );
        for g in &self.groups {
            let at = place(self.file.as_deref(), g.line);
            let share = 100.0 * g.differing as f64 / g.pixels as f64;
            let _ = writeln!(
                s,
                "{}  {at}   {share:.1} % of its {} pixels differ; {} are black in yours",
                g.name(),
                g.pixels,
                g.black_in_theirs
            );
            let [a, b] = [g.ours, g.theirs];
            let _ = writeln!(
                s,
                "  e.g. ({}, {}): glint {} {} {}, yours {} {} {}  ->  {}",
                g.example.0,
                g.example.1,
                a[0],
                a[1],
                a[2],
                b[0],
                b[1],
                b[2],
                self.explain_command(g.example)
            );
        }
        s
    }

    /// One JSON object (schema: docs/debugging.md).
    pub fn to_json(&self) -> Value {
        let groups: Vec<Value> = self
            .groups
            .iter()
            .map(|g| {
                json!({
                    "primitive": g.primitive,
                    "light": g.light,
                    "type": g.kind,
                    "file": self.file,
                    "line": g.line,
                    "pixels": g.pixels,
                    "differing": g.differing,
                    "share": g.differing as f64 / g.pixels as f64,
                    "black_in_theirs": g.black_in_theirs,
                    "example": {
                        "pixel": [g.example.0, g.example.1],
                        "glint": g.ours,
                        "theirs": g.theirs,
                        "explain": self.explain_command(g.example),
                    },
                })
            })
            .collect();
        json!({
            "file": self.file,
            "size": [self.size.0, self.size.1],
            "threshold": self.threshold,
            "differing": self.differing,
            "share": self.share(),
            "mae": self.mae,
            "groups": groups,
        })
    }
}

/// Reads their picture (BMP or PNG, anything `image` decodes) as 8-bit RGB.
pub fn read_picture(path: &Path) -> Result<(Vec<u8>, (u32, u32)), String> {
    if path.is_dir() {
        return Err(format!("{} is a directory, not a picture", path.display()));
    }
    let img = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?
        .decode()
        .map_err(|e| format!("cannot decode {}: {e}", path.display()))?
        .to_rgb8();
    let size = img.dimensions();
    Ok((img.into_raw(), size))
}
