//! One FMU instance, in safe Rust: the scene read from the FMU's resources, the parameters set
//! by the importer (checked like `--set`), and the model with its held drive force, stepped
//! by the library's integrators (co-simulation) or evaluated for the importer's integrator
//! (model exchange). Every instance owns everything it uses: two instances in one process
//! are independent.

use std::path::{Path, PathBuf};
use telescopic::fmu::held::HeldDrive;
use telescopic::fmu::{Causality, FmuVariables, SCENE_RESOURCE, scene_guid};
use telescopic::run::models::{ModelChoice, ModelRegistry};
use telescopic::run::{HeldInputStepper, SimulationOptions, plan};
use telescopic::runtime::model::sensors::Sensors;
use telescopic::runtime::{Drive, Model, Profile, Scene, TimeSpan, rest_state};

/// What an instance is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// The importer integrates.
    ModelExchange,
    /// `fmi2DoStep` integrates.
    CoSimulation,
}

/// Where an instance is in its life (FMI 2.0's state machine, simplified).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Instantiated: parameters may be set.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialization,
    /// Stepping (co-simulation) or in continuous-time / event mode (model exchange).
    Running,
    /// After `fmi2Terminate`.
    Terminated,
}

impl Phase {
    /// The state in FMI 2.0's words.
    fn describe(self) -> &'static str {
        match self {
            Phase::Instantiated => "instantiated",
            Phase::Initialization => "in initialization mode",
            Phase::Running => "initialized (stepping)",
            Phase::Terminated => "terminated",
        }
    }
}

/// The run a co-simulation instance advances over its communication steps (none for model
/// exchange, where the importer integrates).
type CoSimulationRun<'a> = Option<HeldInputStepper<'a>>;

self_cell::self_cell!(
    /// The model with its held input and the run that borrows it.
    struct Stepping {
        owner: HeldDrive,
        #[not_covariant]
        dependent: CoSimulationRun,
    }
);

/// The model and the integration of a running instance.
struct Running {
    stepping: Stepping,
    sensors: Sensors,
    /// `[z, zd]` (for co-simulation, the run's state after each step).
    y: Vec<f64>,
    ydot: Vec<f64>,
    outputs: Vec<f64>,
    xi: Vec<f64>,
    xi_dot: Vec<f64>,
    half_band: f64,
    /// The model's own outputs (the sensors follow them).
    own_outputs: usize,
    /// The longest communication step the step limit affords (s), and the stable step it
    /// assumes (s); infinite for a method without a bound.
    affordable: (f64, f64),
}

/// One FMU instance.
pub struct Instance {
    /// The instance name the importer gave (for the logger).
    pub name: String,
    kind: Kind,
    /// The scene as the FMU's resources hold it (parameters set on a copy).
    base: Scene,
    /// The scene with the parameters set so far.
    scene: Scene,
    vars: FmuVariables,
    /// `(scene key, value)` of every parameter set, in order.
    overrides: Vec<(String, f64)>,
    phase: Phase,
    time: f64,
    force: f64,
    running: Option<Running>,
}

/// An error for the importer's logger: the message names what was wrong.
pub type Failure = String;

/// Largest time (s) the FMU takes: far beyond any run, and a step of a microsecond still
/// advances it in double precision.
const MAX_TIME_S: f64 = 1e9;

/// Refuses an array of `given` entries where `call` fills `needed`.
fn sized(call: &str, given: usize, needed: usize) -> Result<(), Failure> {
    if given == needed {
        return Ok(());
    }
    Err(format!(
        "{call}: an array of {given} entries given, the model has {needed}"
    ))
}

/// A library error as the FMU's log tells it. The FMU sets its run's options itself, so an
/// option error names the setting and is a bug of the FMU, not of the importer.
fn failure(error: telescopic::Error) -> Failure {
    match error {
        telescopic::Error::Option { option, rule, .. } => format!(
            "the FMU's own run setting {option} breaks its rule: {rule} (a bug in telescopic's \
             FMU export; please report it)"
        ),
        e => e.to_string(),
    }
}

