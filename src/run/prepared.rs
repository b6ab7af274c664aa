//! One run path: a [`PreparedRun`] is a scene with its model chosen from the registry and
//! its method and settings resolved. Simulation, control, sweeps, convergence and
//! work-precision all prepare a run this way and integrate it through
//! [`PreparedRun::integrate`], which checks the work budget first.
//!
//! ```
//! use telescopic::run::PreparedRun;
//! use telescopic::run::SimulationOptions;
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=0.2".into()])?;
//! let run = PreparedRun::new(&scene, &SimulationOptions::default(), &Silent)?;
//! let trajectory = run.integrate(&Silent)?;
//! assert_eq!(trajectory.rows.len(), 201);
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::report::Reporter;
use crate::run::method::{MethodReason, Plan, plan};
use crate::run::models::ChosenModel;
use crate::run::options::SimulationOptions;
use crate::run::simulation::Simulation;
use crate::run::stress::StationRows;
use crate::run::trajectory::{self, Trajectory};
use crate::{Error, Result};
use telescopic_runtime::model::sensors::Sensors;
use telescopic_runtime::{
    Method, Model, Scene, Settings, model::rest_state, simulate, specializations,
};

/// A scene ready to integrate: its model and its resolved plan.
pub struct PreparedRun<'s> {
    /// The scene.
    pub scene: &'s Scene,
    /// The model that runs it and what it is.
    pub chosen: ChosenModel,
    /// The method and settings.
    pub plan: Plan,
    /// The stations whose moments and stresses are output columns.
    pub stations: StationRows,
    /// The memory its outputs may take (bytes, [`SimulationOptions::memory_budget`]).
    pub memory_budget: u64,
    /// Whether the generalized coordinates are output columns too
    /// ([`SimulationOptions::coordinates`]).
    pub coordinates: bool,
}

impl<'s> PreparedRun<'s> {
    /// Resolves `options` on `scene` ([`plan()`]) and chooses the model from
    /// `options.models` by `options.model`; a fallback note goes to `reporter`.
    ///
    /// # Errors
    /// [`Error::Option`] for bad options, [`Error::Model`] when no model can be had.
    pub fn new(
        scene: &'s Scene,
        options: &SimulationOptions,
        reporter: &dyn Reporter,
    ) -> Result<Self> {
        let plan = plan(scene, options)?;
        let chosen = options.models.build(&scene.params, options.model)?;
        crate::run::memory::check_station_count(options.stations.len())?;
        let stations = StationRows::new(scene, chosen.model.as_ref(), &options.stations)?;
        if let Some(note) = &chosen.note {
            reporter.note(note);
        }
        Ok(PreparedRun {
            scene,
            chosen,
            plan,
            stations,
            memory_budget: options.memory_budget,
            coordinates: options.coordinates,
        })
    }

    /// A run of `scene` on an already chosen model with `method` and `settings`, its outputs
    /// within `memory_budget` (bytes).
    pub fn with_model(
        scene: &'s Scene,
        chosen: ChosenModel,
        (method, settings): (Method, Settings),
        memory_budget: u64,
    ) -> Self {
        PreparedRun {
            scene,
            chosen,
            plan: Plan {
                method,
                reason: MethodReason::Given,
                settings,
                integration_error_m: None,
                integration_statistics_rel: None,
            },
            stations: StationRows::none(),
            memory_budget,
            coordinates: false,
        }
    }

    /// The model.
    pub fn model(&self) -> &dyn Model {
        self.chosen.model.as_ref()
    }

    /// Integrates the scene on its model from rest, after checking the work budget.
    ///
    /// # Errors
    /// [`Error::Unaffordable`] before any work, [`Error::Simulation`] or
    /// [`Error::NonFiniteOutput`] for a failed run.
    pub fn integrate(&self, reporter: &dyn Reporter) -> Result<Trajectory> {
        self.integrate_on(self.model(), self.model(), reporter)
    }

