//! A measured record: the time column `t`, the input the machine applied if the record has
//! it (the drive force `F`, or the vehicle's prescribed position `s`) and sensor columns named by their outputs (`vehicle`, `kappa_1_0`,
//! `tip_rel`, ...), evenly sampled. Every rule a record breaks is named with its column and
//! line.

use crate::{Error, Result};
use std::path::Path;
use telescopic_runtime::{LinearInput, Output};

/// The time column's name.
pub const TIME_COLUMN: &str = "t";

/// The prescribed position's column (a position-controlled drive's setpoint, m).
pub const POSITION_COLUMN: &str = "s";

/// How far an interval may stray from the record's median interval before it is a gap (or
/// a jump back): 1 % of the interval. The model is sampled on the even grid.
pub const INTERVAL_TOLERANCE: f64 = 0.01;

/// Fewest samples a record must have.
pub const MIN_SAMPLES: usize = 20;

/// A measured record, checked: times strictly increasing and evenly spaced, every value
/// finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Where it came from (a file's path, `DataFrame`), for messages.
    pub source: String,
    /// Sample times (s).
    pub times: Vec<f64>,
    /// The drive force the machine applied at each sample (N), held until the next one.
    pub force: Option<Vec<f64>>,
    /// The vehicle's prescribed position at each sample (m), the setpoint of a
    /// position-controlled drive: the scene is driven by its smooth interpolation.
    pub position: Option<Vec<f64>>,
    /// Each sensor's samples, in the record's column order.
    pub sensors: Vec<(Output, Vec<f64>)>,
}

