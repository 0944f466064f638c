use std::fmt;
use std::path::{Path, PathBuf};

/// A scene that cannot run, with where and why, on one line.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    pub file: Option<PathBuf>,
    /// 1-based line and column for syntax and type errors.
    pub line_col: Option<(usize, usize)>,
    /// Dotted path of the offending field (`contact.normal.stiffness`), when known.
    pub field: Option<String>,
    pub message: String,
}

impl SceneError {
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError { file: None, line_col: None, field: Some(field.into()), message: message.into() }
    }

    pub fn in_file(mut self, file: &Path) -> Self {
        self.file = Some(file.to_path_buf());
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some((l, c)) = self.line_col {
                write!(f, ":{l}:{c}")?;
            }
            write!(f, ": ")?;
        } else if let Some((l, c)) = self.line_col {
            write!(f, "line {l}, column {c}: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "{}: ", one_line(field, MAX_FIELD_CHARS))?;
        }
        write!(f, "{}", one_line(&self.message, MAX_MESSAGE_CHARS))
    }
}

impl std::error::Error for SceneError {}

/// The longest field path and message a refusal prints, in characters: a few terminal lines.
/// The message's bound leaves room for the longest refusal with its remedy in full (an
/// overlap between two named groups, about 400), while a list a scene makes long (the names
/// of a thousand materials) is still cut.
const MAX_FIELD_CHARS: usize = 100;
const MAX_MESSAGE_CHARS: usize = 420;

/// `text` as one bounded terminal line, whatever a scene put into it: control characters
/// escaped, quoted text over 60 characters cut to 40, numbers of 20 or more digits (`{}` of
/// 1e308) in exponent form, and the whole cut at `max` characters.
pub(crate) fn one_line(text: &str, max: usize) -> String {
    let escaped: String = text.chars().flat_map(|c| if c.is_control() { c.escape_default().collect::<Vec<_>>() } else { vec![c] }).collect();
    let short = shorten_numbers(&shorten_quoted(&shorten_quoted(&escaped, '"'), '`'));
    let count = short.chars().count();
    if count <= max {
        return short;
    }
    let head: String = short.chars().take(max.saturating_sub(30)).collect();
    format!("{head}… ({count} characters)")
}

/// `message` with every text between two `quote`s over 60 characters cut to its first 40
/// (a scene's value is echoed back, and it may be any length).
fn shorten_quoted(message: &str, quote: char) -> String {
    let mut out = String::new();
    for (k, part) in message.split(quote).enumerate() {
        if k > 0 {
            out.push(quote);
        }
        // Odd parts are inside quotes.
        if k % 2 == 1 && part.chars().count() > 60 {
            out.extend(part.chars().take(40));
            out.push_str(&format!("… ({} characters)", part.chars().count()));
        } else {
            out.push_str(part);
        }
    }
    out
}

/// Decimal numbers of 20 or more digits written again in exponent form (`1e308`), so an
/// extreme value does not fill the line.
fn shorten_numbers(message: &str) -> String {
    let chars: Vec<char> = message.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit() && (i == 0 || !(chars[i - 1].is_alphanumeric() || chars[i - 1] == '.'));
        let mut j = i;
        if starts {
            while j < chars.len() && (chars[j].is_ascii_digit() || (chars[j] == '.' && chars.get(j + 1).is_some_and(char::is_ascii_digit))) {
                j += 1;
            }
        }
        let token: String = chars[i..j].iter().collect();
        match token.parse::<f64>() {
            Ok(v) if token.chars().filter(char::is_ascii_digit).count() >= 20 => {
                out.push_str(&format!("{v:e}"));
                i = j;
            }
            _ => {
                out.push(chars[i]);
                i += 1;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_message_prints_as_one_bounded_line() {
        let e = SceneError::field("name", format!("got \"a\nb\r\0{}\"", "y".repeat(100))).to_string();
        assert!(e.starts_with(r#"name: got "a\nb\r\u{0}yyy"#) && e.ends_with("… (111 characters)\"") && !e.contains('\n'), "{e}");
        let e = SceneError::field("contact.restitution", format!("must lie in (0, 1], got {}; at {:?}", f64::MAX, [0.5, -1e300, 1e-320]));
        assert_eq!(e.to_string(), "contact.restitution: must lie in (0, 1], got 1.7976931348623157e308; at [0.5, -1e300, 1e-320]");
        let long = format!("got {}", 1e-320);
        assert_eq!(one_line(&long, 100), "got 1e-320");
        let e = SceneError::field("run.integrator", format!("unknown variant `{}`, expected `verlet`", "z".repeat(1000)));
        assert!(e.to_string().contains("… (1000 characters)`, expected `verlet`"), "{e}");
        let many = "word ".repeat(200);
        let shown = one_line(&many, MAX_MESSAGE_CHARS);
        assert!(shown.chars().count() <= MAX_MESSAGE_CHARS && shown.ends_with("… (1000 characters)"), "{shown}");
        assert_eq!(one_line("3 of 12 at 0.25 and 12345678901234567890123", 100), "3 of 12 at 0.25 and 1.2345678901234568e22");
    }
}
