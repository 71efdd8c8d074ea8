//! Whole-render benchmarks of the framework's scenes (default sampling).
//! `cargo bench --bench render`; the CLI's summary line gives the same figure
//! for one run: `glint render ../shared/scenes/framework/scene1.txt`.

use criterion::{Criterion, criterion_group, criterion_main};
use glint::{Control, RenderOptions, Renderer, Scene};
use std::time::Duration;

fn scene1(c: &mut Criterion) {
    let path = "../shared/scenes/framework/scene1.txt";
    let Ok(scene) = Scene::from_file(path) else {
        eprintln!("skipping: {path} not found");
        return;
    };
    let renderer = Renderer::new(scene);
    let mut group = c.benchmark_group("render");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(30));
    group.bench_function("scene1 1280x760 adaptive", |b| {
        b.iter(|| {
            let done = renderer.render_with(&RenderOptions::default(), Control::default());
            done.map(|(_, stats)| stats.rays.total())
        })
    });
    group.finish();
}

criterion_group!(benches, scene1);
criterion_main!(benches);
