//! Nearest hits for a packet of coherent rays (a tile's camera rays): one
//! walk of the tree for the whole packet. A node is tested with the first
//! ray that can still enter it, and, when the rays share their origin, the
//! whole packet skips a box that lies outside all of them at once. Each
//! answer is exactly that of [`Accel::intersect`] for the same ray.

use super::bvh::split_slot;
use super::node::{NO_CHILD, WIDTH};
use super::ray_box::{FAR_SLACK, MISS, RayBox, clip, fold_slab, max_num, min_num};
use super::walk::{STACK_SIZE, in_order};
use super::{Accel, PACKET_MAX, Primitive};
use crate::geometry::{Hit, Ray};
use glam::DVec3;

impl<P: Primitive> Accel<P> {
    /// The nearest hit of each ray (`ray.t_min` < t, at any distance) into
    /// `out`: for each ray exactly what [`Accel::intersect`] returns.
    pub fn intersect_packet(&self, rays: &[Ray], out: &mut [Option<(u32, Hit)>]) {
        self.isa.run(
            #[inline(always)]
            || {
                for (rays, out) in rays.chunks(PACKET_MAX).zip(out.chunks_mut(PACKET_MAX)) {
                    let mut t_best = [f64::INFINITY; PACKET_MAX];
                    for (j, ray) in rays.iter().enumerate() {
                        out[j] = None;
                        for &i in &self.unbounded {
                            self.test::<true>(i, ray, &mut out[j], &mut t_best[j]);
                        }
                    }
                    self.walk_packet(rays, &mut t_best, |j, prims, t| {
                        for &p in prims {
                            self.test::<false>(p, &rays[j], &mut out[j], t);
                        }
                    });
                }
            },
        )
    }

    /// Walks the tree once for up to [`PACKET_MAX`] rays: `leaf(j, prims,
    /// t)` runs for every leaf that ray j enters within its limit `t[j]`,
    /// which the call may lower.
    #[inline(always)]
    fn walk_packet(
        &self,
        rays: &[Ray],
        t: &mut [f64; PACKET_MAX],
        mut leaf: impl FnMut(usize, &[u32], &mut f64),
    ) {
        let n = rays.len().min(PACKET_MAX);
        let bvh = &self.bvh;
        let Some(last) = n.checked_sub(1).filter(|_| !bvh.wide.is_empty()) else {
            return;
        };
        // Slots past n repeat the last ray; they are never tested.
        let mut rb = [RayBox::new(&rays[last]); PACKET_MAX];
        for (b, ray) in rb.iter_mut().zip(&rays[..last]) {
            *b = RayBox::new(ray);
        }
        let frustum = Frustum::of(&rb[..n]);
        let lanes = Lanes::of(&rb[..n], &rb);
        // Children are visited in the order their centres lie along the
        // packet's mean direction: near first, for most of its rays.
        let dir: DVec3 = rays[..n].iter().map(|r| r.dir).sum();
        let along = |b: &[f32; 6]| {
            (b[0] + b[3]) as f64 * dir.x
                + (b[1] + b[4]) as f64 * dir.y
                + (b[2] + b[5]) as f64 * dir.z
        };
        // The farthest any ray may still reach: never below any ray's limit.
        let farthest = |t: &[f64; PACKET_MAX]| t[..n].iter().fold(0.0, |a: f64, &x| max_num(x, a));
        let mut t_all = farthest(t);
        // Pending subtrees (slots) with the first ray that may enter them;
        // WIDTH − 1 pushes a level, and the tree is shallower than STACK_SIZE.
        let mut stack = [(0u32, 0u32); WIDTH * STACK_SIZE];
        let mask = WIDTH * STACK_SIZE - 1;
        let mut sp = 0;
        // The subtree visited: its box, and its node (count 0) or leaf.
        let (mut bounds, mut child, mut count) = (bvh.root, 0, 0);
        let mut first = 0;
        'walk: loop {
            'visit: {
                if frustum.as_ref().is_some_and(|f| f.misses(&bounds, t_all)) {
                    break 'visit;
                }
                // Rays before the first that enters this box miss all of its
                // descendants too: their boxes lie inside it, and limits only fall.
                if count > 0 {
                    let s = child as usize;
                    let prims = &bvh.prims[s..s + count as usize];
                    // Each ray's own test: no leaf call changes another's limit.
                    let mut entered = entering(lanes.as_ref(), &rb[..n], &bounds, t, first);
                    // Only a ray that had the farthest limit can lower it.
                    let mut lowered = false;
                    while entered != 0 {
                        let j = entered.trailing_zeros() as usize;
                        entered &= entered - 1;
                        let before = t[j];
                        leaf(j, prims, &mut t[j]);
                        lowered |= before == t_all && t[j] < before;
                    }
                    if lowered && frustum.is_some() {
                        t_all = farthest(t);
                    }
                    break 'visit;
                }
                // The first ray that enters the node: mostly the first
                // candidate; past it, the rest at once.
                let i = if rb[first].entry(&bounds, t[first]) != MISS {
                    first
                } else {
                    match entering(lanes.as_ref(), &rb[..n], &bounds, t, first) {
                        0 => break 'visit,
                        m => m.trailing_zeros() as usize,
                    }
                };
                // The children, nearest first: push the others farthest
                // first, go to the nearest.
                let w = child as usize;
                let node = &bvh.wide[w];
                let mut used = 0u32;
                let mut key = [0.0; WIDTH];
                for k in (0..WIDTH).filter(|&k| node.child[k] != NO_CHILD) {
                    used |= 1 << k;
                    key[k] = along(&node.bounds(k));
                }
                let (order, used) = in_order(&key, used);
                for &k in order[1..used].iter().rev() {
                    stack[sp & mask] = ((w * WIDTH + k) as u32, i as u32);
                    sp += 1;
                }
                let k = order[0];
                (bounds, child, count) = (node.bounds(k), node.child[k], node.count[k]);
                first = i;
                continue 'walk;
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            let (slot, f) = stack[sp & mask];
            let (w, k) = split_slot(slot);
            let node = &bvh.wide[w];
            (bounds, child, count) = (node.bounds(k), node.child[k], node.count[k]);
            first = f as usize;
        }
    }
}

