//! What a periodic sum of site multipoles takes and gives: positions,
//! charges and space-frame dipoles and (traceless, Buckingham) quadrupoles
//! in; the energy and each site's potential, fields and force out. Any sum
//! (the mesh Ewald sum of this module; cutoff sums later) fills the same
//! [`SiteResponse`], so that moving bodies can take any of them.

use super::cartesian::{source_coefficients, Tables, DERIVATIVES, SOURCES};
use nalgebra::{Matrix3, Vector3};

/// The sources of one evaluation (`None`: that multipole is zero at every
/// site). Every given slice has one entry per site, in site order.
#[derive(Clone, Copy, Debug)]
pub struct Sources<'a> {
    /// Site positions (length), any periodic image.
    pub positions: &'a [Vector3<f64>],
    /// Charges `q_i`.
    pub charges: Option<&'a [f64]>,
    /// Space-frame point dipoles `mu_i`.
    pub dipoles: Option<&'a [Vector3<f64>]>,
    /// Space-frame traceless quadrupoles `Theta_i` (Buckingham's convention).
    pub quadrupoles: Option<&'a [Matrix3<f64>]>,
}

impl Sources<'_> {
    /// Number of sites.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no sites.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The highest multipole order carried (0 charges, 1 dipoles, 2 quadrupoles).
    pub fn order(&self) -> usize {
        if self.quadrupoles.is_some() {
            2
        } else if self.dipoles.is_some() {
            1
        } else {
            0
        }
    }

    /// The coefficients `c_E` of site `i`'s operator `D = q + mu.grad +
    /// 1/3 Theta:grad grad` (see [`super::cartesian`]).
    pub(crate) fn coefficients(&self, i: usize) -> [f64; SOURCES] {
        source_coefficients(
            self.charges.map_or(0.0, |q| q[i]),
            &self.dipoles.map_or(Vector3::zeros(), |m| m[i]),
            &self.quadrupoles.map_or(Matrix3::zeros(), |t| t[i]),
        )
    }

    /// The total dipole `M = sum_i (q_i r_i + mu_i)` of the given positions.
    pub fn total_dipole(&self, positions: &[Vector3<f64>]) -> Vector3<f64> {
        let mut total = Vector3::zeros();
        for (i, r) in positions.iter().enumerate() {
            total += r * self.charges.map_or(0.0, |q| q[i]);
            total += self.dipoles.map_or(Vector3::zeros(), |m| m[i]);
        }
        total
    }
}

/// The response of every site, with the conventions of
/// `crate::potential::multipole::kernels`: `E_i = -dV/dmu_i`, `W_i =
/// dV/dTheta_i`, and the force `F_i = -dV/dr_i` at fixed multipoles.
#[derive(Clone, Debug, Default)]
pub struct SiteResponse {
    /// The total energy `V`.
    pub energy: f64,
    /// The electrostatic potential `phi_i = dV/dq_i`.
    pub potential: Vec<f64>,
    /// The field `E_i = -grad phi`.
    pub field: Vec<Vector3<f64>>,
    /// `W_i = 1/3 grad grad phi` (symmetric).
    pub quadrupole_conjugate: Vec<Matrix3<f64>>,
    /// `F_i = -(q grad phi + (mu.grad) grad phi + 1/3 Theta:grad grad grad phi)`.
    pub force: Vec<Vector3<f64>>,
    /// The atomic virial `W = -(dV/d eps)^T` under a homogeneous strain
    /// `r -> (1 + eps) r` of the box and the positions at fixed space-frame
    /// multipoles (for pairs, `sum_pairs r_ij f_ij^T`); zero when the sum
    /// was not asked for it.
    pub virial: Matrix3<f64>,
}

impl SiteResponse {
    /// A response for `sites` sites (the buffers an evaluation fills).
    pub fn zeros(sites: usize) -> Self {
        SiteResponse {
            energy: 0.0,
            potential: vec![0.0; sites],
            field: vec![Vector3::zeros(); sites],
            quadrupole_conjugate: vec![Matrix3::zeros(); sites],
            force: vec![Vector3::zeros(); sites],
            virial: Matrix3::zeros(),
        }
    }

    /// Fills the response from each site's potential derivatives `d^A phi`
    /// (the first [`DERIVATIVES`] multi-indices of [`super::cartesian`]):
    /// `V = 1/2 sum_i sum_E c_E d^E phi_i`, `F_i = -sum_E c_E d^(E + e_a) phi_i`.
    pub(crate) fn fill(&mut self, sources: &Sources<'_>, derivatives: &[[f64; DERIVATIVES]]) {
        let tables = Tables::get();
        let mut energy = 0.0;
        for (i, d) in derivatives.iter().enumerate() {
            let c = sources.coefficients(i);
            let mut force = Vector3::zeros();
            for (e, c) in c.iter().enumerate() {
                energy += c * d[e];
                for a in 0..3 {
                    force[a] -= c * d[tables.raise[e][a]];
                }
            }
            self.potential[i] = d[0];
            self.field[i] = -Vector3::new(d[1], d[2], d[3]);
            self.quadrupole_conjugate[i] =
                Matrix3::from_fn(|a, b| d[tables.sum[1 + a][1 + b]] / 3.0);
            self.force[i] = force;
        }
        self.energy = 0.5 * energy;
    }
}
