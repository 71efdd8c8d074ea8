//! Surface materials, stored compactly: a colour per material and its
//! other keys (its "finish") shared between materials that agree bit for bit.

use super::room::make_room;
use glam::DVec3;
use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};

/// Surface material (the same keys on every primitive).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Base colour (`color=`).
    pub color: DVec3,
    /// Diffuse coefficient (`diff=`).
    pub diff: f64,
    /// Specular coefficient (`spec=`).
    pub spec: f64,
    /// Mirror reflection coefficient (`refl=`).
    pub refl: f64,
    /// Glossiness of the reflection (`drefl=`, 0: perfect mirror).
    pub drefl: f64,
    /// Transmission coefficient (`refr=`).
    pub refr: f64,
    /// Index of refraction (`rindex=`).
    pub rindex: f64,
    /// Beer absorption per unit length inside, per channel (`absor=`).
    pub absor: DVec3,
    /// Index into the scene's textures (`texture=`).
    pub texture: Option<u32>,
    /// Index into the scene's textures of a normal map (`NT=`, the lineage V's key).
    pub normal_map: Option<u32>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            color: DVec3::ZERO,
            diff: 0.0,
            spec: 0.0,
            refl: 0.0,
            drefl: 0.0,
            refr: 0.0,
            rindex: 0.0,
            absor: DVec3::ZERO,
            texture: None,
            normal_map: None,
        }
    }
}

/// The exact bit patterns of a material's keys other than its colour (its
/// "finish"): what "equal" means for sharing (-0.0 is not 0.0, and a NaN
/// equals the same NaN), so a shared value is always the very value the
/// file gave.
fn finish_bits(m: &Material) -> [u64; 11] {
    [
        m.diff.to_bits(),
        m.spec.to_bits(),
        m.refl.to_bits(),
        m.drefl.to_bits(),
        m.refr.to_bits(),
        m.rindex.to_bits(),
        m.absor.x.to_bits(),
        m.absor.y.to_bits(),
        m.absor.z.to_bits(),
        // Never a u32: untextured differs from every texture index.
        m.texture.map_or(u64::MAX, u64::from),
        m.normal_map.map_or(u64::MAX, u64::from),
    ]
}

/// A stored material: its colour and the index of its finish (32 bytes).
#[derive(Clone, Copy, Debug)]
struct MaterialEntry {
    color: DVec3,
    finish: u32,
}

fn color_bits(c: DVec3) -> [u64; 3] {
    [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()]
}

/// The scene's materials, compact: a million spheres that differ only in
/// colour cost 32 bytes each, not a full [`Material`] (104).
#[derive(Clone, Debug, Default)]
pub(crate) struct MaterialTable {
    /// Indexed by an object's material index.
    entries: Vec<MaterialEntry>,
    /// Distinct finishes (bit for bit), in order of first use: materials
    /// whose colour is unused (black).
    finishes: Vec<Material>,
    /// Finish index by a hash of its bits. Keyed by the hash alone to cost
    /// 16 bytes a finish, not 80 of bits: the bits are checked on a hit, and a
    /// different finish with the same hash (never seen in practice) is
    /// stored unshared.
    by_hash: HashMap<u64, u32>,
    /// Entry index by a hash of its colour's bits and its finish, the last
    /// entry stored in each slot (empty until the first entry): an entry
    /// equal to one in its slot is shared, so files that cycle through a few
    /// colours keep a few entries, hot in the cache when shaded.
    recent: Vec<u32>,
    /// The index [`MaterialTable::add`] returned last.
    last: u32,
}

impl MaterialTable {
    /// The material at `index` (one [`MaterialTable::add`] returned).
    #[inline]
    pub fn get(&self, index: u32) -> Material {
        let e = self.entries[index as usize];
        Material {
            color: e.color,
            ..self.finishes[e.finish as usize]
        }
    }

    /// A number read from material `index`'s entry (its finish; 0 when out
    /// of range), of no use but to bring the entry into the cache ahead of
    /// [`MaterialTable::get`].
    #[inline]
    pub fn read_ahead(&self, index: u32) -> u32 {
        self.entries.get(index as usize).map_or(0, |e| e.finish)
    }

    /// Adds a material and returns its index. One identical (bit for bit)
    /// to the last added, or to the last stored in its slot of
    /// [`RECENT_SLOTS`], is shared.
    pub fn add(&mut self, material: &Material) -> u32 {
        let bits = finish_bits(material);
        let last = self
            .entries
            .get(self.last as usize)
            .map(|e| (e, finish_bits(&self.finishes[e.finish as usize])));
        let finish = match last {
            // Generated files repeat the same material block after block.
            Some((e, last_bits)) if last_bits == bits => {
                if color_bits(e.color) == color_bits(material.color) {
                    return self.last;
                }
                // Only the colour is new: no hashing of the finish needed.
                e.finish
            }
            _ => {
                let finish = Material {
                    color: DVec3::ZERO,
                    ..*material
                };
                self.intern(finish, bits, hash_bits(&bits))
            }
        };
        if self.recent.is_empty() {
            self.recent = vec![u32::MAX; RECENT_SLOTS];
        }
        let slot = recent_slot(material.color, finish);
        let seen = self.recent[slot];
        self.last = match self.entries.get(seen as usize) {
            Some(e) if e.finish == finish && color_bits(e.color) == color_bits(material.color) => {
                seen
            }
            _ => {
                self.entries.push(MaterialEntry {
                    color: material.color,
                    finish,
                });
                let index = (self.entries.len() - 1) as u32;
                self.recent[slot] = index;
                index
            }
        };
        self.last
    }

