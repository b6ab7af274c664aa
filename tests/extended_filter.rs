//! The extended Kalman filter's own model of the plant: it equals the generated model
//! (derived by Symbolica) to rounding, it is recorded in the controller file and checked
//! there, a run on a changed plant predicts with it, not with the plant, and its step
//! allocates nothing (counted by this binary's global allocator, on the test's own thread).
mod common;
use common::scene;

use rand::{Rng, SeedableRng};
use telescopic::control::closed_loop::sampled::simulate_sampled;
use telescopic::control::law::estimator_model::{EstimatorModel, PreparedEstimatorModel};
use telescopic::control::{Controller, DesignOptions, design};
use telescopic::run::PreparedRun;
use telescopic::run::SimulationOptions;
use telescopic::run::models::{ModelChoice, ModelRegistry};
use telescopic::runtime::nalgebra::DMatrix;
use telescopic::runtime::{ContactState, Drive};
use telescopic::{Scene, Silent};

/// Counts the allocations of the thread that makes them.
struct Counting;

thread_local! {
    static THREAD_ALLOCATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

// SAFETY: forwards to the system allocator; the counter is a thread-local cell.
unsafe impl std::alloc::GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = THREAD_ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    THREAD_ALLOCATIONS.with(|c| c.get())
}

/// The LQR on the extended filter from the encoder and the strain gauge, tip scale `tip` (m).
fn extended_design(plant: &Scene, tip: f64) -> Controller {
    let options = DesignOptions {
        sensors: vec!["vehicle".into(), "kappa_1_0".into()],
        estimator: telescopic::control::Estimator::Extended,
        tip_scale: tip,
        ..DesignOptions::default()
    };
    design(plant, &options).unwrap()
}

