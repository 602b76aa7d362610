//! Uniform external fields acting on every rotor.

use super::PotentialError;
use crate::checks::{each, finite, finite_matrix, symmetric};
use nalgebra::{Matrix3, Vector3};

/// Uniform external fields, each optional; an absent field costs nothing.
///
/// * `field` `E0` (reduced units, 4 pi eps0 = 1) couples to dipoles:
///   `V = -sum_i mu_i . E0`.
/// * `field_gradient` `G0`, with `G0[(a, b)] = dE_b/dr_a`, couples to the
///   Buckingham quadrupoles: `V = -1/3 sum_i Theta_i : G0`. A static field's
///   gradient is symmetric (required here); its trace does not couple to a
///   traceless `Theta`, so any trace is accepted and has no effect.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExternalFields {
    /// Uniform electric field `E0`, space frame.
    pub field: Option<Vector3<f64>>,
    /// Uniform field gradient `G0 = grad E`, space frame, symmetric.
    pub field_gradient: Option<Matrix3<f64>>,
}

impl ExternalFields {
    /// No external field at all.
    pub const NONE: ExternalFields = ExternalFields {
        field: None,
        field_gradient: None,
    };

    /// Checks the fields: every component finite (paths `field[k]`,
    /// `field_gradient[i][j]`), the gradient symmetric within
    /// [`crate::rotor::TENSOR_TOLERANCE`] (path `field_gradient`).
    pub fn validate(&self) -> Result<(), PotentialError> {
        if let Some(e0) = &self.field {
            each(e0.as_slice(), finite).map_err(|e| e.at("field"))?;
        }
        if let Some(g0) = &self.field_gradient {
            finite_matrix(g0)
                .and_then(|()| symmetric(g0))
                .map_err(|e| e.at("field_gradient"))?;
        }
        Ok(())
    }
}
