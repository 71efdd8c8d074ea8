//! The BVH's build, layout and walks against brute force and hand cases.

use super::build::{BINS, Extents, MAX_LEAF, PARALLEL_MIN, SAH_MAX_DEPTH, TRAVERSAL_COST, split};
use super::bvh::{Binary, Bvh, NO_LEAF, ROOT, split_slot};
use super::hull::Hull;
use super::isa::Isa;
use super::node::{
    EMPTY, Item, NO_CHILD, Node, Pair, WIDTH, Wide, f32_down, f32_up, half_area, union,
};
use super::ray_box::{MISS, RayBox};
use super::walk::STACK_SIZE;
use crate::accel::QueryCost;
use crate::geometry::{Aabb, Ray};
use glam::DVec3;
use rand::{Rng, SeedableRng};

fn unit_box() -> [f32; 6] {
    [0.0, 0.0, 0.0, 1.0, 1.0, 1.0]
}

/// A box in f32, rounded outward, around `c` with half sizes `h`.
fn f32_box(c: DVec3, h: DVec3) -> [f32; 6] {
    let (lo, hi) = (c - h, c + h);
    [
        f32_down(lo.x),
        f32_down(lo.y),
        f32_down(lo.z),
        f32_up(hi.x),
        f32_up(hi.y),
        f32_up(hi.z),
    ]
}

#[test]
fn hull_meets_every_box_a_ray_into_its_box_enters() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(31);
    fn v(rng: &mut rand_pcg::Pcg64, s: f64) -> DVec3 {
        DVec3::new(
            rng.random_range(-s..s),
            rng.random_range(-s..s),
            rng.random_range(-s..s),
        )
    }
    let (mut culled, mut kept) = (0, 0);
    for k in 0..2000 {
        let scale = [1.0, 1.0 / 1024.0, 1024.0][k % 3];
        // Light boxes: solid, flat on an axis (a square light along the
        // axes, on a plane f32 holds exactly), or a single point.
        let mut centre = v(&mut rng, 5.0 * scale);
        let mut half = v(&mut rng, scale).abs();
        let flat = k / 4 % 3;
        match k % 4 {
            0 => {
                half[flat] = 0.0;
                centre[flat] = (centre[flat] / scale).round() * scale;
            }
            1 => half = DVec3::ZERO,
            _ => {}
        }
        // Origins at a corner of the box, inside it (on its plane when
        // it is flat), nearby, or far off.
        let origin = match k % 5 {
            0 => centre + half * DVec3::new(1.0, -1.0, 1.0),
            1 => centre + v(&mut rng, 0.5 * scale) * half.signum().abs(),
            2 => centre + v(&mut rng, scale),
            _ => centre + v(&mut rng, 20.0 * scale),
        };
        let hull = Hull::new(origin, centre - half, centre + half);
        for _ in 0..20 {
            // A sample point of the light: inside, on a corner or an edge.
            let mut u = v(&mut rng, 1.0);
            for a in 0..3 {
                if rng.random_bool(0.3) {
                    u[a] = u[a].signum();
                }
            }
            let q = centre + half * u;
            let to = q - origin;
            let dist = to.length();
            if dist == 0.0 {
                continue;
            }
            let rb = RayBox::new(&Ray::new(origin, to * (1.0 / dist)));
            // Boxes around points of the segment (touching it, beside
            // it, containing the origin or q), and anywhere.
            for _ in 0..10 {
                let at = match rng.random_range(0..4) {
                    0 => origin + to * rng.random_range(-0.2..1.2),
                    1 => origin,
                    2 => q,
                    _ => centre + v(&mut rng, 10.0 * scale),
                };
                let size = [1e-6, 1e-2, 0.3][rng.random_range(0..3)] * scale;
                let h = v(&mut rng, size).abs();
                let mut b = f32_box(at + v(&mut rng, scale) * h, h);
                if k % 4 == 0 && rng.random_bool(0.3) {
                    // Beyond a flat light, touching its plane: rays reach
                    // it at their very end.
                    let (a, side) = (flat, (q[flat] - origin[flat]).signum());
                    let (near, far) = if side > 0.0 { (a, a + 3) } else { (a + 3, a) };
                    b[near] = centre[a] as f32;
                    b[far] = (centre[a] + side * size) as f32;
                }
                if rb.entry(&b, dist) != MISS {
                    assert!(hull.meets(&b), "{origin} -> {q}: {b:?}");
                    kept += 1;
                } else if !hull.meets(&b) {
                    culled += 1;
                }
            }
        }
    }
    // Both outcomes occur often: the test has teeth.
    assert!(
        culled > 20_000 && kept > 20_000,
        "{culled} culled, {kept} kept"
    );
}

