//! Thermostats on the rotational degrees of freedom: canonical sampling at a
//! temperature `T` (reduced units, `k_B = 1`) of `exp(-(K + V)/T)` over the
//! orientations (uniform measure on rotations) and the body angular momenta.
//!
//! Each thermostat is a type of its own that arranges a kick-based step
//! ([`crate::thermostat_hook::Thermostat`], acting between the pieces of a
//! [`crate::thermostat_hook::SplitDynamics`]), so NO_SQUISH and DLM run with
//! it monomorphised; none of them knows the integrators:
//!
//! * [`Langevin`] (`langevin`): friction and noise per principal axis, BAOAB
//!   with the exact Ornstein-Uhlenbeck step;
//! * [`Bussi`] (`bussi`): stochastic rescaling of the kinetic energy, in
//!   the middle of the step as Langevin's O step (orientations exact for a
//!   harmonic libration at any `dt`; the full-step momenta read low by
//!   `(w0 dt / 2)^2`, as Langevin's);
//! * [`NoseHoover`] (`nose_hoover`): Nose-Hoover chains, a reversible
//!   splitting with the chain in the middle of the step; scheme A integrates the same chain ([`NoseHooverChain`], a
//!   [`crate::thermostat_hook::ChainEquations`]): the friction with its
//!   predictor-corrector, the chain by a composition of the same splitting.
//!
//! Bussi and Nose-Hoover act on the degrees of freedom of
//! [`crate::thermostat_hook::CoupledDegrees`]: a spin the dynamics conserves
//! is left out.
//!
//! Each records the thermostat's share of a conserved energy
//! ([`crate::thermostat_hook::ThermostatState`]): the chain's energy, or
//! minus the heat the stochastic ones put into the rotors ([`HeatNoise`],
//! their one record). [`ThermostatSpec`] (the scene's `[thermostat]` table)
//! chooses one; [`crate::dynamics`] pairs it with an integrator, or refuses
//! the pair naming `thermostat.kind`. The seeded, checkpointed random
//! numbers are internal (`noise`).

mod bussi;
mod langevin;
pub(crate) mod noise;
mod nose_hoover;
mod spec;

pub use bussi::{Bussi, BussiOptions};
pub use langevin::{Langevin, LangevinOptions};
pub use noise::HeatNoise;
pub use nose_hoover::{
    NoseHoover, NoseHooverChain, NoseHooverChains, NoseHooverOptions, MAX_CHAIN,
};
pub use spec::ThermostatSpec;
