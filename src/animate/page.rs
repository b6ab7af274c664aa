//! The self-contained HTML document of a view: the page, its style and script (compiled
//! into the library) and the movie as JSON in the page. Nothing is loaded from anywhere: the
//! page's content security policy forbids it, so it works offline and from disk.

use serde::Serialize;

const TEMPLATE: &str = include_str!("page.html");
const STYLE: &str = include_str!("view.css");
const SCRIPT: &str = include_str!("view.js");

/// The HTML document that shows `movie` (a [`super::RunMovie`] or [`super::ModeMovie`])
/// titled `title`.
pub fn document<T: Serialize>(title: &str, movie: &T) -> String {
    let json = serde_json::to_string(movie).expect("plain data serializes");
    // inside <script>, "</script" or "<!--" in a label would end or confuse the element
    let json = json.replace('<', "\\u003c");
    let title = escape(title);
    fill(TEMPLATE, |name| match name {
        "TITLE" => Some(title.as_str()),
        "STYLE" => Some(STYLE),
        "SCRIPT" => Some(SCRIPT),
        "DATA" => Some(json.as_str()),
        _ => None,
    })
}

/// `template` with each `{{NAME}}` replaced by `value(NAME)`, in one pass: a value that
/// holds a placeholder's text (a scene named `{{SCRIPT}}`) is copied as it is, never
/// expanded. An unknown name stays as written.
fn fill<'v>(template: &str, value: impl Fn(&str) -> Option<&'v str>) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        let Some(length) = rest[start + 2..].find("}}") else {
            break;
        };
        let name = &rest[start + 2..start + 2 + length];
        out.push_str(&rest[..start]);
        match value(name) {
            Some(v) => out.push_str(v),
            None => out.push_str(&rest[start..start + 4 + length]),
        }
        rest = &rest[start + 4 + length..];
    }
    out.push_str(rest);
    out
}

/// `text` with the characters HTML gives a meaning escaped, and control characters (which
/// HTML and XML refuse) replaced by U+FFFD.
fn escape(text: &str) -> String {
    let text: String = text
        .chars()
        .map(|c| {
            if c.is_control() && !matches!(c, '\t' | '\n') {
                '\u{fffd}'
            } else {
                c
            }
        })
        .collect();
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_cannot_end_the_script_or_inject_markup() {
        #[derive(Serialize)]
        struct Movie {
            label: &'static str,
        }
        let page = document(
            "a <b> & c",
            &Movie {
                label: "</script><script>alert(1)</script>",
            },
        );
        assert!(page.contains("<title>a &lt;b&gt; &amp; c</title>"));
        assert_eq!(page.matches("</script>").count(), 2); // the data's and the code's
        assert!(!page.contains("http://") && !page.contains("https://"));
    }

    #[test]
    fn a_title_that_names_a_placeholder_is_copied_not_expanded() {
        let page = document("{{SCRIPT}} {{DATA}}\u{1}", &[1.0]);
        assert!(
            page.contains("<title>{{SCRIPT}} {{DATA}}\u{fffd}</title>"),
            "{page}"
        );
        // the script and the data once each, where the template puts them
        assert_eq!(page.matches(SCRIPT).count(), 1);
        assert_eq!(page.matches("id=\"data\">[1.0]</script>").count(), 1);
        assert!(!page.contains('\u{1}'));
    }
}
