//! The `quatrot` command line: `run`, `scenes` and `check`. A thin layer over
//! [`crate::scene`] and [`crate::run`]; every user error becomes a message
//! and an exit code, never a panic.

mod args;
mod commands;
mod progress;

pub use commands::main;
