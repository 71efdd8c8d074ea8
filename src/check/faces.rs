//! Flat faces: coincident faces (two faces in one plane that overlap: the
//! nearer of the two flips from pixel to pixel), squares whose edges miss
//! each other (the cracks of a cube built from six squares), and shapes
//! too degenerate to be seen.

use super::finding::{Code, Findings};
use super::primitive_blocks::{PrimitiveBlock, name};
use crate::geometry::Shape;
use crate::render::Renderer;
use glam::DVec3;
use std::collections::{BTreeSet, HashMap};

/// A gap between edges is a crack below this share of the shorter edge
/// (above it the squares are apart on purpose) ...
pub const GAP_MAX_SHARE: f64 = 0.05;
/// ... and above this share of it (below it, rounding).
pub const GAP_MIN_SHARE: f64 = 1e-6;

/// A triangle is degenerate when its height over its longest edge is below
/// this share of that edge (its corners are collinear, to rounding).
pub const FLAT_SHARE: f64 = 1e-9;

/// A flat face: a square, a cube's face, or a plane (`dx`, `dy` zero).
struct Face {
    block: u32,
    center: DVec3,
    dx: DVec3,
    dy: DVec3,
    /// Unit normal (a cube face's points outward).
    normal: DVec3,
    /// Whether it is a face of a cube (a solid's outside).
    solid: bool,
    plane: bool,
}

/// The faces of the scene's squares, cubes and planes.
fn faces(renderer: &Renderer, blocks: &[PrimitiveBlock]) -> Vec<Face> {
    let objects = renderer.accel().objects();
    let mut out = Vec::new();
    for b in blocks {
        for &i in &b.objects {
            match objects[i as usize].shape() {
                Shape::Square(s) => out.push(Face {
                    block: b.index,
                    center: s.center,
                    dx: s.dx,
                    dy: s.dy,
                    normal: s.normal,
                    solid: false,
                    plane: false,
                }),
                Shape::Plane(p) => out.push(Face {
                    block: b.index,
                    center: p.normal * p.offset,
                    dx: DVec3::ZERO,
                    dy: DVec3::ZERO,
                    normal: p.normal,
                    solid: false,
                    plane: true,
                }),
                Shape::Cube(c) => {
                    for a in 0..3 {
                        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
                        for sign in [1.0, -1.0] {
                            out.push(Face {
                                block: b.index,
                                center: c.center + c.axes[a] * (c.half[a] * sign),
                                dx: c.axes[u] * c.half[u],
                                dy: c.axes[v] * c.half[v],
                                normal: c.axes[a] * sign,
                                solid: true,
                                plane: false,
                            });
                        }
                    }
                }
                _ => {}
            }
        }
    }
    out
}

/// The size of the scene: the largest side of its bounded objects' box (at least 1).
fn scale(blocks: &[PrimitiveBlock]) -> f64 {
    let mut size: f64 = 1.0;
    for b in blocks {
        if let Some(a) = b.bounds.filter(|a| !a.is_empty()) {
            let d = a.max - a.min;
            if d.is_finite() {
                size = size.max(d.max_element());
            }
        }
    }
    size
}

/// `n` or `−n`, whichever has its first non-zero component positive.
fn canonical(n: DVec3) -> DVec3 {
    let first = [n.x, n.y, n.z]
        .into_iter()
        .find(|c| c.abs() > 1e-9)
        .unwrap_or(0.0);
    if first < 0.0 { -n } else { n }
}

/// Whether two coplanar faces overlap over more than a sliver `eps` wide.
fn overlap(a: &Face, b: &Face, eps: f64) -> bool {
    if a.plane || b.plane {
        return true;
    }
    let n = a.normal;
    let d = b.center - a.center;
    [a.dx, a.dy, b.dx, b.dy].iter().all(|e| {
        let u = n.cross(*e).normalize_or_zero();
        let r = |f: &Face| f.dx.dot(u).abs() + f.dy.dot(u).abs();
        u == DVec3::ZERO || d.dot(u).abs() < r(a) + r(b) - eps
    })
}

