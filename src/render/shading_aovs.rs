//! The AOVs of the camera hit: its surface (`normal`, `depth`,
//! `position`, `uv`, `primitive`, `albedo`) and its shading (`light:N`,
//! `shade`, `why`, `clamp`, `photons`), tallied by a small observer
//! ([`LightTally`], no allocation) as pass 1 traces each pixel's centre
//! sample, so every value is the one the render computed at that hit (and
//! no ray is traced again for them); refined pixels are described by their
//! centre sample too. With `--spp` above 1 pass 1 traces no centre sample,
//! and the tally traces it apart (one more ray per pixel and its shadow rays).

use super::aov::{Aov, albedo};
use super::verdict::{Cause, FirstHit, LightCounts, kind};
use crate::geometry::{Hit, Ray, Shape};
use crate::integrator::photons::Gathered;
use crate::integrator::{LightSeen, NoObserver, PathObserver, RayKind, SurfaceSeen};
use crate::scene::{Material, Origin, Scene};
use glam::{DVec2, DVec3};

/// `light:N` AOVs one render takes at most (the tally keeps their terms inline).
pub const LIGHT_AOVS_MAX: usize = 8;

/// What the camera ray of one sample met, and its shading there: what the
/// shading AOVs show. Only the camera ray's own hit is tallied (the rays
/// it spawns are not).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LightTally {
    /// The lights whose terms are kept (the `light:N` AOVs asked for).
    wanted: [u32; LIGHT_AOVS_MAX],
    /// How many of `wanted` are in use.
    wanted_len: usize,
    /// Rays begun and not yet done (the camera ray alone: 1).
    open: u32,
    /// Whether the camera ray hit an area light's surface.
    emitter: bool,
    /// The material at the camera ray's hit on a primitive.
    material: Option<Material>,
    /// The texture coordinates there (found only where a light term is
    /// kept and the material is textured: what the albedo needs).
    uv: DVec2,
    /// Each wanted light's diffuse + specular weight (`None`: not computed).
    terms: [Option<f64>; LIGHT_AOVS_MAX],
    /// The lights counted as the verdict counts them.
    lights: LightCounts,
    /// The sum and the smallest of the shade factors of the lights faced.
    shade_sum: f64,
    shade_min: f64,
    /// The camera ray's sum before the clamp.
    unclamped: Option<DVec3>,
    /// The photon term at the camera ray's hit (PM).
    photons: DVec3,
    /// Whether an AOV of the hit's surface is wanted (normal, depth...).
    geometry: bool,
    /// The block or light the camera ray hit.
    origin: Option<Origin>,
    /// The camera ray's hit, where an AOV of its surface is wanted.
    surface: Option<FirstSurface>,
}

/// The camera ray's hit, as the AOVs of its surface show it.
#[derive(Clone, Copy, Debug)]
struct FirstSurface {
    /// The distance along the ray.
    t: f64,
    /// The point.
    point: DVec3,
    /// The unit geometric normal, turned against the ray.
    normal: DVec3,
    /// Texture coordinates.
    uv: DVec2,
}

impl FirstSurface {
    fn of(shape: &Shape, ray: &Ray, hit: &Hit) -> Self {
        let s = shape.surface(ray, hit);
        FirstSurface {
            t: hit.t,
            point: s.point,
            normal: if s.normal.dot(ray.dir) < 0.0 {
                s.normal
            } else {
                -s.normal
            },
            uv: s.uv,
        }
    }
}

impl LightTally {
    /// A tally keeping the terms of `lights` (and the hit's surface when
    /// `geometry`); `Err(their number)` past [`LIGHT_AOVS_MAX`].
    fn new(lights: &[u32], geometry: bool) -> Result<Self, usize> {
        if lights.len() > LIGHT_AOVS_MAX {
            return Err(lights.len());
        }
        let mut tally = LightTally {
            wanted_len: lights.len(),
            shade_min: f64::INFINITY,
            geometry,
            ..LightTally::default()
        };
        tally.wanted[..lights.len()].copy_from_slice(lights);
        Ok(tally)
    }

    /// Whether the event seen now is the camera ray's own.
    #[inline(always)]
    fn at_camera(&self) -> bool {
        self.open == 1
    }

    /// What the camera ray met, as the verdict reads it.
    fn first(&self) -> FirstHit<'_> {
        match (&self.material, self.emitter) {
            (_, true) => FirstHit::Light,
            (Some(m), false) => FirstHit::Surface(Some(m)),
            (None, false) => FirstHit::Nothing,
        }
    }
}

impl PathObserver for LightTally {
    type Fan<'s> = NoObserver;

    #[inline(always)]
    fn fan(&mut self) -> NoObserver {
        NoObserver
    }

    type Queries<'q> = ();

    #[inline(always)]
    fn queries(&mut self) {}

    #[inline(always)]
    fn hit(&mut self, origin: Origin) {
        if self.at_camera() {
            self.origin = Some(origin);
        }
    }

    #[inline(always)]
    fn point_light(&mut self, _: u32) {}

    #[inline(always)]
    fn ray(&mut self, _: RayKind, _: u32, _: &Ray) {
        self.open += 1;
    }

    #[inline(always)]
    fn surface(&mut self, seen: &SurfaceSeen<'_>) {
        if self.at_camera() {
            self.material = Some(*seen.material);
            if self.geometry {
                let first = FirstSurface::of(seen.shape, seen.ray, seen.hit);
                self.uv = first.uv;
                self.surface = Some(first);
            } else if self.wanted_len > 0 && seen.material.texture.is_some() {
                self.uv = seen.shape.surface(seen.ray, seen.hit).uv;
            }
        }
    }

