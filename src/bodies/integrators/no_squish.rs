//! Velocity Verlet for the centres with NO_SQUISH for the rotations, as
//! LAMMPS `fix rigid/nve/small` does (Miller et al., J. Chem. Phys. 116,
//! 8649 (2002); Kamberaj, Low and Neal, J. Chem. Phys. 122, 224114 (2005)).
//!
//! One step of `dt`: half kicks `v += dt/2 F / m` and, on the conjugate
//! quaternion momentum `P = 2 Q*(0, L_b)`, `P += dt/2 * 2 Q*(0, A(Q) tau)`
//! (the rotors' NO_SQUISH kick); drift `R += dt v` and the free rotation
//! of the rotors' NO_SQUISH ([`NoSquishOptions`], its options); forces and
//! torques at the new configuration (one evaluation); half kicks again.
//!
//! Properties: second order, symplectic, time reversible; total linear
//! momentum is conserved to round-off (the site forces of each pair are
//! opposite), and the angular momentum of an open cluster too. Stores per
//! body `P` (4) besides the state, and the last evaluation.

use crate::bodies::evaluate::Evaluation;
use crate::bodies::system::BodySystem;
use crate::checks::{finite_and_positive, InputError};
use crate::integrators::free_rotation::BodyMomentum;
use crate::integrators::{NoSquishOptions, Splitting};
use crate::quaternion::Quat;
use rayon::prelude::*;

/// The integrator of body systems.
#[derive(Clone, Debug)]
pub struct BodyNoSquish {
    rotation: NoSquishOptions,
    dt: f64,
    momentum: Vec<Quat>,
    evaluation: Evaluation,
}

impl BodyNoSquish {
    /// Sets up on `system` (one evaluation) with time step `dt` (> 0) and
    /// the rotation's options.
    pub fn new(
        system: &mut BodySystem,
        dt: f64,
        rotation: NoSquishOptions,
    ) -> Result<Self, InputError> {
        let dt = finite_and_positive("dt", dt)?;
        let momentum = system
            .bodies
            .iter()
            .map(|b| NoSquishOptions::momentum(&b.orientation, &b.angular_momentum_body))
            .collect();
        let mut evaluation = Evaluation::default();
        system.evaluate(&mut evaluation);
        Ok(BodyNoSquish {
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
                NoSquishOptions::kick(momentum, &body.orientation, &e.torque[i], half);
                body.angular_momentum_body = momentum.angular_momentum_body(&body.orientation);
            });
    }
}