/// The rays of `rb` from the `from`-th on that enter box `b` within their
/// limits `t`, a bit each: by `lanes` where the rays have them, else one by
/// one (inlined into the instruction set's dispatch, as the whole walk).
#[inline(always)]
fn entering(
    lanes: Option<&Lanes>,
    rb: &[RayBox],
    b: &[f32; 6],
    t: &[f64; PACKET_MAX],
    from: usize,
) -> u64 {
    match lanes {
        Some(l) => l.entered(b, t) & (u64::MAX >> (PACKET_MAX - rb.len())) & (u64::MAX << from),
        None => (from..rb.len()).fold(0, |m, j| m | u64::from(rb[j].entry(b, t[j]) != MISS) << j),
    }
}

/// A packet's rays that share their origin and the sides they enter boxes
/// by, their inverse directions axis by axis: a box is tested for all of
/// them in SIMD lanes, lane j's answer [`RayBox::entry`]'s for ray j to the
/// bit (the same operations in the same order).
struct Lanes {
    origin: [f64; 3],
    near: [usize; 3],
    inv: [[f64; PACKET_MAX]; 3],
}

impl Lanes {
    /// The lanes of the rays prepared in `rb` (`slots`: the packet's slots,
    /// those past `rb` holding placeholders), or `None` when two rays differ
    /// in origin or sides.
    fn of(rb: &[RayBox], slots: &[RayBox; PACKET_MAX]) -> Option<Lanes> {
        let first = rb.first()?;
        let (origin, near) = (first.origin(), first.near());
        if rb.iter().any(|r| r.origin() != origin || r.near() != near) {
            return None;
        }
        let mut inv = [[0.0; PACKET_MAX]; 3];
        for (j, r) in slots.iter().enumerate() {
            for (a, v) in r.inv_dir().into_iter().enumerate() {
                inv[a][j] = v;
            }
        }
        Some(Lanes { origin, near, inv })
    }

    /// Bit j set when ray j enters box `b` within its limit `t[j]` by
    /// [`RayBox::entry`].
    #[inline(always)]
    fn entered(&self, b: &[f32; 6], t: &[f64; PACKET_MAX]) -> u64 {
        let mut t0 = [0.0; PACKET_MAX];
        let mut t1 = *t;
        for (a, inv) in self.inv.iter().enumerate() {
            let near = self.near[a] & 3;
            // (b − o) is each ray's own first operation: the origins are
            // equal (+0 and −0 may differ, in the sign of a zero offset,
            // which no comparison below can see).
            let dn = b[near + a] as f64 - self.origin[a];
            let df = b[(near ^ 3) + a] as f64 - self.origin[a];
            for ((t0, t1), &inv) in t0.iter_mut().zip(&mut t1).zip(inv) {
                fold_slab(dn, df, inv, t0, t1);
            }
        }
        t0.iter()
            .zip(&t1)
            .enumerate()
            .fold(0, |m, (j, (&t0, &t1))| {
                m | u64::from(clip(t0, t1) != MISS) << j
            })
    }
}

/// The bounds of a packet of rays from one origin whose directions agree in
/// sign on every axis: enough to tell that a box lies outside all of them.
struct Frustum {
    origin: [f64; 3],
    /// Per axis: 0 if the rays run towards +axis (enter at the box's min), else 3.
    near: [usize; 3],
    /// Per axis: the least and greatest inverse direction component.
    inv_lo: [f64; 3],
    inv_hi: [f64; 3],
}

