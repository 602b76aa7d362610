//! The sums of a pair pass ([`super::pair_pass`]): energies, virial,
//! the force on each site and the electrostatic potential and field at
//! each, one block per thread, added in range order.

use super::electrostatics::SiteResponse;
use crate::lanes::{Lanes, V4};
use nalgebra::{Matrix3, Vector3};

/// The sums of a pass (of one thread's range of sites, before they are
/// added).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PairSums {
    /// The Lennard-Jones energy.
    pub lennard_jones: f64,
    /// How many Lennard-Jones pairs may overlap (closer than a part in 1e9
    /// over [`super::overlap::OVERLAP_FRACTION`] of their sigma), NaN
    /// when not summed.
    pub overlaps: f64,
    /// The electrostatic energy.
    pub electrostatic: f64,
    /// The atomic virial `sum_pairs r_ij f_ij^T` of both terms.
    pub virial: Matrix3<f64>,
    /// The force on each site, both terms.
    pub force: Vec<Vector3<f64>>,
    /// The electrostatic potential and field at each site (empty without
    /// electrostatics).
    pub potential: Vec<f64>,
    pub field: Vec<Vector3<f64>>,
}

impl PairSums {
    /// The electrostatic response of the sums (their forces those of the
    /// electrostatics only when the pass had no Lennard-Jones term).
    pub(super) fn fill(&self, out: &mut SiteResponse) {
        out.energy = self.electrostatic;
        out.virial = self.virial;
        out.potential.copy_from_slice(&self.potential);
        out.field.copy_from_slice(&self.field);
        out.force.copy_from_slice(&self.force);
        out.quadrupole_conjugate.fill(Matrix3::zeros());
    }

    /// Zero sums for `n` sites (with the electrostatic ones or not).
    pub(super) fn reset(&mut self, n: usize, electrostatics: bool) {
        (self.lennard_jones, self.electrostatic, self.overlaps) = (0.0, 0.0, 0.0);
        self.virial = Matrix3::zeros();
        self.force.clear();
        self.force.resize(n, Vector3::zeros());
        let m = if electrostatics { n } else { 0 };
        self.potential.clear();
        self.potential.resize(m, 0.0);
        self.field.clear();
        self.field.resize(m, Vector3::zeros());
    }

    /// Site `i`'s field and (with `SUMS`) potential summed in lanes over
    /// its rows, added.
    #[inline(always)]
    pub(super) fn add_field<T: Lanes, const SUMS: bool>(
        &mut self,
        i: usize,
        field: V4<T>,
        potential: T,
    ) {
        if SUMS {
            self.potential[i] += potential.total();
        }
        self.field[i] += field.total();
    }
}
