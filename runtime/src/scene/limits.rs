//! Upper bounds on every size a scene sets, checked before anything is allocated (see the
//! scene reference in `docs/scenes.md`). Each says why it is where it is.

/// Most sections: real telescopes (mobile cranes, rack feeders) have up to about 8; 16 with
/// 30 modes each is a 480-coordinate model, whose dense eigen analysis still takes well
/// under a second.
pub const MAX_SECTIONS: usize = 16;

/// Most contact points per overlap: two (the ends of the overlap) model roller guides; more
/// only stiffen the coupling (`telescopic converge`), and 32 keeps the contact loops short.
pub const MAX_CONTACT_POINTS: usize = 32;

/// Most output values of one run (samples times columns, `t` included): 10^8 values are
/// 800 MB in memory and about 2 GB of CSV text. Raise `time.sample` or shorten the span.
pub const MAX_OUTPUT_VALUES: u64 = 100_000_000;

/// Columns of a run's output, `t` included: `t`, `vehicle`, `tip_rel`, `top1_rel`, a gap and
/// a force per contact point, `drive_force` for a prescribed motion, and the two sensor
/// outputs `kappa_1_0` and `acc_load`.
pub fn output_columns(sections: usize, contact_points: usize, motion: bool) -> u64 {
    6 + 2 * (sections.saturating_sub(1) as u64) * contact_points as u64 + u64::from(motion)
}

/// Output samples of a span `[start, end]` every `sample` seconds, the start included (the
/// end too when it is not on the grid); `u64::MAX` when it does not fit.
pub fn sample_count(start: f64, end: f64, sample: f64) -> u64 {
    let whole = ((end - start) / sample * (1.0 + 1e-9)).floor();
    if !(whole.is_finite() && whole < 1e18) {
        return u64::MAX;
    }
    whole as u64 + 2
}
