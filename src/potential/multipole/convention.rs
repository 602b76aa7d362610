//! The quadrupole convention, and the conversion to OpenMM's.
//!
//! quatrot uses Buckingham's traceless quadrupole
//! `Theta = 1/2 sum_a q_a (3 r_a r_a^T - |r_a|^2 I)`,
//! whose potential is `phi(r) = r^T Theta r / |r|^5` and whose energy in an
//! external field gradient `G = grad E` is `V = -1/3 Theta : G`.
//!
//! Other codes differ by factors: the "primitive" traceless form
//! `Q = sum q (3 r r^T - r^2 I) = 2 Theta` is common in textbooks, and
//! OpenMM's `AmoebaMultipoleForce` (like Tinker internally, which divides the
//! parameter-file values by 3) expects `Theta / 3`, in e nm^2. The factor 3
//! between quatrot and OpenMM is tested against OpenMM itself
//! (`tests/openmm_fixtures.rs`).

use nalgebra::{Matrix3, Vector3};

/// Buckingham's traceless quadrupole `1/2 sum q (3 r r^T - r^2 I)` of point
/// charges `(q, r)`, with `r` relative to the expansion centre.
pub fn buckingham_quadrupole(charges: &[(f64, Vector3<f64>)]) -> Matrix3<f64> {
    charges.iter().fold(Matrix3::zeros(), |acc, (q, r)| {
        acc + (r * r.transpose() * 3.0 - Matrix3::identity() * r.norm_squared()) * (0.5 * q)
    })
}

/// The quadrupole OpenMM's `AmoebaMultipoleForce` expects for a Buckingham `Theta`: `Theta / 3`.
pub fn quadrupole_to_openmm(theta: &Matrix3<f64>) -> Matrix3<f64> {
    theta / 3.0
}

/// The Buckingham `Theta` of an OpenMM `AmoebaMultipoleForce` quadrupole: `3 Q_openmm`.
pub fn quadrupole_from_openmm(q_openmm: &Matrix3<f64>) -> Matrix3<f64> {
    q_openmm * 3.0
}
