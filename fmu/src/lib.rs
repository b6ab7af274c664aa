//! The shared library of telescopic's FMUs (FMI 2.0, model exchange and co-simulation):
//! every `fmi2*` function of the standard, over [`instance::Instance`] and the `telescopic`
//! library. `telescopic fmu SCENE --out X.fmu` packs this library with the scene and its
//! `modelDescription.xml` (docs/fmu.md).
//!
//! Robust as a library: no panic crosses the C boundary (each function runs under
//! `catch_unwind`; a panic becomes `fmi2Fatal` with a message to the logger), nothing is
//! printed, every error goes to the importer's logger callback with the instance's name, and
//! instances share nothing.

#![allow(clippy::missing_safety_doc)]

pub mod ffi;
pub mod instance;

use ffi::{
    Boolean, CallbackFunctions, Component, ComponentEnvironment, DISCARD, ERROR, EventInfo, FATAL,
    FmiString, Logger, OK, Status, ValueReference,
};
use instance::{Instance, Kind};
use std::ffi::{CStr, CString, c_char, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// An instance with the importer's logger.
struct Wrapped {
    instance: Instance,
    logger: Logger,
    environment: ComponentEnvironment,
    debug: bool,
}

/// Sends `message` to `logger` with `status` (the message passed as `%s`, never as a format).
fn log(logger: Logger, env: ComponentEnvironment, name: &str, status: Status, message: &str) {
    let Some(logger) = logger else { return };
    let clean = |s: &str| CString::new(s.replace('\0', " ")).unwrap_or_default();
    let (name, message) = (clean(name), clean(message));
    let category = if status >= ERROR {
        c"logStatusError"
    } else {
        c"logAll"
    };
    // SAFETY: the importer's callback, with NUL-terminated strings that outlive the call
    unsafe {
        logger(
            env,
            name.as_ptr(),
            status,
            category.as_ptr(),
            c"%s".as_ptr(),
            message.as_ptr(),
        )
    };
}

/// A C string argument, or `""`.
unsafe fn text<'a>(s: FmiString) -> &'a str {
    if s.is_null() {
        return "";
    }
    // SAFETY: the importer passes NUL-terminated strings
    unsafe { CStr::from_ptr(s) }.to_str().unwrap_or("")
}

/// A slice of `n` values at `p` (empty for `n = 0`; `None` for a null pointer with `n > 0`).
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    // SAFETY: the importer passes `n` valid values at `p`
    (!p.is_null()).then(|| unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice of `n` values at `p`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        return Some(&mut []);
    }
    // SAFETY: the importer passes room for `n` values at `p`
    (!p.is_null()).then(|| unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// Runs `body` on the instance `c` under `catch_unwind`: `Err` goes to the logger as
/// `fmi2Error`, a panic as `fmi2Fatal`.
unsafe fn with(
    c: Component,
    call: &str,
    body: impl FnOnce(&mut Instance) -> Result<(), String>,
) -> Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: `c` is a pointer this library returned from fmi2Instantiate
    let w = unsafe { &mut *(c as *mut Wrapped) };
    let (logger, env) = (w.logger, w.environment);
    match catch_unwind(AssertUnwindSafe(|| body(&mut w.instance))) {
        Ok(Ok(())) => {
            if w.debug {
                log(logger, env, &w.instance.name, OK, &format!("{call}: ok"));
            }
            OK
        }
        Ok(Err(message)) => {
            log(
                logger,
                env,
                &w.instance.name,
                ERROR,
                &format!("{call}: {message}"),
            );
            ERROR
        }
        Err(panic) => {
            log(
                logger,
                env,
                &w.instance.name,
                FATAL,
                &format!("{call}: {}", telescopic::Error::from_panic(panic.as_ref())),
            );
            FATAL
        }
    }
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Component,
    on: Boolean,
    _n: usize,
    _categories: *const FmiString,
) -> Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: an instance of this library
    unsafe { (*(c as *mut Wrapped)).debug = on != 0 };
    OK
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    name: FmiString,
    kind: c_int,
    guid: FmiString,
    resources: FmiString,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging_on: Boolean,
) -> Component {
    // SAFETY: the importer's strings and callback struct
    let (name, guid, resources) = unsafe { (text(name), text(guid), text(resources)) };
    let (logger, env) = if functions.is_null() {
        (None, std::ptr::null_mut())
    } else {
        // SAFETY: a valid fmi2CallbackFunctions
        unsafe { ((*functions).logger, (*functions).component_environment) }
    };
    let kind = match kind {
        ffi::MODEL_EXCHANGE => Kind::ModelExchange,
        ffi::CO_SIMULATION => Kind::CoSimulation,
        other => {
            log(
                logger,
                env,
                name,
                ERROR,
                &format!("fmi2Instantiate: unknown fmuType {other}"),
            );
            return std::ptr::null_mut();
        }
    };
    let made = catch_unwind(|| Instance::new(name, kind, guid, resources));
    match made {
        Ok(Ok(instance)) => Box::into_raw(Box::new(Wrapped {
            instance,
            logger,
            environment: env,
            debug: logging_on != 0,
        })) as Component,
        Ok(Err(message)) => {
            log(
                logger,
                env,
                name,
                ERROR,
                &format!("fmi2Instantiate: {message}"),
            );
            std::ptr::null_mut()
        }
        Err(_) => {
            log(
                logger,
                env,
                name,
                FATAL,
                "fmi2Instantiate: internal error (a bug in telescopic)",
            );
            std::ptr::null_mut()
        }
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Component) {
    if !c.is_null() {
        // SAFETY: a pointer from fmi2Instantiate, freed once
        drop(unsafe { Box::from_raw(c as *mut Wrapped) });
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Component,
    _tolerance_defined: Boolean,
    _tolerance: f64,
    start: f64,
    _stop_defined: Boolean,
    _stop: f64,
) -> Status {
    unsafe { with(c, "fmi2SetupExperiment", |i| i.setup_experiment(start)) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
    unsafe {
        with(
            c,
            "fmi2EnterInitializationMode",
            Instance::enter_initialization,
        )
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
    unsafe {
        with(
            c,
            "fmi2ExitInitializationMode",
            Instance::exit_initialization,
        )
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: Component) -> Status {
    unsafe { with(c, "fmi2Terminate", Instance::terminate) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Component) -> Status {
    unsafe { with(c, "fmi2Reset", Instance::reset) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    values: *mut f64,
) -> Status {
    unsafe {
        with(c, "fmi2GetReal", |i| {
            let (refs, out) = (slice(vr, n), slice_mut(values, n));
            let (Some(refs), Some(out)) = (refs, out) else {
                return Err("null pointer for value references or values".into());
            };
            i.get_real(refs, out)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    values: *const f64,
) -> Status {
    unsafe {
        with(c, "fmi2SetReal", |i| {
            let (Some(refs), Some(values)) = (slice(vr, n), slice(values, n)) else {
                return Err("null pointer for value references or values".into());
            };
            i.set_real(refs, values)
        })
    }
}

/// `fmi2Get/SetInteger`, `Boolean`, `String`: the FMU has no such variables; asking for
/// none is fine, asking for one is an error.
unsafe fn no_variables(c: Component, call: &str, n: usize) -> Status {
    unsafe {
        with(c, call, |i| {
            i.value_access(call, call.starts_with("fmi2Set"))?;
            if n == 0 {
                Ok(())
            } else {
                Err("the FMU has only Real variables".into())
            }
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *mut c_int,
) -> Status {
    unsafe { no_variables(c, "fmi2GetInteger", n) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const c_int,
) -> Status {
    unsafe { no_variables(c, "fmi2SetInteger", n) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *mut Boolean,
) -> Status {
    unsafe { no_variables(c, "fmi2GetBoolean", n) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const Boolean,
) -> Status {
    unsafe { no_variables(c, "fmi2SetBoolean", n) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *mut FmiString,
) -> Status {
    unsafe { no_variables(c, "fmi2GetString", n) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: Component,
    _vr: *const ValueReference,
    n: usize,
    _v: *const FmiString,
) -> Status {
    unsafe { no_variables(c, "fmi2SetString", n) }
}

/// A capability the FMU does not declare: an error naming it.
unsafe fn unsupported(c: Component, call: &str) -> Status {
    unsafe {
        with(c, call, |_| {
            Err("not supported by this FMU (see its modelDescription.xml)".into())
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, _s: *mut *mut std::ffi::c_void) -> Status {
    unsafe { unsupported(c, "fmi2GetFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, _s: *mut std::ffi::c_void) -> Status {
    unsafe { unsupported(c, "fmi2SetFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, _s: *mut *mut std::ffi::c_void) -> Status {
    unsafe { unsupported(c, "fmi2FreeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Component,
    _s: *mut std::ffi::c_void,
    _n: *mut usize,
) -> Status {
    unsafe { unsupported(c, "fmi2SerializedFMUstateSize") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    _s: *mut std::ffi::c_void,
    _b: *mut u8,
    _n: usize,
) -> Status {
    unsafe { unsupported(c, "fmi2SerializeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    _b: *const u8,
    _n: usize,
    _s: *mut *mut std::ffi::c_void,
) -> Status {
    unsafe { unsupported(c, "fmi2DeSerializeFMUstate") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Component,
    _u: *const ValueReference,
    _nu: usize,
    _z: *const ValueReference,
    _nz: usize,
    _dv: *const f64,
    _dz: *mut f64,
) -> Status {
    unsafe { unsupported(c, "fmi2GetDirectionalDerivative") }
}

// ---- model exchange ----

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterEventMode(c: Component) -> Status {
    unsafe {
        with(c, "fmi2EnterEventMode", |i| {
            i.model_exchange("fmi2EnterEventMode")
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2NewDiscreteStates(c: Component, info: *mut EventInfo) -> Status {
    unsafe {
        with(c, "fmi2NewDiscreteStates", |i| {
            i.model_exchange("fmi2NewDiscreteStates")?;
            if info.is_null() {
                return Err("null event info".into());
            }
            // the contact law picks its branch from the gap: nothing discrete to update
            *info = EventInfo {
                new_discrete_states_needed: 0,
                terminate_simulation: 0,
                nominals_of_continuous_states_changed: 0,
                values_of_continuous_states_changed: 0,
                next_event_time_defined: 0,
                next_event_time: 0.0,
            };
            Ok(())
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Component) -> Status {
    unsafe {
        with(c, "fmi2EnterContinuousTimeMode", |i| {
            i.model_exchange("fmi2EnterContinuousTimeMode")
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: Component,
    _no_set_prior: Boolean,
    enter_event_mode: *mut Boolean,
    terminate: *mut Boolean,
) -> Status {
    unsafe {
        with(c, "fmi2CompletedIntegratorStep", |i| {
            i.model_exchange("fmi2CompletedIntegratorStep")?;
            if !enter_event_mode.is_null() {
                *enter_event_mode = 0;
            }
            if !terminate.is_null() {
                *terminate = 0;
            }
            Ok(())
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetTime(c: Component, t: f64) -> Status {
    unsafe { with(c, "fmi2SetTime", |i| i.set_time(t)) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetContinuousStates(c: Component, x: *const f64, n: usize) -> Status {
    unsafe {
        with(c, "fmi2SetContinuousStates", |i| {
            let x = slice(x, n).ok_or("null states")?;
            i.set_states(x)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetContinuousStates(c: Component, x: *mut f64, n: usize) -> Status {
    unsafe {
        with(c, "fmi2GetContinuousStates", |i| {
            let x = slice_mut(x, n).ok_or("null states")?;
            i.get_states(x)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDerivatives(c: Component, dx: *mut f64, n: usize) -> Status {
    unsafe {
        with(c, "fmi2GetDerivatives", |i| {
            let dx = slice_mut(dx, n).ok_or("null derivatives")?;
            i.get_derivatives(dx)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetEventIndicators(c: Component, z: *mut f64, n: usize) -> Status {
    unsafe {
        with(c, "fmi2GetEventIndicators", |i| {
            let z = slice_mut(z, n).ok_or("null event indicators")?;
            i.get_event_indicators(z)
        })
    }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
    c: Component,
    x: *mut f64,
    n: usize,
) -> Status {
    unsafe {
        with(c, "fmi2GetNominalsOfContinuousStates", |_| {
            slice_mut(x, n).ok_or("null nominals")?.fill(1.0);
            Ok(())
        })
    }
}

// ---- co-simulation ----

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _n: usize,
    _order: *const c_int,
    _v: *const f64,
) -> Status {
    unsafe { unsupported(c, "fmi2SetRealInputDerivatives") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _n: usize,
    _order: *const c_int,
    _v: *mut f64,
) -> Status {
    unsafe { unsupported(c, "fmi2GetRealOutputDerivatives") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Component,
    t: f64,
    h: f64,
    _no_set_prior: Boolean,
) -> Status {
    unsafe { with(c, "fmi2DoStep", |i| i.do_step(t, h)) }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Component) -> Status {
    unsafe { unsupported(c, "fmi2CancelStep") }
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, _kind: c_int, _value: *mut Status) -> Status {
    let _ = c;
    DISCARD
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut f64) -> Status {
    // fmi2LastSuccessfulTime (2): the time reached
    if kind != 2 || value.is_null() || c.is_null() {
        return DISCARD;
    }
    // SAFETY: an instance of this library and a place for the value
    unsafe { *value = (*(c as *mut Wrapped)).instance.time() };
    OK
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    _c: Component,
    _kind: c_int,
    _value: *mut c_int,
) -> Status {
    DISCARD
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    _c: Component,
    _kind: c_int,
    _value: *mut Boolean,
) -> Status {
    DISCARD
}

#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    _c: Component,
    _kind: c_int,
    _value: *mut FmiString,
) -> Status {
    DISCARD
}
