//! An [`Explanation`] as text for a terminal or as one JSON object (the
//! schema is in docs/debugging.md). Fans of glossy rays are summed up
//! (count, mean, spread) unless `expand` is asked for.

use super::pixel::{Explanation, ProgressiveTerm, Sampling};
use crate::integrator::{LightTerm, RayKind, RayNode};
use crate::render::verdict::{named, place};
use glam::DVec3;
use serde_json::{Value, json};
use std::fmt::Write;

/// A run of a node's children: one ray, or a glossy fan summed up.
enum Child<'a> {
    One(&'a RayNode),
    Fan(&'a [RayNode]),
}

/// How an explanation is shown: the scene file its places name, and
/// whether glossy fans and samples are listed ray by ray.
#[derive(Clone, Copy)]
struct Shown<'e> {
    file: Option<&'e str>,
    expand: bool,
}

/// A node's children, glossy fans grouped unless `expand`.
fn children(node: &RayNode, expand: bool) -> Vec<Child<'_>> {
    let mut out = Vec::new();
    let kids = &node.children;
    let mut i = 0;
    while i < kids.len() {
        let fan = matches!(kids[i].kind, RayKind::Glossy { .. });
        let end = if fan && !expand {
            i + kids[i..]
                .iter()
                .take_while(|c| matches!(c.kind, RayKind::Glossy { .. }))
                .count()
        } else {
            i + 1
        };
        out.push(if end - i > 1 {
            Child::Fan(&kids[i..end])
        } else {
            Child::One(&kids[i])
        });
        i = end;
    }
    out
}

/// Mean and per-channel standard deviation of the rays' colours, and their summed weight.
fn fan_stats(rays: &[RayNode]) -> (DVec3, DVec3, DVec3) {
    let n = rays.len().max(1) as f64;
    let mean = rays.iter().map(|r| r.color).sum::<DVec3>() / n;
    let var = rays
        .iter()
        .map(|r| (r.color - mean) * (r.color - mean))
        .sum::<DVec3>()
        / n;
    let weight = rays.iter().map(|r| r.weight).sum::<DVec3>();
    let v = var.max(DVec3::ZERO);
    (mean, DVec3::new(v.x.sqrt(), v.y.sqrt(), v.z.sqrt()), weight)
}

/// The kind's name: `camera`, `reflection`, `glossy`, `refraction`, `total_internal_reflection`.
fn kind_name(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Camera => "camera",
        RayKind::Reflection => "reflection",
        RayKind::Glossy { .. } => "glossy",
        RayKind::Refraction => "refraction",
        RayKind::TotalInternalReflection => "total_internal_reflection",
    }
}

/// A vector as a JSON array.
fn v3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

