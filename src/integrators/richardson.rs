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

use super::free_rotation::omega_from_momentum;
use super::kick::KickState;
use super::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// The Richardson integrator (scene name `richardson`).
#[derive(Clone, Debug, Default)]
pub struct Richardson {
    state: KickState<Vector3<f64>>,
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
}

/// Richardson's half kick: `L_s += half n_s`.
fn kick(momentum_space: &mut Vector3<f64>, _q: &Quat, torque_space: &Vector3<f64>, half: f64) {
    *momentum_space += torque_space * half;
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
        self.state = KickState::new(inertia, potential, initial, dt, |q, l_body| {
            q.body_to_space(l_body)
        })?;
        Ok(())
    }

    fn step<P: Potential>(&mut self, potential: &P) {
        self.state.half_kick(kick);
        let (dt, half) = (self.state.dt, 0.5 * self.state.dt);
        self.state.update(|q, l, i| {
            let w = omega_space(q, l, i);
            let q_full = euler(q, &w, dt);
            let q_half = euler(q, &w, half);
            let q_two = euler(&q_half, &omega_space(&q_half, l, i), half);
            *q = (q_two * 2.0 - q_full).try_normalize().unwrap_or(q_two);
        });
        self.state.evaluate_torques(potential);
        self.state.half_kick(kick);
    }

    fn orientations(&self) -> &[Quat] {
        &self.state.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        self.state
            .omega_body(out, |l, q, i| omega_from_momentum(&q.space_to_body(l), i));
    }

    /// Layout of [`KickState::checkpoint`]: `Q`, then `L_s`, then torques.
    fn checkpoint(&self) -> Vec<f64> {
        self.state.checkpoint()
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        self.state.restore(state)
    }
}