#[test]
fn ray_in_a_face_plane_with_zero_direction_enters() {
    // Origin on the min-x and max-z faces' planes, direction along y only:
    // both 0·∞ cases must leave the slab open.
    for dir in [DVec3::Y, DVec3::NEG_Y] {
        for x in [0.0, 1.0] {
            let o = DVec3::new(x, if dir.y > 0.0 { -2.0 } else { 3.0 }, 1.0);
            let rb = RayBox::new(&Ray::new(o, dir));
            assert_eq!(rb.entry(&unit_box(), f64::INFINITY), 2.0, "{o} {dir}");
        }
    }
    // Negative zero components pick the other side.
    let d = DVec3::new(-0.0, 1.0, -0.0);
    let rb = RayBox::new(&Ray::new(DVec3::new(1.0, -2.0, 0.0), d));
    assert_eq!(rb.entry(&unit_box(), f64::INFINITY), 2.0);
    // Just outside the slab: miss.
    let o = DVec3::new(1.0f64.next_up(), -2.0, 0.5);
    let rb = RayBox::new(&Ray::new(o, DVec3::Y));
    assert_eq!(rb.entry(&unit_box(), f64::INFINITY), MISS);
}

#[test]
fn box_behind_or_beyond_t_best_is_missed() {
    let rb = RayBox::new(&Ray::new(DVec3::new(0.5, 0.5, 5.0), DVec3::Z));
    assert_eq!(rb.entry(&unit_box(), f64::INFINITY), MISS);
    let rb = RayBox::new(&Ray::new(DVec3::new(0.5, 0.5, -5.0), DVec3::Z));
    assert_eq!(rb.entry(&unit_box(), 4.0), MISS);
    assert_eq!(rb.entry(&unit_box(), 5.0), 5.0);
    // Origin inside: entry at 0.
    let rb = RayBox::new(&Ray::new(DVec3::splat(0.5), DVec3::Z));
    assert_eq!(rb.entry(&unit_box(), 1.0), 0.0);
}

#[test]
fn f32_rounding_is_outward() {
    for x in [0.1f64, -0.1, 1e-30, -1e-30, 1e29, -3.3e29, 7.0, 0.0] {
        assert!((f32_down(x) as f64) <= x && (f32_up(x) as f64) >= x, "{x}");
    }
    let b = Aabb::from_points(DVec3::splat(0.1), DVec3::splat(0.3));
    let it = Item::new(0, &b);
    for a in 0..3 {
        assert!(
            it.is_some_and(|it| (it.bounds[a] as f64) < 0.1 && (it.bounds[a + 3] as f64) > 0.3)
        );
    }
    let huge = Aabb::from_points(DVec3::ZERO, DVec3::splat(1e31));
    assert!(Item::new(0, &huge).is_none());
    let nan = Aabb {
        min: DVec3::ZERO,
        max: DVec3::new(f64::NAN, 1.0, 1.0),
    };
    assert!(Item::new(0, &nan).is_none());
}

