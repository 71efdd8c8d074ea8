//! `glint render --tile I/N --tiles-dir DIR`: one part of a render into
//! its tile file, for `glint merge`, and the part's summary.

use crate::{Failure, check_interrupt, fail, render_failure};
use glint::tiles::{Fingerprint, FingerprintError, TileFile};
use glint::{Control, RenderOptions, RenderStats, Renderer, Tile};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// Refuses a tiles folder that is not a folder glint can write into.
pub fn check_folder(dir: &Path) -> Result<(), Failure> {
    let meta = std::fs::metadata(dir).map_err(|e| {
        fail(format!(
            "error: --tiles-dir {}: {e} (create the folder first)",
            dir.display()
        ))
    })?;
    if !meta.is_dir() {
        return Err(fail(format!(
            "error: --tiles-dir {}: not a folder",
            dir.display()
        )));
    }
    if meta.permissions().readonly() {
        return Err(fail(format!(
            "error: --tiles-dir {}: the folder cannot be written",
            dir.display()
        )));
    }
    Ok(())
}

/// One part of a render to write into a folder.
pub struct Part<'a> {
    pub renderer: &'a Renderer,
    pub options: &'a RenderOptions,
    pub tile: Tile,
    pub dir: &'a Path,
    /// Leave a valid tile of the same render alone.
    pub skip_existing: bool,
}

impl Part<'_> {
    /// Renders the part and writes its tile file: its path and the
    /// figures, or `None` when a valid tile of the same render was left alone.
    pub fn render(
        &self,
        progress: &(dyn Fn(u64, u64) + Sync),
        interrupt: &AtomicBool,
    ) -> Result<Option<(PathBuf, RenderStats)>, Failure> {
        let fingerprint = Fingerprint::of(self.renderer, self.options, self.tile.count)
            .map_err(|e| fail(format!("error: {e}")))?;
        let path = self.dir.join(TileFile::name(self.tile));
        if self.skip_existing
            && let Ok(old) = TileFile::read(&path)
            && old.tile == self.tile
            && old.fingerprint == fingerprint
        {
            crate::say(&format!(
                "{}: already rendered by the same render, left alone (--skip-existing)",
                path.display()
            ));
            return Ok(None);
        }
        let control = Control {
            progress: Some(progress),
            cancel: Some(interrupt),
            ..Control::default()
        };
        let rendered = TileFile::render(
            self.renderer,
            self.options,
            control,
            std::env::args().collect(),
        );
        check_interrupt(interrupt)?;
        let (file, stats) = rendered.map_err(|e| match e {
            FingerprintError::Render(e) => render_failure(e),
            e => fail(format!("error: {e}")),
        })?;
        let written = file.write(self.dir, interrupt);
        check_interrupt(interrupt)?;
        let path = written.map_err(|e| {
            fail(format!(
                "error: cannot write the tile {}: {e}",
                path.display()
            ))
        })?;
        Ok(Some((path, stats)))
    }
}

/// How long the part's process spent reading the scene, and in all.
pub struct Times {
    pub read: Duration,
    pub wall: Duration,
}

/// The part's summary line: its bands, what every part pays again
/// (reading the scene, the BVH, the photon map) and its render.
pub fn summary(
    path: &Path,
    tile: Tile,
    options: &RenderOptions,
    renderer: &Renderer,
    stats: &RenderStats,
    times: Times,
) -> String {
    let (bands, rows) = renderer.frame_size(options).map_or((0, 0), |(w, h)| {
        let region = options.region.unwrap_or(glint::Region::full(w, h));
        let rows = tile.runs(region).iter().map(|r| r.height).sum::<u32>();
        (tile.bands(region).count(), rows)
    });
    format!(
        "{}: part {tile}, {} bands ({rows} rows); each part pays: read {:.3} s, BVH {:.3} s, photons {:.3} s; render {:.3} s, {:.1} M rays, {:.1} Mrays/s; {:.3} s wall",
        path.display(),
        bands,
        times.read.as_secs_f64(),
        stats.build.as_secs_f64(),
        stats.photons.elapsed.as_secs_f64(),
        stats.elapsed.as_secs_f64(),
        stats.rays.total() as f64 / 1e6,
        stats.mrays_per_sec(),
        times.wall.as_secs_f64(),
    )
}
