//! Which runs of a sweep one process makes (`--shard I/N`), and its parsing.

use crate::OptionName;
use crate::{Error, Result};
use std::str::FromStr;

/// Which runs of a sweep this process makes: run `i` when `i % count == index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard (0-based).
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Every run.
    pub fn whole() -> Self {
        Shard { index: 0, count: 1 }
    }

    /// The shard of a job array: Slurm's `SLURM_ARRAY_TASK_ID` (less
    /// `SLURM_ARRAY_TASK_MIN`, over `SLURM_ARRAY_TASK_STEP`) of `SLURM_ARRAY_TASK_COUNT`,
    /// else Kubernetes'
    /// `JOB_COMPLETION_INDEX` of `count` (which Kubernetes does not export). `var` gives a
    /// variable's value by name: the caller reads the environment (the library does not).
    ///
    /// # Errors
    /// [`Error::Option`] naming the missing or bad variable.
    pub fn of_job_array(
        var: impl Fn(&str) -> Option<String>,
        count: Option<usize>,
    ) -> Result<Self> {
        let parse = |name: &str, v: String| {
            v.trim().parse::<usize>().map_err(|_| {
                Error::option(
                    OptionName::Shard,
                    format!("{name}={v:?} is not a whole number"),
                )
            })
        };
        let shard = if let Some(id) = var("SLURM_ARRAY_TASK_ID") {
            let id = parse("SLURM_ARRAY_TASK_ID", id)?;
            let min = var("SLURM_ARRAY_TASK_MIN")
                .map(|v| parse("SLURM_ARRAY_TASK_MIN", v))
                .transpose()?
                .unwrap_or(0);
            let total = match var("SLURM_ARRAY_TASK_COUNT") {
                Some(v) => parse("SLURM_ARRAY_TASK_COUNT", v)?,
                None => count.ok_or_else(|| {
                    Error::option_see(
                        OptionName::Shard,
                        "SLURM_ARRAY_TASK_COUNT is not set; give the shard count",
                        OptionName::ShardCount,
                    )
                })?,
            };
            let step = var("SLURM_ARRAY_TASK_STEP")
                .map(|v| parse("SLURM_ARRAY_TASK_STEP", v))
                .transpose()?
                .unwrap_or(1)
                .max(1);
            let offset = id.checked_sub(min).filter(|o| o % step == 0);
            let shard = Shard {
                index: offset.map_or(usize::MAX, |o| o / step),
                count: total,
            };
            if shard.index >= total {
                return Err(Error::option(
                    OptionName::Shard,
                    format!(
                        "array task {id} (min {min}, step {step}, count {total}) is not one of an \
                         evenly spaced range; submit with sbatch --array=0-{} (optionally %LIMIT)",
                        total.saturating_sub(1)
                    ),
                ));
            }
            shard
        } else if let Some(id) = var("JOB_COMPLETION_INDEX") {
            let total = count.ok_or_else(|| {
                Error::option_see(
                    OptionName::Shard,
                    "JOB_COMPLETION_INDEX is set but not the count: give the shard count (the \
                     job's completions)",
                    OptionName::ShardCount,
                )
            })?;
            Shard {
                index: parse("JOB_COMPLETION_INDEX", id)?,
                count: total,
            }
        } else {
            return Err(Error::option(
                OptionName::Shard,
                "neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX (a \
                 Kubernetes indexed job) is set",
            ));
        };
        shard.check(OptionName::Shard)?;
        Ok(shard)
    }

    fn check(&self, option: OptionName) -> Result<()> {
        self.rule().map_err(|rule| Error::option(option, rule))
    }

    /// The rule a shard keeps: index below a non-zero count.
    fn rule(&self) -> std::result::Result<(), String> {
        if self.count == 0 || self.index >= self.count {
            return Err(format!(
                "shard {} of {}: need 0 <= I < N",
                self.index, self.count
            ));
        }
        Ok(())
    }

    /// Whether run `index` belongs to this shard.
    pub fn owns(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| "expected I/N (e.g. 0/4) or auto".to_string())?;
        let parse = |v: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|_| format!("`{v}` is not a whole number"))
        };
        let shard = Shard {
            index: parse(i)?,
            count: parse(n)?,
        };
        shard.rule()?;
        Ok(shard)
    }
}
