//! Scheme A for bodies: the rotors' scheme A for the rotations (the note's
//! coupled 5-value Gear correctors for eq 10 and Euler's equations) with
//! the same corrector for the centres' first-order pair `r' = v`,
//! `v' = F/m` (Allen and Tildesley, Computer Simulation of Liquids, sec. 3.2
//! and app. E: Gear's coefficients `251/720, 1, 11/12, 1/3, 1/24` for
//! first-order equations with 5 values).
//!
//! One step of `h`: (a), (b) predict `r`, `v`, `Q`, `w_b` by their Taylor
//! series; (c) forces and torques at the predicted centres and orientations
//! (`Q/|Q|`), the one evaluation; (d)-(f) correct `v` with `F/m`, then `r`
//! with the corrected `v`, and `w_b` with Euler's equations, then `Q` with
//! `1/2 Q*(0, w_b)` ([`correct_pair`] for both pairs); renormalise `Q` if
//! asked ([`GearAOptions`], whose start-up is the bodies' too:
//! `gear_start`). Every body is integrated as a general top (no
//! spherical-top shortcut).
//!
//! With a Nose-Hoover thermostat (`gear_chains`):
//! after (c) the chains are advanced over the step with the kinetic
//! energies of the predicted `v` and `w_b`, and (d) corrects `v` and `w_b`
//! with their frictions at the end of the step subtracted from `F/m` and
//! Euler's equations (the rotors' scheme A with a chain does the same).
//! The conserved energy is the total energy plus the chains' energy.
//!
//! Properties: global error of order 5 in `h` with the consistent start-up,
//! as for the rotors; neither symplectic nor time reversible. Total linear
//! momentum is conserved to round-off (the corrector is linear and the
//! forces sum to zero, so `sum m v^(k)` stays 0 for `k >= 1`); the angular
//! momentum of an open cluster to the truncation error (the rotation is
//! corrected in the body frame). Needs three positive moments per body.
//! Stores per body 5 values each of `r`, `v`, `Q`, `w_b`, and the
//! evaluation at the last predicted configuration. The thermostat keeps the
//! total momentum too (its friction acts on `v - V`).

use super::gear_chains::GearChains;
use super::gear_start::{evaluate_at, GearSetup};
use crate::bodies::checkpoint::{take_nordsieck, take_thermostat};
use crate::bodies::evaluate::{Evaluation, Scope};
use crate::bodies::system::BodySystem;
use crate::checks::InputError;
use crate::integrators::gear::{correct_pair, Nordsieck};
use crate::integrators::rigid_body::{General, PrincipalMoments, TopKind};
use crate::integrators::torque::torque_body;
use crate::integrators::GearAOptions;
use crate::integrators::IntegratorError;
use crate::quaternion::Quat;
use crate::thermostat_hook::ThermostatState;
use crate::thermostats::NoseHooverOptions;
use nalgebra::Vector3;

/// Scheme A for bodies (module doc).
#[derive(Clone, Debug)]
pub struct BodyGearA {
    options: GearAOptions,
    dt: f64,
    moments: Vec<PrincipalMoments>,
    position: Nordsieck<Vector3<f64>, 5>,
    velocity: Nordsieck<Vector3<f64>, 5>,
    q: Nordsieck<Quat, 5>,
    omega_body: Nordsieck<Vector3<f64>, 5>,
    evaluation: Evaluation,
    /// The Nose-Hoover chains, if any (boxed: they are large, and most runs
    /// have none).
    chains: Option<Box<GearChains>>,
}

impl BodyGearA {
    /// Sets up on `system` (the start-up's evaluations, then one at the
    /// initial state) with time step `dt` (> 0) and the scheme's options,
    /// at constant energy.
    pub fn new(
        system: &mut BodySystem,
        dt: f64,
        options: GearAOptions,
    ) -> Result<Self, InputError> {
        Self::with_nose_hoover(system, dt, options, None)
    }

    /// [`BodyGearA::new`] with Nose-Hoover chains of checked options
    /// `nose_hoover` (none: constant energy), at rest at t = 0.
    pub fn with_nose_hoover(
        system: &mut BodySystem,
        dt: f64,
        options: GearAOptions,
        nose_hoover: Option<&NoseHooverOptions>,
    ) -> Result<Self, InputError> {
        let chains = nose_hoover.map(|o| Box::new(GearChains::new(o, system)));
        let setup = GearSetup::new(system, dt, options.startup, chains.as_deref())?;
        Ok(BodyGearA {
            options,
            dt: setup.dt,
            moments: setup.moments,
            position: setup.start.position.truncated(),
            velocity: setup.start.velocity.truncated(),
            q: setup.start.q.truncated(),
            omega_body: setup.start.omega_body.truncated(),
            evaluation: setup.evaluation,
            chains,
        })
    }

