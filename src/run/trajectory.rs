//! The samples of one run: output names, rows `[t, outputs...]` and the run's statistics.

use std::io::Write;
use telescopic_runtime::RunStats;

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
