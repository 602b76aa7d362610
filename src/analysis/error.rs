//! The one error type of the analysis layer.

use std::fmt;

/// Input the analysis cannot use, or a quantity no formula gives: names the
/// input at fault and says what is wrong with it, with the value found.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisError {
    /// The input at fault, e.g. `orientations[12, 3]`, `volume`, `boundary`.
    pub what: String,
    /// What is wrong with it.
    pub problem: String,
}

impl AnalysisError {
    pub(crate) fn new(what: impl Into<String>, problem: impl Into<String>) -> Self {
        AnalysisError {
            what: what.into(),
            problem: problem.into(),
        }
    }
}

impl fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.what, self.problem)
    }
}

impl std::error::Error for AnalysisError {}

/// Checks that `value` (input `what`) is finite and > 0.
pub(crate) fn positive(what: &str, value: f64) -> Result<f64, AnalysisError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(AnalysisError::new(
            what,
            format!("must be finite and > 0, got {value}"),
        ))
    }
}
