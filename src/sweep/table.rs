//! Result files of a sweep, read as strictly as they are written: the header (which sweep,
//! how many runs, which shard), the column line, rows checked one by one against both, and a
//! closing line with the row count and a SHA-256 of everything above it, so that a truncated,
//! corrupted or edited file is refused rather than merged.
//!
//! A work file (`<out>.partial`, rows appended as runs finish) has no closing line; its rows
//! are checked the same way and a torn last line (a killed process) is cut off.

use super::file::MAX_RUNS;
use super::shard::Shard;
use crate::{Error, Result};
use sha2::{Digest, Sha256};
use std::collections::HashSet;
use std::io::Write;
use std::path::Path;

/// The metric columns after the override columns, with their meaning (docs/sweeps.md).
pub const METRIC_COLUMNS: [&str; 14] = [
    "tip_rel_max",
    "tip_rel_rms",
    "contact_force_max",
    "contact_switches",
    "residual_std",
    "f1_hz",
    "steps",
    "rejected",
    "rhs_evals",
    "jacobian_evals",
    "factorizations",
    "status",
    "error",
    "wall_s",
];

/// Largest result or shard file read (bytes): 4 GiB, some 10^7 rows.
pub const MAX_RESULT_BYTES: u64 = 4 << 30;

/// Most characters of a bad line quoted in an error.
const QUOTE_LIMIT: usize = 200;

/// The `status` values a row may hold: `ok`, or the kind of error its run ended with.
pub const STATUSES: [&str; 16] = [
    "ok",
    "invalid",
    "option",
    "model",
    "unaffordable",
    "diverged",
    "step-underflow",
    "newton",
    "position",
    "step-limit",
    "settings",
    "stopped",
    "non-finite",
    "eigen",
    "panic",
    "error",
];

/// A result file: its header (which sweep and shard), its column line and its rows by index.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepTable {
    /// The first line (`# telescopic sweep ...`).
    pub header: String,
    /// The column names, comma-separated.
    pub columns: String,
    /// `(index, the whole line without its line break)`.
    pub rows: Vec<(usize, String)>,
}

impl SweepTable {
    /// Writes the file, closed by its `# end` line (row count and SHA-256).
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let body = self.body();
        w.write_all(body.as_bytes())?;
        writeln!(w, "{}", closing_line(&body, self.rows.len()))
    }

    /// The header, column and row lines, each ended by a line break.
    fn body(&self) -> String {
        let mut text = format!("{}\n{}\n", self.header, self.columns);
        for (_, line) in &self.rows {
            text.push_str(line);
            text.push('\n');
        }
        text
    }

    /// A field of the header (`sweep`, `runs`, `shard`, ...).
    pub fn header_field(&self, name: &str) -> Option<&str> {
        header_field(&self.header, name)
    }

    /// The run count of the header, bounded by [`MAX_RUNS`].
    pub fn runs(&self) -> Option<usize> {
        header_runs(&self.header)
    }

    /// The shard of the header (`whole` for a merged file).
    pub fn shard(&self) -> Option<Shard> {
        header_shard(&self.header)
    }

    /// The cells of a column, by name, in row order (quotes removed).
    pub fn column(&self, name: &str) -> Option<Vec<String>> {
        let i = split_csv(&self.columns).iter().position(|c| c == name)?;
        Some(
            self.rows
                .iter()
                .map(|(_, l)| split_csv(l).get(i).cloned().unwrap_or_default())
                .collect(),
        )
    }
}

/// A field of a header line (`sweep`, `runs`, `shard`, ...).
fn header_field<'h>(header: &'h str, name: &str) -> Option<&'h str> {
    header
        .split("; ")
        .find_map(|part| part.strip_prefix(name).and_then(|v| v.strip_prefix(' ')))
}

