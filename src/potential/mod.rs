//! Potential energy of a set of rotors as a function of their orientations.
//!
//! Every term provides the energy, the unconstrained quaternion gradient of
//! eq 14 (`N = -dV/dQ`, computed analytically through `dA/dq_k`), and the
//! space-fixed torques. Eq 13 relates the two: after the projection of the
//! note, `-dV/dQ + (Q.dV/dQ) Q = 2 N_s*Q` with `N_s = (0, torque_space)`.

use crate::quaternion::Quat;
use nalgebra::Vector3;

pub mod multipole;

pub use multipole::{
    Boundary, ExternalFields, MultipolePotential, PeriodicSum, PotentialError, SumMethod, SumPath,
    Surface,
};

/// A potential energy term (or a sum of terms). Implementors are plain data
/// shared by all threads; the integrators are generic over it so the hot
/// loop is monomorphised.
pub trait Potential: Sync {
    /// The potential energy `V(Q_1, ..., Q_n)`.
    fn energy(&self, orientations: &[Quat]) -> f64;

    /// Adds `dV/dq_k` (eq 14, unconstrained: the four components are treated
    /// as independent) into `gradient`, one quaternion per rotor.
    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]);

    /// Adds the space-fixed torque on each rotor into `torques_space`.
    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]);

    /// The energy, and `dV/dq_k` added into `gradient`, in one pass where the
    /// implementor can share the work (the default calls the two methods).
    fn energy_and_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) -> f64 {
        self.accumulate_gradient(orientations, gradient);
        self.energy(orientations)
    }
}

/// No interactions at all: free rotors.
#[derive(Clone, Copy, Debug, Default)]
pub struct Free;

impl Potential for Free {
    fn energy(&self, _: &[Quat]) -> f64 {
        0.0
    }
    fn accumulate_gradient(&self, _: &[Quat], _: &mut [Quat]) {}
    fn accumulate_torques(&self, _: &[Quat], _: &mut [Vector3<f64>]) {}
}