impl Instance {
    /// Reads the scene from the FMU's resources at `resources` (a `file:` URI or a path) and
    /// checks that the FMU's description (`guid`) is this scene's.
    ///
    /// # Errors
    /// A message naming the missing file, the invalid scene or the GUID mismatch.
    pub fn new(name: &str, kind: Kind, fmu_guid: &str, resources: &str) -> Result<Self, Failure> {
        let dir = resource_dir(resources)?;
        let scene_path = dir.join(SCENE_RESOURCE);
        // capped like every scene: a link to an endless file is refused, not read
        let scene_text = telescopic::runtime::input::read_text(
            &scene_path,
            telescopic::runtime::input::MAX_TEXT_INPUT_BYTES,
        )
        .map_err(|e| format!("reading the FMU's scene {}: {e}", scene_path.display()))?;
        let scene =
            Scene::from_toml_str(&scene_text, &scene_path, &[]).map_err(|e| e.to_string())?;
        let vars = FmuVariables::of(&scene).map_err(|e| e.to_string())?;
        let ours = scene_guid(&scene).map_err(|e| e.to_string())?;
        if ours != fmu_guid {
            return Err(format!(
                "the FMU's GUID {fmu_guid} is not its scene's ({ours}): the modelDescription.xml \
                 and resources/{SCENE_RESOURCE} come from different exports"
            ));
        }
        let force = vars.variables[0].start.unwrap_or(0.0);
        Ok(Instance {
            name: name.to_string(),
            kind,
            base: scene.clone(),
            time: scene.time.start,
            scene,
            vars,
            overrides: Vec::new(),
            phase: Phase::Instantiated,
            force,
            running: None,
        })
    }

    /// Refuses `call` outside the states of FMI 2.0's state machine it belongs to.
    fn expect_phase(&self, call: &str, allowed: &[Phase]) -> Result<(), Failure> {
        if allowed.contains(&self.phase) {
            return Ok(());
        }
        Err(format!(
            "{call} is not allowed now: the instance is {} (FMI 2.0's state machine)",
            self.phase.describe()
        ))
    }

