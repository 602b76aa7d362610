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
//! potential evaluation per step. The step itself is [`Kicked`]'s.

use super::free_rotation::omega_from_momentum;
use super::kick::{Kicked, Splitting};
use super::spec::IntegratorOptions;
use super::Integrator;
use crate::quaternion::Quat;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The Richardson integrator (scene name `richardson`).
pub type Richardson = Kicked<RichardsonOptions>;

/// Options of [`Richardson`]: none (the scene's `[integrator]` table with
/// `kind = "richardson"` takes no other key).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RichardsonOptions {}

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

impl IntegratorOptions for RichardsonOptions {
    const NAME: &'static str = "richardson";

    fn build(&self) -> Box<dyn Integrator> {
        Box::new(Richardson::new(*self))
    }
}

impl Splitting for RichardsonOptions {
    /// The space-fixed angular momentum `L_s`.
    type Momentum = Vector3<f64>;

    fn momentum(q: &Quat, angular_momentum_body: &Vector3<f64>) -> Vector3<f64> {
        q.body_to_space(angular_momentum_body)
    }

    /// `L_s += half n_s`.
    fn kick(momentum_space: &mut Vector3<f64>, _q: &Quat, torque_space: &Vector3<f64>, half: f64) {
        *momentum_space += torque_space * half;
    }

    /// Step 2 of the module doc, rotor by rotor.
    fn rotate<const K: usize>(
        &self,
        q: &mut [Quat; K],
        momentum_space: &mut [Vector3<f64>; K],
        moments: &[Vector3<f64>; K],
        dt: f64,
    ) {
        let half = 0.5 * dt;
        for ((q, l), moments) in q.iter_mut().zip(&*momentum_space).zip(moments) {
            let w = omega_space(q, l, moments);
            let q_full = euler(q, &w, dt);
            let q_half = euler(q, &w, half);
            let q_two = euler(&q_half, &omega_space(&q_half, l, moments), half);
            *q = (q_two * 2.0 - q_full).try_normalize().unwrap_or(q_two);
        }
    }

    fn omega_body(momentum_space: &Vector3<f64>, q: &Quat, moments: &Vector3<f64>) -> Vector3<f64> {
        omega_from_momentum(&q.space_to_body(momentum_space), moments)
    }

    fn angular_momentum_body(momentum_space: &Vector3<f64>, q: &Quat) -> Vector3<f64> {
        q.space_to_body(momentum_space)
    }
}
