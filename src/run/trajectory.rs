//! The samples of one run: output names, rows `[t, outputs...]` and the run's statistics.

use std::io::Write;
use telescopic_runtime::{ContactLaw, Output, RunStats};

/// The samples of one run: output names and rows `[t, outputs...]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Output names, without `t` (the model documentation's section on outputs).
    pub names: Vec<String>,
    /// Rows `[t, outputs...]` (s, then SI units of each output).
    pub rows: Vec<Vec<f64>>,
    /// What the run did.
    pub stats: RunStats,
}

impl Trajectory {
    /// Index in a row of the output `name` (`t` is index 0).
    pub fn index(&self, name: &str) -> Option<usize> {
        if name == "t" {
            return Some(0);
        }
        self.names.iter().position(|n| n == name).map(|i| i + 1)
    }

    /// The samples of one output (or `t`), in time order.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.index(name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Index in a row of `output`.
    pub fn index_of(&self, output: Output) -> Option<usize> {
        self.index(&output.to_string())
    }

    /// The samples of `output`, in time order.
    pub fn column_of(&self, output: Output) -> Option<Vec<f64>> {
        self.column(&output.to_string())
    }

    /// The columns that are outputs ([`Output`]), with their index in a row.
    pub fn outputs(&self) -> impl Iterator<Item = (usize, Output)> + '_ {
        self.names
            .iter()
            .enumerate()
            .filter_map(|(i, name)| Output::parse(name).map(|o| (i + 1, o)))
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

    /// Writes the CSV: a header `t,<names>` and one row per sample.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "t,{}", self.names.join(","))?;
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
