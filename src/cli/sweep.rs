//! `quatrot sweep ARGS`: a launcher for the Python sweep, which runs the
//! runs as Dask tasks. It checks that the interpreter (`$QUATROT_PYTHON`,
//! default `python3`) can import `quatrot.sweep`, then becomes (on Unix:
//! `exec`) `python -m quatrot.sweep ARGS`, so signals and the exit code are
//! the Python program's own.

use std::ffi::OsString;
use std::process::{Command, Stdio};

/// The variable naming the interpreter.
const PYTHON_VAR: &str = "QUATROT_PYTHON";
/// The interpreter when the variable is unset.
const DEFAULT_PYTHON: &str = "python3";
/// What the interpreter runs.
const MODULE: &str = "quatrot.sweep";

/// Why the sweep could not start.
#[derive(Debug, thiserror::Error)]
pub enum LaunchError {
    #[error("cannot start the Python interpreter `{python}` (set {PYTHON_VAR} to one that has quatrot): {message}")]
    Start { python: String, message: String },
    #[error("`{python}` cannot import {MODULE}: {message}; install it with `pip install 'quatrot[sweep]'` (quatrot with Dask) or set {PYTHON_VAR} to an interpreter that has it")]
    Import { python: String, message: String },
}

/// Runs `python -m quatrot.sweep args` and returns its exit code (on Unix
/// the process becomes the interpreter and this returns only on failure).
pub fn launch(args: &[String]) -> Result<i32, LaunchError> {
    let python = std::env::var_os(PYTHON_VAR).unwrap_or_else(|| OsString::from(DEFAULT_PYTHON));
    let name = python.to_string_lossy().into_owned();
    let start_error = |e: std::io::Error| LaunchError::Start {
        python: name.clone(),
        message: e.to_string(),
    };
    let check = Command::new(&python)
        .args(["-c", &format!("import {MODULE}")])
        .stdin(Stdio::null())
        .output()
        .map_err(start_error)?;
    if !check.status.success() {
        let stderr = String::from_utf8_lossy(&check.stderr);
        let message = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("it exited with an error and no message")
            .trim()
            .to_string();
        return Err(LaunchError::Import {
            python: name,
            message,
        });
    }
    become_or_wait(Command::new(&python).args(["-m", MODULE]).args(args)).map_err(start_error)
}

/// Replaces this process by `command` (returns only its error).
#[cfg(unix)]
fn become_or_wait(command: &mut Command) -> std::io::Result<i32> {
    use std::os::unix::process::CommandExt;
    Err(command.exec())
}

/// Runs `command` to its end and returns its exit code.
#[cfg(not(unix))]
fn become_or_wait(command: &mut Command) -> std::io::Result<i32> {
    Ok(command.status()?.code().unwrap_or(super::EXIT_ERROR))
}
