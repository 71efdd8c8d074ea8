//! Scene-file parsing: a generated file of 100 000 spheres, each with its
//! own colour (the million-sphere benchmark scene's kind of block), read
//! from disk in chunks as `glint render` reads it. `cargo bench --bench parse`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glint::Scene;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use std::fmt::Write;
use std::time::Duration;

/// Spheres in the generated file.
const SPHERES: usize = 100_000;

/// The text of a scene of `n` random spheres over a floor, as
/// `scripts/bench.sh` writes them.
fn spheres(n: usize) -> String {
    let mut rng = Pcg32::seed_from_u64(42);
    let mut text = String::from(
        "camera\n O= 0 -14 6\n N= 0 1 -0.25\nend\nlight point\n O= 6 -10 16\n color= 1 1 1\nend\n\
         primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.8\nend\n",
    );
    let r = 2.5 * (n as f64).powf(-1.0 / 3.0);
    let mut u = || rng.random::<f64>();
    for _ in 0..n {
        let (x, y, z) = (10.0 * u() - 5.0, 10.0 * u() - 5.0, 10.0 * u() + 0.5);
        let (cr, cg, cb) = (u(), u(), u());
        // Writing to a String cannot fail.
        let _ = write!(
            text,
            "primitive sphere\n O= {x:.5} {y:.5} {z:.5}\n R= {r:.5}\n color= {cr:.3} {cg:.3} {cb:.3}\n diff= 0.9\nend\n"
        );
    }
    text
}

fn parse(c: &mut Criterion) {
    let text = spheres(SPHERES);
    let path = std::env::temp_dir().join(format!("glint-parse-bench-{}.txt", std::process::id()));
    if let Err(e) = std::fs::write(&path, &text) {
        eprintln!("skipping: cannot write {}: {e}", path.display());
        return;
    }
    // The bench measures a successful parse of every sphere (and the floor).
    match Scene::from_file(&path) {
        Ok(s) if s.objects().len() == SPHERES + 1 => {}
        other => {
            eprintln!("skipping: the generated scene did not parse as expected: {other:?}");
            let _ = std::fs::remove_file(&path);
            return;
        }
    }
    let mut g = c.benchmark_group("parse");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(5))
        .throughput(Throughput::Bytes(text.len() as u64));
    g.bench_function("spheres-100k-file", |b| {
        b.iter(|| Scene::from_file(&path).map(|s| s.objects().len()))
    });
    g.finish();
    let _ = std::fs::remove_file(&path);
}

criterion_group!(benches, parse);
criterion_main!(benches);
