//! The emitted C setpoint filter of a plan, compiled with every warning an error, loaded, and
//! fed tick by tick with the raw S-curve (position, velocity, acceleration, jerk) and the
//! telescopic position as the plant has it: its output equals the library's shaped profile
//! to 1e-12 of the distance, for a fixed and a position-scheduled period; ticks that are not
//! finite or not one tick on are rejected.

use telescopic::Scene;
mod common;

use telescopic::plan::candidates::{Candidate, shaped, unshaped};
use telescopic::plan::emit::{FILTER_FILES, write_filter_c};
use telescopic::plan::shapers::Shaper;
use telescopic::plan::{first_period, moving_scene};
use telescopic_runtime::{Profile, SCurve};

/// The C filter behind its two entry points, loaded from a shared library.
struct CFilter {
    state: Vec<f64>,
    step: unsafe extern "C" fn(*mut f64, f64, *const f64, f64) -> f64,
}

impl CFilter {
    /// Emits `candidate`'s filter at `rate_hz`, compiles and loads it.
    fn load(scene: &Scene, candidate: &Candidate, rate_hz: f64, tag: &str) -> CFilter {
        let dir =
            std::env::temp_dir().join(format!("telescopic-filter-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        write_filter_c(scene, candidate, rate_hz, &dir).unwrap();
        let header = std::fs::read_to_string(dir.join(FILTER_FILES[0])).unwrap();
        let history: usize = header
            .lines()
            .find_map(|l| l.strip_prefix("#define TS_HISTORY "))
            .and_then(|l| l.split_whitespace().next())
            .and_then(|n| n.parse().ok())
            .expect("TS_HISTORY");
        let library = dir.join("libts.so");
        common::compile_c(
            &["-O2", "-shared", "-fPIC"],
            &[&dir.join(FILTER_FILES[1])],
            &dir,
            &library,
        );
        type Init = unsafe extern "C" fn(*mut f64);
        type Step = unsafe extern "C" fn(*mut f64, f64, *const f64, f64) -> f64;
        let path = std::ffi::CString::new(library.to_str().unwrap()).unwrap();
        // ts_state: history[TS_HISTORY] of 5 doubles, two longs, a double and an unsigned
        // long, all 8 bytes on this platform
        let words = 5 * history + 4;
        // SAFETY: dlopen/dlsym with NUL-terminated strings; the symbols have the signatures
        // of telescopic_setpoint.h, and the state has the words of its ts_state.
        let (step, state) = unsafe {
            let handle = libc::dlopen(path.as_ptr(), libc::RTLD_NOW);
            assert!(!handle.is_null(), "dlopen failed");
            let init: Init = std::mem::transmute(libc::dlsym(handle, c"ts_init".as_ptr()));
            let step: Step = std::mem::transmute(libc::dlsym(handle, c"ts_step".as_ptr()));
            let mut state = vec![0.0; words];
            init(state.as_mut_ptr());
            (step, state)
        };
        std::fs::remove_dir_all(&dir).unwrap();
        CFilter { state, step }
    }

    /// `ts_state.rejected`: the state's last word (an `unsigned long`).
    fn rejected(&self) -> u64 {
        self.state[self.state.len() - 1].to_bits()
    }

    fn step(&mut self, t: f64, raw: [f64; 4], position: f64) -> f64 {
        // SAFETY: the state is the filter's (see `load`), raw holds 4 doubles.
        unsafe { (self.step)(self.state.as_mut_ptr(), t, raw.as_ptr(), position) }
    }
}

/// The case study's 23 m move, its held scene and its first mode's schedule.
fn case_study() -> (Scene, SCurve, Profile, f64) {
    let scene = Scene::load("scenes/case-study.toml".as_ref(), &[]).unwrap();
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 23.0,
        v_max: 2.5,
        a_max: 0.7,
        j_max: 2.0,
    };
    let arrival = unshaped(&curve).arrival_s;
    let held = moving_scene(&scene, &unshaped(&curve).profile, arrival + 30.0).unwrap();
    let (schedule, period) = first_period(&held, arrival, arrival + 8.0).unwrap();
    (scene, curve, schedule, period)
}

/// The largest difference (m) of the filter and the library's profile at every tick of
/// `rate_hz` until the candidate has arrived and rested a second.
fn largest_difference(scene: &Scene, curve: &SCurve, candidate: &Candidate, rate_hz: f64) -> f64 {
    let mut filter = CFilter::load(scene, candidate, rate_hz, &candidate.name.replace(' ', "-"));
    let position = &scene.params.positions[0];
    let ticks = ((candidate.arrival_s + 1.0) * rate_hz).ceil() as usize;
    let mut worst = 0.0_f64;
    for k in 0..=ticks {
        let t = k as f64 / rate_hz;
        let (p, v, a) = curve.state(t);
        let shaped = filter.step(t, [p, v, a, curve.jerk(t)], position.value(t));
        worst = worst.max((shaped - candidate.profile.value(t)).abs());
    }
    assert_eq!(filter.rejected(), 0);
    worst
}

#[test]
#[ignore = "needs a C compiler (cc); the test command installs gcc"]
fn the_emitted_filter_gives_the_library_profile_to_1e_12_of_the_distance() {
    let (scene, curve, schedule, period) = case_study();
    let fixed = Profile::Constant(period);
    for (candidate, rate) in [
        (
            shaped("zv".into(), &curve, Shaper::Zv, (&fixed, 1.0, 1.0)),
            1000.0,
        ),
        (
            shaped("ei".into(), &curve, Shaper::Ei, (&fixed, 1.0, 1.0)),
            250.0,
        ),
        (
            shaped(
                "zvd scheduled".into(),
                &curve,
                Shaper::Zvd,
                (&schedule, 1.05, 0.94),
            ),
            1000.0,
        ),
        (
            shaped(
                "2ei scheduled".into(),
                &curve,
                Shaper::TwoHumpEi,
                (&schedule, 1.0, 1.0),
            ),
            500.0,
        ),
    ] {
        let worst = largest_difference(&scene, &curve, &candidate, rate);
        eprintln!(
            "{} at {rate} Hz: largest difference {worst:e} m",
            candidate.name
        );
        assert!(worst <= 1e-12 * 23.0, "{}: {worst:e} m", candidate.name);
    }
}

#[test]
#[ignore = "needs a C compiler (cc); the test command installs gcc"]
fn the_emitted_filter_rejects_bad_ticks_and_holds_its_output() {
    let (scene, curve, schedule, _) = case_study();
    let candidate = shaped(
        "zvd scheduled".into(),
        &curve,
        Shaper::Zvd,
        (&schedule, 1.0, 1.0),
    );
    let mut filter = CFilter::load(&scene, &candidate, 1000.0, "hostile");
    let raw = |t: f64| {
        let (p, v, a) = curve.state(t);
        [p, v, a, curve.jerk(t)]
    };
    let a = |t: f64| scene.params.positions[0].value(t);
    let mut last = 0.0;
    for k in 0..=3000 {
        let t = f64::from(k) / 1000.0;
        last = filter.step(t, raw(t), a(t));
    }
    let t = 3.001;
    assert_eq!(filter.step(t, [f64::NAN, 0.0, 0.0, 0.0], a(t)), last);
    assert_eq!(filter.step(t, raw(t), f64::INFINITY), last);
    assert_eq!(filter.step(t + 0.0005, raw(t + 0.0005), a(t)), last);
    assert_eq!(filter.rejected(), 3);
    // and it goes on from the tick it expects
    let next = filter.step(t, raw(t), a(t));
    assert!(
        (next - candidate.profile.value(t)).abs() <= 1e-12 * 23.0,
        "{next} against {}",
        candidate.profile.value(t)
    );
}
