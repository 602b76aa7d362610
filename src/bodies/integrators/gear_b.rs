//! Scheme B for bodies: the rotors' scheme B for the rotations (the 6-value
//! Gear corrector for second-order equations on eq 12, with the note's
//! switched corrections) with the same corrector for the centres'
//! `r'' = F/m` (Allen and Tildesley, Computer Simulation of Liquids,
//! sec. 3.2 and app. E: Gear's coefficients `c0, 251/360, 1, 11/18, 1/6,
//! 1/60` for second-order equations with 6 values; `c0` is the scheme's,
//! `3/16` by default since the coupled right-hand side depends on `Q'`).
//!
//! One step of `h`: (a) predict `r` and `Q` by their Taylor series; (b)
//! forces and torques at the predicted centres and orientations (`Q/|Q|`),
//! the one evaluation; the quaternion force is `N = 2 Q*(0, n_b)` (eq 13
//! inverted with `n0 = 0`: a torque has no norm component, so the torque
//! projection of eq 15b holds by construction); (c) correct `r` with
//! `h^2/2 F/m - r_2` and `Q` with `h^2/2 Q'' - q_2` (eq 12, the rotors'
//! `scheme_b::acceleration`); then the switched corrections of
//! [`GearBOptions`], the rotors' own. Bodies are integrated as general tops.
//!
//! Properties: global error of order 5 in `h` with the consistent start-up,
//! as for the rotors; neither symplectic nor time reversible. Total linear
//! momentum is conserved to round-off (`sum m r^(k)` stays 0 for
//! `k >= 2`); the angular momentum of an open cluster to the truncation
//! error. Needs three positive moments per body, and `project_torque`
//! (there is no unprojected gradient). Stores per body 6 values each of `r`
//! and `Q`, and the evaluation at the last predicted configuration.

use super::gear_start::{evaluate_at, GearSetup};
use crate::bodies::checkpoint::take_nordsieck;
use crate::bodies::evaluate::{Evaluation, Scope};
use crate::bodies::system::BodySystem;
use crate::checks::InputError;
use crate::integrators::gear::{second_order_6, Nordsieck};
use crate::integrators::rigid_body::{General, PrincipalMoments};
use crate::integrators::scheme_b::acceleration;
use crate::integrators::torque::torque_body;
use crate::integrators::GearBOptions;
use crate::integrators::IntegratorError;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// Scheme B for bodies (module doc).
#[derive(Clone, Debug)]
pub struct BodyGearB {
    options: GearBOptions,
    coefficients: [f64; 6],
    dt: f64,
    moments: Vec<PrincipalMoments>,
    position: Nordsieck<Vector3<f64>, 6>,
    q: Nordsieck<Quat, 6>,
    evaluation: Evaluation,
}

impl BodyGearB {
    /// Refuses options bodies cannot use (`project_torque = false`).
    pub fn check(options: &GearBOptions) -> Result<(), InputError> {
        if options.project_torque {
            Ok(())
        } else {
            Err(InputError::new(
                "project_torque",
                "must be true for bodies: their torques have no norm component to keep",
            ))
        }
    }

    /// Sets up on `system` (the start-up's evaluations, then one at the
    /// initial state) with time step `dt` (> 0) and the scheme's options.
    pub fn new(
        system: &mut BodySystem,
        dt: f64,
        options: GearBOptions,
    ) -> Result<Self, InputError> {
        Self::check(&options)?;
        let setup = GearSetup::new(system, dt, options.startup, None)?;
        Ok(BodyGearB {
            options,
            coefficients: second_order_6(options.c0.value()),
            dt: setup.dt,
            moments: setup.moments,
            position: setup.start.position,
            q: setup.start.q,
            evaluation: setup.evaluation,
        })
    }

    /// The evaluation at the last step's predicted configuration (at the
    /// set-up's initial state before the first step, a restored one's too).
    pub fn evaluation(&self) -> &Evaluation {
        &self.evaluation
    }

    /// Appends the integrator's own state: the scaled derivatives of
    /// `position`, `q`, each derivative-major.
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        self.position.write_flat(out);
        self.q.write_flat(out);
    }

    /// Reads back [`BodyGearB::write_checkpoint`]'s output from the front
    /// of `data`, returning the rest. Nothing is evaluated: the next step
    /// evaluates at its prediction, as the run would have (an evaluation
    /// here could rebuild the neighbour list at another step).
    pub(crate) fn read_checkpoint<'a>(
        &mut self,
        data: &'a [f64],
    ) -> Result<&'a [f64], IntegratorError> {
        let data = take_nordsieck(data, &mut self.position, "the centres' scaled derivatives")?;
        let data = take_nordsieck(data, &mut self.q, "the orientations' scaled derivatives")?;
        Ok(data)
    }

    /// One step (module doc). The centres are read from `system` first
    /// (where a neighbour-list build may have wrapped them).
    pub fn step(&mut self, system: &mut BodySystem) {
        self.step_in(system, Scope::Full);
    }

    /// One step, its evaluation at the predicted configuration (the one
    /// [`Self::evaluation`] then gives) in `scope`.
    pub fn step_in(&mut self, system: &mut BodySystem, scope: Scope) {
        let h = self.dt;
        let half_h2 = 0.5 * h * h;
        for (r, body) in self.position.r[0].iter_mut().zip(&system.bodies) {
            *r = body.position;
        }
        self.position.predict();
        self.q.predict();
        let e = &mut self.evaluation;
        evaluate_at(system, &mut self.position.r[0], &self.q.r[0], e, scope);
        let (mut r, mut q) = (self.position.as_chunk(), self.q.as_chunk());
        for (i, body) in system.bodies.iter().enumerate() {
            let delta = e.force[i] * (half_h2 / system.types[body.kind].mass) - r.r[2][i];
            r.correct(i, &self.coefficients, delta);
            let q_i = q.r[0][i];
            let force = q_i * Quat::pure(&torque_body(&q_i, &e.torque[i])) * 2.0;
            let q_dot = q.r[1][i] * (1.0 / h);
            let q_ddot = acceleration::<General>(&self.moments[i], &q_i, &q_dot, &force);
            let delta = q_ddot * half_h2 - q.r[2][i];
            q.correct(i, &self.coefficients, delta);
        }
        self.options.correct_switched(&mut q);
        for (i, body) in system.bodies.iter_mut().enumerate() {
            let q = self.q.r[0][i];
            let q_dot = self.q.r[1][i] * (1.0 / h);
            body.position = self.position.r[0][i];
            body.velocity = self.position.r[1][i] * (1.0 / h);
            body.orientation = q * (1.0 / q.norm());
            body.angular_momentum_body = q
                .omega_body_from_q_dot(&q_dot)
                .component_mul(&self.moments[i].moments);
        }
    }
}
