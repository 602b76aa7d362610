//! The one error type of the potential layer.

use thiserror::Error;

/// An invalid potential definition. The message names the offending input and
/// its value, e.g. `cutoff: must be finite and > 0, got -1`.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("{what}: {problem}")]
pub struct PotentialError {
    /// The input at fault, e.g. `rotors[3].quadrupole_body` or `cutoff`.
    pub what: String,
    /// What is wrong with it, with the value found.
    pub problem: String,
}

impl PotentialError {
    pub(crate) fn new(what: impl Into<String>, problem: impl Into<String>) -> Self {
        PotentialError {
            what: what.into(),
            problem: problem.into(),
        }
    }
}