impl Record {
    /// Reads a CSV record: `#` lines are comments, the first other line names the columns.
    ///
    /// # Errors
    /// [`Error::Input`] naming the file, the line and the column: unreadable, an unknown
    /// column, a value that is not a finite number, time not increasing, a gap, too short.
    pub fn read(path: &Path) -> Result<Record> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| Error::Input {
            subject: source.clone(),
            rule: format!("cannot be read: {e}"),
        })?;
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (_, header) = lines.next().ok_or_else(|| Error::Input {
            subject: source.clone(),
            rule: "has no header line (t, F and sensor columns)".into(),
        })?;
        let names = crate::sweep::split_csv(header);
        let mut columns = vec![Vec::new(); names.len()];
        let mut line_numbers = Vec::new();
        for (number, line) in lines {
            let fields = crate::sweep::split_csv(line);
            if fields.len() != names.len() {
                return Err(bad(
                    &source,
                    &format!("line {number}"),
                    &format!("{} fields, the header names {}", fields.len(), names.len()),
                ));
            }
            for ((column, name), field) in columns.iter_mut().zip(&names).zip(&fields) {
                let value = field.trim().parse::<f64>().ok().filter(|v| v.is_finite());
                let Some(value) = value else {
                    return Err(bad(
                        &source,
                        &format!("line {number}, column {name}"),
                        &format!("`{}` is not a finite number", field.trim()),
                    ));
                };
                column.push(value);
            }
            line_numbers.push(number);
        }
        Record::checked(source, &names, columns, |i| {
            format!("line {}", line_numbers[i])
        })
    }

    /// A record from named columns (Python's DataFrame): rows are named by their index.
    ///
    /// # Errors
    /// As [`Record::read`], naming the column and the row.
    pub fn from_columns(source: &str, names: &[String], columns: Vec<Vec<f64>>) -> Result<Record> {
        if names.len() != columns.len() {
            return Err(bad(source, "columns", "one name per column"));
        }
        for (name, column) in names.iter().zip(&columns) {
            if let Some(i) = column.iter().position(|v| !v.is_finite()) {
                return Err(bad(
                    source,
                    &format!("row {i}, column {name}"),
                    &format!("{} is not a finite number", column[i]),
                ));
            }
        }
        Record::checked(source.to_string(), names, columns, |i| format!("row {i}"))
    }

    /// The record of `columns` named `names`, checked; `place(i)` names sample `i`.
    fn checked(
        source: String,
        names: &[String],
        mut columns: Vec<Vec<f64>>,
        place: impl Fn(usize) -> String,
    ) -> Result<Record> {
        let position = |name: &str| names.iter().position(|n| n.trim() == name);
        let time_index = position(TIME_COLUMN).ok_or_else(|| {
            bad(
                &source,
                "columns",
                &format!(
                    "no time column `{TIME_COLUMN}` (s); the columns: {}",
                    names.join(", ")
                ),
            )
        })?;
        let force_name = LinearInput::DriveForce.name();
        let (mut force, mut position) = (None, None);
        let mut sensors = Vec::new();
        for (i, name) in names.iter().enumerate() {
            let name = name.trim();
            if i == time_index {
                continue;
            }
            let column = std::mem::take(&mut columns[i]);
            if name == force_name {
                force = Some(column);
                continue;
            }
            if name == POSITION_COLUMN {
                position = Some(column);
                continue;
            }
            let output: Output = name.parse().map_err(|rule: String| {
                bad(
                    &source,
                    &format!("column {name}"),
                    &format!(
                        "{rule}; the drive force is `{force_name}`, the prescribed position \
                         `{POSITION_COLUMN}`, the time `{TIME_COLUMN}`"
                    ),
                )
            })?;
            if sensors.iter().any(|(o, _)| *o == output) {
                return Err(bad(&source, &format!("column {name}"), "is given twice"));
            }
            sensors.push((output, column));
        }
        if sensors.is_empty() {
            return Err(bad(
                &source,
                "columns",
                "no sensor column (vehicle, kappa_1_0, acc_load, tip_rel, ...)",
            ));
        }
        if force.is_some() && position.is_some() {
            return Err(bad(
                &source,
                "columns",
                &format!(
                    "give the drive force `{force_name}` or the prescribed position \
                     `{POSITION_COLUMN}`, not both: the drive is one or the other"
                ),
            ));
        }
        let times = std::mem::take(&mut columns[time_index]);
        check_times(&source, &times, &place)?;
        Ok(Record {
            source,
            times,
            force,
            position,
            sensors,
        })
    }

    /// The even sample interval (s): the median interval.
    pub fn interval(&self) -> f64 {
        median_interval(&self.times)
    }

    /// The record's span (s).
    pub fn span(&self) -> (f64, f64) {
        (
            self.times[0],
            *self.times.last().expect("checked non-empty"),
        )
    }

    /// The record's first `n` samples.
    pub fn first(&self, n: usize) -> Record {
        Record {
            source: self.source.clone(),
            times: self.times[..n].to_vec(),
            force: self.force.as_ref().map(|f| f[..n].to_vec()),
            position: self.position.as_ref().map(|s| s[..n].to_vec()),
            sensors: self
                .sensors
                .iter()
                .map(|(o, y)| (*o, y[..n].to_vec()))
                .collect(),
        }
    }

    /// The samples of `output`, if the record has it.
    pub fn sensor(&self, output: Output) -> Option<&[f64]> {
        self.sensors
            .iter()
            .find(|(o, _)| *o == output)
            .map(|(_, v)| v.as_slice())
    }
}

/// The error of `place` in `source` breaking `rule`.
fn bad(source: &str, place: &str, rule: &str) -> Error {
    Error::Input {
        subject: format!("{source}, {place}"),
        rule: rule.to_string(),
    }
}

/// The median of the intervals between `times` (at least two).
fn median_interval(times: &[f64]) -> f64 {
    let mut intervals: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    intervals.sort_by(f64::total_cmp);
    intervals[intervals.len() / 2]
}

