//! The `quatrot` command line: `run`, `scenes`, `check` and `sweep`. A thin
//! layer over [`crate::scene`] and [`crate::run`] (and, for `sweep`, over the
//! Python package `quatrot.sweep`); every user error becomes a message and an
//! exit code, never a panic.

mod args;
mod commands;
mod progress;
mod sweep;

pub use commands::main;
#[cfg(feature = "python")]
pub use commands::main_from;

/// Exit code of a scene or run error (and of a sweep that cannot start).
const EXIT_ERROR: i32 = 2;
