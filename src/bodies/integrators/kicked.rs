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

use crate::bodies::checkpoint::take_values;
use crate::bodies::evaluate::Evaluation;
use crate::bodies::system::BodySystem;
use crate::checks::{finite_and_positive, InputError};
use crate::integrators::checkpoint::write_values;
use crate::integrators::{IntegratorError, Splitting};
use rayon::prelude::*;

/// A body integrator: velocity Verlet for the centres, the splitting `S`
/// for the rotations.
#[derive(Clone, Debug)]
pub struct BodyKicked<S: Splitting> {
    rotation: S,
    dt: f64,
    momentum: Vec<S::Momentum>,
    evaluation: Evaluation,
}

impl<S: Splitting> BodyKicked<S> {
    /// Sets up on `system` (one evaluation) with time step `dt` (> 0) and
    /// the rotation's options.
    pub fn new(system: &mut BodySystem, dt: f64, rotation: S) -> Result<Self, InputError> {
        let dt = finite_and_positive("dt", dt)?;
        let momentum = system
            .bodies
            .iter()
            .map(|b| S::momentum(&b.orientation, &b.angular_momentum_body))
            .collect();
        let mut evaluation = Evaluation::default();
        system.evaluate(&mut evaluation);
        Ok(BodyKicked {
            rotation,
            dt,
            momentum,
            evaluation,
        })
    }

    /// The evaluation at the current state.
    pub fn evaluation(&self) -> &Evaluation {
        &self.evaluation
    }

    /// Appends the integrator's own state: the splitting's momentum of
    /// every body.
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        write_values(&self.momentum, out);
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
        system.evaluate(&mut self.evaluation);
        Ok(rest)
    }

    /// One step.
    pub fn step(&mut self, system: &mut BodySystem) {
        let dt = self.dt;
        self.kick(system);
        let (types, rotation) = (&system.types, &self.rotation);
        system
            .bodies
            .par_iter_mut()
            .zip(&mut self.momentum)
            .for_each(|(body, momentum)| {
                body.position += body.velocity * dt;
                rotation.rotate(
                    &mut body.orientation,
                    momentum,
                    &types[body.kind].moments,
                    dt,
                );
            });
        system.evaluate(&mut self.evaluation);
        self.kick(system);
    }

    /// Half kicks of the centres and the rotations with the current forces
    /// and torques; the bodies' angular momenta follow.
    fn kick(&mut self, system: &mut BodySystem) {
        let half = 0.5 * self.dt;
        let (types, e) = (&system.types, &self.evaluation);
        system
            .bodies
            .par_iter_mut()
            .zip(&mut self.momentum)
            .enumerate()
            .for_each(|(i, (body, momentum))| {
                body.velocity += e.force[i] * (half / types[body.kind].mass);
                S::kick(momentum, &body.orientation, &e.torque[i], half);
                body.angular_momentum_body = S::angular_momentum_body(momentum, &body.orientation);
            });
    }
}