impl Frustum {
    /// The bounds of the rays prepared in `rb` (their own inverse
    /// directions, so the bounds hold each ray's arithmetic), or `None` when
    /// they do not share an origin or a direction component is zero,
    /// subnormal or NaN (its inverse is not finite) or changes sign.
    fn of(rb: &[RayBox]) -> Option<Frustum> {
        let first = rb.first()?;
        let origin = first.origin();
        let mut f = Frustum {
            origin,
            near: [0; 3],
            inv_lo: [f64::INFINITY; 3],
            inv_hi: [f64::NEG_INFINITY; 3],
        };
        let negative = first.inv_dir().map(|inv| inv < 0.0);
        for (a, &neg) in negative.iter().enumerate() {
            f.near[a] = if neg { 3 } else { 0 };
        }
        for r in rb {
            if r.origin() != origin {
                return None;
            }
            for (a, inv) in r.inv_dir().into_iter().enumerate() {
                // A zero or subnormal component has an infinite inverse:
                // 0·∞ would leave a ray's slab open where the bounds here
                // would close it.
                if !inv.is_finite() || (inv < 0.0) != negative[a] {
                    return None;
                }
                f.inv_lo[a] = f.inv_lo[a].min(inv);
                f.inv_hi[a] = f.inv_hi[a].max(inv);
            }
        }
        Some(f)
    }

