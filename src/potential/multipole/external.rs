//! Uniform external fields acting on every rotor.

use super::PotentialError;
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

/// Relative asymmetry tolerated in user matrices (round-off of their construction).
pub(crate) const SYMMETRY_TOLERANCE: f64 = 1e-10;

impl ExternalFields {
    /// No external field at all.
    pub const NONE: ExternalFields = ExternalFields {
        field: None,
        field_gradient: None,
    };

    pub(crate) fn validate(&self) -> Result<(), PotentialError> {
        if let Some(e0) = self.field {
            if !e0.iter().all(|x| x.is_finite()) {
                return Err(PotentialError::new(
                    "field",
                    format!("must be finite, got [{}, {}, {}]", e0.x, e0.y, e0.z),
                ));
            }
        }
        if let Some(g0) = self.field_gradient {
            if !g0.iter().all(|x| x.is_finite()) {
                return Err(PotentialError::new("field_gradient", "must be finite"));
            }
            let asymmetry = (g0 - g0.transpose()).abs().max();
            if asymmetry > SYMMETRY_TOLERANCE * g0.abs().max() {
                return Err(PotentialError::new(
                    "field_gradient",
                    format!("must be symmetric (a static field is curl-free), got |G - G^T|max = {asymmetry:e}"),
                ));
            }
        }
        Ok(())
    }
}
