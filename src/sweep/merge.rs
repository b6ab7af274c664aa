//! Merging the shards of one sweep into one file after checking that they belong together
//! and that every run is there exactly once (each shard's rows are checked as it is read).

use super::table::{SweepTable, read_table};
use crate::{Error, Result};
use std::path::Path;

/// Merges the shard files of one sweep: same sweep hash, run count and shard count in every
/// header, every shard once, every index `0..runs` exactly once; rows sorted by index.
///
/// # Errors
/// [`Error::Input`] naming the mismatch, the missing shards or indices, or the duplicates.
pub fn merge_shards(paths: &[&Path]) -> Result<SweepTable> {
    let refuse = |why: String| Error::input("sweep-merge", why);
    if paths.is_empty() {
        return Err(refuse("no shard files given".into()));
    }
    let tables: Vec<SweepTable> = paths.iter().map(|p| read_table(p)).collect::<Result<_>>()?;
    let first = &tables[0];
    let runs = first.runs().ok_or_else(|| {
        refuse(format!(
            "{}: no valid run count in its header",
            paths[0].display()
        ))
    })?;
    let count_of = |t: &SweepTable| t.shard().map_or(0, |s| s.count);
    let mut seen_shards: Vec<(usize, usize)> = Vec::new();
    for (t, p) in tables.iter().zip(paths) {
        if t.header_field("sweep") != first.header_field("sweep")
            || t.runs() != Some(runs)
            || t.columns != first.columns
        {
            return Err(refuse(format!(
                "{} is from another sweep (sweep {:?}, runs {:?}) than {} (sweep {:?}, runs {runs}); all shards must come from the same sweep file and base scene",
                p.display(),
                t.header_field("sweep"),
                t.header_field("runs"),
                paths[0].display(),
                first.header_field("sweep")
            )));
        }
        let Some(shard) = t.shard() else {
            return Err(refuse(format!("{}: no shard in its header", p.display())));
        };
        if shard.count != count_of(first) {
            return Err(refuse(format!(
                "{} is shard {} of {}, {} is of {}: all shards must come from one split",
                p.display(),
                shard.index,
                shard.count,
                paths[0].display(),
                count_of(first)
            )));
        }
        if seen_shards.iter().any(|&(j, _)| j == shard.index) {
            return Err(refuse(format!(
                "shard {} is given twice ({})",
                shard.index,
                p.display()
            )));
        }
        seen_shards.push((shard.index, shard.count));
    }
    let mut rows: Vec<(usize, String)> =
        tables.iter().flat_map(|t| t.rows.iter().cloned()).collect();
    rows.sort_by_key(|(i, _)| *i);
    // every row's index is in range (checked as each file was read): count them
    let mut count = vec![0u8; runs];
    for (i, _) in &rows {
        count[*i] = count[*i].saturating_add(1);
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
