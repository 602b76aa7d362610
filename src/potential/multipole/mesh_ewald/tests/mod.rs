//! The mesh Ewald sum against independent references ([`references`]: the
//! direct Ewald sum converged to round-off for dipoles and quadrupoles, a
//! textbook charge Ewald sum written there, Madelung constants, closed
//! forms of lattices, finite differences of the energy) and its guarantees
//! ([`guarantees`]: threads, allocations, refusals), and the cost models
//! that choose its parameters ([`costs`]).

mod accuracy;
mod costs;
mod guarantees;
pub(crate) mod references;
mod virial;

use super::*;
use crate::potential::multipole::ewald::EwaldSum;
use crate::potential::multipole::kernels::{DipolesAndQuadrupoles, Lanes, SpaceMultipoles};
use crate::potential::multipole::{EwaldParameters, Surface};
use nalgebra::{Matrix3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;

/// A random configuration: positions in the box, and the multipoles asked for.
#[derive(Clone)]
pub(crate) struct Configuration {
    pub(crate) box_lengths: Vector3<f64>,
    pub(crate) positions: Vec<Vector3<f64>>,
    pub(crate) charges: Option<Vec<f64>>,
    pub(crate) dipoles: Option<Vec<Vector3<f64>>>,
    pub(crate) quadrupoles: Option<Vec<Matrix3<f64>>>,
}

impl Configuration {
    /// `n` sites at least 0.4 apart (periodic images included), charges
    /// summing to zero, dipoles and traceless quadrupoles with components
    /// in (-1, 1).
    pub(crate) fn random(
        seed: u64,
        n: usize,
        box_lengths: Vector3<f64>,
        kinds: (bool, bool, bool),
    ) -> Self {
        let mut rng = ChaCha20Rng::seed_from_u64(seed);
        let mut positions: Vec<Vector3<f64>> = Vec::new();
        while positions.len() < n {
            let r = Vector3::from_fn(|a, _| rng.random_range(0.0..box_lengths[a]));
            let close = positions.iter().any(|s| {
                let mut d = r - s;
                for a in 0..3 {
                    d[a] -= box_lengths[a] * (d[a] / box_lengths[a]).round();
                }
                d.norm() < 0.4
            });
            if !close {
                positions.push(r);
            }
        }
        let charges = kinds.0.then(|| {
            let mut q: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let mean = q.iter().sum::<f64>() / n as f64;
            q.iter_mut().for_each(|q| *q -= mean);
            q
        });
        let dipoles = kinds.1.then(|| {
            (0..n)
                .map(|_| Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)))
                .collect()
        });
        let quadrupoles = kinds.2.then(|| {
            (0..n)
                .map(|_| {
                    let m = Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                    let s = (m + m.transpose()) * 0.5;
                    s - Matrix3::identity() * (s.trace() / 3.0)
                })
                .collect()
        });
        Configuration {
            box_lengths,
            positions,
            charges,
            dipoles,
            quadrupoles,
        }
    }

    pub(crate) fn sources(&self) -> Sources<'_> {
        Sources {
            positions: &self.positions,
            charges: self.charges.as_deref(),
            dipoles: self.dipoles.as_deref(),
            quadrupoles: self.quadrupoles.as_deref(),
        }
    }

    pub(crate) fn mesh(&self, parameters: MeshParameters, surface: Surface) -> SiteResponse {
        let mut sum =
            MeshEwald::new(self.positions.len(), self.box_lengths, parameters, surface).unwrap();
        let mut out = SiteResponse::zeros(self.positions.len());
        sum.evaluate(&self.sources(), &mut out).unwrap();
        out
    }

    /// The direct Ewald sum converged to round-off (`s = 7` in both
    /// spaces), as energy and fields (dipoles and quadrupoles only).
    pub(crate) fn direct(&self, surface: Surface) -> (f64, Vec<Vector3<f64>>, Vec<Matrix3<f64>>) {
        let n = self.positions.len();
        let parameters = EwaldParameters::converged(1.2);
        let sum = EwaldSum::with_parameters(&self.positions, self.box_lengths, parameters, surface)
            .unwrap();
        let multipoles = SpaceMultipoles {
            dipoles: (0..n)
                .map(|i| {
                    let mu = self.dipoles.as_ref().map_or(Vector3::zeros(), |m| m[i]);
                    Lanes([mu.x, mu.y, mu.z, 0.0])
                })
                .collect(),
            quadrupoles: (0..n)
                .map(|i| self.quadrupoles.as_ref().map_or(Matrix3::zeros(), |t| t[i]))
                .collect(),
        };
        let fields = sum.fields::<DipolesAndQuadrupoles>(&multipoles);
        let e: Vec<Vector3<f64>> = fields
            .field
            .iter()
            .map(|f| Vector3::new(f[0], f[1], f[2]))
            .collect();
        let energy = 0.5
            * (0..n)
                .map(|i| {
                    -multipoles.dipoles[i][..3]
                        .iter()
                        .zip(e[i].iter())
                        .map(|(m, e)| m * e)
                        .sum::<f64>()
                        + multipoles.quadrupoles[i].dot(&fields.quadrupole_conjugate[i])
                })
                .sum::<f64>();
        (energy, e, fields.quadrupole_conjugate)
    }
}

/// Root mean square of the differences over root mean square of the reference.
pub(super) fn relative_rms(a: &[f64], b: &[f64]) -> f64 {
    let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let norm: f64 = b.iter().map(|y| y * y).sum();
    (diff / norm).sqrt()
}

pub(super) fn flat3(v: &[Vector3<f64>]) -> Vec<f64> {
    v.iter()
        .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
        .collect()
}

pub(super) fn flat33(v: &[Matrix3<f64>]) -> Vec<f64> {
    v.iter()
        .flat_map(|x| x.iter().copied().collect::<Vec<_>>())
        .collect()
}

/// Fine PME parameters for a box of shortest side `l`: `r_c = l / 2`,
/// `alpha = s / r_c`, order 8 and `K_a = 1.8 s alpha L_a` mesh points,
/// which puts the reciprocal-space error below the real-space one (found
/// by refining `K` and `p` against the converged direct sum).
pub(crate) fn fine(box_lengths: &Vector3<f64>, s: f64) -> MeshParameters {
    let rc = 0.5 * box_lengths.min();
    let alpha = s / rc;
    MeshParameters {
        alpha,
        real_cutoff: rc,
        grid: std::array::from_fn(|a| (1.8 * s * alpha * box_lengths[a]).ceil() as usize),
        order: 8,
    }
}

/// Tolerance of the fine parameters at `s = 4.5` against the converged
/// sums (relative RMS of fields and forces, relative energy): the
/// real-space truncation leaves ~3e-8 (measured), 30 times below.
pub(super) const FINE: f64 = 1e-6;
