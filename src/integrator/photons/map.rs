//! The photon map of PM: one pass's photons in a k-d tree (`kiddo`), and
//! the K-nearest estimate at a diffuse hit (`photon-mapping.md`, The estimate).

use super::plan::PhotonFilter;
use super::trace::Photon;
use super::units::MIN_GATHERED;
use glam::{DVec3, Vec3};
use kiddo::{ImmutableKdTree, NearestNeighbour, SquaredEuclidean};
use std::f64::consts::PI;
use std::num::NonZero;

/// How a gathered photon is weighted by its direction at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Brdf {
    /// `diff=`.
    pub diff: f64,
    /// `spec=` where the lineage gathers with its specular lobe, else 0.
    pub spec: f64,
    /// The eye ray's mirror direction R_I.
    pub mirror: DVec3,
}

impl Brdf {
    /// The weight of a photon that arrived travelling along `d`:
    /// diff + spec·max(0, R_I·(−d))^50.
    #[inline]
    pub fn weight(&self, d: DVec3) -> f64 {
        let r = -self.mirror.dot(d);
        if self.spec > 0.0 && r > 0.0 {
            self.diff + self.spec * r.powi(50)
        } else {
            self.diff
        }
    }
}

/// One estimate: what was gathered and over which radius.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Gathered {
    /// Σ weight·Φ / (π r²) (0 with fewer than 8 photons).
    pub value: DVec3,
    /// Photons gathered.
    pub count: usize,
    /// r²: the K-th nearest distance², or R² when fewer were found.
    pub r2: f64,
}

/// One pass's photons, ready for K-nearest queries.
pub(crate) struct PhotonMap {
    photons: Vec<Photon>,
    /// The photons' directions, apart: what the side test reads.
    dirs: Vec<Vec3>,
    tree: Option<ImmutableKdTree<f64, 3>>,
    k: usize,
    r2: f64,
    filter: PhotonFilter,
}

impl PhotonMap {
    /// The map of `photons`, gathering `k` within radius `radius`.
    pub fn new(photons: Vec<Photon>, k: usize, radius: f64, filter: PhotonFilter) -> Self {
        let points: Vec<[f64; 3]> = photons.iter().map(|p| p.pos.to_array()).collect();
        let tree = (!points.is_empty()).then(|| ImmutableKdTree::new_from_slice(&points));
        let dirs = photons.iter().map(|p| p.dir.as_vec3()).collect();
        PhotonMap {
            photons,
            dirs,
            tree,
            k: k.max(1),
            r2: radius * radius,
            filter,
        }
    }

    /// The K nearest photons within R of `x` that arrived on the side `side`
    /// faces (d·side < 0), nearest first (ties by photon index), and r²:
    /// the K-th one's distance², or R² when R holds fewer. Where photons
    /// from behind crowd the front ones out of the nearest 4K, the front
    /// ones among those 4K are kept and r² is the farthest of the 4K (every
    /// photon that near was looked at, so the density stays exact).
    pub fn nearest(&self, x: DVec3, side: DVec3) -> (Vec<(f64, u32)>, f64) {
        let Some(tree) = &self.tree else {
            return (Vec::new(), self.r2);
        };
        let q = x.to_array();
        let side_f32 = side.as_vec3();
        let mut ask = self.k;
        loop {
            let n = NonZero::new(ask).unwrap_or(NonZero::<usize>::MIN);
            // The nearest `ask` within R (the search narrows as it fills).
            let mut found: Vec<NearestNeighbour<f64, u64>> =
                tree.nearest_n_within::<SquaredEuclidean>(&q, self.r2, n, true);
            found.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.item.cmp(&b.item)));
            let farthest = found.last().map_or(0.0, |f| f.distance);
            // Every photon within R has been looked at.
            let exhausted = found.len() < ask;
            let mut kept: Vec<(f64, u32)> = found
                .iter()
                .filter(|f| self.dirs[f.item as usize].dot(side_f32) < 0.0)
                .map(|f| (f.distance, f.item as u32))
                .collect();
            if kept.len() >= self.k {
                kept.truncate(self.k);
                let r2 = kept[self.k - 1].0.max(f64::MIN_POSITIVE);
                return (kept, r2);
            }
            if exhausted {
                return (kept, self.r2);
            }
            if ask >= 4 * self.k {
                return (kept, farthest.max(f64::MIN_POSITIVE));
            }
            ask *= 2;
        }
    }

    /// The estimate at `x` (facing `side`) with the hit's `brdf`.
    pub fn estimate(&self, x: DVec3, side: DVec3, brdf: &Brdf) -> Gathered {
        let (near, r2) = self.nearest(x, side);
        if near.len() < MIN_GATHERED {
            return Gathered {
                value: DVec3::ZERO,
                count: near.len(),
                r2,
            };
        }
        let r = r2.sqrt();
        let (mut sum, mut norm) = (DVec3::ZERO, 1.0);
        if self.filter == PhotonFilter::Cone {
            norm = 1.0 - 2.0 / (3.0 * 1.1);
        }
        for &(d2, i) in &near {
            let p = &self.photons[i as usize];
            let w = match self.filter {
                PhotonFilter::Box => 1.0,
                PhotonFilter::Cone => 1.0 - d2.sqrt() / (1.1 * r),
            };
            sum += p.power * (w * brdf.weight(p.dir));
        }
        Gathered {
            value: sum / (norm * PI * r2),
            count: near.len(),
            r2,
        }
    }
}
