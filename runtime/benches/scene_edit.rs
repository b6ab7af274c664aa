//! A scene edit: `Scene::with_values` (the typed scene patched and validated) against the
//! same edit as `--set` text (the file parsed, overridden and validated), on case-study.
//! Run with `cargo bench -p telescopic-runtime --bench scene_edit`; docs/benchmarks.md
//! records the medians.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::Path;
use telescopic_runtime::Scene;

fn scene_edit(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/case-study.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = Scene::load(&path, &[]).unwrap();
    let mut group = c.benchmark_group("scene_edit");
    group.bench_function("with_values (typed)", |b| {
        b.iter(|| {
            black_box(
                scene
                    .with_values(&[("masses.load", 25.0), ("contact.clearance", 0.015)])
                    .unwrap(),
            )
        })
    });
    let overrides = [
        "masses.load=25.0".to_string(),
        "contact.clearance=0.015".into(),
    ];
    group.bench_function("--set text (parse, override, validate)", |b| {
        b.iter(|| black_box(Scene::from_toml_str(&text, &path, &overrides).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, scene_edit);
criterion_main!(benches);
