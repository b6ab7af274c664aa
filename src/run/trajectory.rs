//! The samples of one run: its columns (outputs and coordinates), rows `[t, columns...]`
//! and the run's statistics.

use std::fmt;
use std::io::Write;
use telescopic_runtime::{ContactLaw, Model, Output, RunStats, Sensor};

/// What a trajectory's column after `t` holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Column {
    /// An output (the model's, a sensor's, a station's moment or stress).
    Output(Output),
    /// `z_i`: generalized coordinate `i` (0-based; m, or 1 for a mode's amplitude).
    Coordinate(usize),
}

impl Column {
    /// The column named `name` in a CSV header (an output's name or `z_i`), or `None`.
    pub fn parse(name: &str) -> Option<Column> {
        match name.strip_prefix("z_").map(str::parse::<usize>) {
            Some(Ok(i)) => Some(Column::Coordinate(i)),
            _ => Output::parse(name).map(Column::Output),
        }
    }

    /// The output this column holds, if it is one.
    pub fn output(&self) -> Option<Output> {
        match self {
            Column::Output(o) => Some(*o),
            Column::Coordinate(_) => None,
        }
    }
}

/// The columns every run of `model` starts with: the model's outputs, then the sensors'
/// ([`Sensor::ALL`]).
pub(crate) fn model_and_sensor_columns(model: &dyn Model) -> Vec<Column> {
    let outputs = model.output_quantities().into_iter();
    outputs
        .chain(Sensor::ALL.map(Output::Sensor))
        .map(Column::Output)
        .collect()
}

/// The columns of the first `count` generalized coordinates, `z_0` on.
pub(crate) fn coordinate_columns(count: usize) -> impl Iterator<Item = Column> {
    (0..count).map(Column::Coordinate)
}

impl fmt::Display for Column {
    /// The column's name in a CSV header: the output's name, or `z_i`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Column::Output(o) => write!(f, "{o}"),
            Column::Coordinate(i) => write!(f, "z_{i}"),
        }
    }
}

/// The samples of one run: its columns and rows `[t, columns...]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// What each column after `t` holds (the model documentation's section on outputs).
    pub columns: Vec<Column>,
    /// Rows `[t, outputs...]` (s, then SI units of each output).
    pub rows: Vec<Vec<f64>>,
    /// What the run did.
    pub stats: RunStats,
}

impl Trajectory {
    /// The samples `rows` of `columns`, with the run's `stats`.
    pub fn new(columns: Vec<Column>, rows: Vec<Vec<f64>>, stats: RunStats) -> Self {
        Trajectory {
            columns,
            rows,
            stats,
        }
    }

    /// The columns' names after `t`, as in the CSV header.
    pub fn names(&self) -> Vec<String> {
        self.columns.iter().map(Column::to_string).collect()
    }

    /// Index in a row of the column named `name` (`t` is index 0).
    pub fn index(&self, name: &str) -> Option<usize> {
        if name == "t" {
            return Some(0);
        }
        self.columns
            .iter()
            .position(|c| c.to_string() == name)
            .map(|i| i + 1)
    }

    /// The samples of one output (or `t`), in time order.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.index(name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Index in a row of `output`.
    pub fn index_of(&self, output: Output) -> Option<usize> {
        self.columns
            .iter()
            .position(|c| *c == Column::Output(output))
            .map(|i| i + 1)
    }

    /// The samples of `output`, in time order.
    pub fn column_of(&self, output: Output) -> Option<Vec<f64>> {
        let i = self.index_of(output)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// The columns that are outputs ([`Output`]), with their index in a row.
    pub fn outputs(&self) -> impl Iterator<Item = (usize, Output)> + '_ {
        self.columns
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.output().map(|o| (i + 1, o)))
    }

    /// The row indices of the outputs `which` picks.
    pub fn columns_where(&self, which: impl Fn(&Output) -> bool) -> Vec<usize> {
        self.outputs()
            .filter(|(_, o)| which(o))
            .map(|(i, _)| i)
            .collect()
    }

    /// The row indices of the gaps.
    pub fn gap_columns(&self) -> Vec<usize> {
        self.columns_where(Output::is_gap)
    }

    /// Contact switches between consecutive samples from time `from` (s) on: a gap that is
    /// closed by `law` ([`ContactLaw::is_closed`]) in one sample and open in the next, or the
    /// reverse (none with `l_S = 0`). Counts on the samples, so it can be below the run's
    /// own count ([`RunStats::switches`]) where a contact closes and opens between two.
    pub fn sampled_switches(&self, law: &ContactLaw, from: f64) -> usize {
        let gaps = self.gap_columns();
        let first = self.rows.partition_point(|r| r[0] < from);
        self.rows[first..]
            .windows(2)
            .map(|w| {
                gaps.iter()
                    .filter(|&&g| law.is_closed(w[0][g]) != law.is_closed(w[1][g]))
                    .count()
            })
            .sum()
    }

    /// Writes the CSV: a header `t,<names>` ([`Trajectory::names`]) and one row per sample.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "t,{}", self.names().join(","))?;
        let mut line = String::new();
        for row in &self.rows {
            line.clear();
            for (i, &v) in row.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                line.push_str(&crate::io::output::csv_number(v));
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    }
}
