//! The integrators of body systems, each moving the centres and the
//! orientations with one force-and-torque evaluation per step.
//!
//! * [`no_squish`]: velocity Verlet + NO_SQUISH.

pub mod no_squish;

pub use no_squish::BodyNoSquish;