/// Times strictly increasing, evenly spaced within [`INTERVAL_TOLERANCE`], at least
/// [`MIN_SAMPLES`].
fn check_times(source: &str, times: &[f64], place: &impl Fn(usize) -> String) -> Result<()> {
    if times.len() < MIN_SAMPLES {
        return Err(bad(
            source,
            "rows",
            &format!(
                "{} samples; a record needs at least {MIN_SAMPLES}",
                times.len()
            ),
        ));
    }
    for i in 1..times.len() {
        if times[i] <= times[i - 1] {
            return Err(bad(
                source,
                &format!("{}, column {TIME_COLUMN}", place(i)),
                &format!(
                    "time {} s does not increase (the sample before is at {} s)",
                    times[i],
                    times[i - 1]
                ),
            ));
        }
    }
    let dt = median_interval(times);
    for i in 1..times.len() {
        let step = times[i] - times[i - 1];
        if (step - dt).abs() > INTERVAL_TOLERANCE * dt {
            let what = if step > dt { "a gap" } else { "an uneven step" };
            return Err(bad(
                source,
                &format!("{}, column {TIME_COLUMN}", place(i)),
                &format!(
                    "{what} of {step:.6} s after t = {} s; the record must be sampled evenly, \
                     every {dt:.6} s (within 1 %)",
                    times[i - 1]
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Record> {
        let dir = std::env::temp_dir().join(format!("telescopic-record-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("r{}.csv", text.len()));
        std::fs::write(&path, text).unwrap();
        let record = Record::read(&path);
        std::fs::remove_file(&path).unwrap();
        record
    }

    fn lines(rows: usize, row: impl Fn(usize) -> String) -> String {
        let mut text = String::from("# a comment\nt,F,vehicle,kappa_1_0\n");
        for i in 0..rows {
            text.push_str(&row(i));
            text.push('\n');
        }
        text
    }

    #[test]
    fn a_prescribed_position_reads_and_is_refused_beside_a_force() {
        let names: Vec<String> = ["t", "s", "tip_rel"].map(String::from).to_vec();
        let t: Vec<f64> = (0..30).map(|i| 0.01 * i as f64).collect();
        let record =
            Record::from_columns("frame", &names, vec![t.clone(), t.clone(), t.clone()]).unwrap();
        assert_eq!(record.position.as_ref().unwrap()[7], t[7]);
        assert!(record.force.is_none());
        let both: Vec<String> = ["t", "F", "s", "tip_rel"].map(String::from).to_vec();
        let refused = Record::from_columns("frame", &both, vec![t.clone(); 4]).unwrap_err();
        assert!(refused.to_string().contains("not both"), "{refused}");
    }

    #[test]
    fn a_good_record_reads_with_its_force_and_sensors() {
        let text = lines(30, |i| format!("{},100,{},0", 0.01 * i as f64, i));
        let record = read(&text).unwrap();
        assert_eq!(record.times.len(), 30);
        assert_eq!(record.force.as_ref().unwrap()[3], 100.0);
        assert_eq!(record.sensor(Output::Vehicle).unwrap()[4], 4.0);
        assert!((record.interval() - 0.01).abs() < 1e-12);
    }

    #[test]
    fn bad_records_are_refused_naming_line_and_column() {
        let err = |text: String| read(&text).unwrap_err().to_string();
        // line 1 is the comment, 2 the header, sample i is on line i + 3
        let nan = err(lines(30, |i| {
            let v = if i == 7 {
                "nan".to_string()
            } else {
                "0".into()
            };
            format!("{},100,{v},0", 0.01 * i as f64)
        }));
        assert!(
            nan.contains("line 10, column vehicle") && nan.contains("`nan`"),
            "{nan}"
        );
        let back = err(lines(30, |i| {
            let t = if i == 12 { 0.05 } else { 0.01 * i as f64 };
            format!("{t},100,0,0")
        }));
        assert!(
            back.contains("line 15, column t") && back.contains("does not increase"),
            "{back}"
        );
        let gap = err(lines(30, |i| {
            let t = 0.01 * i as f64 + if i >= 20 { 0.02 } else { 0.0 };
            format!("{t},100,0,0")
        }));
        assert!(
            gap.contains("line 23, column t") && gap.contains("a gap"),
            "{gap}"
        );
        let unknown = err("t,F,strain\n0,0,0\n".to_string());
        assert!(
            unknown.contains("column strain") && unknown.contains("no output"),
            "{unknown}"
        );
        let short = err(lines(5, |i| format!("{},1,0,0", 0.01 * i as f64)));
        assert!(short.contains("5 samples"), "{short}");
        let no_time = err("F,vehicle\n0,0\n".to_string());
        assert!(no_time.contains("no time column"), "{no_time}");
    }
}