/// The run count of a header line, bounded by [`MAX_RUNS`].
fn header_runs(header: &str) -> Option<usize> {
    header_field(header, "runs")
        .and_then(|r| r.parse::<usize>().ok())
        .filter(|&r| (1..=MAX_RUNS).contains(&r))
}

/// The shard of a header line (`whole` for a merged file).
fn header_shard(header: &str) -> Option<Shard> {
    match header_field(header, "shard") {
        Some(s) => s.parse().ok(),
        None => header_field(header, "merged").map(|_| Shard::whole()),
    }
}

/// The closing line of a result file with `body` and `rows` rows.
fn closing_line(body: &str, rows: usize) -> String {
    let digest = Sha256::digest(body.as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("# end; rows {rows}; sha256 {hex}")
}

/// The cells of a CSV line, with quoted cells unquoted.
pub fn split_csv(line: &str) -> Vec<String> {
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => cells.push(std::mem::take(&mut cell)),
            (c, _) => cell.push(c),
        }
    }
    cells.push(cell);
    cells
}

/// A line as an error quotes it: at most [`QUOTE_LIMIT`] characters.
pub(super) fn quoted(line: &str) -> String {
    match line.char_indices().nth(QUOTE_LIMIT) {
        Some((cut, _)) => format!("{:?}... ({} bytes in all)", &line[..cut], line.len()),
        None => format!("{line:?}"),
    }
}

/// The rules of one row against the file's columns, run count and shard.
struct RowRules {
    columns: usize,
    runs: usize,
    shard: Shard,
}

impl RowRules {
    /// Checks the columns line and the header's counts.
    fn new(header: &str, columns: &str) -> std::result::Result<Self, String> {
        let names = split_csv(columns);
        let metrics = names.len().checked_sub(METRIC_COLUMNS.len());
        if names.first().map(String::as_str) != Some("index")
            || metrics.is_none_or(|m| m < 1 || names[m..] != METRIC_COLUMNS)
        {
            return Err(format!(
                "line 2: not the column line of a sweep (index, the keys, then {}): {}",
                METRIC_COLUMNS.join(","),
                quoted(columns)
            ));
        }
        let runs = header_runs(header).ok_or_else(|| {
            format!(
                "line 1: the header's run count must be 1 to {MAX_RUNS}: {}",
                quoted(header)
            )
        })?;
        let shard = header_shard(header)
            .ok_or_else(|| format!("line 1: the header names no shard: {}", quoted(header)))?;
        Ok(RowRules {
            columns: names.len(),
            runs,
            shard,
        })
    }

    /// Checks a row; returns its index.
    fn check(&self, line: &str) -> std::result::Result<usize, String> {
        let cells = split_csv(line);
        if cells.len() != self.columns {
            return Err(format!(
                "{} fields, the columns are {}",
                cells.len(),
                self.columns
            ));
        }
        let index: usize = cells[0]
            .parse()
            .map_err(|_| format!("index {:?} is not a whole number", cells[0]))?;
        if index >= self.runs || !self.shard.owns(index) {
            return Err(format!(
                "index {index} is not a run of shard {}/{} of {} runs",
                self.shard.index, self.shard.count, self.runs
            ));
        }
        let metrics = &cells[self.columns - METRIC_COLUMNS.len()..];
        let cell = |name: &str| {
            let i = METRIC_COLUMNS
                .iter()
                .position(|c| *c == name)
                .expect("a metric");
            metrics[i].as_str()
        };
        let status = cell("status");
        if !STATUSES.contains(&status) {
            return Err(format!(
                "status {status:?} is none of {}",
                STATUSES.join(", ")
            ));
        }
        let wall = cell("wall_s");
        if !wall.parse::<f64>().is_ok_and(|w| w.is_finite() && w >= 0.0) {
            return Err(format!("wall_s {wall:?} is not a time >= 0"));
        }
        for (name, kind) in METRIC_KINDS {
            let v = cell(name);
            let fine = match (status == "ok", kind) {
                (false, _) => v.is_empty(),
                (true, Kind::Number) => v.parse::<f64>().is_ok_and(|x| x.is_finite() && x >= 0.0),
                (true, Kind::Optional) => {
                    v.is_empty() || v.parse::<f64>().is_ok_and(f64::is_finite)
                }
                (true, Kind::Count) => v.parse::<u64>().is_ok(),
            };
            if !fine {
                return Err(format!(
                    "{name} {v:?} is not {} for a run with status {status}",
                    match (status == "ok", kind) {
                        (false, _) => "empty",
                        (true, Kind::Number) => "a finite number >= 0",
                        (true, Kind::Optional) => "empty or a finite number",
                        (true, Kind::Count) => "a whole number >= 0",
                    }
                ));
            }
        }
        Ok(index)
    }
}

