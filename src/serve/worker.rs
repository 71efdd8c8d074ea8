//! What a save sets off. A watcher thread polls the scene file and every
//! file it read; on a change it cancels the running render at once and
//! wakes the worker, which reads the scene again and renders it in stages
//! (coarse preview, full image, passes, comparison), publishing each as it
//! is ready. A broken file leaves the last good picture in place.

use super::file_watch::FileWatch;
use super::picture::Picture;
use super::state::{Compared, Phase, Shared};
use crate::output::Format;
use crate::render::{Aov, Control, RenderError, RenderOptions, Renderer, Stage};
use crate::scene::{Diagnostic, Dialect, Scene, Severity};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// How often the files are polled.
pub(crate) const POLL: Duration = Duration::from_millis(25);
/// How often progress is announced at most.
const PROGRESS_EVERY: Duration = Duration::from_millis(100);
/// Light passes (`light:N`) offered at most.
const MAX_LIGHT_PASSES: usize = 8;

/// A pending save, handed from the watcher to the worker.
struct Pending {
    /// A save was noticed (at this instant) and not yet read.
    noticed: Option<Instant>,
    /// The running render's flag: set by the next save.
    cancel: Arc<AtomicBool>,
}

/// The hand-off between the watcher and the worker.
pub(crate) struct Trigger {
    pending: Mutex<Pending>,
    wake: Condvar,
}

impl Trigger {
    /// A trigger with a save pending (the first read).
    pub fn new() -> Trigger {
        Trigger {
            pending: Mutex::new(Pending {
                noticed: Some(Instant::now()),
                cancel: Arc::new(AtomicBool::new(false)),
            }),
            wake: Condvar::new(),
        }
    }

    /// A save was noticed: the running render stops, the worker wakes.
    pub fn fire(&self) {
        let mut p = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        p.noticed.get_or_insert_with(Instant::now);
        p.cancel.store(true, Ordering::Relaxed);
        self.wake.notify_all();
    }

    /// Waits for a save; returns when it was noticed and the flag of the
    /// render it starts.
    fn next(&self) -> (Instant, Arc<AtomicBool>) {
        let mut p = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if let Some(at) = p.noticed.take() {
                p.cancel = Arc::new(AtomicBool::new(false));
                return (at, p.cancel.clone());
            }
            p = self.wake.wait(p).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// What the worker needs besides the shared state.
pub(crate) struct Config {
    /// The lineage to read the file as (`None`: by its markers).
    pub dialect: Option<Dialect>,
    /// Their picture, 8-bit RGB, and its size (`--compare`).
    pub theirs: Option<(Vec<u8>, (u32, u32))>,
}

/// Polls the files of `watch` for ever, firing `trigger` on a change.
pub(crate) fn watch_loop(watch: &Mutex<FileWatch>, trigger: &Trigger) {
    loop {
        std::thread::sleep(POLL);
        let changed = watch.lock().unwrap_or_else(|e| e.into_inner()).changed();
        if changed {
            trigger.fire();
        }
    }
}

/// Renders every save for ever.
pub(crate) fn work_loop(shared: &Shared, config: &Config, watch: &Mutex<FileWatch>, trigger: &Trigger) {
    let mut version = 0;
    loop {
        let (noticed, cancel) = trigger.next();
        version += 1;
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            render_version(shared, config, watch, version, noticed, &cancel)
        }));
        if run.is_err() {
            // A bug, not the user's: say so on the page, keep serving.
            shared.update(|s| {
                s.phase = Phase::Broken;
                s.diagnostics = vec![internal_error(&shared.scene)];
            });
        }
    }
}

/// A diagnostic for a render that panicked.
fn internal_error(scene: &Path) -> Diagnostic {
    file_error(
        scene,
        "glint failed while rendering this version (a bug in glint: please report it); \
         the last good picture stays"
            .to_string(),
    )
}

/// Rays the coarse preview may take, by [`Renderer::estimate`]: about
/// 50 ms on two cores, so that it comes at once.
const COARSE_RAYS: u64 = 1_000_000;

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

