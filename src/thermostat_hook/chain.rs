//! A thermostat integrated as extended equations of motion.

use super::ThermostatState;
use std::fmt::Debug;

/// The weights of the sixth-order symmetric composition of a second-order
/// symmetric step (Yoshida, Phys. Lett. A 150, 262 (1990), solution A):
/// a chain's step over `h` is its [`ChainEquations::advance`] over `w_k h`
/// in turn (backwards in time for the negative weights), so that its error
/// is of order 6 and a fifth-order Gear scheme keeps its order with a chain.
const YOSHIDA_6: [f64; 7] = {
    let (w1, w2, w3) = (
        -1.177_679_984_178_87,
        0.235_573_213_359_357,
        0.784_513_610_477_560,
    );
    let w0 = 1.0 - 2.0 * (w1 + w2 + w3);
    [w3, w2, w1, w0, w1, w2, w3]
};

/// A thermostat whose variables (positions `eta_j`, momenta `p_j`) obey
/// first-order equations integrated beside the rotors' or the bodies'
/// (scheme A's predictor-corrector and start-up): a friction `p_1/Q_1` on
/// the coupled body angular velocities (or on the centres' velocities
/// relative to their centre of mass), and its own rates, which depend on
/// the thermostatted kinetic energy.
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

    /// Advances the chain over a whole step `h` by the sixth-order
    /// composition `YOSHIDA_6` of [`ChainEquations::advance`], each part with the
    /// thermostatted kinetic energy `kinetic_at(x)` at its start and end,
    /// `x` in `[-1, 0]` standing for the time `t + h (1 + x)`; returns the
    /// friction at the end of the step. The step of a Gear scheme, which
    /// knows its kinetic energy along the step as a polynomial.
    fn step_composed(&mut self, kinetic_at: &mut dyn FnMut(f64) -> f64, h: f64) -> f64 {
        let mut x = -1.0;
        let mut start = kinetic_at(x);
        for w in YOSHIDA_6 {
            x += w;
            let end = kinetic_at(x);
            self.advance(start, end, w * h);
            start = end;
        }
        self.friction(self.momenta())
    }

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
