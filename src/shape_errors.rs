//! `telescopic shape-errors`: the evaluation error of the shape functions for modes 1..30,
//! the paper's printed forms in `f64` against the cancellation-free forms, both measured
//! against the printed forms in 512-bit arithmetic. Shows the failure of the naive form
//! instead of only avoiding it.

use crate::plot::{Figure, LogSeries, YAxis, log_panel, plot_error, save};
use crate::simulate::write_atomically;
use clap::Args;
use plotters::prelude::*;
use std::path::PathBuf;
use telescopic_runtime::shape::{MAX_MODES, SectionKind};
use telescopic_runtime::shape_reference::{Hp, evaluation_errors};

/// Options of `telescopic shape-errors`.
#[derive(Debug, Args)]
pub struct ShapeErrorsArgs {
    /// Section length (m); the errors barely depend on it.
    #[arg(long, default_value_t = 1.35, value_name = "M")]
    pub length: f64,
    /// Evaluation points along the section (derivatives 0 to 3 at each).
    #[arg(long, default_value_t = 41, value_name = "N")]
    pub points: usize,
    /// Chart (SVG or PNG by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: Option<PathBuf>,
    /// CSV: kind, mode, worst scaled error of each form; default: standard output.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
}

/// Worst errors of one mode: `(kind, mode, cancellation-free, printed)`.
type Row = (SectionKind, usize, f64, f64);

/// Runs `telescopic shape-errors`.
pub fn run(args: &ShapeErrorsArgs) -> anyhow::Result<()> {
    if !(args.length > 0.0 && args.length.is_finite()) {
        anyhow::bail!(
            "--length must be a positive number of metres (got {})",
            args.length
        );
    }
    if args.points < 2 {
        anyhow::bail!("--points must be at least 2 (got {})", args.points);
    }
    if let Some(p) = &args.out {
        crate::plot::check_picture_path("--out", p)?;
    }
    let mut hp = Hp::new();
    let mut rows: Vec<Row> = Vec::new();
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        // rigid modes (beta = 0) are exact constants or lines in both forms
        let first_elastic = if kind == SectionKind::GuidedFree {
            2
        } else {
            3
        };
        for i in first_elastic..=MAX_MODES {
            let (free, printed) = evaluation_errors(&mut hp, kind, i, args.length, args.points);
            rows.push((kind, i, free, printed));
        }
    }
    let table = |w: &mut dyn std::io::Write| -> std::io::Result<()> {
        writeln!(w, "kind,mode,cancellation_free_error,printed_error")?;
        for (kind, i, free, printed) in &rows {
            writeln!(w, "{},{i},{free:e},{printed:e}", kind_name(*kind))?;
        }
        Ok(())
    };
    match &args.csv {
        Some(path) => {
            write_atomically(path, |w| table(w))?;
            eprintln!("wrote {}", path.display());
        }
        None => table(&mut std::io::stdout().lock())?,
    }
    if let Some(path) = &args.out {
        save(&ShapeErrorChart { rows: &rows }, path)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

fn kind_name(kind: SectionKind) -> &'static str {
    match kind {
        SectionKind::GuidedFree => "guided-free",
        SectionKind::FreeFree => "free-free",
    }
}

struct ShapeErrorChart<'a> {
    rows: &'a [Row],
}

impl Figure for ShapeErrorChart<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 520)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> anyhow::Result<()> {
        root.fill(&WHITE).map_err(plot_error)?;
        let mut series = Vec::new();
        for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
            for (form, pick) in [
                ("printed", (|r: &Row| r.3) as fn(&Row) -> f64),
                ("cancellation-free", |r: &Row| r.2),
            ] {
                series.push(LogSeries {
                    label: format!("{} {form}", kind_name(kind)),
                    points: self
                        .rows
                        .iter()
                        .filter(|r| r.0 == kind)
                        // an exact evaluation shows at the floor of the axis
                        .map(|r| (r.1 as f64, pick(r).max(1e-17)))
                        .collect(),
                    marks: Vec::new(),
                });
            }
        }
        log_panel(
            &root,
            (
                "shape functions in f64: worst error vs 512-bit printed form (derivatives 0-3)",
                "mode i (log scale)",
                "scaled error",
            ),
            &series,
            YAxis::Log,
            Some((1e-12, "1e-12")),
        )?;
        root.present().map_err(plot_error)
    }
}
