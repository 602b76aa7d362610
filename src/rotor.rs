//! The rotor model: a rigid body pinned to a fixed site, with principal moments
//! of inertia and body-fixed point multipoles.
//!
//! Units are reduced throughout (4 pi eps0 = 1, and whatever length, mass and
//! time units the scene uses). Rotors never translate: the site is fixed.

use crate::checks::{each, finite, finite_matrix, symmetric, traceless, InputError};
use nalgebra::{Matrix3, Vector3};

pub use crate::checks::TENSOR_TOLERANCE;

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

    /// The inertia of principal moments `moments`: [`Inertia::Spherical`]
    /// for a spherical top ([`is_spherical_top`]), otherwise
    /// [`Inertia::Principal`].
    pub fn from_moments(moments: Vector3<f64>) -> Inertia {
        if is_spherical_top(&moments) {
            Inertia::Spherical(moments.x)
        } else {
            Inertia::Principal(moments)
        }
    }

    /// True for a spherical top ([`is_spherical_top`]; no inertia-tensor
    /// work needed), whichever variant holds the moments.
    pub fn is_spherical(&self) -> bool {
        is_spherical_top(&self.principal())
    }
}

/// True when the three principal moments are equal and positive: the one
/// definition of a spherical top (the Gear schemes' shortcut, the exact free
/// flow of the baselines, the rotors built from arrays).
pub fn is_spherical_top(moments: &Vector3<f64>) -> bool {
    moments.x > 0.0 && moments.x == moments.y && moments.y == moments.z
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

impl Rotor {
    /// Checks the site and the multipoles ([`check_site`], [`check_dipole`],
    /// [`check_quadrupole`]); the error's path names the field
    /// (`site[0]`, `quadrupole_body`).
    pub fn check(&self) -> Result<(), InputError> {
        check_site(&self.site).map_err(|e| e.at("site"))?;
        if let Some(mu) = &self.dipole_body {
            check_dipole(mu).map_err(|e| e.at("dipole_body"))?;
        }
        if let Some(theta) = &self.quadrupole_body {
            check_quadrupole(theta).map_err(|e| e.at("quadrupole_body"))?;
        }
        Ok(())
    }
}

/// A site: every component finite (path `[k]`).
pub fn check_site(site: &Vector3<f64>) -> Result<(), InputError> {
    each(site.as_slice(), finite)
}

/// A body dipole: every component finite (path `[k]`).
pub fn check_dipole(dipole_body: &Vector3<f64>) -> Result<(), InputError> {
    each(dipole_body.as_slice(), finite)
}

/// A body quadrupole (Buckingham, `potential::multipole::convention`):
/// every entry finite (path `[i][j]`), symmetric and traceless within
/// [`TENSOR_TOLERANCE`] of its largest entry.
pub fn check_quadrupole(quadrupole_body: &Matrix3<f64>) -> Result<(), InputError> {
    finite_matrix(quadrupole_body)?;
    symmetric(quadrupole_body)?;
    traceless(quadrupole_body)
}