/// Depth of the deepest leaf, and checks every primitive is in exactly one leaf.
fn depth_and_coverage(bvh: &Binary, n: usize) -> usize {
    let mut seen = vec![0u32; n];
    let mut max_depth = 0;
    let mut todo = vec![(0u32, 0usize)];
    while let Some((i, d)) = todo.pop() {
        let node = bvh.node(i);
        max_depth = max_depth.max(d);
        if node.count > 0 {
            let s = node.start as usize;
            for &p in &bvh.prims[s..s + node.count as usize] {
                seen[p as usize] += 1;
                assert!(node.count as usize <= MAX_LEAF);
            }
        } else {
            for c in [node.start, node.start + 1] {
                let child = bvh.node(c);
                for a in 0..3 {
                    assert!(child.bounds[a] >= node.bounds[a]);
                    assert!(child.bounds[a + 3] <= node.bounds[a + 3]);
                }
                todo.push((c, d + 1));
            }
        }
    }
    assert!(seen.iter().all(|&k| k == 1));
    max_depth
}

/// A walk that no leaf stops or shortens visits the root (if the ray enters
/// the tree's box) and exactly the
/// children (nodes and leaves) whose boxes the ray enters (a child's box
/// lies in its parent's), and tests the primitives of those that are
/// leaves: counted by brute force over every slot of the wide tree.
#[test]
fn a_walk_counts_every_child_whose_box_the_ray_enters() {
    // Many levels, and one node (its children all leaves: walked apart).
    for (n, levels) in [(3000, true), (3, false)] {
        let items = sphere_items(n, 5);
        let bvh = Bvh::build(items.clone(), n);
        assert_eq!(bvh.wide.len() == 1, !levels);
        let slots: Vec<(&Wide, usize)> = bvh
            .wide
            .iter()
            .flat_map(|n| (0..WIDTH).map(move |k| (n, k)))
            .filter(|(n, k)| n.child[*k] != NO_CHILD)
            .collect();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        let (mut deep, mut leaves) = (0, 0);
        for _ in 0..400 {
            let o = DVec3::new(rng.random(), rng.random(), rng.random()) * 140.0 - 20.0;
            let mut d = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
            if !levels {
                // Few boxes: aimed near one of them.
                let it = &items[rng.random_range(0..n)];
                let c = DVec3::from_array([0, 1, 2].map(|a| f64::from(it.centroid(a))));
                d = c + d * 2.0 - o;
            }
            let ray = Ray::new(o, d.normalize());
            let rb = RayBox::new(&ray);
            let entered: Vec<&(&Wide, usize)> = slots
                .iter()
                .filter(|(n, k)| rb.entry(&n.bounds(*k), f64::INFINITY) != MISS)
                .collect();
            // The root node is visited when the ray enters the whole tree's box.
            let root = u64::from(rb.entry(&bvh.root, f64::INFINITY) != MISS);
            let want = QueryCost {
                nodes: root + entered.len() as u64,
                tests: entered.iter().map(|(n, k)| u64::from(n.count[*k])).sum(),
            };
            // Nearest first or in slot order, a walk no leaf stops visits the same.
            let (mut nearest, mut any) = (QueryCost::default(), QueryCost::default());
            let mut t = f64::INFINITY;
            let count = |prims: &[u32], _: &mut f64| (false, prims.len());
            let isa = Isa::best();
            bvh.traverse::<true>(None, &ray, &mut t, isa, &mut nearest, count);
            bvh.traverse::<false>(None, &ray, &mut t, isa, &mut any, count);
            assert_eq!(nearest, want, "{ray:?}");
            assert_eq!(any, want, "{ray:?}");
            deep += usize::from(want.nodes > 10 && want.tests > 0);
            leaves += usize::from(want.tests > 0);
        }
        if levels {
            assert!(deep > 30, "{deep} rays entered many boxes");
        } else {
            assert!(leaves > 10, "{leaves} rays entered a leaf");
        }
    }
}

