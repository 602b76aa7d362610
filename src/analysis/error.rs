//! The error of the analysis layer: the crate's input error, naming the
//! input at fault (`orientations[12, 3]`, `volume`, `boundary`) and what is
//! wrong with it, with the value found.

/// Input the analysis cannot use, or a quantity no formula gives.
pub type AnalysisError = crate::checks::InputError;
