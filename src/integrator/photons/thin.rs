//! `max_photons=` (`photon-mapping.md`, Keys): a pass keeps at most that
//! many of its stored photons, chosen evenly by a hash of their index, as
//! they are traced, so it never holds more than the cap and a batch.

use crate::integrator::observer::mix;

/// The photons of a pass kept so far: of those stored, the `max` with the
/// least (hash of the index, index), in photon order.
pub(crate) struct Kept<T> {
    max: usize,
    key: u64,
    photons: Vec<T>,
    /// Each kept photon's hash.
    hashes: Vec<u64>,
    /// Photons stored so far, kept or not: the next one's index.
    stored: u64,
    /// A photon whose hash is at least this is never kept: `max` earlier
    /// ones rank before it (none until the first cut).
    bound: Option<u64>,
}

impl<T: Copy> Kept<T> {
    /// None kept yet of a pass whose photons are ranked by `key`.
    pub fn new(max: u64, key: u64) -> Self {
        Kept {
            max: usize::try_from(max).unwrap_or(usize::MAX).max(1),
            key,
            photons: Vec::new(),
            hashes: Vec::new(),
            stored: 0,
            bound: None,
        }
    }

    /// The rank of stored photon `i` (its index breaks ties).
    fn hash(&self, i: u64) -> u64 {
        mix(self.key ^ 0x7448_494e ^ i)
    }

    /// Takes the next stored photons, in photon order.
    pub fn extend(&mut self, photons: &[T]) {
        for p in photons {
            let h = self.hash(self.stored);
            self.stored += 1;
            // A later photon loses a tie on the hash: its index is larger.
            if self.bound.is_none_or(|b| h < b) {
                self.photons.push(*p);
                self.hashes.push(h);
            }
        }
        // Cut back once an eighth over the cap, not at every batch: a cut
        // costs a selection over all that are kept.
        if self.photons.len() > self.max.saturating_add(self.max / 8) {
            self.cut();
        }
    }

    /// Keeps the `max` least, in photon order.
    fn cut(&mut self) {
        if self.photons.len() <= self.max {
            return;
        }
        let mut ranks = self.hashes.clone();
        let (below, &mut last, _) = ranks.select_nth_unstable(self.max - 1);
        // Of the photons whose hash is `last`, the first ones in photon
        // order (the least indices) take the places left.
        let mut ties = self.max - below.iter().filter(|&&h| h < last).count();
        let mut at = 0;
        for i in 0..self.photons.len() {
            let h = self.hashes[i];
            let keep = h < last || (h == last && ties > 0);
            if h == last && keep {
                ties -= 1;
            }
            if keep {
                self.photons[at] = self.photons[i];
                self.hashes[at] = h;
                at += 1;
            }
        }
        self.photons.truncate(at);
        self.hashes.truncate(at);
        self.bound = Some(last);
    }

    /// The kept photons, each given to `scale` with stored/kept when some
    /// were dropped (to scale its power), and how many were.
    pub fn finish(mut self, scale: impl Fn(&mut T, f64)) -> (Vec<T>, u64) {
        self.cut();
        self.hashes = Vec::new();
        // Give back the room of the photons cut (their pages were touched).
        self.photons.shrink_to_fit();
        let n = self.stored;
        let kept = self.photons.len() as u64;
        if n > kept {
            let by = n as f64 / kept as f64;
            self.photons.iter_mut().for_each(|p| scale(p, by));
        }
        (self.photons, n - kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A photon as far as keeping it goes: which one, and its power.
    type Photon = (u32, DVec3);

    fn scale(p: &mut Photon, by: f64) {
        p.1 *= by;
    }

    /// The selection over the whole pass at once, as glint made it before
    /// it kept photons as they came: rank all, select the `max` least,
    /// back into photon order, scale.
    fn thin_at_once(photons: &[Photon], max: u64, key: u64) -> (Vec<Photon>, u64) {
        let n = photons.len() as u64;
        if n <= max {
            return (photons.to_vec(), 0);
        }
        let mut ranked: Vec<(u64, u32)> = (0..n as u32)
            .map(|i| (mix(key ^ 0x7448_494e ^ u64::from(i)), i))
            .collect();
        ranked.select_nth_unstable(max as usize - 1);
        let mut keep: Vec<u32> = ranked[..max as usize].iter().map(|&(_, i)| i).collect();
        keep.sort_unstable();
        let scale = n as f64 / max as f64;
        let kept = keep
            .iter()
            .map(|&i| {
                let mut p = photons[i as usize];
                p.1 *= scale;
                p
            })
            .collect();
        (kept, n - max)
    }

    fn photon(i: u32) -> Photon {
        let x = f64::from(i);
        (i, DVec3::new(0.1 + x * 1e-3, 0.3, 1.0 / (x + 1.0)))
    }

    /// Kept as they come, in batches of any length, the photons, their
    /// order, their power (bit for bit) and the count dropped are those of
    /// the selection over the whole pass.
    #[test]
    fn keeping_as_they_come_is_selecting_at_once() {
        let all: Vec<Photon> = (0..20_000).map(photon).collect();
        for max in [1, 7, 999, 5_000, 19_999, 20_000, 50_000] {
            for batch in [1, 333, 4096, 20_000] {
                let mut kept = Kept::new(max, 42);
                all.chunks(batch).for_each(|c| kept.extend(c));
                let got = kept.finish(scale);
                assert_eq!(got, thin_at_once(&all, max, 42), "max {max}, batch {batch}");
            }
        }
    }

    /// Never more than an eighth over the cap, and a batch.
    #[test]
    fn it_holds_the_cap_and_a_batch() {
        let all: Vec<Photon> = (0..100_000).map(photon).collect();
        let mut kept = Kept::new(1000, 7);
        for c in all.chunks(500) {
            kept.extend(c);
            assert!(kept.photons.len() <= 1000 + 125 + 500);
        }
        assert_eq!(kept.finish(scale).0.len(), 1000);
    }
}
