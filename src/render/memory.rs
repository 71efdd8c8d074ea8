//! An upper bound of the memory a render takes on top of what the process
//! holds when it starts (the scene, its BVH, the program), for refusing a
//! render that cannot fit before any of it is spent.

use crate::integrator::photons::{
    HitPoint, HitPointSeed, MAX_PHOTON_HITS, Photon, PhotonMode, Plan,
};
use std::mem::size_of;

/// Bytes every render takes whatever its size: the program's code as it
/// runs (paged in as it is first run), the allocator's and the encoders'
/// first pages (measured: 1 to 2 MiB over what a 64×48 render held
/// before it started).
const BASE: u64 = 16 << 20;

/// Bytes each worker thread takes: its stack and allocator arena as far
/// as they are touched.
const THREAD: u64 = 1 << 20;

/// Bytes a pixel takes in every render: the film, the adaptive
/// anti-aliasing's hashes and the output's copies and encoder. Measured
/// peaks at 2000×2000 were 19 B a pixel (.png), 28 (.hdr), 41 (.exr with
/// the adaptive hashes), so 48.
const PIXEL: u64 = 48;

/// Bytes a pixel takes for each channel of a pass: its plane (f32), the
/// output's float copy and the encoder's buffers (measured: 7 (.png) to 11
/// (.exr layers) for all passes at once).
const PASS_CHANNEL: u64 = 16;

/// Bytes a pixel takes in PPM and SPPM besides its hit points: the direct
/// light, its running sum, the eye pass's colours, the composed pictures
/// and the photons pass (about 150), with room.
const PROGRESSIVE_PIXEL: u64 = 192;

/// Bytes a stored photon takes once the map is built: the k-d tree's
/// positions, directions and indices, the build's entries and splits, the
/// map's photons in tree order, the grid's keys and lists (about 210), with
/// room.
const MAP_PHOTON: u64 = 256;

/// What a render of `pixels` pixels on `threads` threads, with passes of
/// `channels` channels in all and photons as `plan` says, may hold at its
/// peak beyond what the process holds before it: pixels, passes, PPM's hit
/// points and the photons of a pass (each bounded by its key: at most 10
/// stored per emitted photon, `max_hitpoints=` hit points).
pub(crate) fn memory_needed(pixels: u64, threads: u64, channels: u64, plan: &Plan) -> u64 {
    let mut bytes = BASE + threads * THREAD + pixels * (PIXEL + channels * PASS_CHANNEL);
    if plan.mode != PhotonMode::Off {
        // A pass's photons: each chunk's list (grown by doubling, so up to
        // twice its length) and their concatenation, then the map.
        let stored = plan.emit.saturating_mul(u64::from(MAX_PHOTON_HITS));
        let kept = stored.min(plan.max_photons);
        bytes = bytes
            .saturating_add(stored.saturating_mul(3 * size_of::<Photon>() as u64 + 16))
            .saturating_add(kept.saturating_mul(MAP_PHOTON));
    }
    if matches!(plan.mode, PhotonMode::Ppm | PhotonMode::Sppm) {
        // The eye pass's rows (grown by doubling) and their concatenation,
        // then the hit points built from them; SPPM's running points.
        let seed = size_of::<(u32, HitPointSeed)>() as u64;
        let point = size_of::<HitPoint>() as u64;
        bytes = bytes
            .saturating_add(plan.max_hitpoints.saturating_mul(3 * seed + point))
            .saturating_add(pixels * (PROGRESSIVE_PIXEL + point));
    }
    bytes
}
