//! The library's errors name options as the library spells them (`SimulationOptions::dt`,
//! `Settings::rtol`, `override a=b`); the command line speaks of its flags. This table is
//! the one place that knows both.

/// Library spelling -> flag, longest first where one contains another.
const FLAGS: &[(&str, &str)] = &[
    ("SimulationOptions::rtol/atol", "--rtol/--atol"),
    ("SimulationOptions::method", "--method"),
    ("SimulationOptions::rtol", "--rtol"),
    ("SimulationOptions::atol", "--atol"),
    ("SimulationOptions::dt", "--dt"),
    ("Settings::rtol/atol", "--rtol/--atol"),
    ("Settings::dt", "--dt"),
    ("SweepOptions::resume", "--resume"),
    ("SweepOptions::out", "--out"),
    ("resume to keep them", "give --resume to keep them"),
    ("SweepOptions::jobs", "--jobs"),
    ("Shard::of_job_array", "--shard auto"),
    ("give the shard count", "give --shard-count"),
    ("Shard: ", "--shard: "),
    ("SweepChart x", "--x"),
    ("SweepChart y", "--y"),
    ("SweepChart color", "--color"),
    ("SweepChart heatmap", "--heatmap"),
    ("the color column", "the --color column"),
    (
        "resume the sweep to finish",
        "run again with --resume to finish",
    ),
    ("or do not resume", "or drop --resume"),
    ("ShapeErrorsOptions::length", "--length"),
    ("ShapeErrorsOptions::points", "--points"),
    ("ConvergeOptions::tol", "--tol"),
    ("ConvergeOptions::max_modes", "--max-modes"),
    ("ConvergeOptions::max_contacts", "--max-contacts"),
    ("SimulationOptions::accuracy", "--accuracy"),
    ("SimulationOptions::modes_as_given", "--modes-as-given"),
    ("SimulationOptions::moment_tolerance", "--moment-tolerance"),
    (
        "SimulationOptions::statistics_tolerance",
        "--statistics-tolerance",
    ),
    ("DesignOptions::kind", "--controller"),
    ("DesignOptions::force_limit", "--force-limit"),
    ("DesignOptions::tip_scale", "--tip-scale"),
    ("DesignOptions::vehicle_scale", "--vehicle-scale"),
    ("DesignOptions::sensor_noises", "--measurement-noise"),
    ("DesignOptions::sensors", "--sensors"),
    ("DesignOptions::estimator", "--estimator"),
    ("DesignOptions::rate_hz", "--rate"),
    ("DesignOptions::law", "--law"),
    ("DesignOptions::added_damping", "--added-damping"),
    (
        "DesignOptions::process_noise_floor",
        "--process-noise-floor",
    ),
    ("DesignOptions::sensor_noise", "--sensor-noise"),
    ("DesignOptions::force_noise", "--force-noise"),
    ("DesignOptions::grid_points", "--grid-points"),
    ("DesignOptions::design_modes", "--design-modes"),
    ("WorkPrecisionOptions::repeat", "--repeat"),
    ("WorkPrecisionOptions::methods", "--methods"),
    ("WorkPrecisionOptions::rtols", "--rtols"),
    ("LinearExport format latex", "--format latex"),
    ("LinearizeOptions::at_time", "--at-time"),
    ("LinearizeOptions::positions", "--positions"),
    ("LinearizeOptions::grid", "--grid"),
    ("SimulationOptions::stations", "--stations"),
    ("BodeOptions::inputs", "--inputs"),
    ("BodeOptions::outputs", "--outputs"),
    ("BodeOptions::from_hz", "--from"),
    ("BodeOptions::to_hz", "--to"),
    ("BodeOptions::points", "--points"),
    ("LinearizeOptions::discrete", "--discrete"),
    ("fmu library", "--library"),
    ("ModesOptions::at", "--at"),
    ("ModesOptions::shapes", "--shapes"),
    ("model choice `generated`", "--model generated"),
    ("(with overrides ", "(with --set "),
    ("override ", "--set "),
    ("the stability analysis", "`telescopic stability`"),
    ("raise the memory budget", "raise TELESCOPIC_MEMORY_BUDGET"),
    ("controller: ", "--controller: "),
];

/// `message` with the library's option names replaced by the command's flags.
pub fn in_flags(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    let mut word_start = true;
    'scan: while !rest.is_empty() {
        for (library, flag) in FLAGS.iter().filter(|_| word_start) {
            if rest.starts_with(library) {
                out.push_str(flag);
                rest = &rest[library.len()..];
                word_start = !flag.ends_with(|c: char| c.is_alphanumeric() || c == '_');
                continue 'scan;
            }
        }
        let c = rest.chars().next().expect("not empty");
        // a name starts a word: `override ` inside `no override ` is prose
        word_start = !(c.is_alphanumeric() || c == '_');
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::in_flags;

    #[test]
    fn library_names_become_flags_and_prose_stays() {
        assert_eq!(
            in_flags("SimulationOptions::dt: must be > 0 (got -1)"),
            "--dt: must be > 0 (got -1)"
        );
        assert_eq!(
            in_flags("override a=b: no such field; loosen Settings::rtol/atol"),
            "--set a=b: no such field; loosen --rtol/--atol"
        );
        assert_eq!(in_flags("a shard of 3"), "a shard of 3");
        assert_eq!(in_flags("nooverride x"), "nooverride x");
    }
}
