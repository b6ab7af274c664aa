//! Whole scenes on one core, on their generated models, outputs computed at every sample
//! (as for the CSV, without writing it): the performance record. Each iteration
//! prepares the model too (M^-1, and for moving positions the contact-vector table). Run with
//! `cargo bench -p telescopic-generated --bench whole_scene`; the README reports the medians
//! and their ratios, measured in one run.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::Path;
use telescopic_runtime::{Method, Scene, Settings, auto_plan, model::rest_state, simulate};

/// Scene file, method, settings.
fn cases() -> Vec<(&'static str, &'static str, Settings)> {
    let rtol = |r: f64| Settings {
        rtol: r,
        atol: 1e-3 * r,
        ..Settings::default()
    };
    // dop853 without its stability step cap, for the cap's ratio in this run
    let uncapped = |r: f64| Settings {
        step_cap: false,
        ..rtol(r)
    };
    vec![
        ("adams-clearance.toml", "exact", Settings::default()),
        ("adams-clearance.toml", "dopri5", rtol(1e-7)),
        ("adams-clearance.toml", "dop853", rtol(1e-6)),
        ("adams-clearance.toml", "dop853", uncapped(1e-6)),
        ("adams-clearance.toml", "esdirk", rtol(1e-8)),
        ("adams-clearance.toml", "dop853-imex", rtol(1e-6)),
        ("case-study.toml", "auto", rtol(1e-7)),
        ("case-study.toml", "dop853", rtol(1e-5)),
        ("case-study.toml", "dop853", uncapped(1e-5)),
        ("case-study.toml", "dop853", rtol(1e-6)),
        ("case-study.toml", "dop853-imex", rtol(1e-6)),
        ("case-study.toml", "dopri5", rtol(1e-8)),
        ("case-study.toml", "imex", rtol(1e-7)),
        ("case-study.toml", "auto", Settings::default()),
        // the cheapest setting within 1e-6 m in T_h measured by `work-precision --rtols`:
        // 6.0e-7 m (rtol 1e-5, the next row, reads 1.6e-6 m)
        ("case-study.toml", "auto", rtol(5e-6)),
        ("case-study.toml", "auto", rtol(1e-5)),
        ("case-study-no-clearance.toml", "auto", Settings::default()),
        ("case-study-no-clearance.toml", "dop853", rtol(1e-5)),
        ("case-study-no-clearance.toml", "dopri5", rtol(1e-6)),
        ("case-study-no-clearance.toml", "esdirk", rtol(1e-3)),
        ("three-section.toml", "auto", Settings::default()),
    ]
}

fn whole_scene(c: &mut Criterion) {
    let mut group = c.benchmark_group("whole_scene");
    group.sample_size(10);
    for (file, method_name, settings) in cases() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join("scenes")
            .join(file);
        let scene = Scene::load(&path, &[]).expect("shipped scene");
        let (method, settings) = if method_name == "auto" {
            let (method, exact_from, _) = auto_plan(&scene.params, &scene.time);
            (
                method,
                Settings {
                    exact_from,
                    ..settings
                },
            )
        } else {
            (Method::from_name(method_name).expect("method"), settings)
        };
        let cap = if settings.step_cap { "" } else { "/no-cap" };
        let label = format!("{}/{method_name}/rtol{:e}{cap}", scene.name, settings.rtol);
        group.bench_function(label, |b| {
            b.iter(|| {
                let model = telescopic_generated::prepare(&scene.params)
                    .expect("generated")
                    .expect("prepared");
                let mut out = vec![0.0; model.output_names().len()];
                let y0 = rest_state(model.as_ref(), scene.time.start);
                let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
                    model.outputs(t, y, ydot, &mut out);
                    black_box(&out);
                };
                simulate(
                    model.as_ref(),
                    &y0,
                    &scene.time,
                    method,
                    &settings,
                    &mut observe,
                    None,
                )
                .expect("the scene runs")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, whole_scene);
criterion_main!(benches);
