//! The FMI 2.0 C types this library exchanges with an importer (fmi2TypesPlatform.h,
//! fmi2FunctionTypes.h). Written by hand: `fmi-sys` generates them with bindgen at build
//! time (libclang on every build machine, bindgen compiled into every build) for the
//! dynamic-loading side; the exporting side needs these nine declarations, fixed by the
//! standard since 2014.

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component`: the instance, opaque to the importer.
pub type Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the importer's pointer, passed back to its callbacks.
pub type ComponentEnvironment = *mut c_void;
/// `fmi2String`.
pub type FmiString = *const c_char;
/// `fmi2Boolean`.
pub type Boolean = c_int;
/// `fmi2ValueReference`.
pub type ValueReference = c_uint;
/// `fmi2Status`.
pub type Status = c_int;

/// `fmi2OK`.
pub const OK: Status = 0;
/// `fmi2Warning`.
pub const WARNING: Status = 1;
/// `fmi2Discard`.
pub const DISCARD: Status = 2;
/// `fmi2Error`.
pub const ERROR: Status = 3;
/// `fmi2Fatal`.
pub const FATAL: Status = 4;

/// `fmi2ModelExchange` of `fmi2Type`.
pub const MODEL_EXCHANGE: c_int = 0;
/// `fmi2CoSimulation` of `fmi2Type`.
pub const CO_SIMULATION: c_int = 1;

/// `fmi2CallbackLogger`: `(env, instance name, status, category, message format, ...)`.
pub type Logger = Option<
    unsafe extern "C" fn(ComponentEnvironment, FmiString, Status, FmiString, FmiString, ...),
>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    /// Where messages go.
    pub logger: Logger,
    /// `allocateMemory` (not used: this library allocates with Rust's allocator).
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// `freeMemory` (not used).
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// `stepFinished` (asynchronous steps; not used).
    pub step_finished: Option<unsafe extern "C" fn(ComponentEnvironment, Status)>,
    /// The importer's pointer for the logger.
    pub component_environment: ComponentEnvironment,
}

/// `fmi2EventInfo`.
#[repr(C)]
pub struct EventInfo {
    /// `newDiscreteStatesNeeded`.
    pub new_discrete_states_needed: Boolean,
    /// `terminateSimulation`.
    pub terminate_simulation: Boolean,
    /// `nominalsOfContinuousStatesChanged`.
    pub nominals_of_continuous_states_changed: Boolean,
    /// `valuesOfContinuousStatesChanged`.
    pub values_of_continuous_states_changed: Boolean,
    /// `nextEventTimeDefined`.
    pub next_event_time_defined: Boolean,
    /// `nextEventTime`.
    pub next_event_time: f64,
}
