//! Result files: reading them, and merging the shards of one sweep into one file after
//! checking that they belong together and that every run is there exactly once.

use super::shard::Shard;
use crate::{Error, Result};
use std::io::Write;
use std::path::Path;

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
    /// Writes the file.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "{}", self.header)?;
        writeln!(w, "{}", self.columns)?;
        for (_, line) in &self.rows {
            writeln!(w, "{line}")?;
        }
        Ok(())
    }

    /// A field of the header (`sweep`, `runs`, `shard`, ...).
    pub fn header_field(&self, name: &str) -> Option<&str> {
        self.header
            .split("; ")
            .find_map(|part| part.strip_prefix(name).and_then(|v| v.strip_prefix(' ')))
    }

    /// The cells of a column, by name, in row order (quotes not removed).
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

/// Reads a result file (or work file).
///
/// # Errors
/// [`Error::Option`] for a file that is not a sweep's result.
pub fn read_table(path: &Path) -> Result<SweepTable> {
    let bad = |why: String| Error::option("sweep results", format!("{}: {why}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(format!("cannot be read: {e}")))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("").to_string();
    if !header.starts_with("# telescopic sweep ") {
        return Err(bad(
            "not the result of `telescopic sweep` (no header line)".into()
        ));
    }
    let columns = lines
        .next()
        .ok_or_else(|| bad("no column line".into()))?
        .to_string();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| {
            l.split(',')
                .next()
                .and_then(|i| i.parse::<usize>().ok())
                .map(|i| (i, l.to_string()))
                .ok_or_else(|| bad(format!("a row without an index: {l:?}")))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(SweepTable {
        header,
        columns,
        rows,
    })
}

/// Merges the shard files of one sweep: same sweep hash, run count and shard count in every
/// header, every shard once, every index `0..runs` exactly once; rows sorted by index.
///
/// # Errors
/// [`Error::Option`] naming the mismatch, the missing shards or indices, or the duplicates.
pub fn merge_shards(paths: &[&Path]) -> Result<SweepTable> {
    let refuse = |why: String| Error::option("sweep-merge", why);
    if paths.is_empty() {
        return Err(refuse("no shard files given".into()));
    }
    let tables: Vec<SweepTable> = paths.iter().map(|p| read_table(p)).collect::<Result<_>>()?;
    let first = &tables[0];
    let key = |t: &SweepTable| {
        (
            t.header_field("sweep").map(str::to_string),
            t.header_field("runs").map(str::to_string),
        )
    };
    let (hash, runs) = key(first);
    let runs: usize = runs.and_then(|r| r.parse().ok()).ok_or_else(|| {
        refuse(format!(
            "{}: no run count in its header",
            paths[0].display()
        ))
    })?;
    let shard_count = |t: &SweepTable| {
        t.header_field("shard")
            .and_then(|s| s.parse::<Shard>().ok())
            .map(|s| (s.index, s.count))
    };
    let mut seen_shards = Vec::new();
    for (t, p) in tables.iter().zip(paths) {
        if key(t) != (hash.clone(), Some(runs.to_string())) || t.columns != first.columns {
            return Err(refuse(format!(
                "{} is from another sweep (sweep {:?}, runs {:?}) than {} (sweep {:?}, runs {runs}); all shards must come from the same sweep file and base scene",
                p.display(),
                t.header_field("sweep"),
                t.header_field("runs"),
                paths[0].display(),
                hash
            )));
        }
        let Some((i, n)) = shard_count(t) else {
            return Err(refuse(format!("{}: no shard in its header", p.display())));
        };
        if seen_shards.iter().any(|&(j, _)| j == i) {
            return Err(refuse(format!(
                "shard {i} is given twice ({})",
                p.display()
            )));
        }
        if let Some(&(_, m)) = seen_shards.first()
            && m != n
        {
            return Err(refuse(format!(
                "{} is shard {i} of {n}, the others of {m}",
                p.display()
            )));
        }
        seen_shards.push((i, n));
    }
    let mut rows: Vec<(usize, String)> =
        tables.iter().flat_map(|t| t.rows.iter().cloned()).collect();
    rows.sort_by_key(|(i, _)| *i);
    let mut count = vec![0usize; runs];
    for (i, _) in &rows {
        if *i >= runs {
            return Err(refuse(format!(
                "row index {i} is beyond the sweep's {runs} runs"
            )));
        }
        count[*i] += 1;
    }
    let missing: Vec<usize> = (0..runs).filter(|&i| count[i] == 0).collect();
    let twice: Vec<usize> = (0..runs).filter(|&i| count[i] > 1).collect();
    if !missing.is_empty() || !twice.is_empty() {
        let list = |v: &[usize]| {
            let shown: Vec<String> = v.iter().take(10).map(usize::to_string).collect();
            format!(
                "{}{}",
                shown.join(", "),
                if v.len() > 10 { ", ..." } else { "" }
            )
        };
        return Err(refuse(format!(
            "{} run(s) missing ({}) and {} given more than once ({}); every index 0..{} must \
             be present exactly once",
            missing.len(),
            list(&missing),
            twice.len(),
            list(&twice),
            runs - 1
        )));
    }
    let shards = seen_shards.first().map_or(1, |&(_, n)| n);
    let header = first
        .header
        .split("; ")
        .map(|part| {
            if part.starts_with("shard ") {
                format!("merged from {shards} shards")
            } else {
                part.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("; ");
    Ok(SweepTable {
        header,
        columns: first.columns.clone(),
        rows,
    })
}