/// The wide tree holds the binary tree's leaves, each once, with their
/// boxes; a node's children lie in its box, and its unused slots come last.
#[test]
fn wide_tree_holds_the_binary_leaves() {
    for n in [1, 2, 3, 7, 3000] {
        let bin = Binary::build(sphere_items(n, 6));
        let bvh = Bvh::build(sphere_items(n, 6), n);
        assert_eq!(bvh.prims, bin.prims);
        let leaves: Vec<([f32; 6], u32, u32)> = (0..2 * bin.pairs.len() as u32)
            .filter(|&k| k != 1)
            .map(|k| bin.node(k))
            .filter(|node| node.count > 0)
            .map(|node| (node.bounds, node.start, node.count))
            .collect();
        let mut found = Vec::new();
        let mut todo = vec![(
            0usize,
            [
                f32::NEG_INFINITY,
                f32::NEG_INFINITY,
                f32::NEG_INFINITY,
                f32::INFINITY,
                f32::INFINITY,
                f32::INFINITY,
            ],
        )];
        let mut visits = 0;
        while let Some((w, outer)) = todo.pop() {
            visits += 1;
            let node = &bvh.wide[w];
            let used = (0..WIDTH)
                .take_while(|&k| node.child[k] != NO_CHILD)
                .count();
            assert!(used >= 1 && (used..WIDTH).all(|k| node.child[k] == NO_CHILD));
            for k in 0..used {
                let b = node.bounds(k);
                assert!((0..3).all(|a| b[a] >= outer[a] && b[a + 3] <= outer[a + 3]));
                if node.count[k] > 0 {
                    found.push((b, node.child[k], node.count[k]));
                } else {
                    todo.push((node.child[k] as usize, b));
                }
            }
        }
        assert_eq!(visits, bvh.wide.len(), "every node reached once");
        let key = |l: &([f32; 6], u32, u32)| l.1;
        found.sort_by_key(key);
        let mut want = leaves.clone();
        want.sort_by_key(key);
        assert_eq!(found, want);
        // A tree of more than WIDTH leaves fills its root.
        if leaves.len() >= WIDTH {
            assert!(bvh.wide[0].child.iter().all(|&c| c != NO_CHILD));
        }
    }
}

/// Each lane of the wide box test is the scalar test of that child's box,
/// to the bit, and an unused slot is always missed.
#[test]
fn wide_box_test_is_the_scalar_one_lane_by_lane() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(12);
    let mut seen = [0; 2];
    for _ in 0..2000 {
        let mut node = Wide::EMPTY;
        let used = rng.random_range(0..=WIDTH);
        for k in 0..used {
            let c = DVec3::new(rng.random(), rng.random(), rng.random()) * 10.0 - 5.0;
            let h = DVec3::new(rng.random(), rng.random(), rng.random()) * 3.0;
            node.set_child(k, &f32_box(c, h), k as u32, 0);
        }
        // Mostly aimed at the middle, where the boxes crowd.
        let o = DVec3::new(rng.random(), rng.random(), rng.random()) * 16.0 - 8.0;
        let aim = DVec3::new(rng.random(), rng.random(), rng.random()) * 6.0 - 3.0;
        let mut d = aim - o;
        // Some directions along an axis or a plane: zero components.
        for a in 0..3 {
            if rng.random_bool(0.2) {
                d[a] = if rng.random_bool(0.5) { 0.0 } else { -0.0 };
            }
        }
        if d == DVec3::ZERO {
            continue;
        }
        let rb = RayBox::new(&Ray::new(o, d.normalize()));
        let t_best = if rng.random_bool(0.5) {
            f64::INFINITY
        } else {
            rng.random::<f64>() * 12.0
        };
        for (k, t) in rb.entries(&node, t_best).into_iter().enumerate() {
            let want = if k < used {
                rb.entry(&node.bounds(k), t_best)
            } else {
                MISS
            };
            assert_eq!(t.to_bits(), want.to_bits(), "lane {k}");
            if k < used {
                seen[usize::from(want != MISS)] += 1;
            }
        }
    }
    // Both answers well exercised.
    assert!(seen.iter().all(|&n| n > 200), "{seen:?} lanes missed, hit");
}

