//! A controller file checked like a scene: every field against its rule and against the
//! scene it is applied to, each error naming the JSON field.

use crate::OptionName;
use crate::control::design::{FORCE_LIMIT_RANGE, SCALE_RANGE};
use crate::control::file::schema::{Controller, Estimator, SampledDesign, SchedulePoint};
use crate::{Error, Result};
use std::path::Path;
use telescopic_runtime::analysis::linear::state_names;
use telescopic_runtime::input::{MAX_TEXT_INPUT_BYTES, read_text};
use telescopic_runtime::model::sensors::SENSOR_OUTPUTS;
use telescopic_runtime::{Drive, ModelParams, Scene, configuration_key};

/// Largest gain entry a controller file may hold (N per SI unit of its state): far above any
/// design at the usable force limits, and far below gains that make the controlled run
/// unaffordably stiff.
pub const MAX_GAIN: f64 = 1e12;

fn field(name: &str, rule: impl std::fmt::Display) -> Error {
    Error::input(format!("controller `{name}`"), rule)
}

/// Reads the controller file at `path` (size-capped like a scene) and parses it with `parse`;
/// every error names the file.
///
/// # Errors
/// [`Error::Option`] naming the file and what is wrong.
pub(crate) fn load_json<T>(path: &Path, parse: impl Fn(&str) -> Result<T>) -> Result<T> {
    let text = read_text(path, MAX_TEXT_INPUT_BYTES).map_err(|e| {
        Error::option(
            OptionName::Controller,
            format!("{}: cannot be read: {e}", path.display()),
        )
    })?;
    parse(&text)
        .map_err(|e| Error::option(OptionName::Controller, format!("{}: {e}", path.display())))
}

impl Controller {
    /// Reads and checks a controller file (size-capped like a scene).
    ///
    /// # Errors
    /// [`Error::Option`] naming the file and what is wrong, or [`Error::Input`] for a field.
    pub fn load(path: &Path) -> Result<Self> {
        load_json(path, Controller::from_json)
    }

    /// Checks that the controller fits `scene`: the same configuration and states in the
    /// model's order, a force drive, design points inside the scene's position ranges and
    /// in ascending order, finite and bounded gains, a valid feedforward profile.
    ///
    /// # Errors
    /// [`Error::Input`] naming the field and the rule; [`Error::Option`] for a scene the
    /// controller cannot drive.
    pub fn check_fits(&self, scene: &Scene) -> Result<()> {
        self.check_params(&scene.params)
    }

    /// [`Controller::check_fits`] on the scene's parameters.
    pub(crate) fn check_params(&self, params: &ModelParams) -> Result<()> {
        self.check_values()?;
        self.check_model(params)?;
        self.check_schedule(params)?;
        self.check_sampled(params)?;
        let errors = telescopic_runtime::scene::profile_errors("feedforward", &self.feedforward);
        if let Some(e) = errors.first() {
            return Err(field(&e.field, &e.rule));
        }
        Ok(())
    }

    /// The scalar settings: finite, positive, inside the ranges a design takes.
    fn check_values(&self) -> Result<()> {
        for (name, v, (low, high), unit) in [
            ("force_limit_n", self.force_limit_n, FORCE_LIMIT_RANGE, "N"),
            ("tip_scale_m", self.tip_scale_m, SCALE_RANGE, "m"),
            ("vehicle_scale_m", self.vehicle_scale_m, SCALE_RANGE, "m"),
            ("total_mass_kg", self.total_mass_kg, (1e-6, 1e9), "kg"),
        ] {
            if !(low..=high).contains(&v) {
                return Err(field(
                    name,
                    format!("must be {low:e} to {high:e} {unit} (got {v})"),
                ));
            }
        }
        Ok(())
    }

    /// The configuration, the state names in the model's order, the drive.
    fn check_model(&self, params: &ModelParams) -> Result<()> {
        let key = configuration_key(params);
        if key != self.configuration {
            return Err(field(
                "configuration",
                format!(
                    "the controller was designed for configuration {} (scene {}), the scene is \
                     {key}",
                    self.configuration, self.scene
                ),
            ));
        }
        let expected = state_names(&params.modes());
        if self.states != expected {
            let first = self
                .states
                .iter()
                .zip(&expected)
                .position(|(a, b)| a != b)
                .unwrap_or(expected.len().min(self.states.len()));
            return Err(field(
                "states",
                format!(
                    "must list the scene's {} states in the model's order ({}, ...); entry {first} \
                     is {:?}, expected {:?}",
                    expected.len(),
                    expected[..expected.len().min(4)].join(", "),
                    self.states.get(first),
                    expected.get(first)
                ),
            ));
        }
        if !matches!(params.drive, Drive::Force(_)) {
            return Err(Error::option(
                OptionName::Controller,
                "the scene has a prescribed motion; a controller drives a force",
            ));
        }
        Ok(())
    }

