//! A body-fixed interaction site: Lennard-Jones, charge, point dipole and
//! point quadrupole, each optional.

use crate::checks::{each, finite, non_negative, positive, InputError};
use crate::rotor::{check_dipole, check_quadrupole};
use nalgebra::{Matrix3, Vector3};

/// Lennard-Jones parameters of a site, `u(r) = 4 eps [(sigma/r)^12 - (sigma/r)^6]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LennardJones {
    /// Well depth `epsilon` (energy, >= 0).
    pub epsilon: f64,
    /// Diameter `sigma` (length, > 0).
    pub sigma: f64,
}

/// One site of a body, in the body's input frame (the frame its type was
/// given in, before the rotation to principal axes).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Site {
    /// Position relative to the body's reference point (length).
    pub position: Vector3<f64>,
    /// Mass (>= 0, default 0): used when the body's mass or inertia is
    /// computed from its sites.
    pub mass: f64,
    /// Lennard-Jones parameters, if any.
    pub lennard_jones: Option<LennardJones>,
    /// Point charge (default 0).
    pub charge: f64,
    /// Point dipole, if any.
    pub dipole: Option<Vector3<f64>>,
    /// Traceless symmetric point quadrupole (Buckingham), if any.
    pub quadrupole: Option<Matrix3<f64>>,
}

impl Site {
    /// Checks every value, the error's path naming the field
    /// (`position[1]`, `lennard_jones.sigma`, ...).
    pub fn check(&self) -> Result<(), InputError> {
        each(self.position.as_slice(), finite).map_err(|e| e.at("position"))?;
        let _ = non_negative(self.mass).map_err(|e| e.at("mass"))?;
        if let Some(lj) = &self.lennard_jones {
            let _ = non_negative(lj.epsilon).map_err(|e| e.at("lennard_jones.epsilon"))?;
            let _ = positive(lj.sigma).map_err(|e| e.at("lennard_jones.sigma"))?;
        }
        let _ = finite(self.charge).map_err(|e| e.at("charge"))?;
        if let Some(mu) = &self.dipole {
            check_dipole(mu).map_err(|e| e.at("dipole"))?;
        }
        if let Some(theta) = &self.quadrupole {
            check_quadrupole(theta).map_err(|e| e.at("quadrupole"))?;
        }
        Ok(())
    }

    /// Whether the site carries a charge, dipole or quadrupole.
    pub fn is_electrostatic(&self) -> bool {
        self.charge != 0.0 || self.dipole.is_some() || self.quadrupole.is_some()
    }
}