/// The passes offered for a scene with `lights` lights.
fn pass_list(lights: usize) -> Vec<Aov> {
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
    list.extend((0..lights.min(MAX_LIGHT_PASSES) as u32).map(Aov::Light));
    list
}

/// Milliseconds since `t`.
fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Reads and renders one version; returns early when `cancel` is set.
fn render_version(
    shared: &Shared,
    config: &Config,
    watch: &Mutex<FileWatch>,
    version: u64,
    noticed: Instant,
    cancel: &AtomicBool,
) {
    shared.update(|s| {
        s.version = version;
        s.phase = Phase::Reading;
        s.timings.clear();
    });
    for p in &shared.progress {
        p.store(0, Ordering::Relaxed);
    }
    // Stamped before reading: a save while the file is read is not missed.
    let mut next = FileWatch::default();
    next.add(&shared.scene);
    let scene = match Scene::from_file_as(&shared.scene, config.dialect) {
        Ok(scene) => scene,
        Err(e) => {
            // Watch what the last good version read too, and the folder (a
            // missing texture may appear there).
            let old: Vec<PathBuf> = watch
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .paths()
                .map(Path::to_path_buf)
                .collect();
            for p in &old {
                next.add(p);
            }
            if let Some(dir) = shared.scene.parent() {
                next.add(if dir.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    dir
                });
            }
            *watch.lock().unwrap_or_else(|e| e.into_inner()) = next;
            shared.update(|s| {
                s.phase = Phase::Broken;
                s.diagnostics = e.diagnostics;
                s.timings.push(("read", ms(noticed)));
            });
            return;
        }
    };
    for f in scene.files() {
        next.add(f);
    }
    *watch.lock().unwrap_or_else(|e| e.into_inner()) = next;
    let mut files = vec![shared.scene.clone()];
    files.extend(scene.files().iter().cloned());
    let warnings = scene.warnings().to_vec();
    let lights = scene.lights().len();
    let renderer = Arc::new(Renderer::new(scene));
    let size = renderer.frame_size(&shared.options).ok();
    shared.update(|s| {
        s.phase = Phase::Coarse;
        s.diagnostics = warnings;
        s.files = files;
        s.timings.push(("read", ms(noticed)));
    });
    if cancel.load(Ordering::Relaxed) {
        return;
    }

    let last = Mutex::new(Instant::now());
    let progress = |done: u64, total: u64| {
        shared.progress[0].store(done, Ordering::Relaxed);
        shared.progress[1].store(total, Ordering::Relaxed);
        if let Ok(mut at) = last.try_lock()
            && at.elapsed() >= PROGRESS_EVERY
        {
            *at = Instant::now();
            let data = serde_json::json!({"version": version, "done": done, "total": total});
            shared.events.send("progress", &data.to_string());
        }
    };
    let control = Control {
        progress: Some(&progress),
        cancel: Some(cancel),
        ..Control::default()
    };
    let options = RenderOptions {
        aovs: vec![Aov::Primitive],
        region: None,
        ..shared.options.clone()
    };
    let publish = |stage: Stage, film: &crate::Film| {
        let (name, next) = match stage {
            Stage::Coarse => ("coarse", Phase::Final),
            Stage::Final => ("final", Phase::Passes),
        };
        let id = shared.next_picture_id();
        let full = size.unwrap_or(film.frame_size());
        let Ok(picture) = Picture::new(id, version, name, full, film, &renderer) else {
            return;
        };
        let picture = Arc::new(picture);
        let summary = picture.summary().to_string();
        shared.update(|s| {
            if stage == Stage::Coarse {
                s.passes.clear();
                s.compare = None;
            }
            s.picture = Some(picture);
            s.renderer = Some(renderer.clone());
            s.good_version = Some(version);
            s.size = size;
            s.phase = next;
            s.timings.push((name, ms(noticed)));
        });
        shared.events.send("frame", &summary);
    };
    let quiet = Control {
        progress: None,
        ..control
    };
    let coarse = coarse_options(&renderer, &options);
    let rendered = coarse
        .map_or(Ok(()), |c| {
            renderer
                .render_with(&c, quiet)
                .map(|(film, _)| publish(Stage::Coarse, &film))
        })
        .and_then(|()| renderer.render_with(&options, control))
        .map(|(film, _)| publish(Stage::Final, &film));
    match rendered {
        Ok(()) => {}
        Err(RenderError::Cancelled) => return,
        Err(e) => {
            shared.update(|s| {
                s.phase = Phase::Broken;
                s.diagnostics.push(render_error(&shared.scene, &e));
            });
            return;
        }
    }

    // The passes: a render of their own, so that the picture came first;
    // they are all of the centre ray, so its colour is rendered at one ray
    // a pixel (which is why `rays`, the render's count, is not offered).
    let pass_options = RenderOptions {
        aovs: pass_list(lights),
        spp: Some(1),
        ..options.clone()
    };
    let Some(film) = passes_film(&renderer, &pass_options, size, control) else {
        return;
    };
    let hit = crate::pass_files::hit_mask(&film);
    let table = renderer.primitive_table();
    let file = renderer.scene_file();
    let passes: Vec<(String, Arc<Vec<u8>>)> = film
        .planes()
        .iter()
        .filter_map(|p| {
            let (rgb, _) = crate::pass_files::pass_image(p, &hit, &table, file.as_deref());
            let (w, h) = (film.image().width(), film.image().height());
            let png = crate::output::encode_rgb8(w, h, rgb, Format::Png).ok()?;
            Some((p.name.clone(), Arc::new(png)))
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        return;
    }
    let has_compare = config.theirs.is_some();
    shared.update(|s| {
        s.passes = passes;
        s.phase = if has_compare {
            Phase::Compare
        } else {
            Phase::Idle
        };
        s.timings.push(("passes", ms(noticed)));
    });

    if let Some((theirs, size)) = &config.theirs {
        let compared =
            match crate::compare(&renderer, theirs, *size, crate::DEFAULT_THRESHOLD, &options) {
                Ok(c) => Compared {
                    summary: c.to_json(),
                    heat: Arc::new(c.heat.encode(Format::Png).unwrap_or_default()),
                },
                Err(e) => Compared {
                    summary: serde_json::json!({"error": e.to_string()}),
                    heat: Arc::new(Vec::new()),
                },
            };
        if cancel.load(Ordering::Relaxed) {
            return;
        }
        shared.update(|s| {
            s.compare = Some(compared);
            s.phase = Phase::Idle;
            s.timings.push(("compare", ms(noticed)));
        });
    }
}

