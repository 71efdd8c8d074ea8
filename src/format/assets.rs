//! Files a scene names: textures and meshes, looked up next to the scene
//! file first, then in the working directory, and loaded once each.

use super::diags::{Diags, Site};
use super::limits::{Limits, not_regular, open_regular, read_bounded};
use super::obj::{LoadedObj, Placement, load_placed};
use crate::scene::Texture;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Where the files a scene names are looked up, the textures loaded so
/// far, and the notes about where files were found.
pub(crate) struct Assets<'p> {
    base: &'p Path,
    /// Whether names are looked up on the file system at all (see
    /// [`Assets::find_nothing`]).
    look: bool,
    /// Texture index by resolved path, so each file is decoded once.
    by_path: HashMap<PathBuf, u32>,
    /// Where each file was found, for verbose output.
    pub notes: Vec<String>,
    /// Every file found (textures, meshes, their MTL files), in the order read.
    pub files: Vec<PathBuf>,
}

/// Why a file named in a scene cannot be used.
enum Unusable {
    /// Nothing there: the places tried.
    NotFound(Vec<PathBuf>),
    /// Something that is not a regular file (a directory, a FIFO): where, and what.
    NotRegular(PathBuf, &'static str),
}

impl<'p> Assets<'p> {
    /// Assets of a scene whose relative paths are looked up in `base` first.
    pub fn new(base: &'p Path) -> Self {
        Assets {
            base,
            look: true,
            by_path: HashMap::new(),
            notes: Vec::new(),
            files: Vec::new(),
        }
    }

    /// Assets that find no file, touching no file system: every name is
    /// reported not found, with the places it would have been looked for.
    /// For the scene reader's fuzz target, whose run must not depend on the
    /// working directory: a name the fuzzer bends into one of the
    /// repository's meshes (`../../shared/...` less a `../`) had it decode
    /// megabytes of OBJ at each execution.
    pub fn find_nothing(base: &'p Path) -> Self {
        Assets {
            look: false,
            ..Assets::new(base)
        }
    }

    /// Finds a file named in the scene: next to the scene file first, then
    /// in the working directory (and, for names written with Windows
    /// separators, the same with `/`). Returns the path and where it was
    /// found, or why not (the places tried, or a path that is not a file).
    fn resolve(&self, name: &str) -> Result<(PathBuf, &'static str), Unusable> {
        self.resolve_from(name, false)
    }

    /// [`Assets::resolve`], then, with `below` and a name that starts with
    /// `../`, the name as a program run one folder below the scene's would
    /// open it (the colon family's `build.sh` runs its program in `build/`,
    /// and its files name `../picture/…`).
    fn resolve_from(&self, name: &str, below: bool) -> Result<(PathBuf, &'static str), Unusable> {
        let mut tried: Vec<PathBuf> = Vec::new();
        let slashed = name.replace('\\', "/");
        let names: &[&str] = if slashed != name {
            &[name, &slashed]
        } else {
            &[name]
        };
        for &n in names {
            let p = Path::new(n);
            let up = p.strip_prefix("..").ok().filter(|_| below);
            let candidates = if p.is_absolute() {
                [
                    (p.to_path_buf(), "as an absolute path"),
                    (p.to_path_buf(), ""),
                    (p.to_path_buf(), ""),
                ]
            } else {
                [
                    (self.base.join(p), "in the scene file's folder"),
                    (p.to_path_buf(), "in the working directory"),
                    match up {
                        Some(rest) => (
                            self.base.join(rest),
                            "as its program, run one folder below the scene's, opens it",
                        ),
                        None => (p.to_path_buf(), ""),
                    },
                ]
            };
            for (path, found) in candidates {
                if found.is_empty() || tried.contains(&path) {
                    continue;
                }
                if let Some(meta) = self.look.then(|| std::fs::metadata(&path).ok()).flatten() {
                    return match not_regular(&meta) {
                        None => Ok((path, found)),
                        Some(why) => Err(Unusable::NotRegular(path, why)),
                    };
                }
                tried.push(path);
            }
        }
        Err(Unusable::NotFound(tried))
    }