    /// Room for `more` materials beyond those stored ([`make_room`]).
    pub fn make_room(&mut self, more: usize) {
        make_room(&mut self.entries, more);
    }

    /// How many materials are stored (shared ones once).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// How many distinct finishes are stored.
    pub fn finish_count(&self) -> usize {
        self.finishes.len()
    }

    /// The index of a finish equal to `finish` bit for bit, added if new;
    /// `hash` is [`hash_bits`] of `bits` (a parameter so a test can collide).
    fn intern(&mut self, finish: Material, bits: [u64; 11], hash: u64) -> u32 {
        if let Some(&i) = self.by_hash.get(&hash)
            && finish_bits(&self.finishes[i as usize]) == bits
        {
            return i;
        }
        let i = self.finishes.len() as u32;
        self.finishes.push(finish);
        self.by_hash.entry(hash).or_insert(i);
        i
    }
}

/// Slots of [`MaterialTable`]'s table of recent entries (16 KiB of them).
pub(crate) const RECENT_SLOTS: usize = 4096;

/// The slot of an entry of colour `color` and finish `finish`: its bits
/// mixed by one multiplication (Fibonacci hashing), the top bits kept.
fn recent_slot(color: DVec3, finish: u32) -> usize {
    let [x, y, z] = color_bits(color);
    let key = x ^ y.rotate_left(21) ^ z.rotate_left(42) ^ u64::from(finish);
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - RECENT_SLOTS.trailing_zeros())) as usize
}

fn hash_bits(bits: &[u64; 11]) -> u64 {
    let mut h = DefaultHasher::new();
    bits.hash(&mut h);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glossy(color: DVec3) -> Material {
        Material {
            color,
            diff: 0.3,
            refl: 0.6,
            drefl: 0.2,
            ..Material::default()
        }
    }

    #[test]
    fn a_material_that_only_brings_a_colour_costs_32_bytes() {
        assert_eq!(std::mem::size_of::<MaterialEntry>(), 32);
        let mut scene = MaterialTable::default();
        for i in 0..1000 {
            let index = scene.add(&glossy(DVec3::splat(i as f64)));
            assert_eq!(index, i);
        }
        assert_eq!((scene.len(), scene.finish_count()), (1000, 1));
        assert_eq!(scene.get(999), glossy(DVec3::splat(999.0)));
    }

    #[test]
    fn materials_read_back_exactly_as_added() {
        let mut scene = MaterialTable::default();
        let all = [
            glossy(DVec3::X),
            Material {
                texture: Some(3),
                ..glossy(DVec3::X)
            },
            Material::default(),
            Material {
                rindex: f64::NAN,
                refr: 1.0,
                absor: DVec3::new(-0.0, 1e-300, 7.0),
                ..glossy(DVec3::Y)
            },
            glossy(DVec3::Z),
        ];
        let indices: Vec<_> = all.iter().map(|m| scene.add(m)).collect();
        assert_eq!(indices, vec![0, 1, 2, 3, 4]);
        assert_eq!(scene.finish_count(), 4);
        for (i, m) in indices.iter().zip(&all) {
            let got = scene.get(*i);
            assert_eq!(finish_bits(&got), finish_bits(m));
            assert_eq!(color_bits(got.color), color_bits(m.color));
        }
        // A NaN is the same NaN: equal bits are shared even where == is
        // false, after other materials as right after itself.
        let nan = all[3];
        assert_eq!(scene.add(&nan), 3);
        assert_eq!(scene.add(&nan), 3);
        assert_eq!((scene.len(), scene.finish_count()), (5, 4));
    }

    #[test]
    fn an_entry_whose_slot_another_took_is_stored_again_exactly() {
        // Two colours of one slot (found by search, not by the slot's formula).
        let slot = |c| recent_slot(c, 0);
        let a = DVec3::new(0.5, 0.25, 1.0);
        let b = (1..)
            .map(|i| DVec3::new(i as f64, 0.0, 0.0))
            .find(|&c| slot(c) == slot(a))
            .expect("a colour of a's slot"); // invariant: 4096 slots, so some colour of the first thousands shares a's
        let mut table = MaterialTable::default();
        let indices: Vec<_> = [a, b, a, a, b]
            .iter()
            .map(|&c| table.add(&glossy(c)))
            .collect();
        // b took a's slot, so a's third add stores it anew; the fourth is
        // the last added, and b's second is in the slot no more.
        assert_eq!(indices, vec![0, 1, 2, 2, 3]);
        for (i, c) in indices.iter().zip([a, b, a, a, b]) {
            assert_eq!(color_bits(table.get(*i).color), color_bits(c));
        }
    }

    #[test]
    fn a_hash_collision_stores_the_finish_unshared() {
        let mut table = MaterialTable::default();
        let a = glossy(DVec3::ZERO);
        let b = Material::default();
        assert_eq!(table.intern(a, finish_bits(&a), 7), 0);
        // Same hash, different bits: never taken for `a`.
        assert_eq!(table.intern(b, finish_bits(&b), 7), 1);
        assert_eq!(table.intern(a, finish_bits(&a), 7), 0);
        assert_eq!(table.finishes.len(), 2);
        assert_eq!(finish_bits(&table.finishes[1]), finish_bits(&b));
    }
}