fn sphere_items(n: usize, seed: u64) -> Vec<Item> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    (0..n)
        .map(|i| {
            let c = DVec3::new(rng.random(), rng.random(), rng.random()) * 100.0;
            let r = DVec3::splat(rng.random_range(0.01..1.0));
            Item::new(i as u32, &Aabb::from_points(c - r, c + r))
        })
        .collect::<Option<Vec<_>>>()
        .unwrap_or_default()
}

#[test]
fn same_tree_on_one_or_two_threads() -> Result<(), rayon::ThreadPoolBuildError> {
    let items = sphere_items(50_000, 1);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(|pool| pool.install(|| Binary::build(items.clone())))
    };
    let (a, b) = (on(1)?, on(2)?);
    assert_eq!(items.len(), 50_000);
    assert_eq!(a.pairs, b.pairs);
    assert_eq!(a.prims, b.prims);
    let depth = depth_and_coverage(&a, items.len());
    assert!(depth < 40, "depth {depth}");
    Ok(())
}

/// The split the surface area heuristic asks for, weighed from the items
/// themselves at every bin boundary (empty bins included): the first
/// cheapest boundary's left items, and both sides' boxes (each bin's items
/// in order, the bins outwards from the first for the left side and
/// inwards from the last for the right, as the build's sweeps take them,
/// which tells 0 from −0); `None` for a leaf. For nodes whose centroids
/// differ (others split at the median).
fn cheapest_split(items: &[Item]) -> Option<(Vec<u32>, [f32; 6], [f32; 6])> {
    let n = items.len();
    let extent = |a: usize| {
        let (lo, hi) = items
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), it| {
                (lo.min(it.centroid(a)), hi.max(it.centroid(a)))
            });
        (lo, hi - lo)
    };
    // The widest axis, the first of equals.
    let axis = (1..3).fold(0, |best, a| {
        if extent(a).1 > extent(best).1 {
            a
        } else {
            best
        }
    });
    let (cmin, width) = extent(axis);
    assert!(width > 0.0);
    // The build's bins: a centroid's bin index as it computes it.
    let bins = n.clamp(4, BINS);
    let scale = 0.5 * bins as f32 / width;
    let shift = cmin * (2.0 * scale);
    let bin_of = |it: &Item| {
        let k = (it.bounds[axis] + it.bounds[axis + 3]) * scale - shift;
        (k as i32).clamp(0, bins as i32 - 1) as usize
    };
    let side_box = |side: &[&Item]| {
        let mut b = EMPTY;
        side.iter().for_each(|it| union(&mut b, &it.bounds));
        b
    };
    let bins_box = |ks: &mut dyn Iterator<Item = usize>| {
        let mut b = EMPTY;
        for k in ks {
            let of_bin: Vec<&Item> = items.iter().filter(|it| bin_of(it) == k).collect();
            union(&mut b, &side_box(&of_bin));
        }
        b
    };
    let mut best: Option<(f64, usize, Vec<&Item>)> = None;
    for i in 0..bins - 1 {
        let (left, right): (Vec<&Item>, Vec<&Item>) = items.iter().partition(|it| bin_of(it) <= i);
        if left.is_empty() || right.is_empty() {
            continue;
        }
        let cost = half_area(&side_box(&left)) * left.len() as f64
            + half_area(&side_box(&right)) * right.len() as f64;
        if best.as_ref().is_none_or(|(c, _, _)| cost < *c) {
            best = Some((cost, i, left));
        }
    }
    let (cost, i, left) = best?;
    let area = half_area(&side_box(&items.iter().collect::<Vec<_>>()));
    if TRAVERSAL_COST * area + cost >= n as f64 * area && n <= MAX_LEAF {
        return None;
    }
    let mut ids: Vec<u32> = left.iter().map(|it| it.index()).collect();
    ids.sort_unstable();
    Some((
        ids,
        bins_box(&mut (0..=i)),
        bins_box(&mut (i + 1..bins).rev()),
    ))
}