/// What a metric cell of a successful run holds.
#[derive(Clone, Copy)]
enum Kind {
    /// A finite number >= 0.
    Number,
    /// Empty (not computable) or a finite number.
    Optional,
    /// A whole number.
    Count,
}

/// The metric cells with a rule (status, error and wall_s are checked on their own).
const METRIC_KINDS: [(&str, Kind); 11] = [
    ("tip_rel_max", Kind::Number),
    ("tip_rel_rms", Kind::Number),
    ("contact_force_max", Kind::Number),
    ("contact_switches", Kind::Count),
    ("residual_std", Kind::Optional),
    ("f1_hz", Kind::Optional),
    ("steps", Kind::Count),
    ("rejected", Kind::Count),
    ("rhs_evals", Kind::Count),
    ("jacobian_evals", Kind::Count),
    ("factorizations", Kind::Count),
];

/// Whether a file is complete (closed by its `# end` line) or a work file in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ending {
    Closed,
    Open,
}

/// Longest line of a result file (bytes): rows are a few hundred bytes; a longer line is
/// not one of them (and is never read whole).
pub const MAX_LINE_BYTES: u64 = 64 << 10;

/// Reads the next line (with its line break, if any) of at most [`MAX_LINE_BYTES`]; `None`
/// at the end of the file.
fn next_line(
    reader: &mut impl std::io::BufRead,
    number: usize,
) -> std::result::Result<Option<String>, String> {
    use std::io::{BufRead, Read};
    let mut bytes = Vec::new();
    reader
        .by_ref()
        .take(MAX_LINE_BYTES + 1)
        .read_until(b'\n', &mut bytes)
        .map_err(|e| format!("cannot be read: {e}"))?;
    if bytes.is_empty() {
        return Ok(None);
    }
    if bytes.len() as u64 > MAX_LINE_BYTES {
        let start = String::from_utf8_lossy(&bytes[..QUOTE_LIMIT]).into_owned();
        return Err(format!(
            "line {number} is longer than {MAX_LINE_BYTES} bytes, no row of a sweep: {start:?}..."
        ));
    }
    String::from_utf8(bytes)
        .map(Some)
        .map_err(|_| format!("line {number} is not UTF-8 text"))
}

