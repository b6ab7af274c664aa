//! The strain-rate law ([`super::strain`]) as self-contained C99: the same header layout and
//! entry points as the filter's ([`super::emit_c`]), computing what
//! [`crate::control::law::strain::StrainRateController`] computes, operation for operation.

use super::common::{banner, header, list, lit, source_start};
use crate::control::file::schema::Controller;
use crate::control::file::schema::StrainRateLaw;
use std::fmt::Write as _;

/// The header and the source of `file`'s strain-rate law over `[start, end]` s.
pub(crate) fn emit_strain_rate(
    file: &Controller,
    law: &StrainRateLaw,
    start: f64,
    end: f64,
) -> (String, String) {
    let sampled = file.sampled.as_ref().expect("checked by the caller");
    let column = |name: &str| {
        sampled
            .sensors
            .iter()
            .position(|s| s == name)
            .expect("checked by the controller file")
    };
    let banner = banner(
        file,
        "the strain-rate law (the strain gauge's rate fed to the drive, a PD on the vehicle)",
    );
    let header = header(
        file,
        &banner,
        "",
        "the previous measurements, the filtered rates and the force now applied (N)",
        "    int started;\n    double vehicle_prev;    /* m */\n    double kappa_prev;      \
         /* 1/m */\n    double vehicle_rate;    /* m/s */\n    double kappa_rate;      \
         /* 1/(m s) */\n    double u;\n",
    );
    let mut s = source_start(file, &banner, start, end);
    let constants = [
        (
            "KP",
            law.vehicle_stiffness_n_per_m,
            "vehicle loop stiffness (N/m)",
        ),
        (
            "KD",
            law.vehicle_damping_n_s_per_m,
            "vehicle loop damping (N s/m)",
        ),
        (
            "ALPHA",
            law.filter_weight(sampled.rate_hz),
            "the rate filters' weight per tick, PERIOD / (tau + PERIOD)",
        ),
    ];
    s.push('\n');
    for (name, value, what) in constants {
        let _ = writeln!(
            s,
            "static const double {name} = {}; /* {what} */",
            lit(value)
        );
    }
    let _ = writeln!(
        s,
        "#define VEHICLE {} /* where vehicle and kappa_1_0 are in y */\n#define KAPPA {}\n",
        column("vehicle"),
        column("kappa_1_0")
    );
    let _ = writeln!(
        s,
        "/* the gain on the curvature's rate at each design point (N per 1/(m s)) */"
    );
    let _ = writeln!(
        s,
        "static const double GAIN[TC_POINTS] = {};",
        list(law.points.iter().map(|p| p.gain), "    ")
    );
    s.push_str(STRAIN_FUNCTIONS);
    (header, s)
}

/// The strain-rate law's init and step.
const STRAIN_FUNCTIONS: &str = include_str!("c/strain_law.c");
