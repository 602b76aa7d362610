//! A potential wrapper that counts torque (gradient) evaluations.

use nalgebra::Vector3;
use quatrot::potential::Potential;
use quatrot::Quat;
use std::sync::atomic::{AtomicU64, Ordering};

/// `P`, counting the calls that compute forces (energies alone are not counted).
pub struct Counting<'a, P> {
    pub inner: &'a P,
    pub evaluations: AtomicU64,
}

impl<'a, P> Counting<'a, P> {
    pub fn new(inner: &'a P) -> Self {
        Counting {
            inner,
            evaluations: AtomicU64::new(0),
        }
    }

    pub fn count(&self) -> u64 {
        self.evaluations.load(Ordering::Relaxed)
    }

    fn tick(&self) {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
    }
}

impl<P: Potential> Potential for Counting<'_, P> {
    fn energy(&self, orientations: &[Quat]) -> f64 {
        self.inner.energy(orientations)
    }

    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) {
        self.tick();
        self.inner.accumulate_gradient(orientations, gradient);
    }

    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]) {
        self.tick();
        self.inner.accumulate_torques(orientations, torques_space);
    }

    fn energy_and_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) -> f64 {
        self.tick();
        self.inner.energy_and_gradient(orientations, gradient)
    }
}
