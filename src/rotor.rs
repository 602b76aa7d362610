//! The rotor model: a rigid body pinned to a fixed site, with principal moments
//! of inertia and body-fixed point multipoles.
//!
//! Units are reduced throughout (4 pi eps0 = 1, and whatever length, mass and
//! time units the scene uses). Rotors never translate: the site is fixed.

use nalgebra::{Matrix3, Vector3};

/// Principal moments of inertia about the body axes 1, 2, 3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Inertia {
    /// A spherical top, `I1 = I2 = I3 = I` (> 0).
    Spherical(f64),
    /// A general (symmetric or asymmetric) top, `(I1, I2, I3)`, each > 0.
    Principal(Vector3<f64>),
}

impl Inertia {
    /// The principal moments `(I1, I2, I3)`.
    pub fn principal(&self) -> Vector3<f64> {
        match *self {
            Inertia::Spherical(i) => Vector3::repeat(i),
            Inertia::Principal(v) => v,
        }
    }

    /// True for a spherical top (no inertia-tensor work needed).
    pub fn is_spherical(&self) -> bool {
        matches!(self, Inertia::Spherical(_))
    }
}

/// One rotor: its fixed site, inertia and body-fixed multipoles.
#[derive(Clone, Debug, PartialEq)]
pub struct Rotor {
    /// Position of the fixed site, space frame.
    pub site: Vector3<f64>,
    /// Principal moments of inertia.
    pub inertia: Inertia,
    /// Point dipole in body-fixed components, if any.
    pub dipole_body: Option<Vector3<f64>>,
    /// Traceless symmetric point quadrupole in body-fixed components, if any
    /// (Buckingham convention: see `potential::multipole::convention`).
    pub quadrupole_body: Option<Matrix3<f64>>,
}
