//! The FMI 2.0 C functions called as an importer calls them (through their C signatures, a
//! logger callback collecting the messages): a co-simulation instance equals
//! `telescopic simulate`, a parameter that breaks the scene is an `fmi2Error` whose message
//! names the field, two instances in one process do not share anything, and misuse is an
//! error, never a crash.

use std::ffi::{CStr, CString, c_char, c_void};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use telescopic::fmu::{FmuVariables, SCENE_RESOURCE, scene_guid, scene_text};
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::{Scene, Silent};
use telescopic_fmu::ffi::{CallbackFunctions, ERROR, Logger, OK};
use telescopic_fmu::*;

/// Messages the logger received: `(status, message)`.
static MESSAGES: Mutex<Vec<(i32, String)>> = Mutex::new(Vec::new());

/// The test's logger. An importer's logger is C-variadic (`message` is a format); this
/// library always calls it with the format `"%s"` and the message as the one variadic
/// argument, which on x86-64 System V (the platform of the FMU's binaries/linux64) arrives
/// where a sixth fixed argument would: so a plain six-argument function can read it (Rust
/// cannot define C-variadic functions on stable).
unsafe extern "C" fn collect(
    _env: *mut c_void,
    _name: *const c_char,
    status: i32,
    _category: *const c_char,
    _format: *const c_char,
    message: *const c_char,
) {
    // SAFETY: the library passes a NUL-terminated message
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    MESSAGES.lock().unwrap().push((status, text));
}

fn callbacks() -> CallbackFunctions {
    type Six = unsafe extern "C" fn(
        *mut c_void,
        *const c_char,
        i32,
        *const c_char,
        *const c_char,
        *const c_char,
    );
    type Variadic =
        unsafe extern "C" fn(*mut c_void, *const c_char, i32, *const c_char, *const c_char, ...);
    // SAFETY: see `collect`
    let logger: Logger = Some(unsafe { std::mem::transmute::<Six, Variadic>(collect as Six) });
    CallbackFunctions {
        logger,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    }
}

/// An unpacked FMU of `scene`: its resources directory and GUID.
fn unpacked(scene: &Scene, name: &str) -> (PathBuf, CString) {
    let dir = std::env::temp_dir().join(format!("telescopic-fmu-{name}-{}", std::process::id()));
    let resources = dir.join("resources");
    std::fs::create_dir_all(&resources).unwrap();
    let (text, back) = scene_text(scene).unwrap();
    std::fs::write(resources.join(SCENE_RESOURCE), text).unwrap();
    (resources, CString::new(scene_guid(&back).unwrap()).unwrap())
}

/// A shipped scene (the tests run in `fmu/`).
fn scene_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"))
}

fn uri(dir: &Path) -> CString {
    CString::new(format!("file://{}", dir.display())).unwrap()
}

/// A co-simulation instance of `scene`, initialized, with `F` = `force`.
unsafe fn co_simulation(scene: &Scene, name: &str, sets: &[(u32, f64)]) -> *mut c_void {
    let (resources, guid) = unpacked(scene, name);
    let functions = callbacks();
    let c = unsafe {
        fmi2Instantiate(
            c"test".as_ptr(),
            ffi::CO_SIMULATION,
            guid.as_ptr(),
            uri(&resources).as_ptr(),
            &functions,
            0,
            0,
        )
    };
    assert!(!c.is_null(), "{:?}", MESSAGES.lock().unwrap());
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, scene.time.start, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        for &(vr, v) in sets {
            assert_eq!(
                fmi2SetReal(c, &vr, 1, &v),
                OK,
                "{:?}",
                MESSAGES.lock().unwrap()
            );
        }
        assert_eq!(
            fmi2ExitInitializationMode(c),
            OK,
            "{:?}",
            MESSAGES.lock().unwrap()
        );
    }
    c
}

/// `tip_rel` (value reference 2) after every one of `steps` steps of `h`.
unsafe fn run(c: *mut c_void, h: f64, steps: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(steps);
    for k in 0..steps {
        let mut tip = 0.0;
        unsafe {
            assert_eq!(
                fmi2DoStep(c, k as f64 * h, h, 1),
                OK,
                "{:?}",
                MESSAGES.lock().unwrap()
            );
            assert_eq!(fmi2GetReal(c, &2, 1, &mut tip), OK);
        }
        out.push(tip);
    }
    out
}

