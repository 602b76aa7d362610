//! Thermostats on the rotational degrees of freedom: canonical sampling at a
//! temperature `T` (reduced units, `k_B = 1`) of `exp(-(K + V)/T)` over the
//! orientations (uniform measure on rotations) and the body angular momenta.
//!
//! Each thermostat is a type of its own that arranges the step of a
//! kick-based baseline ([`crate::integrators::KickThermostat`]), so NO_SQUISH
//! and DLM run with it monomorphised:
//!
//! * [`Langevin`] (`langevin`): friction and noise per principal axis, BAOAB
//!   with the exact Ornstein-Uhlenbeck step;
//! * [`Bussi`] (`bussi`): stochastic rescaling of the kinetic energy;
//! * [`NoseHoover`] (`nose_hoover`): Nose-Hoover chains, a reversible
//!   splitting; scheme A integrates the same chain ([`NoseHooverChain`]) with
//!   its predictor-corrector.
//!
//! Bussi and Nose-Hoover act on the degrees of freedom of [`CoupledDegrees`]:
//! a spin the dynamics conserves is left out.
//!
//! Each records the thermostat's share of a conserved energy
//! ([`crate::integrators::Integrator::thermostat_energy`]): the chain's energy,
//! or minus the heat the stochastic ones put into the rotors. [`ThermostatSpec`]
//! (the scene's `[thermostat]` table) chooses one;
//! [`crate::integrators::IntegratorSpec::build`] builds an integrator with it,
//! or refuses the pair naming `thermostat.kind`. [`noise`] holds the seeded,
//! checkpointed random numbers.

mod bussi;
mod coupled;
mod langevin;
pub mod noise;
mod nose_hoover;
mod spec;

pub use bussi::{Bussi, BussiOptions};
pub use coupled::{CoupledDegrees, Spin};
pub use langevin::{Langevin, LangevinOptions};
pub use nose_hoover::{NoseHoover, NoseHooverChain, NoseHooverOptions, MAX_CHAIN};
pub use spec::{build_kicked, ThermostatSpec};