    /// Whether no ray of the packet enters box `b` at a distance in
    /// [0, `t_far`] by [`RayBox::entry`]'s arithmetic.
    ///
    /// Each ray's slab distance (b − o)·(1/d) is computed from the same
    /// difference as here, and rounding is monotone in the factor 1/d, so it
    /// lies between the two computed with the extreme inverses: the packet's
    /// entry bound is below every ray's entry, its exit bound above every
    /// exit, and a miss here is a miss for every ray.
    #[inline(always)]
    fn misses(&self, b: &[f32; 6], t_far: f64) -> bool {
        let mut t0: f64 = 0.0;
        let mut t1 = t_far;
        for a in 0..3 {
            let near = self.near[a] & 3;
            let dn = b[near + a] as f64 - self.origin[a];
            let df = b[(near ^ 3) + a] as f64 - self.origin[a];
            let (lo, hi) = (self.inv_lo[a], self.inv_hi[a]);
            // Finite factors: no NaN, so plain comparisons do.
            t0 = max_num(min_num(dn * lo, dn * hi), t0);
            t1 = min_num(max_num(df * lo, df * hi), t1);
        }
        t0 > t1 * FAR_SLACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    /// The box of centre `c` and half-extents `h`.
    fn box_around(c: [f32; 3], h: [f32; 3]) -> [f32; 6] {
        [
            c[0] - h[0],
            c[1] - h[1],
            c[2] - h[2],
            c[0] + h[0],
            c[1] + h[1],
            c[2] + h[2],
        ]
    }

    #[test]
    fn frustum_never_culls_a_box_a_ray_enters() {
        let mut rng = Pcg64::seed_from_u64(9);
        let (mut culled, mut kept) = (0, 0);
        for p in 0..3000 {
            let signs = [0, 1, 2].map(|_| if rng.random_bool(0.5) { 1.0 } else { -1.0 });
            // Some packets have components of extreme sizes: tiny, or subnormal
            // (whose inverse overflows: such packets get no frustum).
            let scale = [1.0, 1.0, 1e-12, 1e-300, 1e-310][p % 5];
            let origin = DVec3::new(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            );
            let spread = [1.0, 0.1, 1e-3][rng.random_range(0..3usize)];
            let centre = DVec3::new(rng.random(), rng.random(), rng.random());
            let rays: Vec<Ray> = (0..rng.random_range(1..=64))
                .map(|_| {
                    let mut d = DVec3::ZERO;
                    for a in 0..3 {
                        let m = (centre[a] + spread * rng.random_range(0.0..1.0)).max(1e-3);
                        d[a] = signs[a] * m * if a == p % 3 { scale } else { 1.0 };
                    }
                    // Not normalised: the test is of the slab arithmetic alone.
                    Ray::new(origin, d)
                })
                .collect();
            let rb: Vec<RayBox> = rays.iter().map(RayBox::new).collect();
            let Some(f) = Frustum::of(&rb) else {
                assert_eq!(scale, 1e-310, "only subnormal components are refused");
                continue;
            };
            for _ in 0..20 {
                // Boxes around points along one of the rays, and anywhere.
                let r = &rays[rng.random_range(0..rays.len())];
                let at = if rng.random_bool(0.5) {
                    r.origin + r.dir * rng.random_range(-1.0..6.0)
                } else {
                    DVec3::new(rng.random(), rng.random(), rng.random()) * 8.0 - 4.0
                };
                let c = at.as_vec3().to_array();
                let h = [0, 1, 2].map(|_| rng.random_range(0.0f32..0.5));
                let b = box_around(c, h);
                let t_far = if rng.random_bool(0.5) {
                    f64::INFINITY
                } else {
                    rng.random_range(0.0..8.0)
                };
                let any = rb.iter().any(|r| r.entry(&b, t_far) != MISS);
                if f.misses(&b, t_far) {
                    assert!(!any, "culled a box a ray enters: {b:?} {rays:?}");
                    culled += 1;
                } else {
                    kept += 1;
                }
            }
        }
        // Both outcomes occur often.
        assert!(culled > 5000 && kept > 5000, "{culled} culled, {kept} kept");
    }

    #[test]
    fn lanes_answer_as_each_ray_does() {
        let mut rng = Pcg64::seed_from_u64(13);
        let (mut entered, mut missed) = (0, 0);
        for p in 0..2000 {
            // In f32, so that a box face can pass exactly through it.
            let origin = (DVec3::new(rng.random(), rng.random(), rng.random()) * 4.0 - 2.0)
                .as_vec3()
                .as_dvec3();
            let signs = [0, 1, 2].map(|_| if rng.random_bool(0.5) { 1.0 } else { -1.0 });
            let n = rng.random_range(1..=PACKET_MAX);
            let mut rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let mut d = DVec3::ZERO;
                    for a in 0..3 {
                        // Some components zero (±0, on the packet's side)
                        // or subnormal: infinite inverses.
                        d[a] = match rng.random_range(0..8) {
                            0 if p % 4 == 0 => 0.0,
                            1 if p % 4 == 1 => 1e-310,
                            _ => rng.random_range(1e-3..1.0),
                        } * signs[a];
                    }
                    Ray::new(origin, d)
                })
                .collect();
            // Some packets have a ray on the other side of an axis, or
            // from another origin: no lanes for them.
            let (split, moved) = (p % 8 == 6, p % 8 == 7);
            if split {
                rays[n - 1].dir.x = -signs[0] * 0.5;
            }
            if moved {
                rays[n - 1].origin.y += 1e-3;
            }
            let rb: Vec<RayBox> = rays.iter().map(RayBox::new).collect();
            let mut slots = [rb[n - 1]; PACKET_MAX];
            slots[..n].copy_from_slice(&rb);
            let lanes = Lanes::of(&rb, &slots);
            let apart = (split || moved) && n > 1;
            assert_eq!(lanes.is_none(), apart, "{rays:?}");
            let Some(lanes) = lanes else { continue };
            for _ in 0..10 {
                // Boxes with a face through the origin, around points, anywhere.
                let mut c = (DVec3::new(rng.random(), rng.random(), rng.random()) * 6.0 - 3.0)
                    .as_vec3()
                    .to_array();
                let h = [0, 1, 2].map(|_| rng.random_range(0.0f32..1.5));
                if rng.random_bool(0.3) {
                    let a = rng.random_range(0..3);
                    c[a] = origin[a] as f32 + if rng.random_bool(0.5) { h[a] } else { -h[a] };
                }
                let b = box_around(c, h);
                let t: [f64; PACKET_MAX] = std::array::from_fn(|_| {
                    if rng.random_bool(0.5) {
                        f64::INFINITY
                    } else {
                        rng.random_range(0.0..6.0)
                    }
                });
                let mask = lanes.entered(&b, &t);
                for (j, r) in rb.iter().enumerate() {
                    let hit = r.entry(&b, t[j]) != MISS;
                    assert_eq!(mask >> j & 1 == 1, hit, "ray {j} of {rays:?}, box {b:?}");
                    if hit { entered += 1 } else { missed += 1 }
                }
            }
        }
        assert!(
            entered > 20_000 && missed > 20_000,
            "{entered} entered, {missed} missed"
        );
    }

    #[test]
    fn subnormal_direction_on_a_box_face_is_not_culled() {
        // The first ray runs along the plane x = 0, the box's far x face:
        // its slab test sees (0 − 0)·∞ = NaN and leaves the slab open, so it
        // enters the box at t = 1; a frustum with an infinite inverse would
        // close the slab and cull the box.
        let rays = [
            Ray::new(DVec3::ZERO, DVec3::new(1e-310, 1.0, 0.1)),
            Ray::new(DVec3::ZERO, DVec3::new(0.5, 1.0, 0.1)),
        ];
        let b = [-1.0, 1.0, -1.0, 0.0, 2.0, 1.0];
        assert_ne!(RayBox::new(&rays[0]).entry(&b, f64::INFINITY), MISS);
        let rb = rays.map(|r| RayBox::new(&r));
        assert!(Frustum::of(&rb).is_none_or(|f| !f.misses(&b, f64::INFINITY)));
    }
}
