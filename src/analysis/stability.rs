//! Where the fixed-step explicit methods fail: the stiffest frequency of a scene with closed contacts and the
//! largest stable step of each fixed-step explicit method, from the textbook limits and
//! from the spectral radius of each method's step on the model itself.

use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, Result};
use telescopic_runtime::integrate::exact::{
    ClosedContactSteps, closed_contact_steps, exact_tail_start, lti_obstacle,
};
use telescopic_runtime::integrate::stability::{
    RK4_IMAGINARY_AXIS, RK4_REAL_AXIS, STEP_CAP_SAFETY, StabilityReport, VERLET_LIMIT,
    closed_contact_stable_step, linearization_times, stability_report,
};
use telescopic_runtime::{Method, Model, Scene};

/// The stability facts of a scene: the closed-contact model at its stiffest time, and the
/// largest stable steps of the adaptive explicit methods.
#[derive(Debug, Clone)]
pub struct Stability {
    /// The scene's name.
    pub scene: String,
    /// Which model was linearized.
    pub model: String,
    /// The report at the stiffest of the linearization times.
    pub worst: StabilityReport,
    /// How many times were checked (1 for fixed positions).
    pub times: usize,
    /// Largest stable step (s) of dopri5 and dop853 with closed contacts.
    pub adaptive: Vec<(Method, Option<f64>)>,
    /// Method exact's steps with every contact closed, where it applies to a scene with
    /// clearance.
    pub exact: Option<ClosedContactSteps>,
    /// Set when the model choice fell back to the assembled model.
    pub note: Option<String>,
}

/// The stability analysis of `scene`: `omega_max` and the model's own step limits of the
/// fixed-step explicit methods (and of dopri5, dop853 and imex) with closed contacts.
///
/// # Errors
/// [`Error::Model`] or [`Error::Analysis`] when the model or its modal analysis fails.
pub fn stability_analysis(
    scene: &Scene,
    choice: ModelChoice,
    models: &ModelRegistry,
) -> Result<Stability> {
    let chosen = models.build(&scene.params, choice)?;
    let model = chosen.model.as_ref();
    let times = linearization_times(model, &scene.time);
    let mut reports = Vec::new();
    for &t in &times {
        reports.push(
            stability_report(model, t)
                .map_err(|e| Error::Analysis(format!("scene {}: {e}", scene.name)))?,
        );
    }
    let worst = reports
        .into_iter()
        .min_by(|a, b| a.rk4_step.total_cmp(&b.rk4_step))
        .expect("at least one time");
    let adaptive = [Method::Dopri5, Method::Dop853, Method::Imex]
        .map(|m| (m, closed_contact_stable_step(model, m, &scene.time)))
        .to_vec();
    Ok(Stability {
        scene: scene.name.clone(),
        model: chosen.description,
        worst,
        times: times.len(),
        adaptive,
        exact: exact_steps(model, scene)?,
        note: chosen.note,
    })
}

/// Method exact's closed-contact steps where it runs the scene (from its start, or from
/// where the positions come to rest) and the scene has clearance.
fn exact_steps(model: &dyn Model, scene: &Scene) -> Result<Option<ClosedContactSteps>> {
    if scene.params.contact.clearance <= 0.0 {
        return Ok(None);
    }
    let from = match lti_obstacle(&scene.params) {
        None => scene.time.start,
        Some(_) => match exact_tail_start(&scene.params, &scene.time) {
            Some(t) => t,
            None => return Ok(None),
        },
    };
    closed_contact_steps(model, from, scene.time.sample)
        .map(Some)
        .map_err(|error| Error::Eigen {
            scene: scene.name.clone(),
            error,
        })
}

impl Stability {
    /// The report as text (`telescopic stability`).
    pub fn render(&self) -> String {
        render(
            &self.scene,
            &self.model,
            &self.worst,
            self.times,
            &self.adaptive,
            self.exact,
        )
    }
}