    #[inline(always)]
    fn emitter(&mut self, _: u32, shape: &Shape, ray: &Ray, hit: &Hit) {
        if self.at_camera() {
            self.emitter = true;
            if self.geometry {
                self.surface = Some(FirstSurface::of(shape, ray, hit));
            }
        }
    }

    #[inline(always)]
    fn light(&mut self, seen: &LightSeen) {
        if !self.at_camera() {
            return;
        }
        self.lights.add(seen.l_dot_n, seen.s);
        if seen.l_dot_n > 0.0 {
            self.shade_sum += seen.s;
            self.shade_min = self.shade_min.min(seen.s);
        }
        let wanted = &self.wanted[..self.wanted_len];
        if let Some(k) = wanted.iter().position(|&l| l == seen.light) {
            self.terms[k].get_or_insert(seen.diffuse + seen.specular);
        }
    }

    #[inline(always)]
    fn shaded(&mut self, sum: DVec3) {
        if self.at_camera() {
            self.unclamped = Some(sum);
        }
    }

    #[inline(always)]
    fn photons(&mut self, _: &Gathered, term: DVec3) {
        if self.at_camera() {
            self.photons = term;
        }
    }

    #[inline(always)]
    fn done(&mut self, _: DVec3, _: DVec3) {
        self.open = self.open.saturating_sub(1);
    }
}

/// The shading AOVs a render was asked for, and the tally that gathers them.
pub(crate) struct ShadingAovs<'a> {
    aovs: Vec<Aov>,
    scene: &'a Scene,
    fresh: LightTally,
}

impl<'a> ShadingAovs<'a> {
    /// The shading AOVs of `aovs` over `scene` (`None` when there are
    /// none); `Err(their number)` for more `light:N` than [`LIGHT_AOVS_MAX`].
    pub fn of(aovs: &[Aov], scene: &'a Scene) -> Result<Option<Self>, usize> {
        let aovs: Vec<Aov> = aovs.iter().copied().filter(|a| a.shaded()).collect();
        if aovs.is_empty() {
            return Ok(None);
        }
        let lights: Vec<u32> = aovs
            .iter()
            .filter_map(|a| match a {
                Aov::Light(n) => Some(*n),
                _ => None,
            })
            .collect();
        let geometry = aovs.iter().any(|a| a.of_surface());
        let fresh = LightTally::new(&lights, geometry)?;
        Ok(Some(ShadingAovs { aovs, scene, fresh }))
    }

    /// The AOVs, in the order asked for.
    pub fn aovs(&self) -> &[Aov] {
        &self.aovs
    }

    /// A fresh tally, for a camera sample.
    pub fn tally(&self) -> &LightTally {
        &self.fresh
    }

    /// Pixel `i`'s values of the AOVs, from its centre sample's tally
    /// `t`, into `planes` (one an AOV, in the order of [`Self::aovs`]).
    pub fn fill(&self, planes: &mut [&mut [f32]], i: usize, t: &LightTally) {
        for (plane, &aov) in planes.iter_mut().zip(&self.aovs) {
            let c = aov.channels();
            let out = &mut plane[i * c..][..c];
            let put = |out: &mut [f32], v: DVec3| {
                out.copy_from_slice(&v.as_vec3().to_array()[..out.len()]);
            };
            match aov {
                Aov::Light(n) => put(out, self.light_term(t, n)),
                Aov::Shade if t.lights.facing > 0 => {
                    out[0] = (t.shade_sum / f64::from(t.lights.facing)) as f32;
                    out[1] = t.shade_min as f32;
                }
                Aov::Why => {
                    let kind = kind(t.first(), t.lights);
                    out[0] = Cause::ALL.iter().position(|&c| c == kind).unwrap_or(0) as f32;
                }
                Aov::Clamp => {
                    let over = t
                        .unclamped
                        .map_or(DVec3::ZERO, |u| (u - DVec3::ONE).max(DVec3::ZERO));
                    put(out, over);
                }
                Aov::Photons => put(out, t.photons),
                Aov::Primitive => {
                    out[0] = match t.origin {
                        Some(Origin::Block(b)) => b as f32,
                        Some(Origin::Light(l)) => -2.0 - l as f32,
                        None => -1.0,
                    }
                }
                Aov::Albedo => {
                    if let (Some(m), false) = (&t.material, t.emitter) {
                        put(out, albedo(self.scene, m, t.uv));
                    }
                }
                Aov::Normal | Aov::Depth | Aov::Position | Aov::Uv => {
                    if let Some(f) = &t.surface {
                        let v = match aov {
                            Aov::Normal => f.normal.to_array(),
                            Aov::Position => f.point.to_array(),
                            Aov::Uv => [f.uv.x, f.uv.y, 0.0],
                            _ => [f.t, 0.0, 0.0],
                        };
                        out.iter_mut().zip(v).for_each(|(o, v)| *o = v as f32);
                    }
                }
                Aov::Shade | Aov::Rays | Aov::Cost => {}
            }
        }
    }

    /// Light `n`'s diffuse and specular at the camera ray's hit: colour ×
    /// texture × the light's colour × (diffuse + specular weight), as the
    /// shading sums it (zero where it faces away or is blocked).
    fn light_term(&self, t: &LightTally, n: u32) -> DVec3 {
        let (Some(m), false) = (&t.material, t.emitter) else {
            return DVec3::ZERO;
        };
        let Some(light) = self.scene.lights().get(n as usize) else {
            return DVec3::ZERO;
        };
        let wanted = &t.wanted[..t.wanted_len];
        let term = wanted.iter().position(|&l| l == n).and_then(|k| t.terms[k]);
        term.map_or(DVec3::ZERO, |w| {
            albedo(self.scene, m, t.uv) * light.color * w
        })
    }
}
