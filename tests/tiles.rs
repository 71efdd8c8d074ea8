//! A render cut into parts (`RenderOptions::tile`) and pasted back
//! together (`Film::assemble`) is the whole render, value for value:
//! random frames, part counts and regions, with the adaptive
//! anti-aliasing, `--spp`, AOVs, and under PM, PPM and SPPM.

use glint::{
    Aov, AssembleError, Control, Film, PhotonMode, PhotonOptions, Region, RenderError,
    RenderOptions, Renderer, Scene, TILE_BAND, Tile,
};
use proptest::prelude::*;

/// Every kind of event the anti-aliasing sees.
const SCENE: &str = include_str!("data/events.txt");

/// A glass ball on a floor: caustics for PM, PPM and SPPM.
const GLASS: &str = include_str!("data/glass.txt");

fn renderer(text: &str) -> Renderer {
    Renderer::new(Scene::parse(text, ".").unwrap_or_else(|e| panic!("parses:\n{e}")))
}

/// The whole render's film.
fn whole(r: &Renderer, o: &RenderOptions) -> Film {
    r.render(o).unwrap_or_else(|e| panic!("renders: {e}"))
}

/// Every part of `count` rendered alone, pasted together.
fn pasted(r: &Renderer, o: &RenderOptions, count: u32) -> Film {
    let (w, h) = r.frame_size(o).expect("a valid size");
    let region = o.region.unwrap_or(Region::full(w, h));
    let mut parts = Vec::new();
    for index in 0..count {
        let part = RenderOptions {
            tile: Some(Tile { index, count }),
            ..o.clone()
        };
        let (films, _) = r
            .render_parts(&part, Control::default())
            .unwrap_or_else(|e| panic!("part {index}/{count}: {e}"));
        // Each film is a run of the part's bands, full width.
        for f in &films {
            assert_eq!((f.region().x, f.region().width), (region.x, region.width));
            assert_eq!((f.region().y - region.y) / TILE_BAND % count, index);
        }
        parts.extend(films);
    }
    Film::assemble((w, h), region, parts).unwrap_or_else(|e| panic!("assembles: {e}"))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(30),
        ..ProptestConfig::default()
    })]

    /// Any frame, part count and region: the pasted parts are the whole
    /// render's values, colour and AOVs, with either sampling.
    #[test]
    fn parts_pasted_together_are_the_whole_render(
        w in 1u32..40, h in 1u32..110, count in 1u32..7,
        spp in prop::sample::select(vec![None, Some(2)]),
        seed in 0u64..3,
        cut in prop::option::of((0.0..1.0f64, 0.0..1.0f64)),
    ) {
        let r = renderer(SCENE);
        let region = cut.map(|(fy, fh)| {
            let y = ((h as f64 * fy) as u32).min(h - 1);
            Region { x: 0, y, width: w, height: 1 + ((h - y - 1) as f64 * fh) as u32 }
        });
        let o = RenderOptions {
            width: Some(w),
            height: Some(h),
            spp,
            seed,
            region,
            threads: Some(2),
            aovs: vec![Aov::Normal, Aov::Rays, Aov::Cost, Aov::Why],
            ..RenderOptions::default()
        };
        prop_assert_eq!(pasted(&r, &o, count), whole(&r, &o));
    }
}

#[test]
fn photon_renders_cut_into_parts_are_the_whole_render() {
    let r = renderer(GLASS);
    for mode in [PhotonMode::Pm, PhotonMode::Ppm, PhotonMode::Sppm] {
        for (count, spp) in [(2, None), (3, Some(2)), (5, None)] {
            let o = RenderOptions {
                width: Some(40),
                height: Some(100),
                spp,
                seed: 7,
                threads: Some(2),
                aovs: vec![Aov::Photons],
                photons: PhotonOptions {
                    mode: Some(mode),
                    iterations: Some(3),
                    emit: Some(20_000),
                    ..PhotonOptions::default()
                },
                ..RenderOptions::default()
            };
            assert_eq!(
                pasted(&r, &o, count),
                whole(&r, &o),
                "{mode:?}, {count} parts, spp {spp:?}"
            );
        }
    }
}

