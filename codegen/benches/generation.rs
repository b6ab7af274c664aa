//! Generation time (derive with Symbolica + emit formatted Rust + renderings) for 2..5
//! sections and 2..10 modes per section, optimized as in `generated/build.rs`
//! (`cargo bench -p telescopic-codegen`). The configuration is the most expensive kind: cable
//! force flow, clearance, moving telescopic positions (time-dependent contact vectors).
//!
//! Symbolica runs on the generator's own thread under its lock file, as in a build.

use criterion::{BenchmarkId, Criterion, criterion_group};
use std::hint::black_box;
use std::time::{Duration, Instant};
use telescopic_codegen::{DriveKind, ForceFlow, ModelConfig, Positions, generate};

fn config(sections: usize, modes: usize) -> ModelConfig {
    ModelConfig {
        modes: vec![modes; sections],
        contacts: 2,
        force_flow: ForceFlow::Cable,
        clearance: true,
        positions: Positions::Moving,
        drive: DriveKind::Force,
        static_knots: None,
    }
}

fn generation_time(c: &mut Criterion) {
    // First touch of Symbolica (license check, banner) outside the measurement.
    generate(&config(2, 1)).expect("warm-up generation");
    let mut group = c.benchmark_group("generate");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for sections in SECTIONS {
        for modes in MODES {
            let cfg = config(sections, modes);
            group.bench_with_input(
                BenchmarkId::new(format!("s{sections}"), format!("m{modes}")),
                &cfg,
                |b, cfg| b.iter(|| generate(black_box(cfg)).expect("generation succeeds")),
            );
        }
    }
    group.finish();
}

/// Sizes of the sweep: sections x modes per section.
const SECTIONS: std::ops::RangeInclusive<usize> = 2..=5;
const MODES: [usize; 6] = [2, 4, 5, 6, 8, 10];

/// Least-squares exponent `p` of `time ~ N^p` over the sweep (`N` = total modes), from the
/// fastest of three plain timings per configuration: the growth the issue bounds by 2.
fn growth_exponent() {
    let mut points = Vec::new();
    for sections in SECTIONS {
        for modes in MODES {
            let cfg = config(sections, modes);
            let best = (0..3)
                .map(|_| {
                    let start = Instant::now();
                    generate(&cfg).expect("generation succeeds");
                    start.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            points.push((((sections * modes) as f64).ln(), best.ln()));
        }
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    println!(
        "generation time ~ N^{:.2} in the total number of modes N (least squares over {} configurations)",
        sxy / sxx,
        points.len()
    );
}

criterion_group!(benches, generation_time);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    growth_exponent();
}
