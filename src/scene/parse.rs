//! From text (TOML) or an in-memory table (a Python dict) to a [`RawScene`],
//! with errors naming the field path.

use super::error::SceneError;
use super::raw::RawScene;
use super::tagged::join_path;
use serde::de::DeserializeOwned;

/// Reads `T` from a TOML value, turning the error into a field error at the
/// path where it occurred (`(top level)` for the root).
pub(super) fn parse_value<T: DeserializeOwned>(value: toml::Value) -> Result<T, SceneError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let outer = e.path().to_string();
        let outer = if outer == "." { "" } else { outer.as_str() };
        let message = e.inner().to_string();
        // toml appends "\nin `path`"; the path is reported in front instead.
        let message = message.lines().next().unwrap_or_default();
        let (path, message) = join_path(outer, message);
        let path = if path.is_empty() {
            "(top level)".to_string()
        } else {
            path
        };
        SceneError::field(path, message)
    })
}

/// Line and column (1-based) of a byte offset in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Parses a scene written in TOML.
pub fn parse_toml(text: &str) -> Result<RawScene, SceneError> {
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
