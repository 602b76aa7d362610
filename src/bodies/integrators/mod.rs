//! The integrators of body systems, each moving the centres and the
//! orientations with one force-and-torque evaluation per step.
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
