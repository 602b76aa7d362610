//! The hook between the integrators and the thermostats: what a thermostat
//! sees of an integrator's step, and what an integrator asks of a
//! thermostat. Both [`crate::integrators`] and [`crate::thermostats`] use
//! this module; neither uses the other, and [`crate::dynamics`] pairs them.
//!
//! * [`SplitDynamics`]: the pieces of a kick-based step a thermostat acts
//!   between (the half kick, the free flow over any duration, the torques)
//!   and the state it sees through the body angular velocities (kinetic
//!   energy, scaling, per-rotor updates), implemented by the integrators.
//! * [`Thermostat`]: the operators a thermostat puts around or inside that
//!   step, and its [`ThermostatState`] (its share of the conserved energy and
//!   its checkpoint), implemented by the thermostats; [`Nve`] is none.
//! * [`ChainEquations`]: a thermostat whose variables are integrated with
//!   the rotors' equations of motion (scheme A's predictor-corrector).
//! * [`CoupledDegrees`]: the degrees of freedom a global thermostat acts on
//!   and counts.
//!
//! Translation (issue 39). A body that moves as well as rotates adds its
//! centre's momentum to the step: the half kick and the free flow of
//! [`SplitDynamics`] move the centres too, and besides the rotational view
//! (body angular velocities) it offers the translational one (the centres'
//! velocities and masses; empty for rotors on fixed sites). The dynamics
//! owns what it evaluates ([`SplitDynamics::evaluate`]: a rotor potential
//! or a body system), so the thermostats keep acting between the same
//! pieces and none learns which integrator, or which kind of system, it
//! runs in. [`CoupledDegrees`] counts each kind on its own (`3N - 3`
//! translational when the total momentum is kept, the rotational count as
//! for rotors).

mod chain;
mod degrees;
mod dynamics;
mod thermostat;

pub use chain::ChainEquations;
pub use degrees::{CoupledDegrees, Spin};
pub use dynamics::SplitDynamics;
pub use thermostat::{BadCheckpoint, Nve, Thermostat, ThermostatState};
