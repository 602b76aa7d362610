//! The kick-based body integrators as one, [`BodyKicked`], over a rotor
//! [`Splitting`] (NO_SQUISH, DLM, Richardson): velocity Verlet for the
//! centres around the splitting's own kick and orientation update, called
//! per body, so the rotation of a body is exactly the rotors' (one function
//! for both).
//!
//! One step of `dt`: half kicks `v += dt/2 F / m` and
//! [`Splitting::kick`]`(dt/2)` with the space-frame torque; drift
//! `R += dt v` and [`Splitting::rotate`]`(dt)`; forces and torques at the
//! new configuration (one evaluation); half kicks again.
//!
//! Total linear momentum is conserved to round-off by every splitting (the
//! site forces of each pair are opposite, and every body gets the same
//! kicks), and the angular momentum of an open cluster to the accuracy of
//! the rotation's update (round-off when it is symplectic). Stores per body
//! the splitting's momentum variable besides the state, and the last
//! evaluation.
//!
//! A thermostat ([`AnyThermostat`]) arranges the step as it does the
//! rotors' ([`crate::thermostats`]), seeing it through [`BodyStep`]: the
//! half kick (centres and rotations), the free flow (drift and rotation)
//! over any duration, the forces and torques, the body angular velocities
//! and the centres' velocities. Without one ([`crate::thermostat_hook::Nve`])
//! the step is the one above.

use crate::bodies::checkpoint::{take_thermostat, take_values};
use crate::bodies::evaluate::{Evaluation, Scope};
use crate::bodies::system::BodySystem;
use crate::checks::{finite_and_positive, InputError};
use crate::dynamics::AnyThermostat;
use crate::integrators::checkpoint::write_values;
use crate::integrators::{rotate_all, IntegratorError, Splitting, ROTATED_TOGETHER};
use crate::quaternion::Quat;
use crate::thermostat_hook::{SplitDynamics, Thermostat};
use crate::thermostats::ThermostatSpec;
use nalgebra::Vector3;
use rayon::prelude::*;

/// A body integrator: velocity Verlet for the centres, the splitting `S`
/// for the rotations, with its thermostat.
#[derive(Clone, Debug)]
pub struct BodyKicked<S: Splitting> {
    rotation: S,
    thermostat: AnyThermostat,
    dt: f64,
    momentum: Vec<S::Momentum>,
    evaluation: Evaluation,
}

impl<S: Splitting> BodyKicked<S> {
    /// Sets up on `system` (one evaluation) with time step `dt` (> 0) and
    /// the rotation's options, at constant energy.
    pub fn new(system: &mut BodySystem, dt: f64, rotation: S) -> Result<Self, InputError> {
        Self::with_thermostat(system, dt, rotation, None)
    }

    /// [`BodyKicked::new`] with `thermostat` (none: constant energy), whose
    /// pairing has passed [`crate::dynamics::check`].
    pub fn with_thermostat(
        system: &mut BodySystem,
        dt: f64,
        rotation: S,
        thermostat: Option<&ThermostatSpec>,
    ) -> Result<Self, InputError> {
        let dt = finite_and_positive("dt", dt)?;
        let momentum = system
            .bodies
            .iter()
            .map(|b| S::momentum(&b.orientation, &b.angular_momentum_body))
            .collect();
        let mut evaluation = Evaluation::default();
        system.evaluate(&mut evaluation);
        let mut thermostat = AnyThermostat::new(thermostat);
        let moments: Vec<Vector3<f64>> = system
            .bodies
            .iter()
            .map(|b| system.types[b.kind].moments)
            .collect();
        thermostat.setup(&moments, &system.coupled_degrees(), dt);
        Ok(BodyKicked {
            rotation,
            thermostat,
            dt,
            momentum,
            evaluation,
        })
    }

    /// The thermostat's share of the conserved energy (0 without one).
    pub fn thermostat_energy(&self) -> f64 {
        self.thermostat.state().energy()
    }

    /// The evaluation at the current state.
    pub fn evaluation(&self) -> &Evaluation {
        &self.evaluation
    }

    /// Appends the integrator's own state: the splitting's momentum of
    /// every body, then the thermostat's state (none without one).
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        write_values(&self.momentum, out);
        self.thermostat.state().write_checkpoint(out);
    }

    /// Reads back [`BodyKicked::write_checkpoint`]'s output from the front
    /// of `data`, returning the rest, and evaluates `system` (restored
    /// first, its neighbour list too): the evaluation the last step ended
    /// on, bit for bit (no site has moved since that step's evaluation, so
    /// the list is not rebuilt).
    pub(crate) fn read_checkpoint<'a>(
        &mut self,
        system: &mut BodySystem,
        data: &'a [f64],
    ) -> Result<&'a [f64], IntegratorError> {
        let rest = take_values(data, &mut self.momentum, "the bodies' momenta")?;
        let rest = take_thermostat(rest, self.thermostat.state_mut(), "the bodies' momenta")?;
        system.evaluate(&mut self.evaluation);
        Ok(rest)
    }

    /// One step, arranged by the thermostat.
    pub fn step(&mut self, system: &mut BodySystem) {
        self.step_in(system, Scope::Full);
    }

    /// One step, its evaluation (the one [`BodyKicked::evaluation`] then
    /// gives) in `scope`.
    pub fn step_in(&mut self, system: &mut BodySystem, scope: Scope) {
        let mut step = BodyStep {
            rotation: &self.rotation,
            dt: self.dt,
            momentum: &mut self.momentum,
            evaluation: &mut self.evaluation,
            scope,
            system,
        };
        self.thermostat.step(&mut step);
    }
}

