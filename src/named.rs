//! Fieldless enums chosen by name (command-line options, file fields): one table per enum
//! gives its names, its parsing and its display, so the three cannot drift apart.

/// Implements, for a fieldless enum, `NAMES` (every name, in order), `name()`, `FromStr`
/// (unknown names get "`x` is not WHAT; use a, b or c") and `Display`, from one table of
/// `Variant => "name"` entries.
macro_rules! named_enum {
    ($ty:ty, $what:literal, { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every value's name, in order.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            /// The value's name (what parses back to it).
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$variant => $name),+
                }
            }
        }

        impl std::str::FromStr for $ty {
            type Err = String;

            fn from_str(s: &str) -> std::result::Result<Self, String> {
                match s {
                    $($name => Ok(Self::$variant),)+
                    _ => Err(format!(
                        "`{s}` is not {}; use {}",
                        $what,
                        $crate::named::one_of(Self::NAMES)
                    )),
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}
pub(crate) use named_enum;

/// `a, b or c`.
pub(crate) fn one_of(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::one_of;

    #[test]
    fn lists_read_as_a_sentence() {
        assert_eq!(one_of(&["zv"]), "zv");
        assert_eq!(one_of(&["zv", "zvd"]), "zv or zvd");
        assert_eq!(one_of(&["a", "b", "c"]), "a, b or c");
    }
}