    /// The design points: positions inside the scene's ranges and ascending along the
    /// schedule, gains of the state's size, finite and bounded.
    fn check_schedule(&self, params: &ModelParams) -> Result<()> {
        if self.schedule.is_empty() {
            return Err(field("schedule", "must hold at least one design point"));
        }
        let n = self.states.len();
        let npos = params.positions.len();
        for (j, point) in self.schedule.iter().enumerate() {
            let at = |name: &str| format!("schedule[{j}].{name}");
            if point.positions.len() != npos {
                return Err(field(
                    &at("positions"),
                    format!(
                        "has {} position(s), the scene has {npos} (a_2..a_n)",
                        point.positions.len()
                    ),
                ));
            }
            for (i, &a) in point.positions.iter().enumerate() {
                let (min, max) = params.position_range(i);
                if !(min..=max).contains(&a) {
                    return Err(field(
                        &at(&format!("positions[{i}]")),
                        format!(
                            "a_{} = {a} m is outside the scene's range [{min}, {max}] m",
                            i + 2
                        ),
                    ));
                }
            }
            check_gains(&at("K"), point, n, self.kind.has_lqr())?;
        }
        if let Some(name) = &self.schedule_parameter {
            let Some(k) = self
                .scheduled_section()
                .filter(|k| (2..=npos + 1).contains(k))
            else {
                return Err(field(
                    "schedule_parameter",
                    format!("the schedule runs over {name}, which the scene does not have"),
                ));
            };
            let ascending = self
                .schedule
                .windows(2)
                .all(|w| w[0].positions[k - 2] < w[1].positions[k - 2]);
            if !ascending {
                return Err(field(
                    "schedule",
                    format!("the design points are not in ascending order of {name}"),
                ));
            }
        }
        Ok(())
    }
}

impl Controller {
    /// The sampled part: sensors the scene has, positive noise and rate, one discrete point
    /// per design point with matrices of the state's size.
    fn check_sampled(&self, params: &ModelParams) -> Result<()> {
        let Some(sampled) = &self.sampled else {
            return Ok(());
        };
        let layout = telescopic_runtime::Layout::new(&params.modes(), params.contact_points);
        let mut outputs = layout.output_names(matches!(params.drive, Drive::Motion(_)));
        outputs.extend(SENSOR_OUTPUTS.iter().map(|s| s.to_string()));
        if let Some(s) = sampled.sensors.iter().find(|s| !outputs.contains(s)) {
            return Err(field(
                "sampled.sensors",
                format!(
                    "`{s}` is not an output of the scene; its outputs: {}",
                    outputs.join(", ")
                ),
            ));
        }
        if sampled.sensors.is_empty() || sampled.noise.len() != sampled.sensors.len() {
            return Err(field(
                "sampled.noise",
                "must give one noise level per sensor",
            ));
        }
        if let Some(v) = sampled.noise.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(field(
                "sampled.noise",
                format!("must be finite numbers > 0 (got {v})"),
            ));
        }
        let (low, high) = crate::control::design::PROCESS_NOISE_FLOOR_RANGE;
        if let Some(floor) = sampled.process_noise_floor {
            if sampled.estimator != Estimator::Extended {
                return Err(field(
                    "sampled.process_noise_floor",
                    "is a setting of the extended estimator only",
                ));
            }
            if !(low..=high).contains(&floor) {
                return Err(field(
                    "sampled.process_noise_floor",
                    format!("must be {low:e} to {high:e} (got {floor:e})"),
                ));
            }
        }
        if !(sampled.rate_hz.is_finite() && (1.0..=1e6).contains(&sampled.rate_hz)) {
            return Err(field(
                "sampled.rate_hz",
                format!("must be 1 to 1e6 Hz (got {})", sampled.rate_hz),
            ));
        }
        if let Some(law) = &sampled.strain_rate {
            return self.check_strain_rate(law, sampled.estimator, &sampled.sensors);
        }
        if sampled.estimator == Estimator::None {
            return Err(field(
                "sampled.estimator",
                "`none` goes with a strain-rate law only",
            ));
        }
        if sampled.estimator == Estimator::Extended
            && (sampled.process_noise_floor.is_none() || sampled.model.is_none())
        {
            return Err(field(
                "sampled",
                "the extended estimator needs its process_noise_floor and model",
            ));
        }
        self.check_discrete_points(sampled)?;
        if let Some(model) = &sampled.model {
            if sampled.estimator != Estimator::Extended {
                return Err(field(
                    "sampled.model",
                    "is the extended estimator's model only",
                ));
            }
            model.check(layout.dof(), layout.contact_count())?;
        }
        Ok(())
    }

    /// The discrete filters: one per design point, each matrix of its shape and finite.
    fn check_discrete_points(&self, sampled: &SampledDesign) -> Result<()> {
        let n = self.states.len();
        let m = sampled.sensors.len();
        if sampled.points.len() != self.schedule.len() {
            return Err(field(
                "sampled.points",
                "must hold one point per design point",
            ));
        }
        for (j, p) in sampled.points.iter().enumerate() {
            for (name, rows, shape) in [
                ("Ad", &p.ad, (n, n)),
                ("Bd", &p.bd, (n, 1)),
                ("C", &p.c, (m, n)),
                ("L", &p.l, (n, m)),
            ] {
                crate::io::rows::from_rows(rows, Some(shape))
                    .map_err(|e| field(&format!("sampled.points[{j}].{name}"), e))?;
                if rows.iter().flatten().any(|v| !v.is_finite()) {
                    return Err(field(
                        &format!("sampled.points[{j}].{name}"),
                        "must be finite",
                    ));
                }
            }
        }
        Ok(())
    }
}

