//! `telescopic stability`: the stiffest frequency of a scene with closed contacts and the
//! largest stable step of each fixed-step explicit method, from the textbook limits and
//! from the spectral radius of each method's step on the model itself.

use crate::choose::{ModelChoice, build_model};
use crate::cli::SceneArgs;
use clap::Args;
use telescopic_runtime::Method;
use telescopic_runtime::integrate::stability::{
    RK4_IMAGINARY_AXIS, RK4_REAL_AXIS, STEP_CAP_SAFETY, StabilityReport, VERLET_LIMIT,
    closed_contact_stable_step, linearization_times, stability_report,
};

/// Options of `telescopic stability`.
#[derive(Debug, Args)]
pub struct StabilityArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Which model is linearized.
    #[arg(long, value_enum, default_value_t)]
    pub model: ModelChoice,
}

/// Runs `telescopic stability`.
pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let (model, word) = build_model(&scene.params, args.model)?;
    let times = linearization_times(model.as_ref(), &scene.time);
    let mut reports = Vec::new();
    for &t in &times {
        reports.push(stability_report(model.as_ref(), t).map_err(anyhow::Error::msg)?);
    }
    let worst = reports
        .iter()
        .min_by(|a, b| a.rk4_step.total_cmp(&b.rk4_step))
        .expect("at least one time");
    let adaptive = [Method::Dopri5, Method::Dop853].map(|m| {
        (
            m,
            closed_contact_stable_step(model.as_ref(), m, &scene.time),
        )
    });
    println!(
        "{}",
        render(&scene.name, &word, worst, times.len(), &adaptive)
    );
    Ok(())
}

/// The report as text.
fn render(
    scene: &str,
    word: &str,
    r: &StabilityReport,
    times: usize,
    adaptive: &[(Method, Option<f64>)],
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
            "\nAdaptive explicit methods, largest stable step with closed contacts: {}.\n\
             dop853's step is capped at {STEP_CAP_SAFETY} of it while a contact is closed, so its step\n\
             control does not hover at the boundary; dopri5's PI control stays off it on its own.",
            steps.join(", ")
        );
    }
    s
}