fn reference(scene: &Scene) -> Vec<f64> {
    let sim = simulate_scene(scene, &SimulationOptions::default(), &Silent).unwrap();
    sim.trajectory.column("tip_rel").unwrap()
}

fn worst(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn co_simulation_equals_simulate_and_instances_are_independent() {
    let over = |s: &str| vec!["time.end=0.3".to_string(), s.to_string()];
    let clearance = Scene::load(
        &scene_file("adams-clearance"),
        &over("contact.clearance=0.01"),
    )
    .unwrap();
    let linear = Scene::load(&scene_file("adams-linear"), &over("masses.load=17.897")).unwrap();
    unsafe {
        let a = co_simulation(&clearance, "a", &[]);
        let b = co_simulation(&linear, "b", &[]);
        // interleaved: each instance's steps between the other's
        let (mut ta, mut tb) = (Vec::new(), Vec::new());
        for k in 0..300 {
            for (c, out) in [(a, &mut ta), (b, &mut tb)] {
                let mut tip = 0.0;
                assert_eq!(fmi2DoStep(c, k as f64 * 1e-3, 1e-3, 1), OK);
                assert_eq!(fmi2GetReal(c, &2, 1, &mut tip), OK);
                out.push(tip);
            }
        }
        let (ra, rb) = (reference(&clearance), reference(&linear));
        let (ea, eb) = (worst(&ta, &ra[1..]), worst(&tb, &rb[1..]));
        eprintln!("co-simulation against simulate: clearance {ea:.2e} m, linear {eb:.2e} m");
        assert!(ea < 1e-9 && eb < 1e-9, "{ea} {eb}");
        // they differ from each other (no shared state)
        assert!(worst(&ta, &tb) > 1e-3);
        fmi2FreeInstance(a);
        fmi2FreeInstance(b);
    }
}

#[test]
fn a_parameter_is_a_set_and_a_bad_one_is_an_error_naming_the_field() {
    let scene = Scene::load(
        &scene_file("adams-clearance"),
        &["time.end=0.2".to_string()],
    )
    .unwrap();
    let vars = FmuVariables::of(&scene).unwrap();
    let vr = |key: &str| vars.parameters().find(|(_, k)| *k == key).unwrap().0;
    unsafe {
        // a valid parameter equals --set
        let c = co_simulation(&scene, "set", &[(vr("contact.clearance"), 0.004)]);
        let tip = run(c, 1e-3, 200);
        let set = Scene::load(
            &scene_file("adams-clearance"),
            &[
                "time.end=0.2".to_string(),
                "contact.clearance=0.004".to_string(),
            ],
        )
        .unwrap();
        let e = worst(&tip, &reference(&set)[1..]);
        assert!(e < 1e-9, "{e}");
        assert!(
            worst(&tip, &reference(&scene)[1..]) > 1e-6,
            "the parameter changed the run"
        );
        let mut got = 0.0;
        assert_eq!(fmi2GetReal(c, &vr("contact.clearance"), 1, &mut got), OK);
        assert_eq!(got, 0.004);
        // after initialization a parameter cannot be set
        let v = 0.002;
        assert_eq!(fmi2SetReal(c, &vr("contact.clearance"), 1, &v), ERROR);
        fmi2FreeInstance(c);

        // a value that breaks the scene's rules: fmi2Error, the field named to the logger
        let (resources, guid) = unpacked(&scene, "bad");
        let functions = callbacks();
        let c = fmi2Instantiate(
            c"bad".as_ptr(),
            ffi::CO_SIMULATION,
            guid.as_ptr(),
            uri(&resources).as_ptr(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        MESSAGES.lock().unwrap().clear();
        let bad = -1.0;
        assert_eq!(fmi2SetReal(c, &vr("contact.clearance"), 1, &bad), ERROR);
        let messages = MESSAGES.lock().unwrap().clone();
        assert!(
            messages
                .iter()
                .any(|(s, m)| *s == ERROR && m.contains("contact.clearance") && m.contains(">= 0")),
            "{messages:?}"
        );
        // the instance is still usable: a valid value, then a run
        let good = 0.01;
        assert_eq!(fmi2SetReal(c, &vr("contact.clearance"), 1, &good), OK);
        assert_eq!(
            fmi2DoStep(c, 0.0, 1e-3, 1),
            ERROR,
            "stepping before initialization"
        );
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 1e-3, 1), OK);
        assert_eq!(
            fmi2DoStep(c, 0.5, 1e-3, 1),
            ERROR,
            "a step from the wrong time"
        );
        assert_eq!(fmi2DoStep(c, 1e-3, -1.0, 1), ERROR, "a negative step");
        let unknown = 999;
        let mut v = 0.0;
        assert_eq!(fmi2GetReal(c, &unknown, 1, &mut v), ERROR);
        assert_eq!(
            fmi2GetReal(c, &0, 1, std::ptr::null_mut()),
            ERROR,
            "null values"
        );
        fmi2FreeInstance(c);

        // a description from another scene: no instance, and the logger says why
        refuses_another_scenes_description(&resources, &functions);
        // null instances are errors, not crashes
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 1e-3, 1), ERROR);
        fmi2FreeInstance(std::ptr::null_mut());
    }
}