#[test]
fn split_takes_the_cheapest_bin_boundary() {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(47);
    let (mut splits, mut leaves) = (0, 0);
    for case in 0..4000 {
        // Items in a few tight clusters, so that most bins stay empty, of
        // boxes from slivers to large.
        let n = if case % 2 == 0 {
            rng.random_range(2..=MAX_LEAF)
        } else {
            rng.random_range(2..=70)
        };
        let clusters: Vec<DVec3> = (0..rng.random_range(1..=4))
            .map(|_| DVec3::new(rng.random(), rng.random(), rng.random()) * 50.0)
            .collect();
        let spread = [1e-3, 0.1, 5.0][case % 3];
        // Some cases hold boxes whose lowest y is 0 or −0 (made directly:
        // padded boxes reach below 0): sides that join several must take
        // their bins in the sweeps' order.
        let zeros = case % 4 == 3;
        let items: Vec<Item> = (0..n)
            .filter_map(|i| {
                let c = clusters[rng.random_range(0..clusters.len())]
                    + DVec3::new(rng.random(), rng.random(), rng.random()) * spread;
                let h = DVec3::new(rng.random(), rng.random(), rng.random())
                    * 10f64.powf(rng.random_range(-3.0..0.5));
                if zeros && rng.random_bool(0.5) {
                    let zero = if rng.random_bool(0.5) { -0.0 } else { 0.0 };
                    let (lo, hi) = ((c - h).as_vec3(), (c + h).as_vec3());
                    let bounds = [lo.x, zero, lo.z, hi.x, hi.y.max(1.0), hi.z];
                    return Some(Item {
                        bounds,
                        index: i as u32,
                    });
                }
                Item::new(i as u32, &Aabb::from_points(c - h, c + h))
            })
            .collect();
        let want = cheapest_split(&items);
        let mut got = items.clone();
        let ext = Extents::of(&items);
        match (split(&mut got, &ext, 0), want) {
            (None, None) => leaves += 1,
            (Some((mid, left, right)), Some((ids, left_box, right_box))) => {
                let mut left_ids: Vec<u32> = got[..mid].iter().map(|it| it.index()).collect();
                left_ids.sort_unstable();
                assert_eq!(left_ids, ids, "case {case}: {items:?}");
                let bits = |b: [f32; 6]| b.map(f32::to_bits);
                assert_eq!(
                    (bits(left.bounds), bits(right.bounds)),
                    (bits(left_box), bits(right_box)),
                    "case {case}: {items:?}"
                );
                splits += 1;
            }
            (got, want) => panic!("case {case}: split {got:?}, cheapest {want:?}, {items:?}"), // invariant: a test's failure (split and the reference disagree)
        }
    }
    assert!(
        splits > 1000 && leaves > 100,
        "{splits} splits, {leaves} leaves"
    );
}

/// Centroids at 2^k: each SAH split peels off only the largest few, so
/// the tree gets deeper than [`SAH_MAX_DEPTH`].
fn deep_items() -> Vec<Item> {
    (-120..99)
        .flat_map(|k| {
            let x = 2f64.powi(k);
            [DVec3::new(x, 0.0, 0.0), DVec3::new(0.0, -x, 0.0)]
        })
        .enumerate()
        .map(|(i, c)| {
            Item::new(
                i as u32,
                &Aabb::from_points(c - c.abs() * 0.25, c + c.abs() * 0.25),
            )
        })
        .collect::<Option<_>>()
        .unwrap_or_default()
}

