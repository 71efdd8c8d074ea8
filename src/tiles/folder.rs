//! A folder of parts: which are done, missing, corrupt or of another
//! render, and the film they make together once all are there.

use super::file::{ReadError, TileFile};
use super::fingerprint::Fingerprint;
use super::indices::index_list;
use crate::image::Image;
use crate::job::quote;
use crate::output::{PrimitiveTable, primitive_colour};
use crate::render::{AssembleError, Film, Region, Tile};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a folder holds of one part.
#[derive(Clone, Debug, PartialEq)]
pub enum TileState {
    /// Its file is there, whole, of the same render as the others.
    Done,
    /// No file.
    Missing,
    /// A file that cannot be read as a tile (cut short, changed, another
    /// program's, a newer glint's), and why.
    Corrupt(String),
    /// A whole tile of another render, and what differs.
    Foreign(String),
}

/// The parts of one render in a folder.
pub struct Folder {
    /// The folder.
    pub dir: PathBuf,
    /// Parts the render was cut into.
    pub count: u32,
    /// Each part's state, by index.
    pub states: Vec<TileState>,
    /// Files of a render cut into another number of parts: name and count.
    pub others: Vec<(String, u32)>,
    /// The parts that are done, by index.
    tiles: BTreeMap<u32, TileFile>,
}

/// Why a folder cannot be read as parts of a render.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    /// The folder cannot be listed.
    #[error("{dir}: {message}")]
    Io {
        /// The folder.
        dir: String,
        /// Why.
        message: String,
    },
    /// No file named `tile-I-of-N.glt` in it.
    #[error("{dir}: no tile files (tile-I-of-N.glt) in this folder")]
    Empty {
        /// The folder.
        dir: String,
    },
}

/// Why the parts do not make a picture: each part that is not done.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// Parts missing, corrupt or foreign: (index, state).
    #[error("{} of {count} tiles are not done", missing.len())]
    Incomplete {
        /// Parts in all.
        count: u32,
        /// Those not done, and why.
        missing: Vec<(u32, TileState)>,
    },
    /// The tiles, all done, do not cover the picture once (they hold other bands than their parts').
    #[error("the tiles do not make the picture: {0}")]
    Assemble(#[from] AssembleError),
}

/// What the parts make together.
pub struct Merged {
    /// The film of one render.
    pub film: Film,
    /// The scene's file name as the render was given it.
    pub scene_file: Option<String>,
    /// The kind and line of each primitive the `primitive` AOV shows.
    pub table: PrimitiveTable,
    /// The command line that rendered part 0.
    pub command: Vec<String>,
}

impl Folder {
    /// Reads every `tile-I-of-N.glt` of `dir`: the count most of them
    /// share, and each part's state against the fingerprint most share.
    pub fn read(dir: &Path) -> Result<Folder, FolderError> {
        let io = |e: std::io::Error| FolderError::Io {
            dir: dir.display().to_string(),
            message: e.to_string(),
        };
        let mut named: Vec<(Tile, PathBuf)> = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(io)? {
            let entry = entry.map_err(io)?;
            let name = entry.file_name();
            if let Some(tile) = name.to_str().and_then(TileFile::parse_name) {
                named.push((tile, entry.path()));
            }
        }
        // The count: the one most files have (ties: the smallest).
        let mut counts: BTreeMap<u32, usize> = BTreeMap::new();
        named
            .iter()
            .for_each(|(t, _)| *counts.entry(t.count).or_default() += 1);
        let Some(count) = counts
            .iter()
            .max_by_key(|&(n, files)| (*files, std::cmp::Reverse(*n)))
            .map(|(n, _)| *n)
        else {
            return Err(FolderError::Empty {
                dir: dir.display().to_string(),
            });
        };
        let mut others = Vec::new();
        let mut read: BTreeMap<u32, Result<TileFile, ReadError>> = BTreeMap::new();
        for (tile, path) in named {
            if tile.count == count {
                read.insert(tile.index, TileFile::read(&path));
            } else {
                others.push((TileFile::name(tile), tile.count));
            }
        }
        others.sort();
        // The fingerprint most whole files share (ties: the lowest index's).
        let mut shared: Vec<(&Fingerprint, usize)> = Vec::new();
        for file in read.values().flatten() {
            match shared.iter_mut().find(|(f, _)| **f == file.fingerprint) {
                Some((_, n)) => *n += 1,
                None => shared.push((&file.fingerprint, 1)),
            }
        }
        let reference = shared
            .iter()
            .rev()
            .max_by_key(|(_, n)| *n)
            .map(|(f, _)| (*f).clone());
        let mut states = vec![TileState::Missing; count as usize];
        let mut tiles = BTreeMap::new();
        for (index, file) in read {
            let state = match file {
                Err(e) => TileState::Corrupt(e.to_string()),
                Ok(file) => match check(&file, index, count, reference.as_ref()) {
                    Some(state) => state,
                    None => {
                        tiles.insert(index, file);
                        TileState::Done
                    }
                },
            };
            states[index as usize] = state;
        }
        Ok(Folder {
            dir: dir.to_path_buf(),
            count,
            states,
            others,
            tiles,
        })
    }

    /// The indices of the parts that are not done, ascending.
    pub fn not_done(&self) -> Vec<u32> {
        (0..self.count)
            .filter(|&i| self.states[i as usize] != TileState::Done)
            .collect()
    }

