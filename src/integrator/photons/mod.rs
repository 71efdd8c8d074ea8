//! Photon mapping (`photon-mapping.md`): photons traced from the lights
//! and stored on diffuse surfaces, then gathered at the eye's diffuse hits,
//! once (PM, through a flat k-d tree) or progressively over iterations (PPM and
//! SPPM, through a hashed grid of each pass's photons).

mod gather;
mod kdtree;
mod map;
mod plan;
mod points;
mod progressive;
mod thin;
mod trace;
mod units;

pub(crate) use gather::PhotonGrid;
pub(crate) use map::{Brdf, Gathered, PhotonMap};
pub(crate) use plan::{FirstRadius, PhotonBrdf, Plan, Term};
pub use plan::{PhotonFilter, PhotonMode, PhotonOptions};
pub(crate) use points::{HitPointObserver, HitPointSeed};
pub(crate) use progressive::{HitPoint, gather, update_hit_point};
pub(crate) use trace::{Photon, batch_emitted, shoot, stored_per_emitted};
pub(crate) use units::power;
