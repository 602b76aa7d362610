//! The integrators of body systems, each moving the centres and the
//! orientations with one force-and-torque evaluation per step, and the one
//! choice among them ([`BodyIntegrator`]) a scene's `[integrator]` makes.
//!
//! * [`kicked`]: velocity Verlet for the centres around a rotor
//!   [`crate::integrators::Splitting`]'s kick and rotation, per body:
//!   [`no_squish`] (NO_SQUISH), [`dlm`] (DLM), [`richardson`] (Richardson).
//! * The note's Gear schemes with Gear correctors of the same order for the
//!   centres: [`gear_a`] (scheme A), [`gear_b`] (scheme B), started by
//!   `gear_start`.

pub mod dlm;
pub mod gear_a;
pub mod gear_b;
mod gear_start;
pub mod kicked;
pub mod no_squish;
pub mod richardson;

pub use dlm::BodyDlm;
pub use gear_a::BodyGearA;
pub use gear_b::BodyGearB;
pub use kicked::BodyKicked;
pub use no_squish::BodyNoSquish;
pub use richardson::BodyRichardson;

use crate::bodies::evaluate::Evaluation;
use crate::bodies::system::BodySystem;
use crate::checks::InputError;
use crate::integrators::IntegratorSpec;

/// The integrator of a body system: one variant per algorithm.
#[derive(Clone, Debug)]
pub enum BodyIntegrator {
    /// Velocity Verlet + NO_SQUISH.
    NoSquish(BodyNoSquish),
}

impl BodyIntegrator {
    /// Whether bodies can be integrated by `spec`; the error (path `kind`)
    /// names the integrators that can.
    pub fn check(spec: &IntegratorSpec) -> Result<(), InputError> {
        match spec {
            IntegratorSpec::NoSquish(_) => Ok(()),
            other => Err(refused(other)),
        }
    }

    /// The integrator `spec` names, set up on `system` with time step `dt`
    /// (one evaluation).
    pub fn new(
        spec: &IntegratorSpec,
        system: &mut BodySystem,
        dt: f64,
    ) -> Result<Self, InputError> {
        match spec {
            IntegratorSpec::NoSquish(options) => {
                BodyNoSquish::new(system, dt, *options).map(BodyIntegrator::NoSquish)
            }
            other => Err(refused(other)),
        }
    }

    /// One step.
    pub fn step(&mut self, system: &mut BodySystem) {
        match self {
            BodyIntegrator::NoSquish(i) => i.step(system),
        }
    }

    /// The evaluation at the current state.
    pub fn evaluation(&self) -> &Evaluation {
        match self {
            BodyIntegrator::NoSquish(i) => i.evaluation(),
        }
    }
}

/// The error of an integrator that cannot move bodies.
fn refused(spec: &IntegratorSpec) -> InputError {
    InputError::new(
        "kind",
        format!(
            "bodies are integrated by no_squish only so far, got {}",
            spec.name()
        ),
    )
}
