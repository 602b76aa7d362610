//! Scenes given to `quatrot.run`: TOML text, a built-in name or a path, or
//! a dict (converted to TOML here, guarded against cycles and deep
//! nesting), read by the scene layer; its errors are the module's
//! `SceneError`, naming the field.

use super::args::{path_or, text_or};
use crate::scene::raw::RawScene;
use crate::scene::{load, load_table, load_text, Overrides, Scene};
use pyo3::create_exception;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

create_exception!(
    quatrot,
    SceneError,
    PyValueError,
    "A scene is invalid; the message names the field."
);
/// The scene layer's error as the module's `SceneError`.
pub(super) fn scene_error(e: &crate::scene::SceneError) -> PyErr {
    SceneError::new_err(e.to_string())
}

/// A `SceneError` for the bad value at `path` of a scene (or of an argument
/// that overrides one), in the scene layer's form.
pub(super) fn field(path: &str, message: String) -> PyErr {
    scene_error(&crate::scene::SceneError::field(path, message))
}

/// The deepest nesting of dicts and lists a scene dict may have (a scene
/// needs 5: a table of arrays of vectors in a table of the top level).
pub(crate) const MAX_DEPTH: usize = 32;

/// How a path of a scene dict is named in a message.
fn here(path: &str) -> &str {
    if path.is_empty() {
        "(top level)"
    } else {
        path
    }
}

/// The conversion of a scene dict to TOML: the containers being converted
/// (by identity, with their paths) guard against cycles, their number
/// against nesting deeper than [`MAX_DEPTH`].
#[derive(Default)]
struct ToToml {
    open: Vec<(usize, String)>,
}

impl ToToml {
    /// Converts `value`, found at `path`, naming the path on error.
    fn value(&mut self, value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
        if value.is_none() {
            let message = "None is not allowed (leave the key out)";
            return Err(field(here(path), message.to_string()));
        }
        if let Ok(b) = value.cast::<PyBool>() {
            return Ok(toml::Value::Boolean(b.is_true()));
        }
        if let Ok(i) = value.cast::<PyInt>() {
            return i.extract::<i64>().map(toml::Value::Integer).map_err(|_| {
                let range = format!("between {} and {}", i64::MIN, i64::MAX);
                let why = "a scene's integers are 64-bit signed";
                field(
                    here(path),
                    format!("must be an integer {range} ({why}), got {i}"),
                )
            });
        }
        if let Ok(f) = value.cast::<PyFloat>() {
            return Ok(toml::Value::Float(f.value()));
        }
        if value.is_instance_of::<PyString>() {
            return text_or(value, here(path), field).map(toml::Value::String);
        }
        let container = value.is_instance_of::<PyDict>()
            || value.is_instance_of::<PyList>()
            || value.is_instance_of::<PyTuple>();
        if container {
            self.enter(value, path)?;
            let converted = self.container(value, path);
            let _ = self.open.pop();
            return converted;
        }
        if value.hasattr("tolist")? {
            // numpy arrays and scalars.
            return self.value(&value.call_method0("tolist")?, path);
        }
        let kind = value.get_type().name()?;
        Err(field(
            here(path),
            format!("unsupported value of type {kind}"),
        ))
    }

    /// Opens the container `value` at `path`: refused if it is one of the
    /// containers it is inside of, or nested too deep.
    fn enter(&mut self, value: &Bound<'_, PyAny>, path: &str) -> PyResult<()> {
        let id = value.as_ptr() as usize;
        if let Some((_, outer)) = self.open.iter().find(|(o, _)| *o == id) {
            let message = format!("refers to itself (it is {})", here(outer));
            return Err(field(here(path), message));
        }
        if self.open.len() >= MAX_DEPTH {
            let message = format!("nested deeper than {MAX_DEPTH} levels");
            return Err(field(here(path), message));
        }
        self.open.push((id, path.to_string()));
        Ok(())
    }

    /// Converts a dict, list or tuple.
    fn container(&mut self, value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
        if let Ok(d) = value.cast::<PyDict>() {
            return self.table(d, path).map(toml::Value::Table);
        }
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(k, item)| self.value(&item?, &format!("{path}[{k}]")))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(toml::Value::Array(items))
    }

    /// Converts the entries of the dict `d` (opened at `path`).
    fn table(&mut self, d: &Bound<'_, PyDict>, path: &str) -> PyResult<toml::Table> {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            if !k.is_instance_of::<PyString>() {
                return Err(field(here(path), format!("keys must be strings, got {k}")));
            }
            let key = text_or(&k, &format!("{}: a key", here(path)), field)?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            let _ = table.insert(key, self.value(&v, &sub)?);
        }
        Ok(table)
    }
}

/// A Python value (a dict, a list of dicts, numbers, ...) as TOML, its
/// errors naming the paths below `path`.
pub(super) fn to_toml(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    ToToml::default().value(value, path)
}

/// TOML text if it has a newline or `=`, otherwise a built-in name or a path.
pub(super) fn load_scene(
    scene: &Bound<'_, PyAny>,
    overrides: &Overrides,
) -> PyResult<(RawScene, Scene)> {
    if let Ok(d) = scene.cast::<PyDict>() {
        let mut convert = ToToml::default();
        convert.enter(d, "")?;
        let table = convert.table(d, "")?;
        return load_table(table, overrides).map_err(|e| scene_error(&e));
    }
    if scene.is_instance_of::<PyString>() {
        let text = &text_or(scene, "scene", field)?;
        let loaded = if text.contains('\n') || text.contains('=') {
            load_text(text, overrides)
        } else {
            load(text, overrides)
        };
        return loaded.map_err(|e| scene_error(&e));
    }
    let path = path_or(scene, "scene", field).map_err(|e| {
        if e.is_instance_of::<PyTypeError>(scene.py()) {
            let message = "expected TOML text, a built-in name, a path or a dict";
            field("scene", message.to_string())
        } else {
            e
        }
    })?;
    let name = path.to_string_lossy().to_string();
    let name = if name.contains(['/', '\\']) || name.ends_with(".toml") {
        name
    } else {
        format!("./{name}")
    };
    load(&name, overrides).map_err(|e| scene_error(&e))
}