fn largest(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[test]
fn the_filter_model_is_the_generated_model_in_every_contact_branch() {
    // two independent paths to the same equations: the generated code (Symbolica's
    // expressions) and the filter's dense loops over the recorded matrices and table
    for (name, times) in [
        ("case-study", vec![0.0, 3.3, 7.77, 11.9, 14.0]),
        ("adams-clearance", vec![0.0, 2.5]),
        ("three-section", vec![0.0, 1.0]),
    ] {
        let plant = scene(name, &[]);
        let model = ModelRegistry::default()
            .build(&plant.params, ModelChoice::Generated)
            .unwrap()
            .model;
        let record = EstimatorModel::of(model.as_ref()).unwrap();
        let mut filter_model = PreparedEstimatorModel::new(&record).unwrap();
        let (n, nc) = (model.dof(), model.layout().contact_count());
        let w = 2 * n;
        let half_band = 0.5 * plant.params.contact.clearance;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut seen = [0usize; 3];
        let (mut ours, mut theirs) = (vec![0.0; w], vec![0.0; w]);
        let (mut jac_ours, mut jac_theirs) = (vec![0.0; w * w], DMatrix::zeros(w, w));
        let (mut xi, mut xi_dot) = (vec![0.0; nc], vec![0.0; nc]);
        for &t in &times {
            for _ in 0..40 {
                // coordinates of a size that puts the gaps on both sides of the band
                let y: Vec<f64> = (0..w)
                    .map(|i| rng.random_range(-1.0..1.0) * if i < n { 0.02 } else { 0.5 })
                    .collect();
                model.contact_gaps(t, &y, &mut xi, &mut xi_dot);
                for x in &xi {
                    let branch = if *x > half_band {
                        2
                    } else if *x < -half_band {
                        0
                    } else {
                        1
                    };
                    seen[branch] += 1;
                }
                let force = match &plant.params.drive {
                    Drive::Force(f) => f.value(t),
                    Drive::Motion(_) => unreachable!("force-driven scenes"),
                };
                filter_model.rhs(t, &y, force, &mut ours);
                model.rhs(t, &y, None, &mut theirs);
                let scale = largest(theirs.iter().copied());
                let worst = largest(ours.iter().zip(&theirs).map(|(a, b)| a - b));
                assert!(
                    worst <= 1e-12 * scale,
                    "{name} rhs at {t}: {worst:e} of {scale:e}"
                );
                filter_model.jacobian(t, &y, &mut jac_ours);
                model.jacobian(t, &y, None::<&[ContactState]>, &mut jac_theirs);
                let scale = largest(jac_theirs.iter().copied());
                let worst = largest(
                    (0..w)
                        .flat_map(|r| (0..w).map(move |c| (r, c)))
                        .map(|(r, c)| jac_ours[r * w + c] - jac_theirs[(r, c)]),
                );
                assert!(worst <= 1e-12 * scale, "{name} Jacobian at {t}: {worst:e}");
            }
        }
        assert!(
            seen.iter().all(|&s| s > 0),
            "{name}: branches lower/free/upper seen {seen:?}"
        );
    }
}

/// The extended filter's record of `scene`'s own model.
fn own_model(scene: &Scene) -> EstimatorModel {
    let model = ModelRegistry::default()
        .build(&scene.params, ModelChoice::Auto)
        .unwrap()
        .model;
    EstimatorModel::of(model.as_ref()).unwrap()
}

#[test]
fn the_controller_file_records_the_filter_model_and_a_changed_plant_does_not_reach_it() {
    let nominal = scene("case-study", &[]);
    let controller = extended_design(&nominal, 0.05);
    let back = Controller::from_json(&controller.to_json()).unwrap();
    assert!(back == controller, "the controller file round-trips");
    let recorded = controller.sampled.as_ref().unwrap().model.clone().unwrap();
    assert_eq!(recorded, own_model(&nominal));
    assert!(recorded.geometry_table.is_some() && recorded.fixed_geometry.is_none());

    // on a 30 kg load the filter predicts with the nominal 17.9 kg it was designed with; a
    // file that records the heavy plant's own model runs differently
    let heavy = scene("case-study", &["masses.load=30"]);
    let sim = telescopic::control::comparison_options(&SimulationOptions::default()).unwrap();
    let run = |file: &Controller| {
        let prepared = PreparedRun::new(&heavy, &sim, &Silent).unwrap();
        simulate_sampled(prepared, file, &Silent).unwrap().forces
    };
    let mut knowing = controller.clone();
    knowing.sampled.as_mut().unwrap().model = Some(own_model(&heavy));
    let (designed, told) = (run(&controller), run(&knowing));
    let differs = designed
        .iter()
        .zip(&told)
        .map(|(a, b)| (a.1 - b.1).abs())
        .fold(0.0, f64::max);
    assert!(differs > 1.0, "largest force difference {differs} N");

    // a record that does not fit is refused naming the field and the rule
    for (edit, field) in [
        (
            &(|v: &mut serde_json::Value| {
                v["sampled"]["model"]["mass_inverse"]
                    .as_array_mut()
                    .unwrap()
                    .pop();
            }) as &dyn Fn(&mut serde_json::Value),
            "`sampled.model.mass_inverse`",
        ),
        (
            &|v: &mut serde_json::Value| {
                v["sampled"]["model"]["geometry_table"]["g"]
                    .as_array_mut()
                    .unwrap()
                    .pop();
            },
            "`sampled.model.geometry_table`",
        ),
        (
            &|v: &mut serde_json::Value| {
                v["sampled"]["model"]["geometry_table"]["varying"] = serde_json::json!([]);
            },
            "`sampled.model.geometry_table.varying`",
        ),
        (
            &|v: &mut serde_json::Value| {
                v["sampled"]["model"]["contacts"] = 3.into();
            },
            "`sampled.model.contacts`",
        ),
        (
            &|v: &mut serde_json::Value| {
                v["sampled"]["model"]["clearance"] = (-0.01).into();
            },
            "`sampled.model.clearance`",
        ),
        (
            &|v: &mut serde_json::Value| {
                v["sampled"]["estimator"] = "linear".into();
                v["sampled"]
                    .as_object_mut()
                    .unwrap()
                    .remove("process_noise_floor");
            },
            "`sampled.model`",
        ),
    ] {
        let mut v: serde_json::Value = serde_json::from_str(&controller.to_json()).unwrap();
        edit(&mut v);
        let err = Controller::from_json(&v.to_string())
            .and_then(|c| c.check_fits(&nominal))
            .unwrap_err()
            .to_string();
        assert!(err.contains(field), "{field}: {err}");
    }
    // the C emission checks the sizes of what it writes as fixed-size arrays
    let mut short = controller.clone();
    short.schedule[0].k[0].pop();
    let err = telescopic::control::emit::emit_c(&short, 0.0, 16.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("`schedule[].k`"), "{err}");
}

#[test]
fn the_filter_step_allocates_nothing() {
    use telescopic::control::law::ekf::ExtendedKalman;
    use telescopic::control::law::sampled::SampledController;
    let plant = scene("case-study", &[]);
    let controller = extended_design(&plant, DesignOptions::default().tip_scale);
    let mut filter = ExtendedKalman::new(&controller, 0.0, 16.0).unwrap();
    // measurements of a moving vehicle and a bending section (large innovations)
    let mut forces = 0.0;
    let before = allocations();
    for k in 0..200 {
        let t = k as f64 * 1e-3;
        let y = [0.5 * t * t, 0.05 * (40.0 * t).sin()];
        forces += filter.step(t, &y, 0.35);
    }
    let made = allocations() - before;
    assert!(forces.is_finite());
    assert_eq!(made, 0, "{made} allocations in 200 steps");
}
