//! What observers see. The runner decides when an observer samples (it owns
//! the intervals) and computes, at that step only, what the observers due
//! then need.

use super::error::RunError;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// What an observer needs beyond the step, the time and the orientations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Needs {
    /// Kinetic, potential and total energy (one potential evaluation).
    pub energies: bool,
    /// Body angular velocities.
    pub omega_body: bool,
    /// `Q'` per rotor.
    pub q_dot: bool,
    /// `Q.N` per rotor (schemes that store `N`).
    pub q_dot_n: bool,
}

impl Needs {
    /// The union of two sets of needs.
    pub fn union(self, other: Needs) -> Needs {
        Needs {
            energies: self.energies || other.energies,
            omega_body: self.omega_body || other.omega_body,
            q_dot: self.q_dot || other.q_dot,
            q_dot_n: self.q_dot_n || other.q_dot_n,
        }
    }
}

/// Energies at a sampled step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Energies {
    pub kinetic: f64,
    pub potential: f64,
    pub total: f64,
    /// `(E - E_0) / s` (see [`super::EnergyReference`]).
    pub error: f64,
}

/// The state at a sampled step; the optional parts are present when some
/// observer due at this step declared them in its [`Needs`].
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    pub step: u64,
    /// `step * dt`.
    pub time: f64,
    pub inertia: &'a [Inertia],
    pub orientations: &'a [Quat],
    pub omega_body: Option<&'a [Vector3<f64>]>,
    pub q_dot: Option<&'a [Quat]>,
    pub q_dot_n: Option<&'a [f64]>,
    pub energies: Option<Energies>,
}

/// Something that records samples: a CSV table, a trajectory, a progress bar.
pub trait Observer {
    /// What `observe` reads from the sample.
    fn needs(&self) -> Needs;
    /// Records one sample.
    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError>;
    /// Flushes and closes; called once, also after a blow-up.
    fn finish(&mut self) -> Result<(), RunError>;
}

/// An observer and its sampling interval in steps (it samples at every
/// multiple of `every`, step 0 included).
pub struct Scheduled<'a> {
    pub every: u64,
    pub observer: &'a mut dyn Observer,
}
