//! What observers see. The run loop decides when an observer samples (it
//! owns the intervals) and computes, at that step only, what the observers
//! due then need.

use super::energy::EnergyReference;
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
    /// `Q.N` per rotor ([`crate::integrators::Integrator::norm_force`];
    /// schemes that store `N`).
    pub norm_force: bool,
}

impl Needs {
    /// The union of two sets of needs.
    pub fn union(self, other: Needs) -> Needs {
        Needs {
            energies: self.energies || other.energies,
            omega_body: self.omega_body || other.omega_body,
            q_dot: self.q_dot || other.q_dot,
            norm_force: self.norm_force || other.norm_force,
        }
    }
}

/// Energies at a sampled step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Energies {
    /// `K = 1/2 sum w_b . I w_b`.
    pub kinetic: f64,
    /// `V`, the potential's value.
    pub potential: f64,
    /// `K + V`.
    pub total: f64,
    /// The conserved energy: `K + V` plus the thermostat's share
    /// ([`crate::integrators::Integrator::thermostat_energy`]; `K + V`
    /// without a thermostat).
    pub conserved: f64,
    /// `(C - C_0) / s` of the conserved energy `C` (see [`EnergyReference`]).
    pub error: f64,
}

/// The state at a sampled step; the optional parts are present when some
/// observer due at this step declared them in its [`Needs`].
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// The step.
    pub step: u64,
    /// `step * dt`.
    pub time: f64,
    /// The moments of inertia.
    pub inertia: &'a [Inertia],
    /// The orientations.
    pub orientations: &'a [Quat],
    /// Body angular velocities.
    pub omega_body: Option<&'a [Vector3<f64>]>,
    /// `Q'` per rotor.
    pub q_dot: Option<&'a [Quat]>,
    /// `Q.N` per rotor.
    pub norm_force: Option<&'a [f64]>,
    /// The energies.
    pub energies: Option<Energies>,
}

/// Something that records samples: a CSV table, a trajectory, a progress
/// bar, an experiment's statistics. `Error` is what recording can fail with
/// (the run layer's file errors; [`std::convert::Infallible`] in memory).
pub trait Observer {
    /// What recording can fail with.
    type Error;
    /// What `observe` reads from the sample.
    fn needs(&self) -> Needs;
    /// Records one sample.
    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), Self::Error>;
    /// Passes what was recorded so far to its files, whole samples only;
    /// called before every checkpoint, so that the files hold at least what
    /// the checkpoint does.
    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
    /// Flushes and closes; called once, also after a blow-up or an interrupt.
    fn finish(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// An observer and when it samples: at every multiple of `every` (step 0
/// included), and at the last step too when `at_end`.
pub struct Scheduled<'a, E> {
    /// The sampling interval in steps (>= 1).
    pub every: u64,
    /// Also sample the last step of the run.
    pub at_end: bool,
    /// The observer.
    pub observer: &'a mut dyn Observer<Error = E>,
}

/// Where checkpoints go: the integrator's state at a step, and the energy
/// reference of the run.
pub trait CheckpointSink {
    /// What writing can fail with.
    type Error;
    /// Stores the state at `step`.
    fn write(
        &mut self,
        step: u64,
        state: &[f64],
        reference: Option<EnergyReference>,
    ) -> Result<(), Self::Error>;
}

/// A checkpoint sink and its interval in steps (never at the first step of
/// the run).
pub struct Checkpoints<'a, E> {
    /// The interval in steps (>= 1).
    pub every: u64,
    /// The sink.
    pub sink: &'a mut dyn CheckpointSink<Error = E>,
}
