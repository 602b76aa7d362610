//! The error of the analysis layer: the crate's input error, naming the
//! input at fault (`orientations[12, 3]`, `volume`, `boundary`) and what is
//! wrong with it, with the value found.

/// Input the analysis cannot use, or a quantity no formula gives.
pub type AnalysisError = crate::checks::InputError;

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
