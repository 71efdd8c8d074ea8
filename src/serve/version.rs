//! One version of the scene, stage by stage: the file read (or its errors
//! shown, the last good picture left in place), the picture (a coarse
//! preview, sharpening band by band, then the full image), the AOVs, the
//! comparison. Each stage
//! publishes what it made as soon as it is ready, and a set cancel flag
//! (the next save) stops the version between and inside stages.

use super::file_watch::FileWatch;
use super::picture::Picture;
use super::state::{Compared, Phase, Shared};
use crate::image::Image;
use crate::output::Format;
use crate::render::{Aov, Control, Film, Region, RenderError, RenderOptions, Renderer};
use crate::scene::{Diagnostic, Dialect, Scene, Severity};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How often progress is announced at most.
const PROGRESS_EVERY: Duration = Duration::from_millis(100);
/// Light AOVs (`light:N`) offered at most.
const MAX_LIGHT_AOVS: usize = 8;
/// Rays the coarse preview may take, by [`Renderer::estimate`]: about
/// 50 ms on two cores, so that it comes at once.
const COARSE_RAYS: u64 = 1_000_000;
/// Bands the AOVs are rendered in: the AOVs are made without
/// a look at the cancel flag, so a save waits for one band at most.
const AOV_BANDS: u32 = 64;

/// Which picture of a version the page is shown.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Shown {
    /// The coarse preview.
    Coarse,
    /// The preview with the bands done so far at full resolution.
    Bands,
    /// The whole picture: `render`'s bytes.
    Final,
}

/// The picture as it sharpens: the coarse preview blown up to the full
/// size (or black), each band pasted over it at full resolution as it comes.
struct Sharpening {
    frame: (u32, u32),
    colour: Vec<[f32; 3]>,
    ids: Vec<f32>,
}

impl Sharpening {
    /// The full `frame` from `coarse` (nearest pixel), or black without one.
    fn new(coarse: Option<&Film>, frame: (u32, u32)) -> Sharpening {
        let (w, h) = frame;
        let n = w as usize * h as usize;
        let mut s = Sharpening {
            frame,
            colour: vec![[0.0; 3]; n],
            ids: vec![-1.0; n],
        };
        if let Some(c) = coarse {
            let image = c.image();
            let (cw, ch) = (image.width(), image.height());
            let ids = c.aov(Aov::Primitive);
            for y in 0..h {
                for x in 0..w {
                    let (sx, sy) = ((x * cw / w).min(cw - 1), (y * ch / h).min(ch - 1));
                    let at = (y * w + x) as usize;
                    s.colour[at] = image.pixel(sx, sy);
                    if let Some(p) = ids {
                        s.ids[at] = p.data[(sy * cw + sx) as usize];
                    }
                }
            }
        }
        s
    }

    /// Pastes a band's film (full width or not, with a primitive plane or not).
    fn paste(&mut self, band: &Film) {
        let r = band.region();
        let image = band.image();
        let ids = band.aov(Aov::Primitive);
        for y in 0..r.height {
            for x in 0..r.width {
                let at = ((r.y + y) * self.frame.0 + r.x + x) as usize;
                self.colour[at] = image.pixel(x, y);
                if let Some(p) = ids {
                    self.ids[at] = p.data[(y * r.width + x) as usize];
                }
            }
        }
    }

    /// The picture so far, as a film of the whole frame.
    fn film(&self) -> Film {
        let (w, h) = self.frame;
        let image = Image::from_pixels(w, h, self.colour.clone());
        let mut film = Film::new(self.frame, Region::full(w, h), image);
        film.set_aov(Aov::Primitive, self.ids.clone());
        film
    }
}

/// One version's render: what each of its stages needs.
pub(crate) struct Version<'a> {
    /// The state it publishes to.
    pub shared: &'a Shared,
    /// Its number (counts the scene's reads).
    pub number: u64,
    /// When the save was noticed (the timings count from it).
    pub noticed: Instant,
    /// Set by the next save.
    pub cancel: &'a AtomicBool,
}

