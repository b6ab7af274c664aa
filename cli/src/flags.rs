//! The command line's names for the library's options, and the library's errors told in
//! them: the one place that knows both spellings.

use telescopic::OptionName;

/// The flag (or environment variable) that sets `option`.
pub fn flag(option: OptionName) -> &'static str {
    use OptionName as O;
    match option {
        O::Method => "--method",
        O::Tolerances => "--rtol/--atol",
        O::Dt => "--dt",
        O::Accuracy => "--accuracy",
        O::MomentTolerance => "--moment-tolerance",
        O::StatisticsTolerance => "--statistics-tolerance",
        O::Stations => "--stations",
        O::ModesAsGiven => "--modes-as-given",
        O::Model => "--model",
        O::MemoryBudget => crate::MEMORY_BUDGET_VARIABLE,
        O::Controller | O::ControllerKind => "--controller",
        O::DesignModes => "--design-modes",
        O::ForceLimit => "--force-limit",
        O::TipScale => "--tip-scale",
        O::VehicleScale => "--vehicle-scale",
        O::Sensors => "--sensors",
        O::SensorNoises => "--measurement-noise",
        O::Estimator => "--estimator",
        O::RateHz => "--rate",
        O::Law => "--law",
        O::AddedDamping => "--added-damping",
        O::SensorNoise => "--sensor-noise",
        O::ForceNoise => "--force-noise",
        O::ProcessNoiseFloor => "--process-noise-floor",
        O::GridPoints => "--grid-points",
        O::Jobs => "--jobs",
        O::Resume => "--resume",
        O::SweepOut => "--out",
        O::Shard => "--shard auto",
        O::ShardCount => "--shard-count",
        O::ChartX => "--x",
        O::ChartY => "--y",
        O::ChartColor => "--color",
        O::ChartHeatmap => "--heatmap",
        O::ShapeLength => "--length",
        O::ShapePoints | O::BodePoints => "--points",
        O::ConvergeTol => "--tol",
        O::MaxModes => "--max-modes",
        O::MaxContacts => "--max-contacts",
        O::Repeat => "--repeat",
        O::Methods => "--methods",
        O::Rtols => "--rtols",
        O::Sizes => "--modes",
        O::ModesAt => "--at",
        O::ModesCount => "--count",
        O::Shapes => "--shapes",
        O::LatexFormat => "--format latex",
        O::AtTime => "--at-time",
        O::Positions => "--positions",
        O::Grid => "--grid",
        O::Discrete => "--discrete",
        O::BodeLinear => "--grid/--discrete",
        O::BodeInputs => "--inputs",
        O::BodeOutputs => "--outputs",
        O::FromHz => "--from",
        O::ToHz => "--to",
        O::FmuLibrary => "--library",
        O::Fps => "--fps",
        O::DeflectionScale => "--scale",
        O::AnimationSize => "--size",
        O::AnimationSpeed => "--speed",
        O::Distance => "--distance",
        O::MoveLimits => "--v-max/--a-max/--j-max",
        O::MoveTolerance => "--tolerance",
        O::MoveMargin => "--margin",
        O::Settle => "--settle",
        O::Robust => "--robust",
        O::Checks => "--checks",
        O::Feedback => "--feedback",
        O::CorrectionLimits => "--correction-v-max/--correction-a-max",
        O::WeighedLoad => "--weighed-load",
        O::Pick => "--pick",
        O::EmitC => "--emit-c",
        O::FilterRate => "--filter-rate",
        O::Free => "--free",
        O::Noise => "--noise",
        O::Start => "--start",
    }
}

/// `error` as the command line tells it: contexts, then the library's error with its
/// options named by their flags and the command's own remedies.
pub fn describe(error: &anyhow::Error) -> String {
    let mut parts = Vec::new();
    for layer in error.chain() {
        if let Some(e) = layer.downcast_ref::<telescopic::Error>() {
            parts.push(library_error(e));
            break; // a library message is whole: its causes are in it
        }
        if let Some(e) = layer.downcast_ref::<telescopic::runtime::SceneError>() {
            parts.push(scene_error(e));
            break;
        }
        parts.push(layer.to_string());
    }
    parts.join(": ")
}

/// A library error with flags for options.
fn library_error(error: &telescopic::Error) -> String {
    use telescopic::Error;
    match error {
        Error::Option { option, rule, see } => format!(
            "{}: {rule}{}",
            flag(*option),
            see.map_or(String::new(), |o| format!(" (see {})", flag(o)))
        ),
        Error::Trial { what, error } => format!("{what}: {}", library_error(error)),
        Error::Scene(e) => scene_error(e),
        Error::OverMemoryBudget { option, .. } => {
            let flag = option.map_or(String::new(), |o| format!("{}: ", flag(o)));
            format!(
                "{flag}{error} ({} sets the budget)",
                crate::MEMORY_BUDGET_VARIABLE
            )
        }
        Error::Interrupted {
            finished,
            total,
            kept: Some(path),
        } => format!(
            "interrupted: {finished} of {total} runs done, kept in {}; run again with --resume \
             to finish",
            path.display()
        ),
        e => e.to_string(),
    }
}

/// A scene error with `--set` for an override.
fn scene_error(error: &telescopic::runtime::SceneError) -> String {
    match error {
        telescopic::runtime::SceneError::Override { argument, rule } => {
            format!("--set {argument}: {rule}")
        }
        e => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_errors_name_flags_and_contexts_stay() {
        let e = anyhow::Error::new(telescopic::Error::option(
            OptionName::Dt,
            "must be > 0 (got -1)",
        ))
        .context("scene a.toml");
        assert_eq!(describe(&e), "scene a.toml: --dt: must be > 0 (got -1)");
        let trial = telescopic::Error::Trial {
            what: "6 modes".into(),
            error: Box::new(telescopic::Error::option(
                OptionName::Tolerances,
                "too tight",
            )),
        };
        assert_eq!(describe(&trial.into()), "6 modes: --rtol/--atol: too tight");
    }

    #[test]
    fn every_flag_is_one_the_command_has() {
        let command = <crate::commands::Cli as clap::CommandFactory>::command();
        let mut longs = std::collections::BTreeSet::new();
        collect_longs(&command, &mut longs);
        for name in OptionName::NAMES {
            let option: OptionName = name.parse().expect("a name parses back");
            for spelled in flag(option).split('/') {
                let name = spelled.split(' ').next().unwrap_or("");
                if let Some(long) = name.strip_prefix("--") {
                    assert!(
                        longs.contains(long),
                        "{option:?} -> {spelled}: no such flag"
                    );
                }
            }
        }
    }

    fn collect_longs(command: &clap::Command, longs: &mut std::collections::BTreeSet<String>) {
        for arg in command.get_arguments() {
            if let Some(long) = arg.get_long() {
                longs.insert(long.to_string());
            }
        }
        for sub in command.get_subcommands() {
            collect_longs(sub, longs);
        }
    }
}