    /// The bash command that renders the parts `redo` again: the array job
    /// `glint job slurm` wrote into the folder (`sbatch --array=2,7
    /// DIR/render.sbatch`), else a loop over the command of a part that is
    /// done, its `--tile` made the loop's.
    pub fn rerun(&self, redo: &[u32]) -> String {
        let list = index_list(redo);
        let script = self.dir.join("render.sbatch");
        if script.is_file() {
            return format!("sbatch --array={list} {}", quote(&script.to_string_lossy()));
        }
        let n = self.count;
        let Some(command) = self.tiles.values().next().map(|t| &t.command) else {
            let dir = quote(&self.dir.to_string_lossy()).into_owned();
            return format!(
                "glint render SCENE --tile I/{n} --tiles-dir {dir} [the same options] for I in {list}"
            );
        };
        let words: Vec<String> = command
            .iter()
            .enumerate()
            .map(|(k, w)| {
                if k > 0 && command[k - 1] == "--tile" {
                    format!("\"$i/{n}\"")
                } else if w.starts_with("--tile=") {
                    format!("--tile=\"$i/{n}\"")
                } else {
                    quote(w).into_owned()
                }
            })
            .collect();
        let each = redo
            .iter()
            .map(u32::to_string)
            .collect::<Vec<_>>()
            .join(" ");
        format!("for i in {each}; do {}; done", words.join(" "))
    }

    /// The film the parts make, when every one is done.
    pub fn merge(self) -> Result<Merged, MergeError> {
        let missing: Vec<(u32, TileState)> = self
            .states
            .iter()
            .enumerate()
            .filter(|(_, s)| **s != TileState::Done)
            .map(|(i, s)| (i as u32, s.clone()))
            .collect();
        let first = self.tiles.values().next();
        let (Some(first), true) = (first, missing.is_empty()) else {
            return Err(MergeError::Incomplete {
                count: self.count,
                missing,
            });
        };
        let (frame, region) = (first.frame, region_of(first));
        let (scene_file, command) = (first.scene_file.clone(), first.command.clone());
        let mut table = PrimitiveTable::new();
        let mut films = Vec::new();
        for tile in self.tiles.into_values() {
            table.extend(tile.primitive_table());
            films.extend(tile.films);
        }
        let film = Film::assemble(frame, region, films)?;
        Ok(Merged {
            film,
            scene_file,
            table,
            command,
        })
    }
}

/// The region a tile's render covers: its fingerprint's, or the frame.
fn region_of(tile: &TileFile) -> Region {
    let r = &tile.fingerprint.to_json()["region"];
    let n: Option<Vec<u32>> = r.as_array().map(|a| {
        a.iter()
            .filter_map(|v| v.as_u64().and_then(|v| u32::try_from(v).ok()))
            .collect()
    });
    match n.as_deref() {
        Some(&[x, y, width, height]) => Region {
            x,
            y,
            width,
            height,
        },
        _ => Region::full(tile.frame.0, tile.frame.1),
    }
}

/// Why a whole tile file named part `index` of `count` is not that part of
/// the render `reference` fingerprints (`None`: it is).
fn check(
    file: &TileFile,
    index: u32,
    count: u32,
    reference: Option<&Fingerprint>,
) -> Option<TileState> {
    if file.tile != (Tile { index, count }) {
        return Some(TileState::Foreign(format!(
            "it holds part {}, not {index}/{count}",
            file.tile
        )));
    }
    if let Some(reference) = reference
        && file.fingerprint != *reference
    {
        let diff = file.fingerprint.differences(reference);
        return Some(TileState::Foreign(format!(
            "another render's: {}",
            diff.join("; ")
        )));
    }
    let fp = file.fingerprint.to_json();
    let size = (fp["width"].as_u64(), fp["height"].as_u64());
    if size != (Some(u64::from(file.frame.0)), Some(u64::from(file.frame.1))) {
        return Some(TileState::Corrupt(
            "its frame is not its fingerprint's".into(),
        ));
    }
    let runs: Vec<Region> = file.films.iter().map(Film::region).collect();
    if runs != file.tile.runs(region_of(file)) {
        return Some(TileState::Corrupt(format!(
            "its bands are not those of part {}",
            file.tile
        )));
    }
    None
}

impl Folder {
    /// Which part rendered which band: the rendered pixels (clamped to
    /// 0–1) half and half with their part's false colour (that of
    /// primitive index I), the bands of parts not done black; `None` when
    /// no part is done (nothing tells the picture's size).
    pub fn picture(&self) -> Option<Image> {
        let first = self.tiles.values().next()?;
        let region = region_of(first);
        let mut pixels = vec![[0f32; 3]; region.area() as usize];
        for (index, tile) in &self.tiles {
            let [r, g, b] = primitive_colour(*index as f32).map(|c| f32::from(c) / 255.0);
            for film in &tile.films {
                let f = film.region();
                for (k, p) in film.image().pixels().iter().enumerate() {
                    let (x, y) = (f.x + k as u32 % f.width, f.y + k as u32 / f.width);
                    let at = ((y - region.y) * region.width + (x - region.x)) as usize;
                    let c = p.map(|v| v.clamp(0.0, 1.0) * 0.5);
                    pixels[at] = [c[0] + r * 0.5, c[1] + g * 0.5, c[2] + b * 0.5];
                }
            }
        }
        Some(Image::from_pixels(region.width, region.height, pixels))
    }
}
