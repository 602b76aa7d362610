//! Integrators of the rotational equations of motion.
//!
//! Every integrator implements [`Integrator`]: it is set up once from the
//! initial orientations and body angular velocities (allocating all its
//! scratch buffers then), and then advanced one step at a time. It is generic
//! over the [`Potential`] so that the step is monomorphised.

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
}
