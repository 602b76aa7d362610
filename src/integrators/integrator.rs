//! The integrator interface: the state of one rotor, the errors of set-up
//! and restore, and the [`Integrator`] trait every scheme implements.

use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use crate::thermostat_hook::BadCheckpoint;
use nalgebra::Vector3;

/// Orientation and body-fixed angular velocity of one rotor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorState {
    /// Unit quaternion (conventions in [`crate::quaternion`]).
    pub orientation: Quat,
    /// Angular velocity, body-fixed components.
    pub omega_body: Vector3<f64>,
}

/// Why an integrator could not be set up or stepped.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum IntegratorError {
    /// The integrator cannot handle this rotor (for example a zero moment).
    #[error("rotor {rotor}: {reason}")]
    Unsupported {
        /// The first offending rotor.
        rotor: usize,
        /// What is wrong with it, with the value found.
        reason: String,
    },
    /// A checkpoint does not match this integrator and system.
    #[error("checkpoint: {0}")]
    BadCheckpoint(String),
    /// The time step is not finite and positive.
    #[error("dt: must be finite and > 0, got {0}")]
    BadTimeStep(f64),
}

/// A thermostat's part of a checkpoint that does not fit.
impl From<BadCheckpoint> for IntegratorError {
    fn from(e: BadCheckpoint) -> Self {
        IntegratorError::BadCheckpoint(e.0)
    }
}

/// Asked by [`Integrator::steps`] with the steps taken whether to take the
/// next one.
pub type GoOn<'a> = &'a mut dyn FnMut(u64) -> bool;

/// A time-stepping scheme for rigid rotors (object safe: runs hold a
/// `Box<dyn Integrator>` from [`crate::dynamics::build`]).
pub trait Integrator: Send {
    /// A short stable name (as used in scene files), e.g. `"gear_a"`.
    fn name(&self) -> &'static str;

    /// Initialises the internal state at t = 0 from `initial` (one entry per
    /// rotor) for steps of `dt`. May evaluate the potential (start-up).
    fn setup(
        &mut self,
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError>;

    /// Advances all rotors by one time step.
    fn step(&mut self, potential: &dyn Potential);

    /// Takes up to `count` steps (at least one), with the same results as
    /// as many calls of [`Integrator::step`]; before the end of each step
    /// but the last it asks `go_on(taken)` (`taken` counting that step)
    /// whether to take the next one. Returns the steps taken. The Gear
    /// schemes override it to predict the next step in the pass that
    /// corrects the current one (one parallel pass per step fewer).
    fn steps(&mut self, potential: &dyn Potential, count: u64, go_on: GoOn<'_>) -> u64 {
        let mut taken = 0;
        loop {
            self.step(potential);
            taken += 1;
            if taken >= count || !go_on(taken) {
                return taken;
            }
        }
    }

    /// The time step it was set up with: the one `dt` of a run (the run
    /// loop's times and the trajectory's header read it here).
    fn dt(&self) -> f64;

    /// The current orientations (not necessarily exactly unit, depending on
    /// the scheme's switches).
    fn orientations(&self) -> &[Quat];

    /// Writes the current body-fixed angular velocities (eq 10 for schemes
    /// that store `Q'` instead).
    fn omega_body(&self, out: &mut [Vector3<f64>]);

    /// The complete internal state (everything `step` reads), flattened, for
    /// checkpoints: `restore` of it after `setup` with the same rotors and
    /// `dt` must make the following steps bit-for-bit identical.
    fn checkpoint(&self) -> Vec<f64>;

    /// Restores a state written by [`Integrator::checkpoint`], after `setup`
    /// with the same rotors and `dt`. Only the layout is checked here: a
    /// restart compares `dt` once, with the identity of the checkpoint file.
    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError>;

    /// Writes `Q'` for each rotor. The default uses eq 10 with the body
    /// angular velocity; schemes that store `Q'` override it.
    fn q_dot(&self, out: &mut [Quat]) {
        let mut omega = vec![Vector3::zeros(); out.len()];
        self.omega_body(&mut omega);
        for ((q_dot, q), w) in out.iter_mut().zip(self.orientations()).zip(&omega) {
            *q_dot = q.q_dot_from_omega_body(w);
        }
    }

    /// The thermostat's share of the conserved energy: the energy of the
    /// Nose-Hoover chain, or minus the heat a stochastic thermostat has put
    /// into the rotors; 0 without a thermostat (the conserved energy is then
    /// the total energy).
    fn thermostat_energy(&self) -> f64 {
        0.0
    }

    /// Writes `Q.N` per rotor ([`crate::observables::norm_force`], the
    /// zeroth component of eq 15b up to a factor 1/2) for schemes that store
    /// the quaternion force `N`, and returns true; schemes working with body
    /// torques satisfy eq 15b by construction and return false.
    fn norm_force(&self, _out: &mut [f64]) -> bool {
        false
    }
}