/// The face lints.
pub(crate) fn check(renderer: &Renderer, blocks: &[PrimitiveBlock], out: &mut Findings) {
    let size = scale(blocks);
    let eps = 1e-6 * size;
    let eye = renderer.scene().camera().origin;
    let name_of = |b: u32| {
        blocks
            .iter()
            .find(|k| k.index == b)
            .map_or_else(|| format!("#{b}"), name)
    };
    let file = out.file.clone();
    let place = |b: u32| crate::render::place(file.as_deref(), renderer.scene().block_line(b));

    // Coincident faces, bucketed by plane (normal and offset, quantised).
    let all = faces(renderer, blocks);
    let key = |f: &Face| {
        let n = canonical(f.normal);
        let q = |v: f64| (v * 1e6).round() as i64;
        (
            q(n.x),
            q(n.y),
            q(n.z),
            (n.dot(f.center) / eps).round() as i64,
        )
    };
    let mut buckets: HashMap<(i64, i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, f) in all.iter().enumerate() {
        buckets.entry(key(f)).or_default().push(i);
    }
    let mut pairs = BTreeSet::new();
    for (i, a) in all.iter().enumerate() {
        let (x, y, z, o) = key(a);
        for off in [o - 1, o, o + 1] {
            for &j in buckets.get(&(x, y, z, off)).into_iter().flatten() {
                let b = &all[j];
                if j <= i || a.block == b.block {
                    continue;
                }
                let (na, nb) = (canonical(a.normal), canonical(b.normal));
                let coplanar =
                    na.dot(nb) > 1.0 - 1e-9 && (na.dot(a.center) - nb.dot(b.center)).abs() < eps;
                // Two boxes that touch: their shared faces face each other, hidden.
                let touching = a.solid && b.solid && a.normal.dot(b.normal) < 0.0;
                // A box's face is seen only from outside it: a box resting on
                // a floor hides the floor's part under it from a camera above.
                let seen = |f: &Face| !f.solid || (eye - f.center).dot(f.normal) > 0.0;
                if coplanar && !touching && seen(a) && seen(b) && overlap(a, b, eps) {
                    pairs.insert((a.block.min(b.block), a.block.max(b.block)));
                }
            }
        }
    }
    for (a, b) in pairs {
        let (na, nb) = (name_of(a), name_of(b));
        let at = place(b);
        out.block(
            Code::CoincidentFaces,
            a,
            format!("{na} and {nb} ({at}) have faces in the same plane that overlap: which one a ray sees flips from pixel to pixel (speckles)"),
            "move one of them apart by a little (e.g. 1e-3 along its normal), or remove one".to_string(),
        );
    }

    // Squares that should share an edge but miss it: pairs roughly at
    // right angles whose boxes (grown by the largest gap) overlap.
    let squares: Vec<&Face> = all.iter().filter(|f| !f.solid && !f.plane).collect();
    let grown: Vec<(DVec3, DVec3)> = squares
        .iter()
        .map(|f| {
            let half = f.dx.abs() + f.dy.abs();
            let pad = DVec3::splat(2.0 * GAP_MAX_SHARE * f.dx.length().max(f.dy.length()));
            (f.center - half - pad, f.center + half + pad)
        })
        .collect();
    let mut order: Vec<usize> = (0..squares.len()).collect();
    order.sort_by(|&i, &j| grown[i].0.x.total_cmp(&grown[j].0.x));
    let mut gaps = BTreeSet::new();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if grown[j].0.x > grown[i].1.x {
                break;
            }
            let (a, b) = (squares[i], squares[j]);
            let boxes = grown[i].0.cmple(grown[j].1).all() && grown[j].0.cmple(grown[i].1).all();
            if !boxes || a.block == b.block || a.normal.dot(b.normal).abs() > 0.1 {
                continue;
            }
            if let Some(g) = edge_gap(a, b) {
                let pair = (a.block.min(b.block), a.block.max(b.block));
                gaps.insert((pair, g.to_bits()));
            }
        }
    }
    let mut said = BTreeSet::new();
    for ((a, b), g) in gaps {
        if !said.insert((a, b)) {
            continue;
        }
        let g = f64::from_bits(g);
        let (na, nb) = (name_of(a), name_of(b));
        let at = place(b);
        out.block(
            Code::EdgeGap,
            a,
            format!("{na} and {nb} ({at}) nearly share an edge but miss it by {g:.3e}: rays pass through the crack (the background shows through a cube made of squares)"),
            "make the half-edges (`Dx=`, `Dy=`) reach the neighbouring face exactly, or use one `primitive cube`".to_string(),
        );
    }

    // Degenerate shapes: zero-area triangles; shapes too small for any ray.
    let objects = renderer.accel().objects();
    for b in blocks {
        let flat = b
            .objects
            .iter()
            .filter(|&&i| match objects[i as usize].shape() {
                Shape::Triangle(t) => {
                    let [a, b, c] = t.vertices;
                    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
                    // Flat: the height over the longest edge is nothing beside it.
                    t.double_area() <= FLAT_SHARE * longest * longest
                }
                _ => false,
            })
            .count();
        let what = name(b);
        if flat > 0 {
            out.block(
                Code::Degenerate,
                b.index,
                format!("{what} has {flat} of its {} triangles with (almost) no area: no ray hits them", b.objects.len()),
                "remove the collapsed faces from the mesh (most modelling tools can: 'merge by distance', 'degenerate dissolve')".to_string(),
            );
        } else if let Some(a) = b.bounds.filter(|a| !a.is_empty())
            && (a.max - a.min).max_element() < 1e-9 * size
        {
            out.block(
                Code::Degenerate,
                b.index,
                format!("{what} is {:.1e} across in a scene {size:.3} across: too small for any ray to hit", (a.max - a.min).max_element()),
                "check its size keys (`R=`, `Dx=`, `x=`...)".to_string(),
            );
        }
    }
}

/// The distance between the nearest pair of parallel, overlapping edges of
/// squares `a` and `b`, when it is a crack (see [`GAP_MAX_SHARE`]).
fn edge_gap(a: &Face, b: &Face) -> Option<f64> {
    let edges = |f: &Face| {
        [
            (f.center + f.dx, f.dy),
            (f.center - f.dx, f.dy),
            (f.center + f.dy, f.dx),
            (f.center - f.dy, f.dx),
        ]
    };
    let shortest = [a.dx, a.dy, b.dx, b.dy]
        .iter()
        .map(|e| 2.0 * e.length())
        .fold(f64::INFINITY, f64::min);
    let mut best: Option<f64> = None;
    for (ma, ea) in edges(a) {
        for (mb, eb) in edges(b) {
            let (ua, ha) = (ea.normalize_or_zero(), ea.length());
            if ua.dot(eb.normalize_or_zero()).abs() < 1.0 - 1e-9 {
                continue;
            }
            let d = mb - ma;
            let along = d.dot(ua);
            if along.abs() >= ha + eb.length() {
                continue;
            }
            let g = (d - ua * along).length();
            best = Some(best.map_or(g, |x: f64| x.min(g)));
        }
    }
    best.filter(|&g| g > GAP_MIN_SHARE * shortest && g < GAP_MAX_SHARE * shortest)
}
