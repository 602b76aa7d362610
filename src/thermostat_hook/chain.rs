//! A thermostat integrated as extended equations of motion.

use super::ThermostatState;
use std::fmt::Debug;

/// A thermostat whose variables (positions `eta_j`, momenta `p_j`) obey
/// first-order equations integrated beside the rotors' (scheme A's
/// predictor-corrector and start-up): a friction `p_1/Q_1` on the coupled
/// body angular velocities, and its own rates, which depend on the rotors'
/// thermostatted kinetic energy.
/// Its share of the conserved energy is its [`ThermostatState::energy`].
pub trait ChainEquations: ThermostatState + Debug + Send + Sync {
    /// Resets the chain to rest for `dof` thermostatted degrees of freedom.
    fn reset(&mut self, dof: usize);

    /// The number of thermostats (>= 1).
    fn len(&self) -> usize;

    /// Never true (a chain has at least one thermostat).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The current positions `eta_j`.
    fn positions(&self) -> &[f64];

    /// The current momenta `p_j`.
    fn momenta(&self) -> &[f64];

    /// The friction on the angular velocities at the chain momenta `momenta`.
    fn friction(&self, momenta: &[f64]) -> f64;

    /// Advances the chain's own equations over `h`, the rotors'
    /// thermostatted kinetic energy being `kinetic_start` at the start and
    /// `kinetic_end` at the end, by exact exponential factors for the
    /// couplings `p_j p_{j+1} / Q_{j+1}` (stable however large they grow,
    /// as they do when a start far from equilibrium releases heat); the
    /// rotors' friction is the caller's.
    fn advance(&mut self, kinetic_start: f64, kinetic_end: f64, h: f64);

    /// The time derivatives at the chain momenta `momenta` and the rotors'
    /// thermostatted kinetic energy `kinetic`: `eta_j'` into `positions_dot`,
    /// `p_j'` into `momenta_dot`.
    fn rates(
        &self,
        momenta: &[f64],
        kinetic: f64,
        positions_dot: &mut [f64],
        momenta_dot: &mut [f64],
    );

    /// A copy.
    fn boxed_clone(&self) -> Box<dyn ChainEquations>;
}

impl Clone for Box<dyn ChainEquations> {
    fn clone(&self) -> Self {
        self.boxed_clone()
    }
}
