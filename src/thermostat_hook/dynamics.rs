//! What a thermostat sees of a kick-based step.

use nalgebra::Vector3;

/// The pieces of a kick-based step (half kick, free flow, forces and
/// torques, half kick) and the state seen in two views: the rotational one
/// through the body angular velocities, the translational one through the
/// centres' velocities (bodies that move; rotors on fixed sites have no
/// centres, and their translational view is empty). The dynamics owns what
/// it evaluates (a rotor potential, a body system), so a thermostat never
/// learns which. Every method acts on all rotors or bodies; the per-body
/// callbacks run in order on one thread, so a thermostat's random numbers
/// do not depend on the thread count. `Send`, so that a thermostat may draw
/// them on one thread while the bodies move on the others.
pub trait SplitDynamics: Send {
    /// The time step.
    fn dt(&self) -> f64;

    /// Half kick: every momentum over `dt/2` with the stored forces and
    /// torques.
    fn half_kick(&mut self);

    /// The integrator's free flow (orientation update, and the centres'
    /// drift) over `duration`.
    fn free_flow(&mut self, duration: f64);

    /// The forces and torques at the current configuration.
    fn evaluate(&mut self);

    /// Half kick, then the free flow over `duration` (an integrator may do
    /// both in one parallel pass over its rotors).
    fn half_kick_then_flow(&mut self, duration: f64) {
        self.half_kick();
        self.free_flow(duration);
    }

    /// The step without a thermostat: half kick, free flow over `dt`,
    /// forces and torques at the new configuration, half kick.
    fn kick_flow_kick(&mut self) {
        self.half_kick_then_flow(self.dt());
        self.evaluate();
        self.half_kick();
    }

    /// The step with a thermostat's action `middle` in the middle of the
    /// free flow (B A M A B): half kick, free flow over `dt/2`, `middle`,
    /// free flow over `dt/2`, forces and torques, half kick. Between two
    /// actions the map is position Verlet, so a thermostat that brings the
    /// momenta there to `T` leaves the orientations of a harmonic libration
    /// exact at any `dt` (`crate::thermostats`, module doc).
    fn kick_flow_around(&mut self, middle: impl FnOnce(&mut Self))
    where
        Self: Sized,
    {
        let half = 0.5 * self.dt();
        self.half_kick_then_flow(half);
        middle(self);
        self.free_flow(half);
        self.evaluate();
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

    /// Calls `f(body, v, mass)` for every moving centre in order, with its
    /// velocity `v` (none for rotors on fixed sites).
    fn for_each_velocity(&self, f: impl FnMut(usize, &Vector3<f64>, f64));

    /// Calls `f(body, v, mass)` for every moving centre in order and keeps
    /// the velocity `f` leaves.
    fn update_velocities(&mut self, f: impl FnMut(usize, &mut Vector3<f64>, f64));
}
