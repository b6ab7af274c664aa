//! Text a user gave (a scene's name, a file's path, a controller file's strings) inside a
//! comment of an emitted file (C, Python, MATLAB, LaTeX): one line, and never the end of a C
//! comment, so that it cannot close the comment and become code.

/// `text` with control characters (a newline) replaced by U+FFFD and `*/` by `* /`.
///
/// ```
/// use telescopic::io::comment::comment_text;
/// assert_eq!(comment_text("a\nb */ c"), "a\u{fffd}b * / c");
/// ```
pub fn comment_text(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { '\u{fffd}' } else { c })
        .collect::<String>()
        .replace("*/", "* /")
}
