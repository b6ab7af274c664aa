//! The `KEY=LOW:HIGH,...` lists of the options that name scene keys with a range
//! (`plan --robust`, `identify --free`): split and numbers read, one rule for both.

use crate::{Error, OptionName, Result};

/// Whether an entry of the list must carry its `=LOW:HIGH`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RangeRule {
    /// Every entry is `KEY=LOW:HIGH`.
    Required,
    /// An entry is `KEY` or `KEY=LOW:HIGH`.
    Optional,
}

/// One entry: the key as written (trimmed) and its range if given.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct KeyRange {
    /// The scene key, unchecked.
    pub key: String,
    /// `(low, high)`, finite; their order is the caller's rule.
    pub range: Option<(f64, f64)>,
}

/// Parses `text` (entries separated by commas; empty entries skipped) for `option`.
///
/// # Errors
/// [`Error::Option`] for `option`, naming the entry: a range missing where `rule` requires
/// one, a range without `:`, a bound that is not a finite number.
pub(crate) fn parse_key_ranges(
    text: &str,
    option: OptionName,
    rule: RangeRule,
) -> Result<Vec<KeyRange>> {
    let bad = |entry: &str, why: &str| Error::option(option, format!("{entry}: {why}"));
    let mut out = Vec::new();
    for entry in text.split(',').map(str::trim).filter(|e| !e.is_empty()) {
        let Some((key, range)) = entry.split_once('=') else {
            if rule == RangeRule::Required {
                return Err(bad(entry, "give KEY=LOW:HIGH, e.g. masses.load=10:30"));
            }
            out.push(KeyRange {
                key: entry.to_string(),
                range: None,
            });
            continue;
        };
        let (low, high) = range
            .split_once(':')
            .ok_or_else(|| bad(entry, "give the range as KEY=LOW:HIGH"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(entry, "LOW and HIGH must be finite numbers"))
        };
        out.push(KeyRange {
            key: key.trim().to_string(),
            range: Some((number(low)?, number(high)?)),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_with_and_without_ranges_are_read_and_bad_ones_named() {
        let read =
            parse_key_ranges(" a.b , c.d=1:2e3,", OptionName::Free, RangeRule::Optional).unwrap();
        assert_eq!(
            read,
            vec![
                KeyRange {
                    key: "a.b".into(),
                    range: None
                },
                KeyRange {
                    key: "c.d".into(),
                    range: Some((1.0, 2e3))
                },
            ]
        );
        let refused = |text: &str, rule| {
            parse_key_ranges(text, OptionName::Robust, rule)
                .unwrap_err()
                .to_string()
        };
        assert!(refused("a.b", RangeRule::Required).contains("a.b: give KEY=LOW:HIGH"));
        assert!(refused("a.b=1", RangeRule::Optional).contains("a.b=1: give the range"));
        assert!(refused("a.b=1:inf", RangeRule::Optional).contains("finite numbers"));
        assert!(refused("a.b=x:2", RangeRule::Required).contains("a.b=x:2"));
    }
}
