//! `--set KEY=VALUE`: replace or add one value of the scene's TOML tree before validation.

use super::error::SceneError;

/// Applies one `KEY=VALUE` override to a parsed scene. `KEY` is a dotted path; a numeric
/// segment indexes a list (`sections.length.1`). `VALUE` is parsed as TOML (a number, a
/// list, an inline table, a quoted string); a bare word that is not TOML is taken as a
/// string (`gravity.force_flow=none`).
///
/// # Errors
/// [`SceneError::Override`] when the argument has no `=`, the key is empty, or the path runs
/// through a value that is not a table or list, or past the end of a list.
pub fn apply_override(table: &mut toml::Table, argument: &str) -> Result<(), SceneError> {
    let err = |rule: String| SceneError::Override {
        argument: argument.to_string(),
        rule,
    };
    let (key, raw) = argument
        .split_once('=')
        .ok_or_else(|| err("expected KEY=VALUE".into()))?;
    let key = key.trim();
    let segments: Vec<&str> = key.split('.').map(str::trim).collect();
    if key.is_empty() || segments.iter().any(|s| s.is_empty()) {
        return Err(err("the key is empty or has an empty segment".into()));
    }
    let value = parse_value(raw.trim());
    let (last, parents) = segments.split_last().expect("at least one segment");
    let mut node = TomlNode::Table(table);
    let mut walked = String::new();
    for seg in parents {
        node = node
            .child(seg)
            .map_err(|e| err(format!("at `{walked}{seg}`: {e}")))?;
        walked.push_str(seg);
        walked.push('.');
    }
    node.set(last, value)
        .map_err(|e| err(format!("at `{walked}{last}`: {e}")))
}

fn parse_value(raw: &str) -> toml::Value {
    match format!("v = {raw}").parse::<toml::Table>() {
        Ok(mut t) => t.remove("v").expect("the key we wrote"),
        Err(_) => toml::Value::String(raw.to_string()),
    }
}

enum TomlNode<'a> {
    Table(&'a mut toml::Table),
    Array(&'a mut Vec<toml::Value>),
}

impl<'a> TomlNode<'a> {
    fn child(self, seg: &str) -> Result<TomlNode<'a>, String> {
        let value = match self {
            TomlNode::Table(t) => t
                .entry(seg.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            TomlNode::Array(a) => index(a, seg)?,
        };
        match value {
            toml::Value::Table(t) => Ok(TomlNode::Table(t)),
            toml::Value::Array(a) => Ok(TomlNode::Array(a)),
            other => Err(format!("is a {}, not a table or list", other.type_str())),
        }
    }

    fn set(self, seg: &str, value: toml::Value) -> Result<(), String> {
        match self {
            TomlNode::Table(t) => {
                t.insert(seg.to_string(), value);
            }
            TomlNode::Array(a) => *index(a, seg)? = value,
        }
        Ok(())
    }
}

fn index<'a>(a: &'a mut [toml::Value], seg: &str) -> Result<&'a mut toml::Value, String> {
    let len = a.len();
    let i: usize = seg
        .parse()
        .map_err(|_| format!("a list takes a numeric index (0..{len}), not `{seg}`"))?;
    a.get_mut(i)
        .ok_or_else(|| format!("index {i} is past the end of a list of {len}"))
}
