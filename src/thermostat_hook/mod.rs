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
//! centre's momentum to the step: [`SplitDynamics`] then gains, beside the
//! rotational pieces, the translational half kick (forces) and drift, and
//! its kinetic energy and updates come per kind of degree of freedom (a
//! `Translational` and a `Rotational` view of the same state, each with its
//! own scaling and per-body update). [`CoupledDegrees`] counts each kind on
//! its own (`3N - 3` translational when the total momentum is conserved, the
//! rotational count as now), so a thermostat thermostats each kind with its
//! own count and reports `T_trans` and `T_rot` apart; the thermostats keep
//! acting between the same pieces, and no thermostat learns which integrator
//! it runs in.

mod chain;
mod degrees;
mod dynamics;
mod thermostat;

pub use chain::ChainEquations;
pub use degrees::{CoupledDegrees, Spin};
pub use dynamics::SplitDynamics;
pub use thermostat::{BadCheckpoint, Nve, Thermostat, ThermostatState};