/// `fmi2Instantiate` with a GUID that is not the scene's: no instance, the GUID named to the
/// logger.
///
/// # Safety
/// Calls the FMI functions with valid pointers only.
unsafe fn refuses_another_scenes_description(resources: &Path, functions: &CallbackFunctions) {
    unsafe {
        MESSAGES.lock().unwrap().clear();
        let c = fmi2Instantiate(
            c"wrong".as_ptr(),
            ffi::CO_SIMULATION,
            c"{0}".as_ptr(),
            uri(resources).as_ptr(),
            functions,
            0,
            0,
        );
        assert!(c.is_null());
        assert!(
            MESSAGES
                .lock()
                .unwrap()
                .iter()
                .any(|(_, m)| m.contains("GUID"))
        );
    }
}

/// adams-linear with the vehicle following a quintic smoothstep from 0 to 1 m over [0, 2] s.
fn moved_scene() -> Scene {
    let text = std::fs::read_to_string(scene_file("adams-linear"))
        .unwrap()
        .replace(
            "force = 100.0            # N from t = 0",
            r#"motion = { kind = "smoothstep", start = 0, end = 2, from = 0, to = 1 }"#,
        );
    Scene::from_toml_str(&text, Path::new("moved.toml"), &["time.end=1".to_string()]).unwrap()
}

#[test]
fn a_prescribed_motion_takes_the_vehicle_acceleration_as_input() {
    let scene = moved_scene();
    let vars = FmuVariables::of(&scene).unwrap();
    assert_eq!(vars.variables[0].name, "a_vehicle");
    assert!(vars.variables.iter().any(|v| v.name == "drive_force"));
    let reference = reference(&scene);
    let s = scene.params.drive_profile().clone();
    let mut errors = Vec::new();
    for (h, every) in [(1e-3_f64, 1), (5e-4, 2)] {
        unsafe {
            let c = co_simulation(&scene, &format!("moved-{every}"), &[]);
            let mut tip = Vec::new();
            for k in 0..(1.0 / h).round() as usize {
                let t = k as f64 * h;
                // the acceleration at the step's midpoint, held over the step
                let a = s.acceleration(t + h / 2.0);
                assert_eq!(fmi2SetReal(c, &0, 1, &a), OK);
                assert_eq!(fmi2DoStep(c, t, h, 1), OK, "{:?}", MESSAGES.lock().unwrap());
                if (k + 1) % every == 0 {
                    let mut v = 0.0;
                    assert_eq!(fmi2GetReal(c, &2, 1, &mut v), OK);
                    tip.push(v);
                }
            }
            fmi2FreeInstance(c);
            errors.push(worst(&tip, &reference[1..]));
        }
    }
    let scale = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    eprintln!(
        "prescribed motion through a_vehicle held per step: {:.2e} m (1 ms), {:.2e} m (0.5 ms) of {scale:.2e} m",
        errors[0], errors[1]
    );
    // the hold of a smooth acceleration is second order in the step
    assert!(errors[0] < 1e-3 * scale, "{errors:?}");
    assert!(errors[1] < errors[0] / 3.0, "{errors:?}");
}

/// The states of FMI 2.0's co-simulation state machine a test walks an instance to.
#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
}

/// A co-simulation instance of adams-linear walked to `state`.
unsafe fn instance_in(state: State, name: &str) -> *mut c_void {
    unsafe { instance_of(ffi::CO_SIMULATION, state, name) }
}

