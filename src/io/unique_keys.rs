//! A JSON file's keys given once: `serde_json` keeps the last of a duplicated key silently,
//! so a file that sets a gain twice would run with whichever came last. Hand-written: no
//! well-kept crate checks this; it is one serde visitor over the document.

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

/// Refuses a JSON document in which an object gives a key twice, naming the key's dotted
/// path (`points[1].first_mode_hz`) and the line.
///
/// ```
/// use telescopic::io::unique_keys::check_unique_keys;
/// assert!(check_unique_keys(r#"{"a": 1, "b": {"c": 2}}"#).is_ok());
/// let err = check_unique_keys(r#"{"a": 1, "b": [{"c": 2, "c": 3}]}"#).unwrap_err();
/// assert!(err.contains("`b[0].c` is given twice"), "{err}");
/// ```
///
/// # Errors
/// The message, also for text that is not JSON.
pub fn check_unique_keys(text: &str) -> Result<(), String> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    Node(String::new())
        .deserialize(&mut deserializer)
        .and_then(|()| deserializer.end())
        .map_err(|e| e.to_string())
}

/// A value at a dotted path.
struct Node(String);

impl<'de> DeserializeSeed<'de> for Node {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Node {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0;
        while seq
            .next_element_seed(Node(format!("{}[{i}]", self.0)))?
            .is_some()
        {
            i += 1;
        }
        Ok(())
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            let node = if self.0.is_empty() {
                Node(key.clone())
            } else {
                Node(format!("{}.{key}", self.0))
            };
            if !seen.insert(key) {
                return Err(de::Error::custom(format!(
                    "the key `{}` is given twice",
                    node.0
                )));
            }
            map.next_value_seed(node)?;
        }
        Ok(())
    }
}