/// One step of a kick-based body integrator as a thermostat sees it: the
/// pieces of velocity Verlet and the splitting over the bodies' state.
pub struct BodyStep<'a, S: Splitting> {
    rotation: &'a S,
    dt: f64,
    momentum: &'a mut [S::Momentum],
    evaluation: &'a mut Evaluation,
    scope: Scope,
    system: &'a mut BodySystem,
}

impl<S: Splitting> SplitDynamics for BodyStep<'_, S> {
    fn dt(&self) -> f64 {
        self.dt
    }

    /// Half kicks of the centres and the rotations with the current forces
    /// and torques; the bodies' angular momenta follow.
    fn half_kick(&mut self) {
        let half = 0.5 * self.dt;
        let (types, e) = (&self.system.types, &*self.evaluation);
        self.system
            .bodies
            .par_iter_mut()
            .zip(&mut *self.momentum)
            .enumerate()
            .for_each(|(i, (body, momentum))| {
                body.velocity += e.force[i] * (half / types[body.kind].mass);
                S::kick(momentum, &body.orientation, &e.torque[i], half);
                body.angular_momentum_body = S::angular_momentum_body(momentum, &body.orientation);
            });
    }

    /// The drift `R += duration v` and the splitting's rotation, of
    /// [`ROTATED_TOGETHER`] bodies at a time (the last few one by one).
    fn free_flow(&mut self, duration: f64) {
        let (types, rotation) = (&self.system.types, self.rotation);
        let bodies = self.system.bodies.par_chunks_mut(ROTATED_TOGETHER);
        bodies
            .zip(self.momentum.par_chunks_mut(ROTATED_TOGETHER))
            .for_each(|(bodies, momenta)| {
                for body in bodies.iter_mut() {
                    body.position += body.velocity * duration;
                }
                let mut q = [Quat::IDENTITY; ROTATED_TOGETHER];
                let mut moments = [Vector3::zeros(); ROTATED_TOGETHER];
                for (k, body) in bodies.iter().enumerate() {
                    (q[k], moments[k]) = (body.orientation, types[body.kind].moments);
                }
                let n = bodies.len();
                rotate_all(rotation, &mut q[..n], momenta, &moments[..n], duration);
                for (body, q) in bodies.iter_mut().zip(q) {
                    body.orientation = q;
                }
            });
    }

    fn evaluate(&mut self) {
        self.system.evaluate_in(self.evaluation, self.scope);
    }

    /// Summed in body order on one thread.
    fn kinetic_energy(&self) -> f64 {
        let mut kinetic = 0.0;
        self.for_each_omega_body(|_, w, i| kinetic += 0.5 * w.dot(&i.component_mul(w)));
        kinetic
    }

    fn for_each_omega_body(&self, mut f: impl FnMut(usize, &Vector3<f64>, &Vector3<f64>)) {
        let types = &self.system.types;
        for (i, (body, p)) in self.system.bodies.iter().zip(&*self.momentum).enumerate() {
            let moments = &types[body.kind].moments;
            f(i, &S::omega_body(p, &body.orientation, moments), moments);
        }
    }

    fn scale_momenta(&mut self, factor: f64) {
        self.update_omega_body(|_, w, _| *w *= factor);
    }

    fn update_omega_body(&mut self, mut f: impl FnMut(usize, &mut Vector3<f64>, &Vector3<f64>)) {
        let types = &self.system.types;
        let bodies = self.system.bodies.iter_mut().zip(&mut *self.momentum);
        for (i, (body, p)) in bodies.enumerate() {
            let (q, moments) = (&body.orientation, &types[body.kind].moments);
            let mut w = S::omega_body(p, q, moments);
            f(i, &mut w, moments);
            *p = S::momentum(q, &w.component_mul(moments));
            body.angular_momentum_body = S::angular_momentum_body(p, q);
        }
    }

    fn for_each_velocity(&self, mut f: impl FnMut(usize, &Vector3<f64>, f64)) {
        let types = &self.system.types;
        for (i, body) in self.system.bodies.iter().enumerate() {
            f(i, &body.velocity, types[body.kind].mass);
        }
    }

    fn update_velocities(&mut self, mut f: impl FnMut(usize, &mut Vector3<f64>, f64)) {
        let types = &self.system.types;
        for (i, body) in self.system.bodies.iter_mut().enumerate() {
            f(i, &mut body.velocity, types[body.kind].mass);
        }
    }
}