/// An instance of adams-linear of `kind` walked to `state` (`Stepping`: initialized, and for
/// co-simulation one step done).
unsafe fn instance_of(kind: std::ffi::c_int, state: State, name: &str) -> *mut c_void {
    let scene = Scene::load(&scene_file("adams-linear"), &[]).unwrap();
    let (resources, guid) = unpacked(&scene, name);
    let functions = callbacks();
    unsafe {
        let c = fmi2Instantiate(
            c"test".as_ptr(),
            kind,
            guid.as_ptr(),
            uri(&resources).as_ptr(),
            &functions,
            0,
            0,
        );
        assert!(!c.is_null());
        if state == State::Instantiated {
            return c;
        }
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        if state == State::Initialization {
            return c;
        }
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        if kind == ffi::CO_SIMULATION {
            assert_eq!(fmi2DoStep(c, 0.0, 1e-3, 1), OK);
        }
        if state == State::Stepping {
            return c;
        }
        assert_eq!(fmi2Terminate(c), OK);
        c
    }
}

#[test]
fn calls_out_of_the_fmi_state_machine_are_errors() {
    type Call = (&'static str, unsafe fn(*mut c_void) -> i32);
    let calls: [Call; 4] = [
        ("fmi2SetupExperiment", |c| unsafe {
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0)
        }),
        ("fmi2EnterInitializationMode", |c| unsafe {
            fmi2EnterInitializationMode(c)
        }),
        ("fmi2ExitInitializationMode", |c| unsafe {
            fmi2ExitInitializationMode(c)
        }),
        ("fmi2DoStep", |c| unsafe {
            let mut t = 0.0;
            fmi2GetRealStatus(c, 2 /* fmi2LastSuccessfulTime */, &mut t);
            fmi2DoStep(c, t, 1e-3, 1)
        }),
    ];
    // (call, the one state it is allowed in)
    let allowed = [
        State::Instantiated,
        State::Instantiated,
        State::Initialization,
        State::Stepping,
    ];
    let states = [
        State::Instantiated,
        State::Initialization,
        State::Stepping,
        State::Terminated,
    ];
    for ((name, call), ok_in) in calls.iter().zip(allowed) {
        for state in states {
            let tag = format!("sm-{name}-{state:?}");
            unsafe {
                let c = instance_in(state, &tag);
                let status = call(c);
                let expected = if state == ok_in { OK } else { ERROR };
                assert_eq!(status, expected, "{name} in {state:?}");
                fmi2FreeInstance(c);
            }
        }
    }
}

#[test]
fn times_that_cannot_be_stepped_and_arrays_of_the_wrong_size_are_errors() {
    unsafe {
        let c = instance_in(State::Instantiated, "far-time");
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 1e300, 0, 0.0), ERROR);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, f64::NAN, 0, 0.0), ERROR);
        fmi2FreeInstance(c);
        let c = instance_in(State::Stepping, "bad-steps");
        for (t, h) in [
            (1e-3, f64::INFINITY),
            (1e-3, f64::NAN),
            (f64::NAN, 1e-3),
            (5.0, 1e-3),
            // finite, but past the step limit however the method steps
            (1e-3, 1e8),
        ] {
            assert_eq!(fmi2DoStep(c, t, h, 1), ERROR, "t = {t}, h = {h}");
        }
        // the time did not move on the refused steps
        let mut t = f64::NAN;
        assert_eq!(
            fmi2GetRealStatus(c, 2 /* fmi2LastSuccessfulTime */, &mut t),
            OK
        );
        assert_eq!(t, 1e-3);
        fmi2FreeInstance(c);
        // arrays must have the model's size: adams-linear has 2 x 10 states
        let c = instance_of(ffi::MODEL_EXCHANGE, State::Stepping, "bad-arrays");
        let mut buffer = vec![f64::NAN; 64];
        for n in [0, 19, 21, 64] {
            assert_eq!(
                fmi2GetContinuousStates(c, buffer.as_mut_ptr(), n),
                ERROR,
                "{n}"
            );
            assert_eq!(fmi2GetDerivatives(c, buffer.as_mut_ptr(), n), ERROR, "{n}");
        }
        assert!(buffer.iter().all(|v| v.is_nan()), "a refused call wrote");
        assert_eq!(fmi2GetContinuousStates(c, buffer.as_mut_ptr(), 20), OK);
        assert_eq!(fmi2GetEventIndicators(c, buffer.as_mut_ptr(), 64), ERROR);
        fmi2FreeInstance(c);
    }
}