/// The wide tree, written in parallel at its top, is the same on one
/// thread or two, in arrays of exactly its size.
#[test]
fn same_wide_tree_on_one_or_two_threads() -> Result<(), rayon::ThreadPoolBuildError> {
    let items = sphere_items(50_000, 11);
    let n = items.len();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(|pool| pool.install(|| Bvh::build(items.clone(), n)))
    };
    let (a, b) = (on(1)?, on(2)?);
    assert!(a.wide.len() > 1000);
    assert_eq!(a.wide, b.wide);
    assert_eq!(a.parent, b.parent);
    assert_eq!(a.leaf_of, b.leaf_of);
    assert_eq!(a.wide.capacity(), a.wide.len());
    assert_eq!(a.parent.len(), a.wide.len());
    Ok(())
}

#[test]
fn upward_links_lead_from_every_leaf_to_the_root() {
    let items = sphere_items(5000, 4);
    let n = items.len();
    // One index left out of the tree: it has no leaf.
    let bvh = Bvh::build(items[1..].to_vec(), n);
    assert_eq!(bvh.leaf_of[items[0].index as usize], NO_LEAF);
    for it in &items[1..] {
        let (w, k) = split_slot(bvh.leaf_of[it.index as usize]);
        let (s, count) = (bvh.wide[w].child[k] as usize, bvh.wide[w].count[k] as usize);
        assert!(count > 0 && bvh.prims[s..s + count].contains(&it.index));
        // Up the parents: each holds the node as a child, and the root is reached.
        let (mut w, mut steps) = (w, 0);
        while bvh.parent[w] != ROOT {
            let (p, k) = split_slot(bvh.parent[w]);
            assert!(bvh.wide[p].count[k] == 0 && bvh.wide[p].child[k] as usize == w);
            w = p;
            steps += 1;
            assert!(steps < STACK_SIZE);
        }
        assert_eq!(w, 0);
    }
}

#[test]
fn depth_stays_within_the_stack() {
    let items = deep_items();
    assert_eq!(items.len(), 2 * 219, "every box is finite");
    let n = items.len();
    let bvh = Binary::build(items);
    let depth = depth_and_coverage(&bvh, n);
    assert!(
        depth > SAH_MAX_DEPTH,
        "the median fallback is not exercised"
    );
    assert!(depth < STACK_SIZE);
}

/// The build as it was before the two-pass one (every subtree got its
/// worst-case 2n − 2 slots, then the used ones were copied out), kept to
/// check that the tree did not change.
mod slot_build {
    use super::*;

    /// The tree over `items` as the slot build made it.
    pub(super) fn build(mut items: Vec<Item>) -> Binary {
        let n = items.len();
        if n == 0 {
            return Binary::default();
        }
        let ext = Extents::of(&items);
        let mut slots = vec![Node::default(); 2 * n - 1];
        let (root, count) = build_node(&mut items, 0, ext, 0, &mut slots[1..], 1);
        let prims = items.iter().map(|it| it.index).collect();
        let pairs = compact(root, &slots, count);
        Binary { pairs, prims }
    }

    /// Builds the subtree over `items` (the first is primitive `offset` of the
    /// final order, `ext` their extents) and returns its root and node count.
    ///
    /// Its descendants go into `desc`, whose first slot has index `base`: a
    /// subtree over n items has at most 2n − 2 descendants, so each subtree gets
    /// exactly that many slots and the two halves of a split can be built on
    /// different threads without sharing anything.
    fn build_node(
        items: &mut [Item],
        offset: u32,
        ext: Extents,
        depth: usize,
        desc: &mut [Node],
        base: u32,
    ) -> (Node, usize) {
        let n = items.len();
        let Some((mid, left_ext, right_ext)) = split(items, &ext, depth) else {
            let leaf = Node {
                bounds: ext.bounds,
                start: offset,
                count: n as u32,
            };
            return (leaf, 1);
        };
        let (pair, rest) = desc.split_at_mut(2);
        let (left_desc, right_desc) = rest.split_at_mut(2 * mid - 2);
        let (left, right) = items.split_at_mut(mid);
        let left_base = base + 2;
        let right_base = left_base + 2 * mid as u32 - 2;
        let right_offset = offset + mid as u32;
        // Sequential: the tree does not depend on the order halves are built in.
        let (l, nl) = build_node(left, offset, left_ext, depth + 1, left_desc, left_base);
        let (r, nr) = build_node(
            right,
            right_offset,
            right_ext,
            depth + 1,
            right_desc,
            right_base,
        );
        pair[0] = l;
        pair[1] = r;
        let interior = Node {
            bounds: ext.bounds,
            start: base,
            count: 0,
        };
        (interior, 1 + nl + nr)
    }

