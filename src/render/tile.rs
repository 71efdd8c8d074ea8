//! Parts of a render for several machines: the rendered region cut into
//! full-width bands of [`TILE_BAND`] rows, band b dealt to part b mod N, so
//! each part holds cheap sky and costly glass alike.

use super::film::Region;

/// Rows of a band.
pub const TILE_BAND: u32 = 32;

/// Part `index` of `count` (`I/N`, as `sbatch --array=0-N−1` and
/// Kubernetes' completion index count).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Tile {
    /// Which part, from 0 to `count − 1`.
    pub index: u32,
    /// Parts in all.
    pub count: u32,
}

/// The most parts a render may be cut into.
pub const MAX_TILES: u32 = 1_000_000;

impl Tile {
    /// Part `index` of `count`, if `index < count ≤ MAX_TILES`.
    pub fn new(index: u32, count: u32) -> Option<Tile> {
        (index < count && count <= MAX_TILES).then_some(Tile { index, count })
    }

    /// The bands of a region `height` rows high.
    pub fn bands_of(height: u32) -> u32 {
        height.div_ceil(TILE_BAND)
    }

    /// Band `band` of `region`: its rows, full width.
    pub fn band(region: Region, band: u32) -> Region {
        let y = band * TILE_BAND;
        Region {
            x: region.x,
            y: region.y + y,
            width: region.width,
            height: TILE_BAND.min(region.height - y),
        }
    }

    /// The bands of `region` this part holds, top to bottom.
    pub fn bands(&self, region: Region) -> impl Iterator<Item = u32> + use<> {
        let step = self.count as usize;
        (self.index..Tile::bands_of(region.height)).step_by(step)
    }

    /// The rows of `region` this part holds, as runs of adjacent bands
    /// (each a region), top to bottom; none when it holds no band.
    pub fn runs(&self, region: Region) -> Vec<Region> {
        let mut runs: Vec<Region> = Vec::new();
        for b in self.bands(region) {
            let band = Tile::band(region, b);
            match runs.last_mut() {
                Some(run) if run.y + run.height == band.y => run.height += band.height,
                _ => runs.push(band),
            }
        }
        runs
    }
}

impl std::fmt::Display for Tile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for Tile {
    type Err = String;

    /// `I/N`: part I (0 to N − 1) of N.
    fn from_str(s: &str) -> Result<Tile, String> {
        let Some((i, n)) = s.split_once('/') else {
            return Err(format!(
                "expected `I/N` (part I of N, I from 0 to N-1), e.g. `--tile 0/4`; got `{s}`"
            ));
        };
        let number = |v: &str, what: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|e| format!("`{}` is not a {what}: {e}", v.trim()))
        };
        let (index, count) = (number(i, "part index")?, number(n, "count of parts")?);
        if count == 0 || count > MAX_TILES {
            return Err(format!(
                "the count of parts must be from 1 to {MAX_TILES} (got {count})"
            ));
        }
        Tile::new(index, count).ok_or_else(|| {
            format!(
                "part {index} of {count} does not exist: parts are numbered 0 to {}",
                count - 1
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_take_the_bands_round_robin_and_cover_each_row_once() {
        let region = Region {
            x: 3,
            y: 5,
            width: 10,
            height: 100,
        };
        // 100 rows: bands of 32, 32, 32 and 4 rows.
        assert_eq!(Tile::bands_of(100), 4);
        for count in 1..7 {
            let mut seen = vec![0u32; 100];
            for index in 0..count {
                let tile = Tile { index, count };
                for run in tile.runs(region) {
                    assert_eq!((run.x, run.width), (3, 10));
                    for y in run.y..run.y + run.height {
                        seen[(y - 5) as usize] += 1;
                        assert_eq!((y - 5) / 32 % count, index, "row {y} of part {tile}");
                    }
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{count} parts: {seen:?}");
        }
        // One part: a single run, the whole region.
        assert_eq!(Tile { index: 0, count: 1 }.runs(region), vec![region]);
        // More parts than bands: the extra parts are empty.
        assert!(Tile { index: 5, count: 6 }.runs(region).is_empty());
    }

    #[test]
    fn bad_parts_are_refused_with_what_to_write() {
        for bad in ["5/5", "0/0", "a/b", "3", "-1/4", "1/2000000", "/4"] {
            assert!(bad.parse::<Tile>().is_err(), "{bad}");
        }
        assert_eq!("2/5".parse::<Tile>(), Ok(Tile { index: 2, count: 5 }));
        assert_eq!(Tile { index: 2, count: 5 }.to_string(), "2/5");
    }
}