#[test]
fn values_terminate_and_model_exchange_calls_keep_to_their_states() {
    use State::*;
    type Call = (&'static str, unsafe fn(*mut c_void) -> i32);
    let calls: [(Call, &[State]); 7] = [
        (
            ("fmi2GetReal", |c| unsafe {
                let mut v = 0.0;
                fmi2GetReal(c, &2, 1, &mut v)
            }),
            &[Initialization, Stepping, Terminated],
        ),
        (
            ("fmi2SetReal F", |c| unsafe { fmi2SetReal(c, &0, 1, &1.0) }),
            &[Instantiated, Initialization, Stepping],
        ),
        (
            ("fmi2Terminate", |c| unsafe { fmi2Terminate(c) }),
            &[Stepping],
        ),
        (
            ("fmi2GetInteger", |c| unsafe {
                fmi2GetInteger(c, std::ptr::null(), 0, std::ptr::null_mut())
            }),
            &[Initialization, Stepping, Terminated],
        ),
        (
            ("fmi2SetBoolean", |c| unsafe {
                fmi2SetBoolean(c, std::ptr::null(), 0, std::ptr::null())
            }),
            &[Instantiated, Initialization, Stepping],
        ),
        (
            ("fmi2GetString", |c| unsafe {
                fmi2GetString(c, std::ptr::null(), 0, std::ptr::null_mut())
            }),
            &[Initialization, Stepping, Terminated],
        ),
        (
            ("fmi2GetFMUstate (not supported)", |c| unsafe {
                let mut state = std::ptr::null_mut();
                fmi2GetFMUstate(c, &mut state)
            }),
            &[],
        ),
    ];
    let me_calls: [Call; 9] = [
        ("fmi2SetTime", |c| unsafe { fmi2SetTime(c, 0.0) }),
        ("fmi2EnterEventMode", |c| unsafe { fmi2EnterEventMode(c) }),
        ("fmi2EnterContinuousTimeMode", |c| unsafe {
            fmi2EnterContinuousTimeMode(c)
        }),
        ("fmi2GetContinuousStates", |c| unsafe {
            let mut x = [0.0; 20];
            fmi2GetContinuousStates(c, x.as_mut_ptr(), 20)
        }),
        ("fmi2GetDerivatives", |c| unsafe {
            let mut dx = [0.0; 20];
            fmi2GetDerivatives(c, dx.as_mut_ptr(), 20)
        }),
        ("fmi2SetContinuousStates", |c| unsafe {
            let x = [0.0; 20];
            fmi2SetContinuousStates(c, x.as_ptr(), 20)
        }),
        ("fmi2GetEventIndicators", |c| unsafe {
            // adams-linear has no clearance: no event indicators
            let mut z = [0.0; 1];
            fmi2GetEventIndicators(c, z.as_mut_ptr(), 0)
        }),
        ("fmi2NewDiscreteStates", |c| unsafe {
            let mut info = std::mem::zeroed::<ffi::EventInfo>();
            fmi2NewDiscreteStates(c, &mut info)
        }),
        ("fmi2CompletedIntegratorStep", |c| unsafe {
            let (mut event, mut stop) = (0, 0);
            fmi2CompletedIntegratorStep(c, 1, &mut event, &mut stop)
        }),
    ];
    let states = [Instantiated, Initialization, Stepping, Terminated];
    let run = |kind, (name, call): Call, allowed: &[State]| {
        for state in states {
            unsafe {
                let c = instance_of(kind, state, &format!("sm2-{kind}-{name}-{state:?}"));
                let expected = if allowed.contains(&state) { OK } else { ERROR };
                assert_eq!(call(c), expected, "{name} in {state:?} (kind {kind})");
                fmi2FreeInstance(c);
            }
        }
    };
    for (call, allowed) in calls {
        run(ffi::CO_SIMULATION, call, allowed);
    }
    for call in me_calls {
        // model exchange only, once initialized; never on a co-simulation instance
        run(ffi::MODEL_EXCHANGE, call, &[Stepping]);
        run(ffi::CO_SIMULATION, call, &[]);
    }
}
