//! The integrators of body systems, each moving the centres and the
//! orientations with one force-and-torque evaluation per step.
//!
//! * [`kicked`]: velocity Verlet for the centres around a rotor
//!   [`crate::integrators::Splitting`]'s kick and rotation, per body:
//!   [`no_squish`] (NO_SQUISH), [`dlm`] (DLM), [`richardson`] (Richardson).

pub mod dlm;
pub mod kicked;
pub mod no_squish;
pub mod richardson;

pub use dlm::BodyDlm;
pub use kicked::BodyKicked;
pub use no_squish::BodyNoSquish;
pub use richardson::BodyRichardson;
