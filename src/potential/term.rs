//! The potential-energy trait: energy, the unconstrained quaternion gradient
//! of eq 14 and the space-fixed torques.

use super::TorqueAxes;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// A potential energy term (or a sum of terms). Implementors are plain data
/// shared by all threads. Integrators take it as `&dyn Potential`: one
/// virtual call per evaluation, the loops inside each implementation
/// monomorphised.
pub trait Potential: Sync {
    /// The potential energy `V(Q_1, ..., Q_n)`.
    fn energy(&self, orientations: &[Quat]) -> f64;

    /// Adds `dV/dq_k` (eq 14, unconstrained: the four components are treated
    /// as independent) into `gradient`, one quaternion per rotor.
    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]);

    /// Adds the space-fixed torque on each rotor into `torques_space`.
    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]);

    /// The directions of the torques on rotor `rotor`, whatever the
    /// orientations ([`TorqueAxes`]; the default knows nothing: any).
    fn torque_axes(&self, _rotor: usize) -> TorqueAxes {
        TorqueAxes::Any
    }

    /// The energy, and `dV/dq_k` added into `gradient`, in one pass where the
    /// implementor can share the work (the default calls the two methods).
    fn energy_and_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) -> f64 {
        self.accumulate_gradient(orientations, gradient);
        self.energy(orientations)
    }
}