    /// The nodes reachable from `root` (children in `slots`), without the
    /// unused slots, as sibling pairs in depth-first order.
    fn compact(root: Node, slots: &[Node], count: usize) -> Vec<Pair> {
        let mut out = Vec::with_capacity(count.div_ceil(2));
        out.push(Pair([root, Node::default()]));
        let mut todo = vec![0u32];
        while let Some(k) = todo.pop() {
            let (p, c) = (k as usize >> 1, k as usize & 1);
            if out[p].0[c].count == 0 {
                let s = out[p].0[c].start as usize;
                let first = 2 * out.len() as u32;
                out.push(Pair([slots[s], slots[s + 1]]));
                out[p].0[c].start = first;
                todo.push(first + 1);
                todo.push(first);
            }
        }
        out
    }
}

/// Every field of every node, bounds as bits. (The boxes are now unions
/// taken in another order: equal values, but a zero bound could change
/// sign; the inputs here have none.)
fn node_bits(bvh: &Binary) -> Vec<[u32; 8]> {
    let bits = |n: &Node| {
        let b = n.bounds.map(f32::to_bits);
        [b[0], b[1], b[2], b[3], b[4], b[5], n.start, n.count]
    };
    bvh.pairs
        .iter()
        .flat_map(|p| [bits(&p.0[0]), bits(&p.0[1])])
        .collect()
}

/// Equal unit boxes centred on 7 points of a line `spread` apart (all
/// at one point for 0): centroids the SAH cannot separate.
fn degenerate_items(n: usize, spread: f64) -> Vec<Item> {
    (0..n)
        .filter_map(|i| {
            let c = DVec3::new(1.0 + spread * (i % 7) as f64, 2.0, 3.0);
            Item::new(i as u32, &Aabb::from_points(c - 0.5, c + 0.5))
        })
        .collect()
}

#[test]
fn same_tree_as_the_slot_build() -> Result<(), rayon::ThreadPoolBuildError> {
    let cases = [
        sphere_items(0, 2),
        sphere_items(1, 2),
        sphere_items(2, 3),
        sphere_items(9, 4),
        sphere_items(1000, 5),
        sphere_items(PARALLEL_MIN - 1, 6),
        sphere_items(PARALLEL_MIN, 7),
        sphere_items(70_000, 8),
        degenerate_items(10_000, 0.0),
        degenerate_items(10_000, 1e-3),
        deep_items(),
    ];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        for items in &cases {
            let (new, old) = pool.install(|| {
                (
                    Binary::build(items.clone()),
                    slot_build::build(items.clone()),
                )
            });
            let n = items.len();
            assert_eq!(new.pairs, old.pairs, "{n} items, {threads} threads");
            assert_eq!(node_bits(&new), node_bits(&old), "{n} items");
            assert_eq!(new.prims, old.prims, "{n} items");
            // The arrays are allocated at exactly their size.
            assert_eq!(new.pairs.capacity(), new.pairs.len());
            assert_eq!(new.prims.capacity(), n);
            if n > 0 {
                depth_and_coverage(&new, n);
            }
        }
    }
    Ok(())
}

#[test]
fn node_is_32_bytes() {
    assert_eq!(size_of::<Node>(), 32);
    assert_eq!(size_of::<Pair>(), 64);
}
