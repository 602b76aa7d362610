//! What a thermostat sees of a kick-based step.

use crate::potential::Potential;
use nalgebra::Vector3;

/// The pieces of a kick-based step (half kick, free flow, torques, half
/// kick) and the rotors' state seen through their body angular velocities,
/// as an integrator offers them to a thermostat. Every method acts on all
/// rotors; the per-rotor callbacks run in rotor order on one thread, so a
/// thermostat's random numbers do not depend on the thread count. `Send`,
/// so that a thermostat may draw them on one thread while the rotors move
/// on the others.
pub trait SplitDynamics: Send {
    /// The time step.
    fn dt(&self) -> f64;

    /// Half kick: every momentum over `dt/2` with the stored torques.
    fn half_kick(&mut self);

    /// The integrator's free flow (orientation update) over `duration`.
    fn free_flow(&mut self, duration: f64);

    /// The torques at the current orientations.
    fn evaluate_torques(&mut self, potential: &dyn Potential);

    /// Half kick, then the free flow over `duration` (an integrator may do
    /// both in one parallel pass over its rotors).
    fn half_kick_then_flow(&mut self, duration: f64) {
        self.half_kick();
        self.free_flow(duration);
    }

    /// The step without a thermostat: half kick, free flow over `dt`,
    /// torques at the new orientations, half kick.
    fn kick_flow_kick(&mut self, potential: &dyn Potential) {
        self.half_kick_then_flow(self.dt());
        self.evaluate_torques(potential);
        self.half_kick();
    }

    /// The total kinetic energy `sum_i 1/2 w_b . I w_b`, summed in rotor
    /// order.
    fn kinetic_energy(&self) -> f64;

    /// Calls `f(rotor, w_b, moments)` for every rotor in order.
    fn for_each_omega_body(&self, f: impl FnMut(usize, &Vector3<f64>, &Vector3<f64>));

    /// Multiplies every angular momentum by `factor`.
    fn scale_momenta(&mut self, factor: f64);

    /// Calls `f(rotor, w_b, moments)` for every rotor in order and sets the
    /// rotor's momentum from the body angular velocity `f` leaves
    /// (`L_b = I w_b`; nothing about axes with zero moment).
    fn update_omega_body(&mut self, f: impl FnMut(usize, &mut Vector3<f64>, &Vector3<f64>));
}