impl Version<'_> {
    /// Reads and renders the version as read as `dialect`, watching what
    /// it reads in `watch`, then renders its picture, its AOVs and the
    /// comparison with `theirs`; returns early when cancelled.
    pub fn render(
        &self,
        dialect: Option<Dialect>,
        watch: &Mutex<FileWatch>,
        theirs: Option<&(Vec<u8>, (u32, u32))>,
    ) {
        let Some(renderer) = self.read(dialect, watch) else {
            return;
        };
        if self.cancelled() {
            return;
        }
        let last = Mutex::new(Instant::now());
        let progress = |done: u64, total: u64| self.progress(&last, done, total);
        let control = Control {
            progress: Some(&progress),
            cancel: Some(self.cancel),
            ..Control::default()
        };
        let options = RenderOptions {
            aovs: vec![Aov::Primitive],
            region: None,
            ..self.shared.options.clone()
        };
        let size = renderer.frame_size(&self.shared.options).ok();
        if !self.picture(&renderer, &options, size, control) {
            return;
        }
        let then = match theirs {
            Some(_) => Phase::Compare,
            None => Phase::Idle,
        };
        if !self.aovs(&renderer, &options, size, control, then) {
            return;
        }
        if let Some(theirs) = theirs {
            self.compare(&renderer, &options, theirs);
        }
    }

    /// Whether the next save has cancelled this version.
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Milliseconds since the save was noticed.
    fn ms(&self) -> f64 {
        self.noticed.elapsed().as_secs_f64() * 1e3
    }

    /// Reads the scene file as `dialect` and prepares it; publishes its
    /// warnings and files, or its errors (`None`: the last good picture
    /// stays). `watch` then holds what it read.
    fn read(&self, dialect: Option<Dialect>, watch: &Mutex<FileWatch>) -> Option<Arc<Renderer>> {
        let shared = self.shared;
        shared.update(|s| {
            s.version = self.number;
            s.phase = Phase::Reading;
            s.timings.clear();
        });
        for p in &shared.progress {
            p.store(0, Ordering::Relaxed);
        }
        // Stamped before reading: a save while the file is read is not missed.
        let mut next = FileWatch::default();
        next.add(&shared.scene);
        let scene = match Scene::from_file_as(&shared.scene, dialect) {
            Ok(scene) => scene,
            Err(e) => {
                watch_after_error(&shared.scene, watch, next);
                shared.update(|s| {
                    s.phase = Phase::Broken;
                    s.diagnostics = e.diagnostics;
                    s.timings.push(("read", self.ms()));
                });
                return None;
            }
        };
        for f in scene.files() {
            next.add(f);
        }
        *watch.lock().unwrap_or_else(|e| e.into_inner()) = next;
        let mut files = vec![shared.scene.clone()];
        files.extend(scene.files().iter().cloned());
        let warnings = scene.warnings().to_vec();
        let renderer = Arc::new(Renderer::new(scene));
        shared.update(|s| {
            s.phase = Phase::Coarse;
            s.diagnostics = warnings;
            s.files = files;
            s.timings.push(("read", self.ms()));
        });
        Some(renderer)
    }

    /// Reports (done, total) camera rays to the state, and to the pages at
    /// most every [`PROGRESS_EVERY`] (`last`: when they were last told).
    fn progress(&self, last: &Mutex<Instant>, done: u64, total: u64) {
        self.shared.progress[0].store(done, Ordering::Relaxed);
        self.shared.progress[1].store(total, Ordering::Relaxed);
        if let Ok(mut at) = last.try_lock()
            && at.elapsed() >= PROGRESS_EVERY
        {
            *at = Instant::now();
            let data = serde_json::json!({"version": self.number, "done": done, "total": total});
            self.shared.events.send("progress", &data.to_string());
        }
    }

    /// Renders the picture (of `size`): a coarse preview, then the full
    /// image band by band (nearest the pointer's last row, or the middle,
    /// first), the preview sharpening as bands arrive, then the whole,
    /// publishing each; false when cancelled or when it cannot be rendered
    /// (said on the page).
    fn picture(
        &self,
        renderer: &Arc<Renderer>,
        options: &RenderOptions,
        size: Option<(u32, u32)>,
        control: Control<'_>,
    ) -> bool {
        let shown = (|| {
            let quiet = Control {
                progress: None,
                ..control
            };
            let coarse = match coarse_options(renderer, options) {
                Some(c) => Some(renderer.render_with(&c, quiet)?.0),
                None => None,
            };
            if let Some(film) = &coarse {
                self.publish(Shown::Coarse, film, renderer, size);
            }
            let frame = renderer.frame_size(options)?;
            let sharpening = Mutex::new(Sharpening::new(coarse.as_ref(), frame));
            let last = Mutex::new(Instant::now());
            let near = self.shared.focus_row();
            let (film, _) = renderer.render_bands(options, near, control, &|band| {
                let mut s = sharpening.lock().unwrap_or_else(|e| e.into_inner());
                s.paste(band);
                let mut at = last.lock().unwrap_or_else(|e| e.into_inner());
                if at.elapsed() >= PROGRESS_EVERY && !self.cancelled() {
                    *at = Instant::now();
                    let film = s.film();
                    drop(s);
                    self.publish(Shown::Bands, &film, renderer, size);
                }
            })?;
            self.publish(Shown::Final, &film, renderer, size);
            Ok(())
        })();
        match shown {
            Ok(()) => true,
            Err(RenderError::Cancelled) => false,
            Err(e) => {
                self.shared.update(|s| {
                    s.phase = Phase::Broken;
                    s.diagnostics.push(render_error(&self.shared.scene, &e));
                });
                false
            }
        }
    }

    /// Publishes `film`, the picture's `shown` image rendered by `renderer`
    /// and standing for an image of `size`, as the current picture.
    fn publish(
        &self,
        shown: Shown,
        film: &Film,
        renderer: &Arc<Renderer>,
        size: Option<(u32, u32)>,
    ) {
        let (name, next) = match shown {
            Shown::Coarse => ("coarse", Phase::Final),
            Shown::Bands => ("bands", Phase::Final),
            Shown::Final => ("final", Phase::Aovs),
        };
        let id = self.shared.next_picture_id();
        let full = size.unwrap_or(film.frame_size());
        let Ok(picture) = Picture::new(id, self.number, name, full, film, renderer) else {
            return;
        };
        let picture = Arc::new(picture);
        let summary = picture.summary().to_string();
        self.shared.update(|s| {
            if shown == Shown::Coarse {
                s.aovs.clear();
                s.compare = None;
            }
            s.picture = Some(picture);
            s.renderer = Some(renderer.clone());
            s.good_version = Some(self.number);
            s.size = size;
            s.phase = next;
            if shown != Shown::Bands {
                s.timings.push((name, self.ms()));
            }
        });
        self.shared.events.send("frame", &summary);
    }

    /// Renders the AOVs of the picture (of `size`) and publishes them as
    /// PNG, the phase going on to `then`; false when cancelled.
    ///
    /// They are a render of their own, so that the picture came first;
    /// they are all of the centre ray, so its colour is rendered at one
    /// ray a pixel (which is why `rays`, the render's count, is not offered).
    fn aovs(
        &self,
        renderer: &Renderer,
        options: &RenderOptions,
        size: Option<(u32, u32)>,
        control: Control<'_>,
        then: Phase,
    ) -> bool {
        let aov_options = RenderOptions {
            aovs: aov_list(renderer.scene().lights().len()),
            spp: Some(1),
            ..options.clone()
        };
        let Some(film) = aovs_film(renderer, &aov_options, size, control) else {
            return false;
        };
        let aovs = aov_pngs(renderer, &film);
        if self.cancelled() {
            return false;
        }
        self.shared.update(|s| {
            s.aovs = aovs;
            s.phase = then;
            s.timings.push(("aovs", self.ms()));
        });
        true
    }

    /// Compares the picture `options` ask for with `theirs` (8-bit RGB and
    /// its size) and publishes the summary and the heat map (or the error).
    fn compare(
        &self,
        renderer: &Renderer,
        options: &RenderOptions,
        (theirs, size): &(Vec<u8>, (u32, u32)),
    ) {
        let compared =
            match crate::compare(renderer, theirs, *size, crate::DEFAULT_THRESHOLD, options) {
                Ok(c) => Compared {
                    summary: c.to_json(),
                    heat: Arc::new(c.heat.encode(Format::Png).unwrap_or_default()),
                },
                Err(e) => Compared {
                    summary: serde_json::json!({"error": e.to_string()}),
                    heat: Arc::new(Vec::new()),
                },
            };
        if self.cancelled() {
            return;
        }
        self.shared.update(|s| {
            s.compare = Some(compared);
            s.phase = Phase::Idle;
            s.timings.push(("compare", self.ms()));
        });
    }
}