    /// The chains' share of the conserved energy (0 without them).
    pub fn thermostat_energy(&self) -> f64 {
        self.chains.as_ref().map_or(0.0, |c| c.chains.energy())
    }

    /// The evaluation at the last step's predicted configuration (at the
    /// set-up's initial state before the first step, a restored one's too).
    pub fn evaluation(&self) -> &Evaluation {
        &self.evaluation
    }

    /// Appends the integrator's own state: the scaled derivatives of
    /// `position`, `velocity`, `q`, `omega_body`, each derivative-major,
    /// then the chains' state (none without them).
    pub(crate) fn write_checkpoint(&self, out: &mut Vec<f64>) {
        self.position.write_flat(out);
        self.velocity.write_flat(out);
        self.q.write_flat(out);
        self.omega_body.write_flat(out);
        if let Some(c) = &self.chains {
            c.chains.write_checkpoint(out);
        }
    }

    /// Reads back [`BodyGearA::write_checkpoint`]'s output from the front
    /// of `data`, returning the rest. Nothing is evaluated: the next step
    /// evaluates at its prediction, as the run would have (an evaluation
    /// here could rebuild the neighbour list at another step).
    pub(crate) fn read_checkpoint<'a>(
        &mut self,
        data: &'a [f64],
    ) -> Result<&'a [f64], IntegratorError> {
        let data = take_nordsieck(data, &mut self.position, "the centres' scaled derivatives")?;
        let data = take_nordsieck(
            data,
            &mut self.velocity,
            "the centre velocities' scaled derivatives",
        )?;
        let data = take_nordsieck(data, &mut self.q, "the orientations' scaled derivatives")?;
        let data = take_nordsieck(
            data,
            &mut self.omega_body,
            "the body angular velocities' scaled derivatives",
        )?;
        match &mut self.chains {
            Some(c) => take_thermostat(data, &mut c.chains, "the scaled derivatives"),
            None => Ok(data),
        }
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
        for (r, body) in self.position.r[0].iter_mut().zip(&system.bodies) {
            *r = body.position;
        }
        self.position.predict();
        self.velocity.predict();
        self.q.predict();
        self.omega_body.predict();
        let e = &mut self.evaluation;
        evaluate_at(system, &mut self.position.r[0], &self.q.r[0], e, scope);
        let frictions =
            (self.chains.as_mut()).map(|c| (c.step(&self.omega_body, &self.velocity, h), &*c));
        let (mut r, mut v) = (self.position.as_chunk(), self.velocity.as_chunk());
        let (mut q, mut w) = (self.q.as_chunk(), self.omega_body.as_chunk());
        for (i, body) in system.bodies.iter().enumerate() {
            let mut acceleration = e.force[i] / system.types[body.kind].mass;
            let q_i = q.r[0][i];
            let n_b = torque_body(&q_i, &e.torque[i]);
            let mut w_dot = General::omega_dot_body(&self.moments[i], &w.r[0][i], &n_b);
            if let Some((f, chains)) = &frictions {
                acceleration -= f.on_translation(&v.r[0][i]);
                w_dot -= chains.on_rotation(f, i, &w.r[0][i]);
            }
            correct_pair(&mut r, &mut v, i, acceleration, |v| *v, h);
            correct_pair(
                &mut q,
                &mut w,
                i,
                w_dot,
                |w| q_i.q_dot_from_omega_body(w),
                h,
            );
        }
        if self.options.renormalise {
            for q in &mut self.q.r[0] {
                *q = *q * (1.0 / q.norm());
            }
        }
        for (i, body) in system.bodies.iter_mut().enumerate() {
            let q = self.q.r[0][i];
            body.position = self.position.r[0][i];
            body.velocity = self.velocity.r[0][i];
            body.orientation = q * (1.0 / q.norm());
            body.angular_momentum_body =
                self.omega_body.r[0][i].component_mul(&self.moments[i].moments);
        }
    }
}
