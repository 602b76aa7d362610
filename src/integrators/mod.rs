//! Integrators of the rotational equations of motion.
//!
//! Every integrator implements [`Integrator`]: it is set up once from the
//! initial orientations and body angular velocities (validated by
//! [`setup::validate_setup`], allocating all its scratch buffers then), and
//! then advanced one step at a time without allocating. It is generic over
//! the [`Potential`] so that the step is monomorphised.
//!
//! * Baselines (the methods MD codes use today): [`NoSquish`], [`Dlm`] and
//!   [`Richardson`], sharing their per-rotor state, kick and checkpoint
//!   (`kick`) and the free-rotation flows of [`free_rotation`].
//! * The note's Gear schemes: [`GearA`] (`scheme_a`) and [`GearB`]
//!   (`scheme_b`), built on the Nordsieck machinery of [`gear`], the Euler
//!   equations of [`rigid_body`] and the start-up of [`startup`].
//! * Shared pieces: [`setup`] (argument validation, all five), `torque` (torques into
//!   a reused buffer, body-frame components), [`checkpoint`] (flat layouts)
//!   and `rotor_chunks` (per-rotor passes over fixed chunks of rotors across
//!   the rayon pool, all five).

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
pub mod setup;
pub mod startup;
mod torque;

pub use dlm::Dlm;
pub use free_rotation::SphericalTops;
pub use no_squish::NoSquish;
pub use richardson::Richardson;
pub use scheme_a::{GearA, GearAOptions};
pub use scheme_b::{FirstCorrector, GearB, GearBOptions};
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
    Unsupported { rotor: usize, reason: String },
    /// A checkpoint does not match this integrator and system.
    #[error("checkpoint: {0}")]
    BadCheckpoint(String),
    /// The time step is not finite and positive.
    #[error("dt: must be finite and > 0, got {0}")]
    BadTimeStep(f64),
}

/// A time-stepping scheme for rigid rotors.
pub trait Integrator {
    /// A short stable name (as used in scene files), e.g. `"gear_a"`.
    fn name(&self) -> &'static str;

    /// Initialises the internal state at t = 0 from `initial` (one entry per
    /// rotor) for steps of `dt`. May evaluate the potential (start-up).
    fn setup<P: Potential>(
        &mut self,
        inertia: &[Inertia],
        potential: &P,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError>;

    /// Advances all rotors by one time step.
    fn step<P: Potential>(&mut self, potential: &P);

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

    /// Writes `Q.N` per rotor (the zeroth component of eq 15b, up to a factor
    /// 1/2) for schemes that store the quaternion force `N`, and returns true;
    /// schemes working with body torques satisfy it by construction and
    /// return false.
    fn q_dot_n(&self, _out: &mut [f64]) -> bool {
        false
    }
}