    /// `fmi2SetupExperiment`: the start time (s), before initialization.
    pub fn setup_experiment(&mut self, start: f64) -> Result<(), Failure> {
        self.expect_phase("fmi2SetupExperiment", &[Phase::Instantiated])?;
        if !(start.is_finite() && start.abs() <= MAX_TIME_S) {
            return Err(format!(
                "the start time must be a finite number of seconds within +-{MAX_TIME_S:e} (got \
                 {start})"
            ));
        }
        self.time = start;
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> Result<(), Failure> {
        self.expect_phase("fmi2EnterInitializationMode", &[Phase::Instantiated])?;
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: builds the model with the parameters set.
    pub fn exit_initialization(&mut self) -> Result<(), Failure> {
        self.expect_phase("fmi2ExitInitializationMode", &[Phase::Initialization])?;
        let mut params = self.scene.params.clone();
        // the input replaces the scene's drive: the base model is driven by nothing
        let (base_drive, planned_drive) = match params.drive {
            Drive::Force(_) => (
                Drive::Force(Profile::Constant(0.0)),
                Drive::Force(Profile::Constant(self.force)),
            ),
            Drive::Motion(_) => (
                Drive::Motion(Profile::Constant(0.0)),
                Drive::Motion(Profile::Constant(0.0)),
            ),
        };
        params.drive = base_drive;
        let chosen = ModelRegistry::default()
            .build(&params, ModelChoice::Auto)
            .map_err(failure)?;
        let model = HeldDrive::new(chosen.model, self.force).map_err(|e| e.to_string())?;
        let mut planned = self.scene.clone();
        planned.params.drive = planned_drive;
        let plan = plan(&planned, &SimulationOptions::default()).map_err(failure)?;
        // the step limit of a whole run applies to each communication step
        let affordable =
            telescopic::run::budget::estimate_steps(&planned, &model, plan.method, &plan.settings)
                .map_err(failure)?
                .map_or((f64::INFINITY, 0.0), |e| {
                    (e.step * plan.settings.max_steps as f64, e.step)
                });
        let n = model.dof();
        let nc = model.layout().contact_count();
        let outputs = self.vars.outputs;
        let own_outputs = model.output_names().len();
        let sensors = Sensors::new(&model);
        let y = rest_state(&model, self.time);
        let span = TimeSpan {
            start: self.time,
            end: self.time.max(self.scene.time.end),
            ..self.scene.time
        };
        let co_simulation = self.kind == Kind::CoSimulation;
        let stepping = Stepping::try_new(model, |model| {
            co_simulation
                .then(|| HeldInputStepper::new(&plan, model, &span, &y))
                .transpose()
        })
        .map_err(|e| format!("the co-simulation run cannot start: {e}"))?;
        self.running = Some(Running {
            own_outputs,
            sensors,
            y,
            half_band: self.scene.params.contact.half_band(),
            stepping,
            ydot: vec![0.0; 2 * n],
            outputs: vec![0.0; outputs],
            xi: vec![0.0; nc],
            xi_dot: vec![0.0; nc],
            affordable,
        });
        self.phase = Phase::Running;
        Ok(())
    }

    /// The running model, or an error naming `call`.
    fn running(&mut self, call: &str) -> Result<&mut Running, Failure> {
        self.running.as_mut().ok_or_else(|| {
            format!("{call} needs an initialized instance (fmi2ExitInitializationMode)")
        })
    }

    /// Refuses a model-exchange call on a co-simulation instance or outside its modes.
    pub fn model_exchange(&self, call: &str) -> Result<(), Failure> {
        if self.kind != Kind::ModelExchange {
            return Err(format!("{call} is for model-exchange instances"));
        }
        self.expect_phase(call, &[Phase::Running])
    }

    /// Refuses a get (`set` false) or set call of values outside the states FMI 2.0 allows it
    /// in: gets from initialization mode on, sets until `fmi2Terminate`.
    pub fn value_access(&self, call: &str, set: bool) -> Result<(), Failure> {
        if set {
            self.expect_phase(
                call,
                &[Phase::Instantiated, Phase::Initialization, Phase::Running],
            )
        } else {
            self.expect_phase(
                call,
                &[Phase::Initialization, Phase::Running, Phase::Terminated],
            )
        }
    }

    /// `fmi2SetReal`.
    pub fn set_real(&mut self, refs: &[u32], values: &[f64]) -> Result<(), Failure> {
        self.value_access("fmi2SetReal", true)?;
        for (&vr, &v) in refs.iter().zip(values) {
            let var = self
                .vars
                .variables
                .get(vr as usize)
                .ok_or_else(|| format!("no variable has value reference {vr}"))?;
            match var.causality {
                Causality::Input => {
                    if !v.is_finite() {
                        return Err(format!("the input {} must be finite (got {v})", var.name));
                    }
                    self.force = v;
                    if let Some(r) = &mut self.running {
                        r.set_input(v);
                    }
                }
                Causality::Parameter => {
                    if self.phase == Phase::Running || self.phase == Phase::Terminated {
                        return Err(format!(
                            "parameter {} can only be set before fmi2ExitInitializationMode",
                            var.name
                        ));
                    }
                    let key = var.name.clone();
                    self.set_parameter(&key, v)?;
                }
                _ => {
                    return Err(format!(
                        "{} is not settable (only F and the parameters are)",
                        var.name
                    ));
                }
            }
        }
        Ok(())
    }

    /// Sets parameter `key` to `value` after checking the scene with it, like `--set`.
    fn set_parameter(&mut self, key: &str, value: f64) -> Result<(), Failure> {
        let mut overrides = self.overrides.clone();
        overrides.retain(|(k, _)| k != key);
        overrides.push((key.to_string(), value));
        let values: Vec<(&str, f64)> = overrides.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let scene = self
            .base
            .with_values(&values)
            .map_err(|e| format!("parameter {key} = {value}: {e}"))?;
        self.scene = scene;
        self.overrides = overrides;
        Ok(())
    }

    /// `fmi2GetReal`.
    pub fn get_real(&mut self, refs: &[u32], values: &mut [f64]) -> Result<(), Failure> {
        self.value_access("fmi2GetReal", false)?;
        let first_state = self.vars.first_state as usize;
        let states = self.vars.states;
        let outputs = self.vars.outputs;
        let (time, force) = (self.time, self.force);
        if let Some(r) = &mut self.running {
            r.evaluate(time);
        }
        for (&vr, value) in refs.iter().zip(values.iter_mut()) {
            let i = vr as usize;
            *value = match i {
                0 => force,
                i if (1..=outputs).contains(&i) => {
                    self.running.as_ref().map_or(0.0, |r| r.outputs[i - 1])
                }
                i if i >= first_state && i < first_state + states => {
                    self.running.as_ref().map_or(0.0, |r| r.y[i - first_state])
                }
                i if i >= first_state + states && i < first_state + 2 * states => self
                    .running
                    .as_ref()
                    .map_or(0.0, |r| r.ydot[i - first_state - states]),
                i => match self.vars.variables.get(i) {
                    Some(v) if v.causality == Causality::Parameter => {
                        self.parameter_value(&v.name, v.start)
                    }
                    _ => return Err(format!("no variable has value reference {vr}")),
                },
            };
        }
        Ok(())
    }

    /// The current value of parameter `key` (set, else its start value).
    fn parameter_value(&self, key: &str, start: Option<f64>) -> f64 {
        self.overrides
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map_or(start.unwrap_or(0.0), |(_, v)| *v)
    }

    /// `fmi2DoStep`: integrates from `t` to `t + h` (s) with `F` held.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), Failure> {
        if self.kind != Kind::CoSimulation {
            return Err("fmi2DoStep is for co-simulation instances".into());
        }
        let now = self.time;
        if (t - now).abs() > 1e-9 * now.abs().max(1.0) {
            return Err(format!(
                "fmi2DoStep from t = {t} s, but the FMU is at t = {now} s"
            ));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("the communication step must be > 0 s (got {h})"));
        }
        if !(t + h > t && (t + h).abs() <= MAX_TIME_S) {
            return Err(format!(
                "a step of {h} s from t = {t} s does not advance the time in double precision \
                 or leaves +-{MAX_TIME_S:e} s"
            ));
        }
        self.expect_phase("fmi2DoStep", &[Phase::Running])?;
        let r = self.running("fmi2DoStep")?;
        let (longest, stable) = r.affordable;
        if h > longest {
            return Err(format!(
                "a communication step of {h} s needs about {:.2e} steps of the stable {stable:.3e} \
                 s, more than the step limit: take steps of at most {longest:.3e} s",
                h / stable
            ));
        }
        r.advance_to(t + h)
            .map_err(|e| format!("the step from t = {t} s to {} s failed: {e}", t + h))?;
        self.time = t + h;
        Ok(())
    }

