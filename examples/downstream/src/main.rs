//! Runs the example scene on the model this crate generated at build time, through the
//! `telescopic` library: its natural frequencies, then the scene with the clearance contact
//! law.
//!
//! `cargo run --release -p telescopic-downstream-example [SCENE.toml]`

use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::run::models::ModelChoice;
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::{Scene, Silent};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| telescopic_downstream_example::SCENE.to_string());
    let scene = Scene::load(path.as_ref(), &[])?;
    let models = telescopic_downstream_example::models();
    let modes = compute_modes(
        &scene,
        &ModesOptions {
            count: Some(4),
            model: ModelChoice::Generated,
            models: models.clone(),
            ..ModesOptions::default()
        },
    )?;
    println!("{}", modes.to_table());
    let run = simulate_scene(
        &scene,
        &SimulationOptions {
            model: ModelChoice::Generated,
            models,
            ..SimulationOptions::default()
        },
        &Silent,
    )?;
    println!("{}", run.summary());
    let tip = run.trajectory.column("tip_rel").expect("tip_rel");
    let peak = tip.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    println!("largest |tip_rel| {peak:.4e} m");
    Ok(())
}
