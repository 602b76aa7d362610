//! Scalar arguments at the boundary: text (lone surrogates refused with the
//! argument's name, not a `UnicodeEncodeError`), paths, integers in a range
//! (no wrap, no panic, no `OverflowError`) and the memory a result would
//! take, estimated before it is allocated; and the two errors of the
//! boundary, built here only: an argument of the wrong type
//! ([`expected`], [`wrong_type`]) and a bad value of an argument the
//! library does not check itself ([`invalid`]: a shape, a keyword
//! combination only Python has, a conversion out of range). What the
//! library checks reaches Python through its own error (`mod.rs`).

use crate::checks::InputError;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt, PyString};
use std::path::PathBuf;

/// The `TypeError` for argument `name` of the wrong type: `what` says what
/// it must be (`steps: expected a sequence of integers`).
pub(crate) fn expected(name: &str, what: &str) -> PyErr {
    PyTypeError::new_err(format!("{name}: expected {what}"))
}

/// The `TypeError` for argument `name` of the wrong type: `what` says what
/// it must be, the message adds the type `obj` has.
pub(crate) fn wrong_type(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyErr {
    let kind = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    expected(name, &format!("{what}, got {kind}"))
}

/// The `ValueError` for a bad value of argument `name` (`name: message`),
/// through the library's input error and its one conversion.
pub(crate) fn invalid(name: &str, message: impl Into<String>) -> PyErr {
    InputError::new(name, message).into()
}

/// The error of a bad value of argument `name`, built from the name and
/// the message: [`invalid`], or the module's `SceneError` for a scene.
pub(crate) type BadValue = fn(&str, String) -> PyErr;

/// The text of `obj` (argument `name`), or the error `error` builds for
/// text that is not valid.
pub(crate) fn text_or(obj: &Bound<'_, PyAny>, name: &str, error: BadValue) -> PyResult<String> {
    let s = obj
        .cast::<PyString>()
        .map_err(|_| wrong_type(obj, name, "a str"))?;
    s.to_str()
        .map(str::to_string)
        .map_err(|_| error(name, "not valid text (a lone surrogate)".to_string()))
}

/// The text of `obj` (argument `name`); bad text is a `ValueError`.
pub(crate) fn text(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<String> {
    text_or(obj, name, invalid)
}

/// The optional text argument `obj`.
pub(crate) fn optional_text(
    obj: Option<&Bound<'_, PyAny>>,
    name: &str,
) -> PyResult<Option<String>> {
    obj.map(|o| text(o, name)).transpose()
}

/// A file-system path (str or `os.PathLike`) for argument `name`; names
/// that cannot be encoded are the error `error` builds.
pub(crate) fn path_or(obj: &Bound<'_, PyAny>, name: &str, error: BadValue) -> PyResult<PathBuf> {
    obj.extract::<PathBuf>().map_err(|e| {
        if e.is_instance_of::<PyTypeError>(obj.py()) {
            expected(name, "a path (str or os.PathLike)")
        } else {
            error(name, "not a valid file name (a lone surrogate)".to_string())
        }
    })
}

/// An integer argument in `[min, max]` (a Python or numpy integer): a
/// `TypeError` for anything else (bool and float included), a `ValueError`
/// naming the range for an integer outside it.
pub(crate) fn integer(obj: &Bound<'_, PyAny>, name: &str, min: u64, max: u64) -> PyResult<u64> {
    let index = if obj.is_instance_of::<PyBool>() || !obj.hasattr("__index__")? {
        None
    } else {
        obj.call_method0("__index__")
            .ok()
            .and_then(|i| i.cast_into::<PyInt>().ok())
    };
    let Some(index) = index else {
        return Err(wrong_type(obj, name, "an integer"));
    };
    match index.extract::<u64>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        _ => Err(invalid(
            name,
            format!("must be between {min} and {max}, got {index}"),
        )),
    }
}

/// The optional integer argument `obj` in `[min, max]`.
pub(crate) fn optional_integer(
    obj: Option<&Bound<'_, PyAny>>,
    name: &str,
    min: u64,
    max: u64,
) -> PyResult<Option<u64>> {
    obj.map(|o| integer(o, name, min, max)).transpose()
}

/// Refuses a result of `bytes` (`None`: the count overflowed) beyond the
/// memory limit of [`crate::memory`], naming the argument `name` that sets
/// its size.
pub(crate) fn check_memory(name: &str, bytes: Option<u64>) -> PyResult<()> {
    let bytes = bytes.map_or(f64::INFINITY, |b| b as f64);
    Ok(crate::memory::check(name, bytes)?)
}