#[test]
fn a_part_renders_only_its_bands_and_more_parts_than_bands_are_empty() {
    let r = renderer(SCENE);
    let o = RenderOptions {
        width: Some(20),
        height: Some(70), // bands of 32, 32 and 6 rows
        spp: Some(1),
        tile: Some(Tile { index: 1, count: 2 }),
        ..RenderOptions::default()
    };
    let (films, stats) = r.render_parts(&o, Control::default()).expect("renders");
    let rows: Vec<_> = films
        .iter()
        .map(|f| (f.region().y, f.region().height))
        .collect();
    assert_eq!(rows, vec![(32, 32)]);
    assert_eq!(stats.rays.camera, 20 * 32); // one ray a pixel of its band
    // A whole film of a part is refused: it has parts.
    assert!(matches!(
        r.render_with(&o, Control::default()),
        Err(RenderError::Parts { .. })
    ));
    let empty = RenderOptions {
        tile: Some(Tile { index: 5, count: 6 }),
        ..o
    };
    let (films, stats) = r.render_parts(&empty, Control::default()).expect("renders");
    assert!(films.is_empty());
    assert_eq!(stats.rays.total(), 0);
}

#[test]
fn parts_that_overlap_or_leave_a_gap_do_not_assemble() {
    let r = renderer(SCENE);
    let o = |index, count| RenderOptions {
        width: Some(10),
        height: Some(70),
        spp: Some(1),
        tile: Some(Tile { index, count }),
        ..RenderOptions::default()
    };
    let part = |index, count| {
        r.render_parts(&o(index, count), Control::default())
            .expect("renders")
            .0
    };
    let full = Region::full(10, 70);
    let gap = Film::assemble((10, 70), full, part(0, 2));
    assert_eq!(gap, Err(AssembleError::Missing { x: 0, y: 32 }));
    let mut twice = part(0, 2);
    twice.extend(part(1, 2));
    twice.extend(part(0, 3)); // rows 0..32 again
    assert_eq!(
        Film::assemble((10, 70), full, twice),
        Err(AssembleError::Twice { x: 0, y: 0 })
    );
    let other = Film::assemble((10, 71), Region::full(10, 71), part(0, 1));
    assert!(matches!(other, Err(AssembleError::Frame { .. })));
}

#[test]
fn bands_stream_nearest_first_and_make_the_whole_render() {
    let r = renderer(SCENE);
    for (threads, spp) in [(1, None), (2, None), (2, Some(2))] {
        let o = RenderOptions {
            width: Some(30),
            height: Some(150), // bands at rows 0, 32, 64, 96 and 128 (22 rows)
            spp,
            threads: Some(threads),
            aovs: vec![Aov::Primitive],
            ..RenderOptions::default()
        };
        let seen = std::sync::Mutex::new(Vec::new());
        let (film, _) = r
            .render_bands(&o, Some(100), Control::default(), &|band| {
                seen.lock().expect("not poisoned").push(band.clone());
            })
            .expect("renders");
        assert_eq!(film, whole(&r, &o), "{threads} threads, spp {spp:?}");
        let seen = seen.into_inner().expect("not poisoned");
        let mut rows: Vec<u32> = seen.iter().map(|b| b.region().y).collect();
        if threads == 1 {
            // Nearest row 100 first: the band of 96..128, then 64..96 and
            // 128..150 (centres 80 and 139), then 32..64, then 0..32.
            assert_eq!(rows, vec![96, 64, 128, 32, 0]);
        }
        rows.sort_unstable();
        assert_eq!(rows, vec![0, 32, 64, 96, 128], "each band once");
        // Each band is those rows of the whole render, at full resolution.
        let pasted = Film::assemble((30, 150), Region::full(30, 150), seen).expect("assembles");
        assert_eq!(pasted, film);
    }
}
