//! Integrators of the rotational equations of motion.
//!
//! Every integrator implements [`Integrator`]: it is set up once from the
//! initial orientations and body angular velocities (validated by
//! `setup_checks::validate_setup`, allocating all its scratch buffers then),
//! and then advanced one step at a time without allocating. The trait is
//! object safe (the potential arrives as `&dyn Potential`, one virtual call
//! per evaluation); the per-rotor loops inside each step are monomorphised.
//! [`IntegratorSpec`] (an enum of the option structs) builds any of them
//! without a thermostat: the one dispatch from a choice of integrator to a
//! running one ([`crate::dynamics`] adds the thermostat).
//!
//! * Baselines (the methods MD codes use today): [`NoSquish`], [`Dlm`] and
//!   [`Richardson`], one [`Kicked`] integrator each over its [`Splitting`]
//!   (`kick`: per-rotor state, kick, checkpoint and every method of the
//!   trait), with the free-rotation flows of [`free_rotation`]; NO_SQUISH
//!   and DLM offer their step to a thermostat ([`KickStep`], the
//!   [`crate::thermostat_hook::SplitDynamics`] of the hook).
//! * The note's Gear schemes: [`GearA`] (`scheme_a`) and [`GearB`]
//!   (`scheme_b`; scheme A also with the extended equations of a
//!   [`crate::thermostat_hook::ChainEquations`]), built on the Nordsieck machinery of [`gear`], the Euler
//!   equations and eq 12 of [`rigid_body`] and the start-up of [`startup`].
//! * Shared pieces (internal): `setup_checks` (argument validation, all five),
//!   `torque` (torques into a reused buffer, body-frame components),
//!   `checkpoint` (flat layouts) and `rotor_chunks` (per-rotor passes over
//!   fixed chunks of rotors across the rayon pool, all five).

pub(crate) mod checkpoint;
mod dlm;
pub mod free_rotation;
pub mod gear;
mod integrator;
mod kick;
mod no_squish;
mod richardson;
pub mod rigid_body;
mod rotor_chunks;
pub mod scheme_a;
pub mod scheme_b;
pub(crate) mod setup_checks;
mod spec;
pub mod startup;
pub(crate) mod torque;

pub use dlm::{Dlm, DlmOptions};
pub use free_rotation::SphericalTops;
pub use integrator::{GoOn, Integrator, IntegratorError, RotorState};
pub use kick::{rotate_all, KickStep, Kicked, Splitting, ROTATED_TOGETHER};
pub use no_squish::{NoSquish, NoSquishOptions, MAX_SUBSTEPS};
pub use richardson::{Richardson, RichardsonOptions};
pub use scheme_a::{GearA, GearAOptions};
pub use scheme_b::{FirstCorrector, GearB, GearBOptions};
pub use spec::{IntegratorOptions, IntegratorSpec};
pub use startup::Startup;