/// A file's rows, checked; for a work file also the length of its whole lines (a torn last
/// line is beyond it).
fn parse(
    path: &Path,
    reader: &mut impl std::io::BufRead,
    ending: Ending,
) -> Result<(SweepTable, usize)> {
    let bad = |why: String| Error::input("sweep results", format!("{}: {why}", path.display()));
    let header = next_line(reader, 1).map_err(bad)?.unwrap_or_default();
    let header = header.trim_end_matches('\n');
    if !header.starts_with("# telescopic sweep ") {
        return Err(bad(format!(
            "line 1: not the result of `telescopic sweep` (no header line): {}",
            quoted(header)
        )));
    }
    let columns = next_line(reader, 2)
        .map_err(bad)?
        .filter(|c| c.ends_with('\n'))
        .ok_or_else(|| bad("no column line".into()))?;
    let columns = columns.trim_end_matches('\n');
    let rules = RowRules::new(header, columns).map_err(bad)?;
    let mut table = SweepTable {
        header: header.to_string(),
        columns: columns.to_string(),
        rows: Vec::new(),
    };
    let mut seen = HashSet::new();
    let mut whole = header.len() + columns.len() + 2;
    let mut closing = None;
    let mut number = 2;
    while let Some(raw) = next_line(reader, number + 1).map_err(bad)? {
        number += 1;
        if closing.is_some() {
            return Err(bad(format!(
                "line {number}: a line after the closing `# end` line"
            )));
        }
        let Some(line) = raw.strip_suffix('\n') else {
            if ending == Ending::Open {
                break; // torn by a kill: cut off by the caller
            }
            return Err(bad(format!(
                "line {number} has no line break: the file is truncated"
            )));
        };
        if line.starts_with("# end;") && ending == Ending::Closed {
            closing = Some((number, line.to_string()));
            continue;
        }
        let index = rules
            .check(line)
            .map_err(|why| bad(format!("line {number}: {why}: {}", quoted(line))))?;
        if !seen.insert(index) {
            return Err(bad(format!("line {number}: run {index} is there twice")));
        }
        table.rows.push((index, line.to_string()));
        whole += raw.len();
    }
    if ending == Ending::Closed {
        check_closing(&table, closing).map_err(bad)?;
    }
    Ok((table, whole))
}

/// The `# end` line: present, last, and matching the rows above it.
fn check_closing(
    table: &SweepTable,
    closing: Option<(usize, String)>,
) -> std::result::Result<(), String> {
    let Some((number, line)) = closing else {
        return Err(
            "ends without its closing `# end` line: the file is truncated (or not written by \
             telescopic sweep)"
                .into(),
        );
    };
    if line != closing_line(&table.body(), table.rows.len()) {
        return Err(format!(
            "line {number}: the rows do not match the closing line's count and SHA-256: the \
             file was changed or corrupted after it was written"
        ));
    }
    Ok(())
}

/// Opens a result file, refusing a regular file over [`MAX_RESULT_BYTES`] before reading.
fn open(path: &Path) -> Result<std::io::BufReader<std::fs::File>> {
    let bad = |why: String| Error::input("sweep results", format!("{}: {why}", path.display()));
    let file = std::fs::File::open(path).map_err(|e| bad(format!("cannot be read: {e}")))?;
    let meta = file
        .metadata()
        .map_err(|e| bad(format!("cannot be read: {e}")))?;
    if meta.is_dir() {
        return Err(bad("is a directory, not a file".into()));
    }
    if meta.is_file() && meta.len() > MAX_RESULT_BYTES {
        return Err(bad(format!(
            "{} bytes, more than the {MAX_RESULT_BYTES} bytes a result file may have",
            meta.len()
        )));
    }
    Ok(std::io::BufReader::new(file))
}

/// Reads a complete result file (of a sweep, a shard or a merge), every row checked.
///
/// # Errors
/// [`Error::Input`] naming the file, the line and the rule.
pub fn read_table(path: &Path) -> Result<SweepTable> {
    Ok(parse(path, &mut open(path)?, Ending::Closed)?.0)
}

/// Reads a work file: its rows checked, and the byte length of its whole lines (a torn last
/// line, from a killed process, lies beyond it).
///
/// # Errors
/// [`Error::Input`] naming the file, the line and the rule.
pub(super) fn read_work_file(path: &Path) -> Result<(SweepTable, usize)> {
    parse(path, &mut open(path)?, Ending::Open)
}

/// Reads work-file text kept in memory (`origin` names it in errors).
///
/// # Errors
/// As [`read_work_file`].
pub(super) fn read_work_bytes(origin: &Path, bytes: &[u8]) -> Result<SweepTable> {
    Ok(parse(origin, &mut &bytes[..], Ending::Open)?.0)
}