impl Shown<'_> {
    /// A light's term at a hit, as JSON.
    fn light_json(self, l: &LightTerm) -> Value {
        let file = self.file;
        json!({
            "light": l.light,
            "type": l.kind,
            "file": file,
            "line": l.line,
            "l_dot_n": l.l_dot_n,
            "shade": format!("{}/{}", l.reached, l.rays),
            "s": l.s,
            "diffuse": l.diffuse,
            "specular": l.specular,
            "blocker": l.blocker.as_ref().map(|b| json!({
                "primitive": b.primitive,
                "light": b.light,
                "type": b.kind,
                "file": file,
                "line": b.line,
                "t": b.t,
            })),
        })
    }

    /// A ray and its subtree, as JSON.
    fn node_json(self, node: &RayNode) -> Value {
        let file = self.file;
        let (k, n) = match node.kind {
            RayKind::Glossy { k, n } => (Some(k), Some(n)),
            _ => (None, None),
        };
        let kids: Vec<Value> = children(node, self.expand)
            .into_iter()
            .map(|c| match c {
                Child::One(c) => self.node_json(c),
                Child::Fan(rays) => {
                    let (mean, spread, weight) = fan_stats(rays);
                    json!({
                        "kind": "glossy_fan",
                        "depth": rays[0].depth,
                        "count": rays.len(),
                        "mean": v3(mean),
                        "spread": v3(spread),
                        "weight": v3(weight),
                    })
                }
            })
            .collect();
        json!({
            "kind": kind_name(node.kind),
            "k": k,
            "n": n,
            "depth": node.depth,
            "origin": v3(node.origin),
            "direction": v3(node.direction),
            "hit": node.hit.as_ref().map(|h| json!({
                "primitive": h.primitive,
                "light": h.light,
                "type": h.kind,
                "file": file,
                "line": h.line,
                "t": h.t,
                "point": v3(h.point),
                "normal": v3(h.normal),
                "front": h.front,
                "uv": [h.uv.x, h.uv.y],
            })),
            "material": node.material.map(|m| json!({
                "color": v3(m.color),
                "diff": m.diff,
                "spec": m.spec,
                "refl": m.refl,
                "drefl": m.drefl,
                "refr": m.refr,
                "rindex": m.rindex,
                "absor": v3(m.absor),
                "texture": m.texture,
            })),
            "lights": node.lights.iter().map(|l| self.light_json(l)).collect::<Vec<_>>(),
            "diffuse": node.lights.iter().map(|l| l.diffuse).sum::<f64>(),
            "specular": node.lights.iter().map(|l| l.specular).sum::<f64>(),
            "children": kids,
            "cut": node.cut.iter().map(|&k| kind_name(k)).collect::<Vec<_>>(),
            "photons": node.photons.as_ref().map(|p| json!({
                "gathered": p.gathered,
                "radius": p.radius,
                "term": v3(p.term),
            })),
            "unclamped": node.unclamped.map(v3),
            "clamped": node.unclamped.is_some_and(|u| u.max_element() > 1.0),
            "weight": v3(node.weight),
            "color": v3(node.color),
        })
    }

    /// A ray and its subtree, as text indented `indent` levels, into `out`.
    fn node_text(self, out: &mut String, node: &RayNode, indent: usize) {
        let file = self.file;
        let pad = "  ".repeat(indent);
        let kind = match node.kind {
            RayKind::Glossy { k, n } => format!("glossy {k} of {n}"),
            RayKind::TotalInternalReflection => "total internal reflection".to_string(),
            k => format!("{} ray", kind_name(k)),
        };
        let weight = if node.kind == RayKind::Camera {
            String::new()
        } else {
            format!("  weight {}", f(node.weight))
        };
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "{pad}{kind}  depth {}  O {}  D {}{weight}",
            node.depth,
            f(node.origin),
            f(node.direction)
        );
        match &node.hit {
            None => {
                let _ = writeln!(out, "{pad}  miss: nothing hit {}", f(node.color));
            }
            Some(h) => {
                let _ = writeln!(
                    out,
                    "{pad}  hit {}  t {:.4}  {}  P {}  N {}  uv ({:.4}, {:.4})",
                    named(h, file),
                    h.t,
                    if h.front { "front" } else { "back" },
                    f(h.point),
                    f(h.normal),
                    h.uv.x,
                    h.uv.y
                );
            }
        }
        if let Some(m) = node.material {
            let _ = writeln!(
                out,
                "{pad}  material  color {}  diff {}  spec {}  refl {}  drefl {}  refr {}  rindex {}  absor {}{}",
                f(m.color),
                m.diff,
                m.spec,
                m.refl,
                m.drefl,
                m.refr,
                m.rindex,
                f(m.absor),
                if m.texture.is_some() {
                    "  textured"
                } else {
                    ""
                }
            );
        }
        for l in &node.lights {
            let at = place(file, l.line);
            let what = if l.l_dot_n <= 0.0 {
                "-> faces away: no diffuse, no specular".to_string()
            } else if l.s <= 0.0 {
                match &l.blocker {
                    Some(b) => format!(
                        "shade 0/{} -> blocked by {} #{} ({}) at t {:.4}",
                        l.rays,
                        b.kind,
                        b.primitive.or(b.light).unwrap_or(0),
                        place(file, b.line),
                        b.t
                    ),
                    None => format!("shade 0/{} -> in shadow", l.rays),
                }
            } else {
                format!(
                    "shade {}/{}  diffuse {:.4}  specular {:.4}",
                    l.reached, l.rays, l.diffuse, l.specular
                )
            };
            let _ = writeln!(
                out,
                "{pad}  light #{} {}  {at}  L·N {:.4}  {what}",
                l.light, l.kind, l.l_dot_n
            );
        }
        for c in children(node, self.expand) {
            match c {
                Child::One(c) => self.node_text(out, c, indent + 1),
                Child::Fan(rays) => {
                    let (mean, spread, weight) = fan_stats(rays);
                    let _ = writeln!(
                        out,
                        "{pad}  glossy fan  depth {}  {} rays  mean {}  spread {}  weight {}  (--expand lists them)",
                        rays[0].depth,
                        rays.len(),
                        f(mean),
                        f(spread),
                        f(weight)
                    );
                }
            }
        }
        for k in &node.cut {
            let _ = writeln!(
                out,
                "{pad}  {} ray not traced: depth limit 10",
                kind_name(*k)
            );
        }
        if let Some(p) = &node.photons {
            let none = if p.gathered < 8 {
                " (fewer than 8: no estimate)"
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "{pad}  photons: {} gathered within r = {:.4}{none}, adding {}",
                p.gathered,
                p.radius,
                f(p.term)
            );
        }
        if let Some(u) = node.unclamped {
            let clamp = if u.max_element() > 1.0 {
                "  clamped to 1"
            } else {
                ""
            };
            let _ = writeln!(out, "{pad}  sum {}{clamp}", f(u));
        }
        let _ = writeln!(out, "{pad}  = {}", f(node.color));
    }
}

