//! From text (TOML) or an in-memory table (a Python dict) to a [`RawScene`],
//! with errors naming the field path.

use super::error::SceneError;
use super::raw::RawScene;
use super::tagged::{forget_pending_path, locate, TaggedError};
use serde::de::DeserializeOwned;

/// Reads `T` from a TOML value, turning the error into a field error at the
/// path where it occurred (`(top level)` for the root).
pub(super) fn parse_value<T: DeserializeOwned>(value: toml::Value) -> Result<T, SceneError> {
    forget_pending_path();
    serde_path_to_error::deserialize(value).map_err(|e| {
        let message = e.inner().to_string();
        // toml appends "\nin `path`"; the path is reported in front instead.
        let message = message.lines().next().unwrap_or_default();
        field_error(locate(e.path(), message))
    })
}

/// The scene's error for an error at `e.path` (relative to the scene); a
/// missing field is named by its own path.
fn field_error(e: TaggedError) -> SceneError {
    let TaggedError { path, message } = e;
    let (path, message) = match message
        .strip_prefix("missing field `")
        .and_then(|m| m.strip_suffix('`'))
    {
        Some(field) if path.is_empty() => (field.to_string(), "missing".to_string()),
        Some(field) => (format!("{path}.{field}"), "missing".to_string()),
        None => (path, message),
    };
    let path = if path.is_empty() {
        "(top level)".to_string()
    } else {
        path
    };
    SceneError::field(path, message)
}

/// Line and column (1-based) of a byte offset in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The deepest nesting of arrays and inline tables a scene may have (a
/// quadrupole in a site's table in the list of sites is 4 deep).
pub const MAX_NESTING: usize = 16;
/// Memory the TOML parser needs per byte of text, at most (a number of a few
/// characters becomes a value of 32 bytes in a vector).
const PARSE_BYTES_PER_BYTE: f64 = 16.0;

/// The byte offset where the nesting of arrays and inline tables in `text`
/// first exceeds [`MAX_NESTING`], if it does. Strings (basic, literal,
/// multi-line) and comments are skipped; table headers count as one or two
/// levels, closed on their line.
fn too_deep(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut at = 0;
    while at < bytes.len() {
        match bytes[at] {
            b'#' => {
                at += bytes[at..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .unwrap_or(bytes.len() - at);
            }
            quote @ (b'"' | b'\'') => {
                let multi = bytes[at..].starts_with(if quote == b'"' { b"\"\"\"" } else { b"'''" });
                let open = if multi { 3 } else { 1 };
                let mut end = at + open;
                while end < bytes.len() {
                    if quote == b'"' && bytes[end] == b'\\' {
                        end += 2;
                        continue;
                    }
                    if bytes[end] == quote && (!multi || bytes[end..].starts_with(&[quote; 3])) {
                        break;
                    }
                    if !multi && bytes[end] == b'\n' {
                        break;
                    }
                    end += 1;
                }
                // Past the closing quotes (a multi-line string may end with
                // up to two more quotes inside it).
                at = end + open;
                while multi && at < bytes.len() && bytes[at] == quote {
                    at += 1;
                }
                continue;
            }
            b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Some(at);
                }
            }
            b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        at += 1;
    }
    None
}

/// Parses a scene written in TOML. Text that would need more memory to
/// parse than the memory limit, or nests arrays and inline
/// tables deeper than [`MAX_NESTING`], is refused before parsing.
pub fn parse_toml(text: &str) -> Result<RawScene, SceneError> {
    crate::memory::check("(scene text)", text.len() as f64 * PARSE_BYTES_PER_BYTE)?;
    if let Some(offset) = too_deep(text) {
        let (line, column) = line_column(text, offset);
        return Err(SceneError::Syntax(format!(
            "line {line}, column {column}: arrays and inline tables nested deeper than {MAX_NESTING}"
        )));
    }
    let table: toml::Table = toml::from_str(text).map_err(|e| {
        let message = e.message().trim().to_string();
        match e.span() {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                SceneError::Syntax(format!("line {line}, column {column}: {message}"))
            }
            None => SceneError::Syntax(message),
        }
    })?;
    parse_value(toml::Value::Table(table))
}

/// Parses a scene given as a TOML table built in memory (the form a Python
/// dict is converted to).
pub fn parse_table(table: toml::Table) -> Result<RawScene, SceneError> {
    parse_value(toml::Value::Table(table))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nesting is counted outside strings and comments only; headers close
    /// on their line.
    #[test]
    fn nesting_is_counted_outside_strings_and_comments() {
        let deep = |n: usize| format!("x = {}{}", "[".repeat(n), "]".repeat(n));
        assert_eq!(too_deep(&deep(MAX_NESTING)), None);
        assert_eq!(too_deep(&deep(MAX_NESTING + 1)), Some(4 + MAX_NESTING));
        let quoted = format!(
            "[[a.b]]\n[[a.b]]\nk = \"{0}\"\nl = '{0}'\nm = \"\"\"{0}\"\"\"\"\"\n# {0}\nn = '\''{0}\'\'\'\nq = \"\\\"[\"",
            "[".repeat(100)
        );
        assert_eq!(too_deep(&quoted), None, "{quoted}");
        assert!(parse_toml(&deep(1000)).is_err_and(|e| e
            .to_string()
            .starts_with("syntax: line 1, column 21: arrays and inline tables nested deeper")));
    }
}
