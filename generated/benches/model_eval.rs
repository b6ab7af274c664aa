//! Right-hand side and Jacobian of the first-order system: the generated model against the
//! quadrature-assembled one, for 2 sections x 5 modes (`adams-clearance`) and 3 sections x 6
//! modes (`three-section` with `sections.modes = 6`). Run with `cargo bench -p
//! telescopic-generated`.
//!
//! The state is a fixed pseudo-random one whose gaps put contacts in all three branches of
//! the clearance law, so both paths do the work of a real step.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use nalgebra::DMatrix;
use std::hint::black_box;
use std::path::Path;
use telescopic_runtime::{AssembledModel, Model, Scene};

/// The scenes of the benchmark: label, scene file, overrides.
const CASES: [(&str, &str, &[&str]); 2] = [
    ("2x5", "adams-clearance.toml", &[]),
    ("3x6", "three-section.toml", &["sections.modes=6"]),
];

/// A state with displacements of the order of the clearance and rates of 0.1 m/s.
fn busy_state(model: &dyn Model) -> Vec<f64> {
    let n = model.dof();
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut y: Vec<f64> = (0..2 * n).map(|_| next()).collect();
    let scale_z = 0.2 * model.params().contact.clearance.max(1e-3);
    for (i, v) in y.iter_mut().enumerate() {
        *v *= if i < n { scale_z } else { 0.1 };
    }
    y
}

fn load(file: &str, overrides: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(file);
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::load(&path, &overrides).expect("benchmark scene loads")
}

fn model_evaluation(c: &mut Criterion) {
    for (label, file, overrides) in CASES {
        let scene = load(file, overrides);
        let generated = telescopic_generated::prepare(&scene.params)
            .expect("the benchmark configurations are in generated/models.toml")
            .expect("generated model accepts the scene");
        let assembled: Box<dyn Model> =
            Box::new(AssembledModel::new(&scene.params).expect("assembled model"));
        let t = 2.5;
        let y = busy_state(generated.as_ref());
        let n = 2 * generated.dof();
        let mut ydot = vec![0.0; n];
        let mut jac = DMatrix::zeros(n, n);

        let mut rhs_group = c.benchmark_group(format!("rhs/{label}"));
        for (path, model) in [("generated", &generated), ("assembled", &assembled)] {
            rhs_group.bench_function(BenchmarkId::from_parameter(path), |b| {
                b.iter(|| model.rhs(black_box(t), black_box(&y), None, &mut ydot))
            });
        }
        rhs_group.finish();

        let mut jac_group = c.benchmark_group(format!("jacobian/{label}"));
        for (path, model) in [("generated", &generated), ("assembled", &assembled)] {
            jac_group.bench_function(BenchmarkId::from_parameter(path), |b| {
                b.iter(|| model.jacobian(black_box(t), black_box(&y), None, &mut jac))
            });
        }
        jac_group.finish();
    }
}

criterion_group!(benches, model_evaluation);
criterion_main!(benches);
