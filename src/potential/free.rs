//! The potential of free rotors.

use super::{Potential, TorqueAxes};
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// No interactions at all: free rotors.
#[derive(Clone, Copy, Debug, Default)]
pub struct Free;

impl Potential for Free {
    fn energy(&self, _: &[Quat]) -> f64 {
        0.0
    }
    fn accumulate_gradient(&self, _: &[Quat], _: &mut [Quat]) {}
    fn accumulate_torques(&self, _: &[Quat], _: &mut [Vector3<f64>]) {}
    fn torque_axes(&self, _: usize) -> TorqueAxes {
        TorqueAxes::Never
    }
}
