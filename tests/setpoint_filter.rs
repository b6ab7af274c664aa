//! The emitted C setpoint filter of a plan, compiled with every warning an error, loaded, and
//! fed tick by tick with the raw S-curve (position, velocity, acceleration, jerk) and the
//! telescopic position as the plant has it: its output equals the library's shaped profile
//! to 1e-12 of the distance, for a fixed and a position-scheduled period. Built with the
//! sanitizers, it follows a machine's clock (skipped, repeated and jittered ticks, a clock
//! that starts at 1e7 s, NaN inputs) to the target: a bad tick is rejected, the next good
//! one taken.

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
    let (schedule, period) =
        first_period(&held, arrival, arrival + 8.0, &telescopic::Silent).unwrap();
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

/// One tick of a machine's clock: what the clock reads, and the plan's time it stands for
/// (`None`: the tick's inputs are not finite).
struct Tick {
    clock: f64,
    time: f64,
    broken: bool,
}

/// The ticks of a 1 kHz clock over the move: `offset` added to its readings, every tick
/// `k` with `skip(k)` left out, `repeat(k)` sent twice, `jitter(k)` (s) added to its time,
/// and a NaN input at the ticks of `broken`.
fn clock(
    end: f64,
    offset: f64,
    skip: &dyn Fn(usize) -> bool,
    repeat: &dyn Fn(usize) -> bool,
    jitter: &dyn Fn(usize) -> f64,
    broken: &[usize],
) -> Vec<Tick> {
    let mut ticks = Vec::new();
    for k in 0..=(end * 1000.0) as usize {
        if skip(k) {
            continue;
        }
        let time = k as f64 / 1000.0 + jitter(k);
        let tick = |broken| Tick {
            clock: offset + time,
            time,
            broken,
        };
        ticks.push(tick(broken.contains(&k)));
        if repeat(k) {
            ticks.push(tick(false));
        }
    }
    ticks
}

/// Runs `ticks` through the filter built with the sanitizers; returns per tick the output
/// (m) and the running count of rejections.
fn run_ticks(
    program: &std::path::Path,
    curve: &SCurve,
    scene: &Scene,
    ticks: &[Tick],
) -> Vec<(f64, u64)> {
    use std::io::Write;
    let mut input = String::new();
    for tick in ticks {
        let (p, v, a) = curve.state(tick.time);
        let p = if tick.broken { f64::NAN } else { p };
        let position = scene.params.positions[0].value(tick.time);
        input.push_str(&format!(
            "{:e} {p:e} {v:e} {a:e} {:e} {position:e}\n",
            tick.clock,
            curve.jerk(tick.time)
        ));
    }
    let mut child = std::process::Command::new(program)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()).unwrap());
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let (shaped, rejected) = l.split_once(' ').unwrap();
            (shaped.parse().unwrap(), rejected.parse().unwrap())
        })
        .collect()
}

#[test]
#[ignore = "needs a C compiler (cc); the test command installs gcc"]
fn the_emitted_filter_follows_skipped_repeated_jittered_and_late_clocks_to_the_target() {
    let (scene, curve, schedule, _) = case_study();
    // the period scheduled on the position, its stretch fixed: the plan's clock may be
    // offset (a stretch changing over a span reads the plan's time)
    let candidate = shaped(
        "zvd scheduled".into(),
        &curve,
        Shaper::Zvd,
        (&schedule, 1.0, 1.0),
    );
    let dir = std::env::temp_dir().join(format!("telescopic-filter-clocks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_filter_c(&scene, &candidate, 1000.0, &dir).unwrap();
    let program = dir.join("filter_ticks");
    let driver = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c/filter_ticks.c");
    common::compile_c(
        &[
            "-O1",
            "-g",
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=all",
        ],
        &[&driver, &dir.join(FILTER_FILES[1])],
        &dir,
        &program,
    );
    let end = candidate.arrival_s + 1.0;
    let never = |_: usize| false;
    let jitter = |k: usize| 1e-6 * ((k as f64 * 12.9898).sin() * 43758.5453).fract();
    let clocks: [(&str, Vec<Tick>, u64); 6] = [
        ("steady", clock(end, 0.0, &never, &never, &|_| 0.0, &[]), 0),
        (
            "skipped",
            clock(
                end,
                0.0,
                &|k| k % 7 == 3 || (5000..5050).contains(&k),
                &never,
                &|_| 0.0,
                &[],
            ),
            0,
        ),
        (
            "repeated",
            clock(end, 0.0, &never, &|k| k % 5 == 0, &|_| 0.0, &[]),
            (end * 1000.0) as u64 / 5 + 1,
        ),
        (
            "jittered by 1 us",
            clock(end, 0.0, &never, &never, &jitter, &[]),
            0,
        ),
        (
            "starting at 1e7 s",
            clock(end, 1e7, &never, &never, &jitter, &[]),
            0,
        ),
        (
            "with NaN ticks",
            clock(end, 0.0, &never, &never, &|_| 0.0, &[3001, 3002, 9000]),
            3,
        ),
    ];
    for (name, ticks, rejections) in clocks {
        let out = run_ticks(&program, &curve, &scene, &ticks);
        assert_eq!(out.len(), ticks.len(), "{name}");
        let mut worst = 0.0_f64;
        let mut previous = 0.0;
        for (tick, &(shaped, _)) in ticks.iter().zip(&out) {
            assert!(shaped.is_finite(), "{name}: {shaped} at {}", tick.time);
            if tick.broken {
                assert_eq!(
                    shaped, previous,
                    "{name}: a rejected tick changed the output"
                );
            } else {
                worst = worst.max((shaped - candidate.profile.value(tick.time)).abs());
            }
            previous = shaped;
        }
        let (last, rejected) = *out.last().unwrap();
        eprintln!("{name}: largest difference {worst:e} m, {rejected} rejected");
        assert_eq!(rejected, rejections, "{name}");
        assert!(
            worst <= 1e-9 * 23.0,
            "{name}: {worst:e} m off the library's profile"
        );
        assert!(
            (last - 23.0).abs() <= 1e-9 * 23.0,
            "{name}: ends at {last} m"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