impl Controller {
    /// The strain-rate law: no estimator, its sensors present, one finite point per design
    /// point, finite positive loop gains and filter.
    fn check_strain_rate(
        &self,
        law: &crate::control::file::schema::StrainRateLaw,
        estimator: Estimator,
        sensors: &[String],
    ) -> Result<()> {
        if estimator != Estimator::None {
            return Err(field(
                "sampled.estimator",
                format!("must be `none` with a strain-rate law (got `{estimator}`)"),
            ));
        }
        if let Some(s) = crate::control::law::strain::STRAIN_RATE_SENSORS
            .iter()
            .find(|s| !sensors.iter().any(|o| o == *s))
        {
            return Err(field(
                "sampled.sensors",
                format!("the strain-rate law reads `{s}`, which is not among them"),
            ));
        }
        if law.points.len() != self.schedule.len() {
            return Err(field(
                "sampled.strain_rate.points",
                "must hold one point per design point",
            ));
        }
        for (name, v) in [
            ("vehicle_stiffness_n_per_m", law.vehicle_stiffness_n_per_m),
            ("vehicle_damping_n_s_per_m", law.vehicle_damping_n_s_per_m),
            ("filter_time_constant_s", law.filter_time_constant_s),
        ] {
            if !(v.is_finite() && (0.0..=MAX_GAIN).contains(&v)) {
                return Err(field(
                    &format!("sampled.strain_rate.{name}"),
                    format!("must be finite, >= 0 and at most {MAX_GAIN:e} (got {v})"),
                ));
            }
        }
        if let Some((j, p)) = law
            .points
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.gain.is_finite() && p.gain.abs() <= MAX_GAIN))
        {
            return Err(field(
                &format!("sampled.strain_rate.points[{j}].gain"),
                format!(
                    "must be finite and at most {MAX_GAIN:e} in size (got {})",
                    p.gain
                ),
            ));
        }
        Ok(())
    }
}

/// A design point's gain: one row of `n` entries when the controller has an LQR, every entry
/// finite and at most [`MAX_GAIN`] in size.
fn check_gains(name: &str, point: &SchedulePoint, n: usize, lqr: bool) -> Result<()> {
    if lqr && (point.k.len() != 1 || point.k[0].len() != n) {
        return Err(field(
            name,
            format!("must be one row of {n} gains (the state's size)"),
        ));
    }
    let entries = point.k.iter().flatten();
    if let Some(g) = entries
        .clone()
        .find(|g| !g.is_finite() || g.abs() > MAX_GAIN)
    {
        return Err(field(
            name,
            format!("holds {g}; every gain must be finite and at most {MAX_GAIN:e} in size"),
        ));
    }
    Ok(())
}
