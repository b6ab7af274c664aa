//! Scene edits (`--set KEY=VALUE`, a sweep's run, Python's `set=`): replace or add one value
//! of the scene's TOML tree before validation.

use super::error::SceneError;

/// One edit of a scene's TOML tree before validation: a dotted key and the value it gets.
/// A numeric segment of the key indexes a list (`sections.length.1`). Its text (`Display`)
/// is `KEY=VALUE` as `--set` reads it, for messages and for reproducing a run.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneEdit {
    /// Dotted key (`contact.clearance`, `sections.length.1`).
    pub key: String,
    /// The value the key gets.
    pub value: toml::Value,
}

impl SceneEdit {
    /// `key` set to `value`.
    pub fn new(key: impl Into<String>, value: toml::Value) -> Self {
        SceneEdit {
            key: key.into(),
            value,
        }
    }

    /// Reads a `KEY=VALUE` argument as a user types it (`--set`). `VALUE` is parsed as TOML
    /// (a number, a list, an inline table, a quoted string); a bare word that is not TOML is
    /// taken as a string (`gravity.force_flow=none`).
    ///
    /// # Errors
    /// [`SceneError::Override`] when the argument has no `=` or the key is empty or has an
    /// empty segment.
    pub fn parse(argument: &str) -> Result<Self, SceneError> {
        let err = |rule: &str| SceneError::Override {
            argument: argument.to_string(),
            rule: rule.into(),
        };
        let (key, raw) = argument
            .split_once('=')
            .ok_or_else(|| err("expected KEY=VALUE"))?;
        let edit = SceneEdit::new(key.trim(), parse_value(raw.trim()));
        edit.segments().map_err(|rule| err(&rule))?;
        Ok(edit)
    }

    /// Reads every `KEY=VALUE` argument of `arguments`, in order ([`SceneEdit::parse`]).
    ///
    /// # Errors
    /// The first argument's [`SceneError::Override`].
    pub fn parse_all(arguments: &[String]) -> Result<Vec<Self>, SceneError> {
        arguments.iter().map(|a| SceneEdit::parse(a)).collect()
    }

    /// The key's segments, none empty.
    fn segments(&self) -> Result<Vec<&str>, String> {
        let segments: Vec<&str> = self.key.split('.').map(str::trim).collect();
        if self.key.is_empty() || segments.iter().any(|s| s.is_empty()) {
            return Err("the key is empty or has an empty segment".into());
        }
        Ok(segments)
    }

    /// Applies the edit to a parsed scene: the key's tables are made as needed.
    ///
    /// # Errors
    /// [`SceneError::Override`] when the key is empty, or its path runs through a value that
    /// is not a table or list, or past the end of a list.
    pub fn apply(&self, table: &mut toml::Table) -> Result<(), SceneError> {
        let err = |rule: String| SceneError::Override {
            argument: self.to_string(),
            rule,
        };
        let segments = self.segments().map_err(err)?;
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
        node.set(last, self.value.clone())
            .map_err(|e| err(format!("at `{walked}{last}`: {e}")))
    }
}

impl std::fmt::Display for SceneEdit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.key, value_text(&self.value))
    }
}

/// A value as TOML text, floats short (`0.005`, `10.0`, `8.3e-11`, `1e15`) and still floats.
pub fn value_text(value: &toml::Value) -> String {
    match value {
        toml::Value::Float(f) if f.is_finite() && *f != 0.0 && !(1e-4..1e7).contains(&f.abs()) => {
            format!("{f:e}")
        }
        toml::Value::Float(f) if f.is_finite() => format!("{f:?}"),
        v => v.to_string(),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_text_reads_back_as_the_same_value() {
        for f in [
            0.0,
            0.005,
            10.0,
            17.897,
            1e-4,
            9.99e6,
            1e7,
            8.3e-11,
            1e15,
            1e300,
            5e-324,
            -1.0 / 3.0,
        ] {
            let text = value_text(&toml::Value::Float(f));
            let back: toml::Table = format!("x = {text}").parse().unwrap();
            assert_eq!(back["x"], toml::Value::Float(f), "{f} written as {text}");
        }
        assert_eq!(value_text(&toml::Value::Float(0.005)), "0.005");
        assert_eq!(value_text(&toml::Value::Float(1e15)), "1e15");
        assert_eq!(value_text(&toml::Value::String("rk4".into())), "\"rk4\"");
    }

    #[test]
    fn an_edit_reads_back_from_its_text() {
        for value in [
            toml::Value::Float(8.3e-11),
            toml::Value::Integer(3),
            toml::Value::String("none".into()),
            toml::Value::Array(vec![toml::Value::Float(1.5), toml::Value::Float(2.0)]),
        ] {
            let edit = SceneEdit::new("sections.length", value);
            assert_eq!(SceneEdit::parse(&edit.to_string()).unwrap(), edit);
        }
    }
}
