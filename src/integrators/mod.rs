//! Integrators of the rotational equations of motion.
//!
//! Every integrator implements [`Integrator`]: it is set up once from the
//! initial orientations and body angular velocities (validated by
//! [`setup_checks::validate_setup`], allocating all its scratch buffers then),
//! and then advanced one step at a time without allocating. The trait is
//! object safe (the potential arrives as `&dyn Potential`, one virtual call
//! per evaluation); the per-rotor loops inside each step are monomorphised.
//! [`IntegratorSpec`] (an enum of the option structs) builds any of them:
//! the one dispatch from a choice of integrator to a running one.
//!
//! * Baselines (the methods MD codes use today): [`NoSquish`], [`Dlm`] and
//!   [`Richardson`], one [`Kicked`] integrator each over its [`Splitting`]
//!   (`kick`: per-rotor state, kick, checkpoint and every method of the
//!   trait), with the free-rotation flows of [`free_rotation`].
//! * The note's Gear schemes: [`GearA`] (`scheme_a`) and [`GearB`]
//!   (`scheme_b`), built on the Nordsieck machinery of [`gear`], the Euler
//!   equations and eq 12 of [`rigid_body`] and the start-up of [`startup`].
//! * Shared pieces: [`setup_checks`] (argument validation, all five),
//!   `torque` (torques into a reused buffer, body-frame components),
//!   [`checkpoint`] (flat layouts) and `rotor_chunks` (per-rotor passes over
//!   fixed chunks of rotors across the rayon pool, all five).

pub mod checkpoint;
mod dlm;
pub mod free_rotation;
pub mod gear;
mod kick;
mod no_squish;
mod richardson;
pub mod rigid_body;
mod rotor_chunks;
pub mod scheme_a;
pub mod scheme_b;
pub mod setup_checks;
mod spec;
pub mod startup;
mod torque;

pub use dlm::{Dlm, DlmOptions};
pub use free_rotation::SphericalTops;
pub use kick::{Kicked, Splitting};
pub use no_squish::{NoSquish, NoSquishOptions};
pub use richardson::{Richardson, RichardsonOptions};
pub use scheme_a::{GearA, GearAOptions};
pub use scheme_b::{FirstCorrector, GearB, GearBOptions};
pub use spec::{IntegratorOptions, IntegratorSpec};
pub use startup::Startup;

use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
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

/// A time-stepping scheme for rigid rotors (object safe: runs hold a
/// `Box<dyn Integrator>` from [`IntegratorSpec::build`]).
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

    /// Restores a state written by [`Integrator::checkpoint`].
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

    /// Writes `Q.N` per rotor ([`crate::observables::norm_force`], the
    /// zeroth component of eq 15b up to a factor 1/2) for schemes that store
    /// the quaternion force `N`, and returns true; schemes working with body
    /// torques satisfy eq 15b by construction and return false.
    fn norm_force(&self, _out: &mut [f64]) -> bool {
        false
    }
}