/// After a read that failed, `watch` becomes `next` (the scene file), what
/// the last good version read and the scene's folder (a missing texture
/// may appear there).
fn watch_after_error(scene: &Path, watch: &Mutex<FileWatch>, mut next: FileWatch) {
    let mut watch = watch.lock().unwrap_or_else(|e| e.into_inner());
    let old: Vec<PathBuf> = watch.paths().map(Path::to_path_buf).collect();
    for p in &old {
        next.add(p);
    }
    if let Some(dir) = scene.parent() {
        next.add(if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        });
    }
    *watch = next;
}

/// The coarse preview's options: one ray a pixel at a quarter of the size,
/// or an eighth or a sixteenth where the scene is costly (glossy fans, area
/// lights), the first whose estimate is within [`COARSE_RAYS`] (`None`
/// when the size is out of range: the full render says why).
fn coarse_options(renderer: &Renderer, options: &RenderOptions) -> Option<RenderOptions> {
    let (w, h) = renderer.frame_size(options).ok()?;
    let at = |d: u32| RenderOptions {
        width: Some(w.div_ceil(d)),
        height: Some(h.div_ceil(d)),
        spp: Some(1),
        ..options.clone()
    };
    let cost = |o: &RenderOptions| renderer.estimate(o).map_or(u64::MAX, |e| e.rays);
    [4, 8, 16]
        .into_iter()
        .map(at)
        .find(|o| cost(o) <= COARSE_RAYS)
        .or_else(|| Some(at(16)))
}

