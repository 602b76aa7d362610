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
//! * [`Bussi`] (`bussi`): stochastic rescaling of the kinetic energy;
//! * [`NoseHoover`] (`nose_hoover`): Nose-Hoover chains, a reversible
//!   splitting; scheme A integrates the same chain ([`NoseHooverChain`], a
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