/// A vector as the text report shows it.
fn f(v: DVec3) -> String {
    format!("({:.4}, {:.4}, {:.4})", v.x, v.y, v.z)
}

impl Explanation {
    /// How the render sampled the pixel, in words.
    fn sampling_text(&self) -> String {
        match self.sampling {
            Sampling::Adaptive { refined: false } => {
                "1 sample; the anti-aliasing left it alone".to_string()
            }
            Sampling::Adaptive { refined: true } => {
                "49 samples: the 7x7 grid, because a neighbour's hash differs".to_string()
            }
            Sampling::Stratified(1) => "1 sample through the centre (--spp 1)".to_string(),
            Sampling::Stratified(n) => format!("{n} stratified samples (--spp {n})"),
            Sampling::Fresh(n) => {
                format!("SPPM: {n} samples, one jittered over the pixel an iteration")
            }
        }
    }

    /// The explanation as text: the first sample's tree (every sample's with
    /// `expand`), the bytes and the verdict.
    pub fn to_text(&self, expand: bool) -> String {
        let shown_as = Shown {
            file: self.file.as_deref(),
            expand,
        };
        let [r, g, b] = self.bytes;
        let c = self.color;
        let mut out = format!(
            "pixel ({}, {}) -> bytes {r} {g} {b}   colour ({}, {}, {})   ({})\n",
            self.pixel.0,
            self.pixel.1,
            c[0],
            c[1],
            c[2],
            self.sampling_text()
        );
        let shown = if expand { self.samples.len() } else { 1 };
        for (i, s) in self.samples.iter().take(shown).enumerate() {
            if self.samples.len() > 1 {
                let _ = writeln!(out, "sample {} of {}:", i + 1, self.samples.len());
            }
            shown_as.node_text(&mut out, s, 0);
        }
        if shown < self.samples.len() {
            let _ = writeln!(
                out,
                "... {} more samples (--expand shows them)",
                self.samples.len() - shown
            );
        }
        if let Some(p) = &self.progressive {
            progressive_text(&mut out, p);
        }
        let _ = writeln!(out, "verdict: {}", self.verdict);
        out
    }

    /// The explanation as one JSON object (no non-finite number: those are `null`).
    pub fn to_json(&self, expand: bool) -> String {
        let file = self.file.as_deref();
        let shown = Shown { file, expand };
        let (mode, refined, spp) = match self.sampling {
            Sampling::Adaptive { refined } => ("adaptive", Some(refined), None),
            Sampling::Stratified(n) => ("stratified", None, Some(n)),
            Sampling::Fresh(n) => ("sppm", None, Some(n)),
        };
        let c = self.color;
        json!({
            "pixel": [self.pixel.0, self.pixel.1],
            "bytes": self.bytes,
            "color": [c[0], c[1], c[2]],
            "sampling": {"mode": mode, "refined": refined, "spp": spp},
            "file": file,
            "samples": self.samples.iter().map(|s| shown.node_json(s)).collect::<Vec<_>>(),
            "progressive": self.progressive.as_ref().map(|p| json!({
                "algorithm": p.algorithm.name(),
                "iterations": p.iterations,
                "emitted": p.emitted,
                "direct": p.direct,
                "points": p.points.iter().map(|h| json!({
                    "point": h.point.map(v3),
                    "weight": v3(h.weight),
                    "radius": h.radius,
                    "photons": h.photons,
                    "term": v3(h.term),
                })).collect::<Vec<_>>(),
            })),
            "verdict": self.verdict,
        })
        .to_string()
    }
}

/// PPM's or SPPM's photon term of a pixel, as text: its hit points and
/// what each adds to the ray-traced part.
fn progressive_text(out: &mut String, p: &ProgressiveTerm) {
    let direct = DVec3::from(p.direct.map(f64::from));
    let _ = writeln!(
        out,
        "photons ({}, {} iterations of {} photons): the ray-traced part {}",
        p.algorithm.name().to_uppercase(),
        p.iterations,
        p.emitted,
        f(direct)
    );
    if p.points.is_empty() {
        let _ = writeln!(out, "  no diffuse hit: no photon term");
    }
    for h in &p.points {
        let at = h
            .point
            .map_or("the pixel's running estimate".to_string(), |v| {
                format!("hit point at {}", f(v))
            });
        let _ = writeln!(
            out,
            "  {at}, weight {}: {:.1} photons within R = {:.4}, adding {}",
            f(h.weight),
            h.photons,
            h.radius,
            f(h.term)
        );
    }
}