    /// Reports a file that was not found or is not a regular file.
    fn unusable(what: &str, name: &str, why: &Unusable, site: Site, diags: &mut Diags) {
        let tried = match why {
            Unusable::NotRegular(path, why) => {
                let message = format!("{what} file `{name}` ({}) {why}", path.display());
                return diags.error(site, message, None);
            }
            Unusable::NotFound(tried) => tried,
        };
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

    /// The index of texture `name` (named at `site`): decoded on first use
    /// and handed to `add`, which gives its index.
    pub fn texture(
        &mut self,
        name: &str,
        site: Site,
        diags: &mut Diags,
        add: &mut dyn FnMut(Texture) -> u32,
    ) -> Option<u32> {
        self.texture_from(name, site, diags, add, false)
    }

    /// [`Assets::texture`] for the colon family, whose program opens names
    /// from one folder below the scene's when they are not next to it (see
    /// [`Assets::resolve_from`]).
    pub fn texture_run_below(
        &mut self,
        name: &str,
        site: Site,
        diags: &mut Diags,
        add: &mut dyn FnMut(Texture) -> u32,
    ) -> Option<u32> {
        self.texture_from(name, site, diags, add, true)
    }

    /// A texture, looked up as [`Assets::resolve_from`] with `below`.
    fn texture_from(
        &mut self,
        name: &str,
        site: Site,
        diags: &mut Diags,
        add: &mut dyn FnMut(Texture) -> u32,
        below: bool,
    ) -> Option<u32> {
        let (path, found) = match self.resolve_from(name, below) {
            Ok(p) => p,
            Err(why) => {
                Self::unusable("texture", name, &why, site, diags);
                return None;
            }
        };
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if !self.files.contains(&path) {
            self.files.push(path.clone());
        }
        if let Some(&i) = self.by_path.get(&key) {
            return Some(i);
        }
        match decode_texture(&path) {
            Ok(t) => {
                let i = add(t);
                self.by_path.insert(key, i);
                self.notes.push(format!(
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

    /// Describes why a file named in the scene cannot be used, for errors
    /// that are not reported at once (an MTL file an OBJ file names).
    fn unusable_text(what: &str, name: &str, why: &Unusable) -> String {
        match why {
            Unusable::NotRegular(path, why) => {
                format!("{what} file `{name}` ({}) {why}", path.display())
            }
            Unusable::NotFound(tried) => {
                let tried = tried
                    .iter()
                    .map(|p| format!("`{}`", p.display()))
                    .collect::<Vec<_>>()
                    .join(" and ");
                format!("{what} file `{name}` not found (looked for {tried})")
            }
        }
    }

    /// The triangles of mesh file `name` (named at `site`), placed by `at`;
    /// with `at.lineage`, also its texture coordinates and the materials of
    /// the MTL files it names (looked up like the mesh itself).
    pub fn mesh(
        &mut self,
        name: &str,
        site: Site,
        at: &Placement,
        diags: &mut Diags,
    ) -> Option<LoadedObj> {
        let (path, found) = match self.resolve(name) {
            Ok(p) => p,
            Err(why) => {
                Self::unusable("mesh", name, &why, site, diags);
                return None;
            }
        };
        if !self.files.contains(&path) {
            self.files.push(path.clone());
        }
        let mtl_files = std::cell::RefCell::new(Vec::new());
        let read_mtl = |file: &str| -> Result<Vec<u8>, String> {
            let (p, _) = self
                .resolve(file)
                .map_err(|why| Self::unusable_text("material", file, &why))?;
            mtl_files.borrow_mut().push(p.clone());
            let f = open_regular(&p).map_err(|e| format!("cannot open `{}`: {e}", p.display()))?;
            read_bounded(f, Limits::DEFAULT)
                .map_err(|e| format!("cannot read `{}`: {e}", p.display()))
        };
        let loaded = load_placed(&path, at, Some(&read_mtl));
        for p in mtl_files.into_inner() {
            if !self.files.contains(&p) {
                self.files.push(p);
            }
        }
        match loaded {
            Ok(loaded) => {
                self.notes.push(format!(
                    "line {}: mesh `{name}` found {found}: {} ({} triangles)",
                    site.line + 1,
                    path.display(),
                    loaded.triangles.len()
                ));
                Some(loaded)
            }
            Err(e) => {
                diags.error(
                    site,
                    format!("cannot load mesh `{name}` ({}): {e}", path.display()),
                    None,
                );
                None
            }
        }
    }
}

/// Decodes an image file (BMP 24/32-bit, PNG, JPEG) into a texture.
pub(crate) fn decode_texture(path: &Path) -> Result<Texture, String> {
    texture_from(image::open(path).map_err(|e| e.to_string())?)
}

/// Decodes an image file's bytes (its format guessed from them) into a texture.
#[cfg(feature = "fuzzing")]
pub(crate) fn decode_texture_bytes(bytes: &[u8]) -> Result<Texture, String> {
    texture_from(image::load_from_memory(bytes).map_err(|e| e.to_string())?)
}

/// A decoded image as a texture, rows from the bottom as the framework has them.
fn texture_from(img: image::DynamicImage) -> Result<Texture, String> {
    let img = img.into_rgb8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    if w == 0 || h == 0 {
        return Err("the image is empty".to_string());
    }
    // image stores rows top-down; the framework's row 0 is the bottom.
    let mut texels = Vec::with_capacity(w * h);
    for row in img.as_raw().chunks_exact(3 * w).rev() {
        texels.extend(row.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
    }
    Ok(Texture::from_rows(w, h, texels))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    #[test]
    fn bmp_rows_are_bottom_up() -> Result<(), Box<dyn std::error::Error>> {
        let tmp = tempfile::Builder::new().prefix("glint-tex-").tempdir()?;
        let dir = tmp.path();
        let path = dir.join("t.bmp");
        // Top row red, bottom row blue, as a person sees the picture.
        let img = image::RgbImage::from_fn(1, 2, |_, y| {
            if y == 0 {
                image::Rgb([255, 0, 0])
            } else {
                image::Rgb([0, 0, 255])
            }
        });
        img.save(&path)?;
        let t = decode_texture(&path)?;
        assert_eq!(t.sample(DVec2::new(0.0, 0.0)), DVec3::Z);
        assert_eq!(t.sample(DVec2::new(0.5, 0.0)), DVec3::X);
        Ok(())
    }
}