/// The report as text.
fn render(
    scene: &str,
    word: &str,
    r: &StabilityReport,
    times: usize,
    adaptive: &[(Method, Option<f64>)],
    exact: Option<ClosedContactSteps>,
) -> String {
    let w = r.omega_max;
    let at = if times > 1 {
        format!(
            "t = {:.3} s (the stiffest of {times} times across the span)",
            r.time
        )
    } else {
        format!("t = {:.3} s (positions fixed)", r.time)
    };
    // rates below 1e-6 omega_max are the rounding of the rigid vehicle mode's double zero
    let growth = if r.growth_rate > 1e-6 * w {
        format!(
            "{:.4e} 1/s (the closed-contact system itself is unstable)",
            r.growth_rate
        )
    } else {
        "0 (stable)".to_string()
    };
    let mut s = format!(
        "{scene} on the {word}, contacts closed, linearized at {at}\n\
         omega_max = {w:.5e} rad/s ({:.5e} Hz), largest growth rate {growth}\n\n",
        w / (2.0 * std::f64::consts::PI)
    );
    s += "method  textbook limit h omega_max          step from it        step limit of the model  h omega_max there\n";
    s += &format!(
        "rk4     {RK4_REAL_AXIS:.3} (real axis) .. {RK4_IMAGINARY_AXIS:.3} (imag.)  {:.4e} .. {:.4e} s  {:.6e} s           {:.4}\n",
        RK4_REAL_AXIS / w,
        RK4_IMAGINARY_AXIS / w,
        r.rk4_step,
        r.rk4_step * w
    );
    s += &format!(
        "verlet  {VERLET_LIMIT:.3} (undamped)                   {:.4e} s            {:.6e} s           {:.4}\n",
        VERLET_LIMIT / w,
        r.verlet_step,
        r.verlet_step * w
    );
    s += "\nThe model's limit is the largest step whose step matrix has spectral radius <= 1 (damping\n\
          included; bisection to 1e-6). Above it the run stops with a divergence error.\n\
          No step limit: galpha, galpha-fixed (unconditionally stable for rho_inf <= 1), esdirk\n\
          (L-stable), bdf1, bdf2 (A-stable). bdf3..bdf5 are not A-stable near the imaginary axis;\n\
          their error control keeps h omega small for excited modes.";
    let steps: Vec<String> = adaptive
        .iter()
        .filter_map(|(m, step)| step.map(|h| format!("{m} {h:.4e} s (h omega_max {:.3})", h * w)))
        .collect();
    if !steps.is_empty() {
        s += &format!(
            "\nAdaptive methods with an explicit part, largest stable step with closed contacts: {}.\n\
             dop853's step is capped at {STEP_CAP_SAFETY} of it while a contact is closed, so its step\n\
             control does not hover at the boundary; dopri5's PI control stays off it on its own.\n\
             imex treats the contacts implicitly (and the static correction shapes' stiff modes):\n\
             its limit is set by the beams' other modes, which its split leaves slightly\n\
             unstable beyond it (docs/numerics.md). dop853-imex takes\n\
             dop853's capped step while a closed contact rings after a switch and imex's once\n\
             dop853's error at that step has stayed below a tenth of the tolerance.",
            steps.join(", ")
        );
    }
    if let Some(steps) = exact {
        let w = steps.omega;
        let over = match steps.long {
            Some(h) => format!(
                "; where the closed contacts' modes have rung down, it steps over them with \
                 {h:.4e} s (h omega_max {:.1}), the beams' own modes' step, certified by a bound \
                 of the contact modes (docs/numerics.md)",
                h * w
            ),
            None => {
                "; the contact modes do not stand apart from the beams', so no longer step".into()
            }
        };
        s += &format!(
            "\nexact (from t = {} s): {:.4e} s while contacts are closed (h omega_max {:.3}){over}.",
            steps.time,
            steps.short,
            steps.short * w
        );
    }
    s
}
