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
    /// Entry indices by a hash of their colour's bits and their finish: in
    /// each set, the two entries of that hash used last, the latest first
    /// (empty until the first entry). An entry equal to one in its set is
    /// shared, so files that cycle through a few colours keep a few
    /// entries, hot in the cache when shaded.
    recent: Vec<[u32; 2]>,
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
    /// to the last added, or to one of the two last used in its set of
    /// [`RECENT_SETS`], is shared.
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
            self.recent = vec![[u32::MAX; 2]; RECENT_SETS];
        }
        let set = &mut self.recent[recent_set(material.color, finish)];
        let entries = &self.entries;
        let equal = |index: u32| {
            entries.get(index as usize).is_some_and(|e| {
                e.finish == finish && color_bits(e.color) == color_bits(material.color)
            })
        };
        self.last = if equal(set[0]) {
            set[0]
        } else if equal(set[1]) {
            set.swap(0, 1);
            set[0]
        } else {
            self.entries.push(MaterialEntry {
                color: material.color,
                finish,
            });
            let index = (self.entries.len() - 1) as u32;
            *set = [index, set[0]];
            index
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

/// Sets of two in [`MaterialTable`]'s table of recent entries (16 KiB).
const RECENT_SETS: usize = 2048;

/// The set of an entry of colour `color` and finish `finish`: its bits
/// mixed by one multiplication (Fibonacci hashing), the top bits kept.
fn recent_set(color: DVec3, finish: u32) -> usize {
    let [x, y, z] = color_bits(color);
    let key = x ^ y.rotate_left(21) ^ z.rotate_left(42) ^ u64::from(finish);
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - RECENT_SETS.trailing_zeros())) as usize
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
    fn an_entry_its_set_forgot_is_stored_again_exactly() {
        // Four colours of one set (found by search, not by the set's formula).
        let set = |c| recent_set(c, 0);
        let a = DVec3::new(0.5, 0.25, 1.0);
        let mut same_set = (1..)
            .map(|i| DVec3::new(i as f64, 0.0, 0.0))
            .filter(|&c| set(c) == set(a));
        let mut next = || same_set.next().expect("a colour of a's set"); // invariant: 2048 sets, so colours of a's set come every few thousand
        let (b, c, d) = (next(), next(), next());
        let mut table = MaterialTable::default();
        let colours = [a, b, a, c, d, a, d, c, b];
        let indices: Vec<_> = colours.iter().map(|&c| table.add(&glossy(c))).collect();
        // The set holds the two used last: a is shared while it is one of
        // them (after b), stored anew once c and d came after it; d is
        // shared after a, c and b are stored anew after three others.
        assert_eq!(indices, vec![0, 1, 0, 2, 3, 4, 3, 5, 6]);
        for (i, c) in indices.iter().zip(colours) {
            assert_eq!(color_bits(table.get(*i).color), color_bits(c));
        }
    }

    #[test]
    fn one_colour_with_two_finishes_of_one_set_is_never_shared() {
        // Finishes 1, 2, ... (their `diff=`), until one falls in the set of
        // finish 0 with the same colour.
        let c = DVec3::new(0.1, 0.6, 0.6);
        let with_diff = |d: f64| Material {
            diff: d,
            ..glossy(c)
        };
        let mut table = MaterialTable::default();
        assert_eq!(table.add(&with_diff(0.0)), 0);
        let mut f = 0;
        while recent_set(c, f) != recent_set(c, 0) || f == 0 {
            f += 1;
            table.add(&with_diff(f64::from(f)));
        }
        // Colour c with finish 0, then with finish f: the set holds both.
        let first = table.add(&with_diff(0.0));
        let second = table.add(&with_diff(f64::from(f)));
        assert_eq!(first, 0);
        assert_ne!(second, first);
        assert_eq!(table.get(second).diff, f64::from(f));
        assert_eq!(table.get(first).diff, 0.0);
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