    /// `fmi2SetTime` (model exchange).
    pub fn set_time(&mut self, t: f64) -> Result<(), Failure> {
        self.model_exchange("fmi2SetTime")?;
        if !(t.is_finite() && t.abs() <= MAX_TIME_S) {
            return Err(format!(
                "the time must be a finite number of seconds within +-{MAX_TIME_S:e} (got {t})"
            ));
        }
        self.time = t;
        Ok(())
    }

    /// `fmi2SetContinuousStates`.
    pub fn set_states(&mut self, x: &[f64]) -> Result<(), Failure> {
        self.model_exchange("fmi2SetContinuousStates")?;
        let r = self.running("fmi2SetContinuousStates")?;
        if x.len() != r.y.len() {
            return Err(format!(
                "{} states given, the model has {}",
                x.len(),
                r.y.len()
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(format!("state {i} is not finite ({})", x[i]));
        }
        r.y.copy_from_slice(x);
        Ok(())
    }

    /// `fmi2GetContinuousStates`.
    pub fn get_states(&mut self, x: &mut [f64]) -> Result<(), Failure> {
        self.model_exchange("fmi2GetContinuousStates")?;
        let r = self.running("fmi2GetContinuousStates")?;
        sized("fmi2GetContinuousStates", x.len(), r.y.len())?;
        x.copy_from_slice(&r.y);
        Ok(())
    }

    /// `fmi2GetDerivatives`.
    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<(), Failure> {
        self.model_exchange("fmi2GetDerivatives")?;
        let t = self.time;
        let r = self.running("fmi2GetDerivatives")?;
        sized("fmi2GetDerivatives", dx.len(), r.ydot.len())?;
        r.stepping.borrow_owner().rhs(t, &r.y, None, &mut r.ydot);
        dx.copy_from_slice(&r.ydot);
        Ok(())
    }

    /// `fmi2GetEventIndicators`: `xi_c - l_S/2` and `xi_c + l_S/2` of every contact (the
    /// band's edges, where the contact law switches).
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> Result<(), Failure> {
        self.model_exchange("fmi2GetEventIndicators")?;
        // the declared count: two per contact with clearance, none without
        sized(
            "fmi2GetEventIndicators",
            z.len(),
            self.vars.event_indicators,
        )?;
        if z.is_empty() {
            return Ok(());
        }
        let t = self.time;
        let r = self.running("fmi2GetEventIndicators")?;
        r.stepping
            .borrow_owner()
            .contact_gaps(t, &r.y, &mut r.xi, &mut r.xi_dot);
        for (pair, &xi) in z.chunks_exact_mut(2).zip(&r.xi) {
            pair[0] = xi - r.half_band;
            pair[1] = xi + r.half_band;
        }
        Ok(())
    }

    /// Number of continuous states.
    pub fn state_count(&self) -> usize {
        self.vars.states
    }

    /// Number of event indicators.
    pub fn indicator_count(&self) -> usize {
        self.vars.event_indicators
    }

    /// The time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), Failure> {
        self.expect_phase("fmi2Terminate", &[Phase::Running])?;
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// `fmi2Reset`: back to just instantiated, parameters at their start values.
    pub fn reset(&mut self) -> Result<(), Failure> {
        self.scene = self.base.clone();
        self.overrides.clear();
        self.running = None;
        self.phase = Phase::Instantiated;
        self.time = self.scene.time.start;
        self.force = self.vars.variables[0].start.unwrap_or(0.0);
        Ok(())
    }
}

impl Running {
    /// Holds input `value` (N, or m/s^2 for a prescribed motion) from now on.
    fn set_input(&mut self, value: f64) {
        self.stepping.with_dependent_mut(|model, run| {
            if model.input() != value {
                model.set_input(value);
                if let Some(run) = run {
                    run.input_changed();
                }
            }
        });
    }

    /// Advances the co-simulation run to `t_end` (s) with the input held.
    fn advance_to(&mut self, t_end: f64) -> Result<(), telescopic::runtime::SimError> {
        let y = &mut self.y;
        self.stepping.with_dependent_mut(|_, run| {
            let run = run.as_mut().expect("a co-simulation instance has its run");
            run.advance_to(t_end)?;
            y.copy_from_slice(run.state());
            Ok(())
        })
    }

    /// Outputs and derivatives at time `t` and the current state.
    fn evaluate(&mut self, t: f64) {
        let model = self.stepping.borrow_owner();
        let n = model.dof();
        model.rhs(t, &self.y, None, &mut self.ydot);
        let (model_out, sensor_out) = self.outputs.split_at_mut(self.own_outputs);
        model.outputs(t, &self.y, &self.ydot, model_out);
        self.sensors.values(n, &self.y, &self.ydot, sensor_out);
    }
}

/// The directory of a `fmuResourceLocation`: a `file:` URI (`file:///dir`, `file:/dir`,
/// percent-encoded) or a plain path.
fn resource_dir(location: &str) -> Result<PathBuf, Failure> {
    let path = match location.strip_prefix("file://") {
        Some(rest) => rest.strip_prefix("localhost").unwrap_or(rest).to_string(),
        None => location
            .strip_prefix("file:")
            .unwrap_or(location)
            .to_string(),
    };
    let decoded = percent_decode(&path)?;
    let dir = Path::new(&decoded);
    if !dir.is_dir() {
        return Err(format!(
            "the FMU's resource location {location} is not a directory"
        ));
    }
    Ok(dir.to_path_buf())
}

/// `%XX` escapes decoded (hand-written: a URI's path is all an FMU needs decoded).
fn percent_decode(text: &str) -> Result<String, Failure> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).map_err(|e| e.to_string())?;
            let b = u8::from_str_radix(hex, 16)
                .map_err(|_| format!("bad escape %{hex} in the resource location"))?;
            out.push(b);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|e| e.to_string())
}