    /// Integrates the scene on `model`, a wrapper of this run's model (a controller or an
    /// observer around it), checking the budget on `budget_model` (the model whose stiffness
    /// sets the step).
    ///
    /// # Errors
    /// As [`PreparedRun::integrate`].
    pub fn integrate_on(
        &self,
        model: &dyn Model,
        budget_model: &dyn Model,
        reporter: &dyn Reporter,
    ) -> Result<Trajectory> {
        let (method, settings) = (self.plan.method, &self.plan.settings);
        let coordinates = if self.coordinates {
            model.layout().dof()
        } else {
            0
        };
        crate::run::memory::check_run(
            self.scene,
            (self.stations.len(), coordinates),
            self.memory_budget,
        )?;
        crate::run::budget::check_run(self.scene, budget_model, method, settings)?;
        let outputs = Outputs {
            stations: &self.stations,
            coordinates,
        };
        integrate_from_rest(self.scene, model, (method, settings), &outputs, reporter)
    }

    /// The finished simulation of this run with `trajectory`.
    pub fn into_simulation(self, trajectory: Trajectory) -> Simulation {
        let plan = &self.plan;
        let specializations = specializations(
            self.model(),
            &self.scene.time,
            plan.method,
            plan.settings.exact_from,
        );
        Simulation {
            scene: self.scene.name.clone(),
            span: (self.scene.time.start, self.scene.time.end),
            model: self.chosen.description,
            specializations,
            plan: self.plan,
            modes: self.scene.params.modes(),
            basis: self.scene.params.basis,
            trajectory,
            error: None,
        }
    }
}

/// The columns a run adds to its model's outputs and sensors.
struct Outputs<'a> {
    /// The stations' moments and stresses.
    stations: &'a StationRows,
    /// How many generalized coordinates follow them (0: none).
    coordinates: usize,
}

/// Integrates `scene` on `model` from rest with `method` and `settings`, collecting every
/// output sample (the model's outputs, the sensors, the stations', then the coordinates);
/// no budget check (that is [`PreparedRun::integrate`]'s).
fn integrate_from_rest(
    scene: &Scene,
    model: &dyn Model,
    (method, settings): (Method, &Settings),
    outputs: &Outputs,
    reporter: &dyn Reporter,
) -> Result<Trajectory> {
    let stations = outputs.stations;
    let own = model.output_quantities().len();
    let mut columns = trajectory::model_and_sensor_columns(model);
    let with_sensors = columns.len();
    columns.extend(stations.columns());
    let with_stations = columns.len();
    columns.extend(trajectory::coordinate_columns(outputs.coordinates));
    let sensors = Sensors::new(model);
    let dof = model.dof();
    // the contact forces f_k_j among the model's outputs (after vehicle, tip, top1 and gaps)
    let contacts = model.layout().contact_count();
    let forces = 3 + contacts..3 + 2 * contacts;
    let mut rows: Vec<Vec<f64>> = Vec::with_capacity(crate::run::budget::sample_count(&scene.time));
    let mut out = vec![0.0; columns.len()];
    let mut bad_output: Option<(f64, String)> = None;
    let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
        let (model_outputs, rest) = out.split_at_mut(own);
        let (sensor_outputs, rest) = rest.split_at_mut(with_sensors - own);
        let (station_outputs, coordinate_outputs) = rest.split_at_mut(with_stations - with_sensors);
        coordinate_outputs.copy_from_slice(&y[..coordinate_outputs.len()]);
        model.outputs(t, y, ydot, model_outputs);
        sensors.values(dof, y, ydot, sensor_outputs);
        stations.values(
            t,
            dof,
            (y, ydot),
            &model_outputs[forces.clone()],
            station_outputs,
        );
        if bad_output.is_none()
            && let Some(i) = out.iter().position(|v| !v.is_finite())
        {
            bad_output = Some((t, columns[i].to_string()));
        }
        let mut row = Vec::with_capacity(out.len() + 1);
        row.push(t);
        row.extend_from_slice(&out);
        rows.push(row);
    };
    let span = scene.time;
    let mut tick = |t: f64| {
        reporter.progress((t - span.start) / (span.end - span.start));
        !reporter.stop_requested()
    };
    reporter.start(&format!("simulating {}", scene.name));
    let y0 = rest_state(model, span.start);
    let result = simulate(
        model,
        &y0,
        &span,
        method,
        settings,
        &mut observe,
        Some(&mut tick),
    );
    reporter.finish();
    let stats = result.map_err(|error| Error::Simulation {
        scene: scene.name.clone(),
        error,
    })?;
    if let Some((t, name)) = bad_output {
        return Err(Error::NonFiniteOutput {
            name,
            t,
            method: method.name(),
        });
    }
    Ok(Trajectory::new(columns, rows, stats))
}
