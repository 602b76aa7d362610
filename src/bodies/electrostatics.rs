//! Electrostatics between sites of different bodies: the interface every
//! method shares (site positions and space-frame multipoles in; energy,
//! virial, per-site potential, field and force out, in the convention of
//! the rotors' `SiteFields`: `E = -dV/dmu`), and the sum truncated at a
//! cutoff.
//!
//! The truncated sum is LAMMPS `pair_style lj/cut/dipole/cut`'s: the bare
//! charge and dipole pair energies (the Cartesian tensors of
//! `potential::multipole::kernels`) for site pairs closer than the cutoff,
//! neither shifted nor smoothed, the forces their exact gradients (no
//! impulse at the cutoff). Point quadrupoles are refused by
//! [`super::BodySystem::new`] for now.

use super::neighbours::NeighbourList;
use super::space::Space;
use crate::checks::{positive, InputError};
use crate::potential::multipole::{charge_dipole_force, dipole_field, radial, ChargeDipole};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Space-frame multipoles of every site (zero where a site has none).
#[derive(Clone, Debug, Default)]
pub struct SiteMultipoles {
    /// Site positions (not necessarily wrapped).
    pub positions: Vec<Vector3<f64>>,
    /// Charges.
    pub charges: Vec<f64>,
    /// Dipoles, space frame.
    pub dipoles: Vec<Vector3<f64>>,
}

/// What an electrostatic method returns.
#[derive(Clone, Debug, Default)]
pub struct SiteResponse {
    /// The energy.
    pub energy: f64,
    /// The atomic virial `sum_pairs r_ij f_ij^T` (pairs of sites).
    pub virial: Matrix3<f64>,
    /// The potential at each site (`dV/dq`).
    pub potential: Vec<f64>,
    /// The field at each site (`E = -dV/dmu`).
    pub field: Vec<Vector3<f64>>,
    /// The force on each site.
    pub force: Vec<Vector3<f64>>,
}

/// A method of electrostatics between sites of different bodies.
pub trait Electrostatics: Send + Sync + std::fmt::Debug {
    /// The distance within which it needs the pairs of sites (its
    /// real-space cutoff).
    fn pair_cutoff(&self) -> f64;

    /// Evaluates the sites' electrostatics into `out` (resized as needed).
    fn evaluate(
        &self,
        sites: &SiteMultipoles,
        space: &Space,
        pairs: &NeighbourList,
        out: &mut SiteResponse,
    );
}

/// The sum truncated at a cutoff (LAMMPS `lj/cut/dipole/cut`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutoffSum {
    cutoff: f64,
}

impl CutoffSum {
    /// The sum over pairs closer than `cutoff` (> 0).
    pub fn new(cutoff: f64) -> Result<Self, InputError> {
        Ok(CutoffSum {
            cutoff: positive(cutoff).map_err(|e| e.at("cutoff"))?,
        })
    }
}

/// One site's share of a pair loop: its energy (half of each pair's), its
/// virial (half of each pair's), and its own sums.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SiteShare {
    pub energy: f64,
    pub virial: Matrix3<f64>,
    pub potential: f64,
    pub field: Vector3<f64>,
    pub force: Vector3<f64>,
}

impl Electrostatics for CutoffSum {
    fn pair_cutoff(&self) -> f64 {
        self.cutoff
    }

    fn evaluate(
        &self,
        sites: &SiteMultipoles,
        space: &Space,
        pairs: &NeighbourList,
        out: &mut SiteResponse,
    ) {
        let cutoff2 = self.cutoff * self.cutoff;
        let charged = |i: usize| ChargeDipole {
            charge: sites.charges[i],
            dipole: sites.dipoles[i],
        };
        let shares: Vec<SiteShare> = (0..sites.positions.len())
            .into_par_iter()
            .map(|i| {
                let target = charged(i);
                let mut share = SiteShare::default();
                if target == ChargeDipole::default() {
                    return share;
                }
                for &j in pairs.partners(i) {
                    let j = j as usize;
                    let source = charged(j);
                    let r = space.minimum_image(sites.positions[i] - sites.positions[j]);
                    if r.norm_squared() >= cutoff2 || source == ChargeDipole::default() {
                        continue;
                    }
                    let b = radial(0.0, r.norm());
                    let force = charge_dipole_force(&r, &b, &target, &source);
                    share.potential += source.charge * b[0] + source.dipole.dot(&r) * b[1];
                    share.field +=
                        r * (source.charge * b[1]) + dipole_field(&r, &b, &source.dipole);
                    share.force += force;
                    share.virial += r * force.transpose() * 0.5;
                }
                share.energy =
                    0.5 * (target.charge * share.potential - target.dipole.dot(&share.field));
                share
            })
            .collect();
        gather(&shares, out);
    }
}

/// The response of the per-site shares (sums in site order: the same bits
/// for any number of threads).
pub(super) fn gather(shares: &[SiteShare], out: &mut SiteResponse) {
    out.energy = shares.iter().map(|s| s.energy).sum();
    out.virial = shares.iter().map(|s| s.virial).sum();
    out.potential = shares.iter().map(|s| s.potential).collect();
    out.field = shares.iter().map(|s| s.field).collect();
    out.force = shares.iter().map(|s| s.force).collect();
}
