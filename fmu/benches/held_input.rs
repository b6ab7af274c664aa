//! Runs with a held input against the plain run of the same scene, in one process on one
//! core: the FMU's co-simulation of case-study at 1 ms communication steps, called through
//! the FMI 2.0 C functions as an importer calls them (the master sets `F` to the scene's
//! drive force before each step), and a 1 kHz sampled controller (an LQR on a Kalman filter
//! of `vehicle` and `kappa_1_0`, designed here) on the full model. docs/benchmarks.md
//! records the medians and their ratios. Run with
//! `cargo bench --manifest-path fmu/Cargo.toml --bench held_input`.

use criterion::{Criterion, criterion_group, criterion_main};
use std::ffi::CString;
use std::hint::black_box;
use std::path::Path;
use telescopic::Silent;
use telescopic::control::{DesignOptions, design, simulate_controlled};
use telescopic::fmu::{SCENE_RESOURCE, scene_guid, scene_text};
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::runtime::Scene;
use telescopic_fmu::ffi::{CO_SIMULATION, CallbackFunctions, OK};
use telescopic_fmu::*;

fn case_study() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/case-study.toml");
    Scene::load(&path, &[]).expect("shipped scene")
}

/// The FMU's resources of `scene` in a temporary directory: its `file://` URI and GUID.
fn unpacked(scene: &Scene) -> (CString, CString) {
    let dir = std::env::temp_dir().join(format!("telescopic-bench-{}", std::process::id()));
    let resources = dir.join("resources");
    std::fs::create_dir_all(&resources).unwrap();
    let (text, back) = scene_text(scene).unwrap();
    std::fs::write(resources.join(SCENE_RESOURCE), text).unwrap();
    let uri = CString::new(format!("file://{}", resources.display())).unwrap();
    (uri, CString::new(scene_guid(&back).unwrap()).unwrap())
}

/// The whole span in communication steps of `h`, `F` (value reference 0) set to the
/// scene's drive force before each; the last `tip_rel`.
fn co_simulate(scene: &Scene, uri: &CString, guid: &CString, h: f64) -> f64 {
    let functions = CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let steps = ((scene.time.end - scene.time.start) / h).round() as usize;
    let drive = scene.params.drive_profile();
    let mut tip = 0.0;
    // SAFETY: the FMI calling sequence with valid pointers; the instance is freed at the end
    unsafe {
        let c = fmi2Instantiate(
            c"bench".as_ptr(),
            CO_SIMULATION,
            guid.as_ptr(),
            uri.as_ptr(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, scene.time.start, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        for k in 0..steps {
            let t = scene.time.start + k as f64 * h;
            let force = drive.value(t);
            assert_eq!(fmi2SetReal(c, &0, 1, &force), OK);
            assert_eq!(fmi2DoStep(c, t, h, 1), OK);
        }
        assert_eq!(fmi2GetReal(c, &2, 1, &mut tip), OK);
        fmi2FreeInstance(c);
    }
    tip
}

fn held_input(c: &mut Criterion) {
    let scene = case_study();
    let plain = SimulationOptions {
        error_estimate: false,
        ..SimulationOptions::default()
    };
    let (uri, guid) = unpacked(&scene);
    let sampled = design(
        &scene,
        &DesignOptions {
            sensors: vec!["vehicle".into(), "kappa_1_0".into()],
            ..DesignOptions::default()
        },
    )
    .expect("a sampled design of case-study");
    let mut group = c.benchmark_group("held_input");
    group.sample_size(10);
    group.bench_function("case-study plain run (auto)", |b| {
        b.iter(|| black_box(simulate_scene(&scene, &plain, &Silent).unwrap()))
    });
    group.bench_function("case-study FMU co-simulation, 1 ms steps", |b| {
        b.iter(|| black_box(co_simulate(&scene, &uri, &guid, 1e-3)))
    });
    group.bench_function(
        "case-study open loop on dopri5 (a continuous law's method)",
        |b| {
            let options = telescopic::control::comparison_options(&plain).unwrap();
            b.iter(|| black_box(simulate_scene(&scene, &options, &Silent).unwrap()))
        },
    );
    group.bench_function("case-study sampled controller, 1 kHz", |b| {
        b.iter(|| black_box(simulate_controlled(&scene, &sampled, &plain, &Silent).unwrap()))
    });
    group.finish();
}

criterion_group!(benches, held_input);
criterion_main!(benches);
