//! The per-call path of a model allocates nothing: right-hand side, Jacobian, gaps and
//! outputs are called under a counting global allocator; so are the integrators' steps.
//! (Allocations are counted per thread: only the test's own thread counts.)

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::Ordering;
use telescopic_runtime::integrate::bdf::Bdf;
use telescopic_runtime::integrate::esdirk::Esdirk;
use telescopic_runtime::integrate::explicit::{DOP853, DOPRI5, ExplicitRk, RK4};
use telescopic_runtime::integrate::generalized_alpha::GeneralizedAlpha;
use telescopic_runtime::integrate::imex::Imex;
use telescopic_runtime::integrate::settled::SettledSteps;
use telescopic_runtime::integrate::verlet::StormerVerlet;
use telescopic_runtime::integrate::{ContactTracker, Stepper, System as Rhs};
use telescopic_runtime::{
    AssembledModel, Basis, ContactLaw, Drive, ForceFlow, Method, Model, ModelParams, Profile,
    RunStats, Settings, ShapedProfile, TimeSpan, rest_state, simulate,
};

struct Counting;

thread_local! {
    /// Allocations made by this thread: the harness's other threads (its timer, its output
    /// capture) allocate while a test runs, and a step runs on the test's thread only.
    static THREAD_ALLOCATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// This thread's allocations so far.
struct Allocations;

impl Allocations {
    fn load(&self, _: Ordering) -> usize {
        THREAD_ALLOCATIONS.with(|c| c.get())
    }
}

static ALLOCATIONS: Allocations = Allocations;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // `try_with`: a thread being torn down has no counter left
        let _ = THREAD_ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn per_call_methods_do_not_allocate() {
    let sec = common::rig_section(6);
    // the static correction shapes too: imex's implicit part then holds their stiff modes
    let cases = [Basis::Modes, Basis::ModesAndStatic].map(|basis| {
        [
            (
                basis,
                Profile::Constant(1.15),
                Drive::Force(Profile::Constant(100.0)),
            ),
            (
                basis,
                Profile::Shaped(ShapedProfile::Smoothstep {
                    start: 0.0,
                    end: 12.0,
                    from: 0.35,
                    to: 1.15,
                }),
                Drive::Motion(Profile::Shaped(ShapedProfile::Smoothstep {
                    start: 0.0,
                    end: 4.0,
                    from: 0.0,
                    to: 2.0,
                })),
            ),
        ]
    });
    for (basis, positions, drive) in cases.into_iter().flatten() {
        let params = ModelParams {
            damping: Default::default(),
            basis,
            sections: vec![sec, sec, sec],
            vehicle_mass: 100.0,
            load_mass: 17.897,
            gravity: 9.81,
            force_flow: ForceFlow::Cable,
            contact_points: 3,
            contact: ContactLaw {
                stiffness: 2.375e8,
                damping: 1000.0,
                clearance: 0.01,
            },
            positions: vec![Profile::Constant(1.0), positions],
            drive,
        };
        let model = AssembledModel::new(&params).unwrap();
        let n = model.dof();
        let mut y = rest_state(&model, 0.0);
        y.iter_mut()
            .enumerate()
            .for_each(|(i, v)| *v += 1e-3 * ((i * 7919 % 13) as f64 - 6.0));
        let mut ydot = vec![0.0; 2 * n];
        let mut jac = nalgebra::DMatrix::zeros(2 * n, 2 * n);
        let nc = model.layout().contact_count();
        let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
        let mut out = vec![0.0; model.output_names().len()];
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for step in 0..100 {
            let t = 0.05 * step as f64;
            model.rhs(t, &y, None, &mut ydot);
            model.jacobian(t, &y, None, &mut jac);
            model.contact_gaps(t, &y, &mut xi, &mut xid);
            model.outputs(t, &y, &ydot, &mut out);
        }
        let after = ALLOCATIONS.load(Ordering::SeqCst);
        assert_eq!(
            after - before,
            0,
            "{} allocations in 100 calls of each",
            after - before
        );
        assert!(ydot.iter().all(|v| v.is_finite()));
        steps_allocate_as_documented(&model, &y, &rest_state(&model, 0.0));
        if matches!(model.params().drive, Drive::Force(_)) {
            exact_runs_allocate_per_branch_not_per_step(&model, &y);
        }
    }
}

/// Exact stepping allocates when it meets a new combination of contact branches (its matrix
/// exponential and the matrices behind it) and at set-up, not per step: the allocations of a
/// run, less a fixed number per combination, do not grow with the run's length.
fn exact_runs_allocate_per_branch_not_per_step(model: &dyn Model, y: &[f64]) {
    let run = |end: f64| {
        let span = TimeSpan {
            start: 0.0,
            end,
            sample: 1e-3,
        };
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        let stats = simulate(
            model,
            y,
            &span,
            Method::Exact,
            &Settings::default(),
            &mut |_, _, _| {},
            None,
        )
        .unwrap();
        (ALLOCATIONS.load(Ordering::SeqCst) - before, stats)
    };
    let (short, short_stats) = run(0.25);
    let (long, long_stats) = run(1.0);
    eprintln!(
        "exact: {short} allocations in {} steps ({} exponentials), {long} in {} steps ({})",
        short_stats.steps, short_stats.exponentials, long_stats.steps, long_stats.exponentials
    );
    assert!(long_stats.steps > 3 * short_stats.steps);
    // the longer run holds a lasting contact: its long steps over the contact modes are
    // counted among the steps that must not allocate
    assert!(
        long_stats.long_steps > 100,
        "{} long steps",
        long_stats.long_steps
    );
    assert!(short_stats.switches > 0, "the rig touches its guides");
    let per_branch = short as f64 / short_stats.exponentials as f64;
    assert!(
        long as f64 <= per_branch * long_stats.exponentials as f64 * 1.5,
        "exact: {long} allocations for {} branches, {per_branch:.0} per branch in the short run",
        long_stats.exponentials
    );
}

/// Explicit steps allocate nothing; a generalized-alpha, ESDIRK or BDF step allocates only
/// nalgebra's pivot record of its one LU factorization (the matrix storage is reused).
fn steps_allocate_as_documented(model: &dyn Model, ringing: &[f64], rest: &[f64]) {
    let n = model.dof();
    let settings = Settings {
        dt: Some(1e-5),
        ..Settings::default()
    };
    let steppers: [(&str, Box<dyn Stepper>, usize); 9] = [
        (
            "dopri5",
            Box::new(ExplicitRk::new(&DOPRI5, 2 * n, &settings)),
            0,
        ),
        (
            "dop853",
            Box::new(ExplicitRk::new(&DOP853, 2 * n, &settings)),
            0,
        ),
        ("rk4", Box::new(ExplicitRk::new(&RK4, 2 * n, &settings)), 0),
        // one Jacobian and one factorization per step, each LU allocating its pivot record
        ("esdirk", Box::new(Esdirk::new(n, &settings)), 1),
        ("bdf", Box::new(Bdf::new(n, 5, &settings)), 1),
        ("verlet", Box::new(StormerVerlet::new(n)), 0),
        // the contact part's low-rank solve works in storage made on the first step
        ("imex", Box::new(Imex::new(n, &settings, 1e-3)), 0),
        // dop853 for its first quiet steps, then imex (a step cap of 2e-5 s: the 1e-5 s
        // steps count as near it)
        (
            "dop853-imex",
            Box::new(SettledSteps::new(n, &settings, 2e-5, 1e-3)),
            0,
        ),
        (
            "galpha",
            Box::new(GeneralizedAlpha::new(n, 0.8, true, &settings)),
            1,
        ),
    ];
    for (name, mut stepper, per_step) in steppers {
        // dop853-imex hands over to imex only once the closed contacts' modes have rung
        // down (its dop853 error at the cap below QUIET_ERROR): it steps from rest
        let y = if name == "dop853-imex" { rest } else { ringing };
        let mut sys = Rhs {
            model,
            tracker: ContactTracker::new(model, 0.0, y),
            stats: RunStats::default(),
            time_cap: f64::INFINITY,
        };
        // every contact closed: the contact forces (imex's implicit part) take part
        sys.tracker.press_all();
        let mut f0 = vec![0.0; 2 * n];
        let mut y1 = vec![0.0; 2 * n];
        let mut inside = vec![0.0; 2 * n];
        sys.rhs(0.0, y, &mut f0);
        // first step outside the count (lazy set-up is allowed)
        stepper.step(&mut sys, 0.0, y, &f0, 1e-5, &mut y1).unwrap();
        stepper.accepted();
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for k in 1..=100 {
            let t = k as f64 * 1e-5;
            stepper.step(&mut sys, t, y, &f0, 1e-5, &mut y1).unwrap();
            // dop853's continuous extension (switch location) works in storage of its own
            if stepper.prepare_extension(&mut sys, t, y, &y1, 1e-5) {
                stepper.extension_state(0.5, &mut inside);
            }
            stepper.accepted();
        }
        let allocations = ALLOCATIONS.load(Ordering::SeqCst) - before;
        assert_eq!(
            allocations,
            100 * per_step,
            "{name}: {allocations} allocations in 100 steps"
        );
        assert!(y1.iter().all(|v| v.is_finite()), "{name}");
        if name == "dop853-imex" {
            assert!(stepper.over_contact_modes(), "imex never took over");
        }
    }
}
