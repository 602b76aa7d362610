//! The Richardson-extrapolated quaternion update of LAMMPS `fix rigid` and
//! `fix nve/asphere`: velocity Verlet for the space-fixed angular momentum,
//! explicit Euler steps of eq 10 for the quaternion, extrapolated.
//!
//! One step of `dt`, with `w_s(L_s, Q) = R(Q) I^-1 A(Q) L_s` (eq 6; zero about
//! axes with `I_k = 0`) and `euler(Q, w, h) = normalise(Q + h/2 (0, w)*Q)`
//! (eq 10, space form):
//! 1. half kick `L_s += dt/2 n_s`;
//! 2. `Q_full = euler(Q, w_s(L_s, Q), dt)`;
//!    `Q_half = euler(Q, w_s(L_s, Q), dt/2)`,
//!    `Q_two = euler(Q_half, w_s(L_s, Q_half), dt/2)`;
//!    `Q <- normalise(2 Q_two - Q_full)`;
//! 3. torques at the new orientations, half kick again.
//!
//! Properties: second order (the extrapolation cancels the `O(dt^2)` local
//! error of the Euler steps); neither symplectic nor time reversible (the
//! quaternion update is explicit and one-sided); `|Q| = 1` by normalisation.
//! Stores per rotor: `Q` (4), the space-fixed angular momentum `L_s` (3) and
//! the space-fixed torque at `Q` (3), plus the principal moments (3). One
//! potential evaluation per step.

use super::checkpoint::{read_kick_state, write_kick_state};
use super::free_rotation::omega_from_momentum;
use super::setup::{validate_setup, Moments, ValidSetup};
use super::torque::evaluate_torques;
use super::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// The Richardson integrator (scene name `richardson`).
#[derive(Clone, Debug, Default)]
pub struct Richardson {
    dt: f64,
    inertia: Vec<Vector3<f64>>,
    orientation: Vec<Quat>,
    momentum_space: Vec<Vector3<f64>>,
    torque_space: Vec<Vector3<f64>>,
}

/// `w_s = R(Q) I^-1 A(Q) L_s`.
fn omega_space(q: &Quat, momentum_space: &Vector3<f64>, inertia: &Vector3<f64>) -> Vector3<f64> {
    q.body_to_space(&omega_from_momentum(
        &q.space_to_body(momentum_space),
        inertia,
    ))
}

/// One explicit Euler step of eq 10 over `h`, normalised.
fn euler(q: &Quat, omega_space: &Vector3<f64>, h: f64) -> Quat {
    let q_new = *q + q.q_dot_from_omega_space(omega_space) * h;
    q_new.try_normalize().unwrap_or(*q)
}

impl Richardson {
    /// A Richardson integrator.
    pub fn new() -> Self {
        Richardson::default()
    }

    /// Adds `dt/2` times the space torque to the space angular momenta.
    fn half_kick(&mut self) {
        let half = 0.5 * self.dt;
        for (l, n) in self.momentum_space.iter_mut().zip(&self.torque_space) {
            *l += n * half;
        }
    }
}

impl Integrator for Richardson {
    fn name(&self) -> &'static str {
        "richardson"
    }

    fn setup<P: Potential>(
        &mut self,
        inertia: &[Inertia],
        potential: &P,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        let ValidSetup { moments, initial } =
            validate_setup(inertia, initial, dt, Moments::MayBeZero)?;
        self.dt = dt;
        self.inertia = moments;
        self.orientation = initial.iter().map(|s| s.orientation).collect();
        self.momentum_space = self
            .orientation
            .iter()
            .zip(&initial)
            .zip(&self.inertia)
            .map(|((q, s), i)| q.body_to_space(&s.omega_body.component_mul(i)))
            .collect();
        self.torque_space = vec![Vector3::zeros(); initial.len()];
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
        Ok(())
    }

    fn step<P: Potential>(&mut self, potential: &P) {
        self.half_kick();
        let (dt, half) = (self.dt, 0.5 * self.dt);
        for ((q, l), i) in self
            .orientation
            .iter_mut()
            .zip(&self.momentum_space)
            .zip(&self.inertia)
        {
            let w = omega_space(q, l, i);
            let q_full = euler(q, &w, dt);
            let q_half = euler(q, &w, half);
            let q_two = euler(&q_half, &omega_space(&q_half, l, i), half);
            *q = (q_two * 2.0 - q_full).try_normalize().unwrap_or(q_two);
        }
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
        self.half_kick();
    }

    fn orientations(&self) -> &[Quat] {
        &self.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        for (((w, l), q), i) in out
            .iter_mut()
            .zip(&self.momentum_space)
            .zip(&self.orientation)
            .zip(&self.inertia)
        {
            *w = omega_from_momentum(&q.space_to_body(l), i);
        }
    }

    /// Layout: all `Q` (4 each), then all `L_s` (3 each), then all torques (3 each).
    fn checkpoint(&self) -> Vec<f64> {
        write_kick_state(&self.orientation, &self.momentum_space, &self.torque_space)
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        read_kick_state(
            state,
            &mut self.orientation,
            &mut self.momentum_space,
            &mut self.torque_space,
        )
    }
}