/// The AOVs offered for a scene with `lights` lights.
fn aov_list(lights: usize) -> Vec<Aov> {
    let mut list = vec![
        Aov::Primitive,
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::Uv,
        Aov::Albedo,
        Aov::Shade,
        Aov::Why,
        Aov::Clamp,
        Aov::Cost,
    ];
    list.extend((0..lights.min(MAX_LIGHT_AOVS) as u32).map(Aov::Light));
    list
}

/// The AOVs of the whole frame (of `size`), rendered band by band,
/// stitched into one film (whose colour is left black: only the planes are
/// used); `None` when cancelled or when the size is out of range.
fn aovs_film(
    renderer: &Renderer,
    options: &RenderOptions,
    size: Option<(u32, u32)>,
    control: Control<'_>,
) -> Option<Film> {
    let (w, h) = size?;
    let band = h.div_ceil(AOV_BANDS).max(1);
    let mut aovs: Vec<(Aov, Vec<f32>)> = Vec::new();
    let mut y = 0;
    while y < h {
        if control.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return None;
        }
        let rows = band.min(h - y);
        let region = crate::Region {
            x: 0,
            y,
            width: w,
            height: rows,
        };
        let part = RenderOptions {
            region: Some(region),
            ..options.clone()
        };
        let (film, _) = renderer.render_with(&part, control).ok()?;
        for p in film.aovs() {
            match aovs.iter_mut().find(|(a, _)| *a == p.aov) {
                Some((_, data)) => data.extend_from_slice(&p.data),
                None => aovs.push((p.aov, p.data.clone())),
            }
        }
        y += rows;
    }
    let black = crate::Image::from_pixels(w, h, vec![[0.0; 3]; w as usize * h as usize]);
    let mut film = Film::new((w, h), crate::Region::full(w, h), black);
    for (aov, data) in aovs {
        film.set_aov(aov, data);
    }
    Some(film)
}

/// Every AOV of `film` (rendered by `renderer`) as PNG, by name, drawn as
/// `glint render --aov` draws them.
fn aov_pngs(renderer: &Renderer, film: &Film) -> Vec<(String, Arc<Vec<u8>>)> {
    let hit = crate::output::hit_mask(film);
    let table = renderer.primitive_table();
    let file = renderer.scene_file();
    let (w, h) = (film.image().width(), film.image().height());
    film.aovs()
        .iter()
        .filter_map(|p| {
            let (rgb, _) = crate::output::aov_picture(p, &hit, &table, file.as_deref());
            let png = crate::output::encode_rgb8(w, h, rgb, Format::Png).ok()?;
            Some((p.aov.name().into_owned(), Arc::new(png)))
        })
        .collect()
}

/// A render that could not start (a size out of range), as a diagnostic.
fn render_error(scene: &Path, e: &RenderError) -> Diagnostic {
    file_error(scene, format!("cannot render: {e}"))
}

/// An error about the scene file as a whole (no line), saying `message`.
pub(crate) fn file_error(scene: &Path, message: String) -> Diagnostic {
    Diagnostic {
        severity: Severity::Error,
        message,
        file: scene.display().to_string(),
        line: 0,
        column: 0,
        len: 0,
        source_line: String::new(),
        help: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn renderer(text: &str) -> Renderer {
        match Scene::parse(text, ".") {
            Ok(s) => Renderer::new(s),
            Err(e) => panic!("{e}"), // invariant: the test's own fixed input (a failure fails the test)
        }
    }

    #[test]
    fn the_coarse_preview_is_a_quarter_unless_that_is_costly() {
        let cheap = renderer(
            "camera\n O= 0 -5 1\n N= 0 1 0\n image_W= 320\n image_H= 240\nend\n\
             light point\n O= 3 -3 3\n color= 1 1 1\nend\n\
             primitive sphere\n O= 0 0 1\n R= 1\n color= 1 0 0\n diff= 0.8\nend\n",
        );
        let size = |r: &Renderer| {
            let o =
                coarse_options(r, &RenderOptions::default()).map(|o| (o.width, o.height, o.spp));
            o.unwrap_or_default()
        };
        assert_eq!(size(&cheap), (Some(80), Some(60), Some(1)));
        // A glossy floor: 16 rays a glossy hit make the quarter cost about 1.9 M rays.
        let glossy = renderer(
            "camera\n O= 0 -5 1\n N= 0 1 0\n image_W= 1280\n image_H= 760\n drefl_quality= 1\nend\n\
             light point\n O= 3 -3 3\n color= 1 1 1\nend\n\
             primitive plane\n N= 0 0 1\n R= 0\n color= 1 1 1\n diff= 0.5\n refl= 0.5\n drefl= 0.1\nend\n",
        );
        assert_eq!(size(&glossy), (Some(160), Some(95), Some(1)));
    }
}
