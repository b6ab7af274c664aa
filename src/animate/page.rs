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
    TEMPLATE
        .replace("{{TITLE}}", &escape(title))
        .replace("{{STYLE}}", STYLE)
        .replace("{{SCRIPT}}", SCRIPT)
        .replace("{{DATA}}", &json)
}

/// `text` with the characters HTML gives a meaning escaped.
fn escape(text: &str) -> String {
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
}