/// Bands the passes are rendered in: the passes' planes are made without
/// a look at the cancel flag, so a save waits for one band at most.
const PASS_BANDS: u32 = 64;

/// The passes of the whole frame (of `size`), rendered band by band,
/// stitched into one film (whose colour is left black: only the planes are
/// used); `None` when cancelled or when the size is out of range.
fn passes_film(
    renderer: &Renderer,
    options: &RenderOptions,
    size: Option<(u32, u32)>,
    control: Control<'_>,
) -> Option<crate::Film> {
    let (w, h) = size?;
    let band = h.div_ceil(PASS_BANDS).max(1);
    let mut planes: Vec<(String, usize, Vec<f32>)> = Vec::new();
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
        for p in film.planes() {
            match planes.iter_mut().find(|(n, _, _)| *n == p.name) {
                Some((_, _, data)) => data.extend_from_slice(&p.data),
                None => planes.push((p.name.clone(), p.channels, p.data.clone())),
            }
        }
        y += rows;
    }
    let black = crate::Image::from_pixels(w, h, vec![[0.0; 3]; w as usize * h as usize]);
    let mut film = crate::Film::new((w, h), crate::Region::full(w, h), black);
    for (name, channels, data) in planes {
        film.set_plane(&name, channels, data);
    }
    Some(film)
}

/// A render that could not start (a size out of range), as a diagnostic.
fn render_error(scene: &Path, e: &RenderError) -> Diagnostic {
    file_error(scene, format!("cannot render: {e}"))
}

/// An error about the scene file as a whole (no line), saying `message`.
fn file_error(scene: &Path, message: String) -> Diagnostic {
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
