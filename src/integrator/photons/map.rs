//! The photon map of PM: one pass's photons in a k-d tree, and the
//! K-nearest estimate at a diffuse hit (`photon-mapping.md`, The estimate).

use super::kdtree::{KdTree, Nearest};
use super::plan::{PhotonBrdf, PhotonFilter};
use super::trace::Photon;
use super::units::MIN_GATHERED;
use crate::scene::Material;
use glam::DVec3;
use std::cell::RefCell;
use std::f64::consts::PI;

/// How a gathered photon is weighted by its direction at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Brdf {
    /// `diff=`.
    pub diff: f64,
    /// `spec=` where the lineage gathers with its specular lobe, else 0.
    pub spec: f64,
    /// The eye ray's mirror direction R_I.
    pub mirror: DVec3,
    /// The unit normal facing the eye where diff is weighted by cos θ (the
    /// colon family's BRDF), else `None`.
    pub cosine: Option<DVec3>,
}

impl Brdf {
    /// The weighting `kind` gives material `m` at a hit whose eye ray's
    /// mirror direction is `mirror` and whose normal facing the eye is
    /// `side` (with the specular lobe where `specular`).
    pub fn of(kind: PhotonBrdf, specular: bool, m: &Material, mirror: DVec3, side: DVec3) -> Brdf {
        let spec = if specular { m.spec } else { 0.0 };
        match kind {
            PhotonBrdf::Lobe => Brdf {
                diff: m.diff,
                spec,
                mirror,
                cosine: None,
            },
            PhotonBrdf::Phong => Brdf {
                diff: m.diff * m.diff,
                spec: m.diff * spec,
                mirror,
                cosine: Some(side),
            },
        }
    }

    /// The weight of a photon that arrived travelling along `d`:
    /// diff + spec·max(0, R_I·(−d))^50, with diff·cos θ where `cosine` says.
    #[inline]
    pub fn weight(&self, d: DVec3) -> f64 {
        let diff = match self.cosine {
            Some(n) => self.diff * (-d.dot(n)).max(0.0),
            None => self.diff,
        };
        let r = -self.mirror.dot(d);
        if self.spec > 0.0 && r > 0.0 {
            diff + self.spec * r.powi(50)
        } else {
            diff
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
    /// The photons, in the tree's order.
    photons: Vec<Photon>,
    tree: KdTree,
    k: usize,
    r2: f64,
    filter: PhotonFilter,
}

thread_local! {
    /// Each thread's search buffer, reused by every estimate on that thread.
    static SCRATCH: RefCell<Nearest> = RefCell::new(Nearest::default());
}

impl PhotonMap {
    /// The map of `photons`, gathering `k` within radius `radius`.
    pub fn new(photons: Vec<Photon>, k: usize, radius: f64, filter: PhotonFilter) -> Self {
        let tree = KdTree::new(&photons);
        let photons = (0..photons.len() as u32)
            .map(|s| photons[tree.index(s) as usize])
            .collect();
        PhotonMap {
            photons,
            tree,
            k: k.max(1),
            r2: radius * radius,
            filter,
        }
    }

    /// Runs `f` on the search of `x`, `side` and its r², with this
    /// thread's scratch buffer (a fresh one if that is in use).
    fn search<R>(&self, x: DVec3, side: DVec3, f: impl FnOnce(&Nearest, f64) -> R) -> R {
        let run = |near: &mut Nearest| {
            self.tree.nearest(x, side, self.k, self.r2, near);
            let r2 = if near.full() {
                near.farthest().max(f64::MIN_POSITIVE)
            } else {
                self.r2
            };
            f(near, r2)
        };
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut near) => run(&mut near),
            Err(_) => run(&mut Nearest::default()),
        })
    }

    /// The K nearest photons within R of `x` that arrived on the side `side`
    /// faces (d·side < 0), as (d², photon index) nearest first (ties by
    /// photon index), and r²: the K-th one's d², or R² when R holds fewer.
    #[cfg(test)]
    pub fn nearest(&self, x: DVec3, side: DVec3) -> (Vec<(f64, u32)>, f64) {
        self.search(x, side, |near, r2| {
            let mut found: Vec<(f64, u32)> = near
                .found()
                .iter()
                .map(|f| (f.d2, self.tree.index(f.slot)))
                .collect();
            found.sort_unstable_by_key(|&(d2, index)| (d2.to_bits(), index));
            (found, r2)
        })
    }

    /// r² of [`Self::nearest`] at `x` facing `side`, without the list.
    pub fn radius2(&self, x: DVec3, side: DVec3) -> f64 {
        self.search(x, side, |_, r2| r2)
    }

    /// The estimate at `x` (facing `side`) with the hit's `brdf`.
    pub fn estimate(&self, x: DVec3, side: DVec3, brdf: &Brdf) -> Gathered {
        self.search(x, side, |near, r2| {
            let found = near.found();
            if found.len() < MIN_GATHERED {
                return Gathered {
                    value: DVec3::ZERO,
                    count: found.len(),
                    r2,
                };
            }
            let r = r2.sqrt();
            let (mut sum, mut norm) = (DVec3::ZERO, 1.0);
            if self.filter == PhotonFilter::Cone {
                norm = 1.0 - 2.0 / (3.0 * 1.1);
            }
            // In the buffer's order: fixed by the map and the query, not the threads.
            for f in found {
                let p = &self.photons[f.slot as usize];
                let w = match self.filter {
                    PhotonFilter::Box => 1.0,
                    PhotonFilter::Cone => 1.0 - f.d2.sqrt() / (1.1 * r),
                };
                sum += p.power * (w * brdf.weight(p.dir));
            }
            Gathered {
                value: sum / (norm * PI * r2),
                count: found.len(),
                r2,
            }
        })
    }
}
