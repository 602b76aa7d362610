//! What an integrator asks of a thermostat.

use super::{CoupledDegrees, SplitDynamics};
use nalgebra::Vector3;
use std::fmt::Debug;

/// A thermostat's checkpoint that does not fit it (the integrators report it
/// as their own bad checkpoint).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct BadCheckpoint(pub String);

/// How a kick-based step is arranged: no thermostat ([`Nve`]) or one of
/// [`crate::thermostats`], each a type of its own so that the step stays
/// monomorphised.
pub trait Thermostat: Clone + Debug + Send + 'static {
    /// What the thermostat records besides the rotors (a trait object for
    /// a thermostat chosen at run time).
    type State: ThermostatState + ?Sized;

    /// Sizes what the thermostat keeps per rotor or body (principal
    /// moments `moments`, zero moments allowed; the degrees of freedom
    /// `degrees`, with the centres' masses of bodies that move) for steps
    /// of `dt`, and resets its state.
    fn setup(&mut self, moments: &[Vector3<f64>], degrees: &CoupledDegrees, dt: f64);

    /// One whole step of `dynamics.dt()`.
    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D);

    /// Its state.
    fn state(&self) -> &Self::State;

    /// Its state, mutable (for restores).
    fn state_mut(&mut self) -> &mut Self::State;
}

/// A thermostat's share of the conserved energy and its checkpoint.
pub trait ThermostatState {
    /// The thermostat's share of the conserved energy
    /// ([`crate::integrators::Integrator::thermostat_energy`]).
    fn energy(&self) -> f64;

    /// The number of values [`ThermostatState::write_checkpoint`] appends.
    fn checkpoint_len(&self) -> usize;

    /// Appends the thermostat's state.
    fn write_checkpoint(&self, out: &mut Vec<f64>);

    /// Reads back the thermostat's state (`data` holds exactly
    /// [`ThermostatState::checkpoint_len`] values).
    fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), BadCheckpoint>;
}

/// No thermostat: the plain step, at constant energy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Nve;

impl Thermostat for Nve {
    type State = Nve;

    fn setup(&mut self, _: &[Vector3<f64>], _: &CoupledDegrees, _: f64) {}

    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D) {
        dynamics.kick_flow_kick();
    }

    fn state(&self) -> &Nve {
        self
    }

    fn state_mut(&mut self) -> &mut Nve {
        self
    }
}

/// Nothing recorded: no energy, an empty checkpoint.
impl ThermostatState for Nve {
    fn energy(&self) -> f64 {
        0.0
    }

    fn checkpoint_len(&self) -> usize {
        0
    }

    fn write_checkpoint(&self, _: &mut Vec<f64>) {}

    fn read_checkpoint(&mut self, _: &[f64]) -> Result<(), BadCheckpoint> {
        Ok(())
    }
}
