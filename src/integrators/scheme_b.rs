//! Scheme B of the note: Allen's direct integration of the second-order
//! quaternion equation (eq 12, corrected) with the 6-value Gear
//! predictor-corrector for second-order equations.
//!
//! Right-hand side (derived from eq 10, `Q' = 1/2 Q*W_b`, `W_b = (0, w_b)`:
//! `Q'' = 1/2 Q'*W_b + 1/2 Q*W_b'` and `W_b = 2 Q~*Q'` for unit `Q`):
//!
//! `Q'' = Q'*Q~*Q' + 1/2 Q*(n0/I0, w_b')`, with `w_b = 2 vec(Q~*Q')`,
//! `I w_b' = n_b - w_b x (I w_b)` (Euler) and `(n0, n_b) = Q~*N/(2|Q|^2)`
//! (eq 13 inverted, for any `|Q|`), `N = -dV/dQ` the gradient of eq 14.
//!
//! For a spherical top this is `Q'' = Q'*Q~*Q' + 1/4 N/I` (the printed eq 12
//! has `Q'*Q'*Q'` and `1/2 N`: ERRATA.md), computed without any body-frame
//! work. `n0` is the norm component of `N` (`n0 = 1/2 Q.N`); it is zero after
//! the torque projection, and otherwise divided by the mean moment `I0`.
//!
//! The corrections of the note, each a switch of [`GearBOptions`]:
//! torque projection `N <- N - (Q.N) Q/|Q|^2` (eq 15b; identical to setting
//! `n0 = 0` in the body frame, since `Q~*Q` is a scalar), velocity projection
//! `Q' <- Q' - (Q.Q') Q/|Q|^2` (eq 15a), renormalisation `Q <- Q/|Q|`, and the
//! answer to the note's open question: the higher derivatives obey the
//! derivatives of `|Q|^2 = const`, `sum_j C(k,j) Q^(j).Q^(k-j) = 0`, which in
//! scaled derivatives read `sum_{j=0..k} r_j.r_{k-j} = 0`; each `r_k`,
//! `k = 2..5`, is projected along `Q` to satisfy its constraint.
//!
//! Properties: stores per rotor 6 quaternions (`Q` and 5 scaled derivatives)
//! plus `Q.N` of the last force evaluation (diagnostics only), and the
//! principal moments; one gradient evaluation per step; neither time
//! reversible nor symplectic.
//!
//! Order: global error of order 5 in `h` with a consistent start-up, for
//! either `c0` (the right-hand side depends on `Q'`; `3/20` reaches 6 only
//! for position-only right-hand sides: the tests of `gear.rs`). The note's
//! "5th order Gear algorithm for 2nd order differential equations" names the
//! highest stored derivative, as for scheme A.

use super::checkpoint::checkpoint_data;
use super::gear::{
    second_order_6, Nordsieck, NordsieckChunk, C0_POSITION_ONLY, C0_VELOCITY_DEPENDENT,
};
use super::rigid_body::{q_ddot, q_ddot_spherical, PrincipalMoments, TopKind};
use super::rotor_chunks::for_each_rotor_chunk;
use super::spec::IntegratorOptions;
use super::startup::{start, GearFrame, GearStart, Startup, TopStep};
use super::{GoOn, Integrator, IntegratorError, RotorState};
use crate::checks::named_choices;
use crate::observables::norm_force;
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The first coefficient `c0` of the second-order corrector table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FirstCorrector {
    /// `3/16`, Gear's value for right-hand sides that depend on `Q'` (eq 12
    /// does). The default.
    #[default]
    VelocityDependent,
    /// `3/20`, Gear's value for position-only right-hand sides.
    PositionOnly,
}

named_choices!(FirstCorrector {
    "3/16" => FirstCorrector::VelocityDependent,
    "3/20" => FirstCorrector::PositionOnly,
});

impl FirstCorrector {
    /// The coefficient `c0`.
    pub fn value(self) -> f64 {
        match self {
            FirstCorrector::VelocityDependent => C0_VELOCITY_DEPENDENT,
            FirstCorrector::PositionOnly => C0_POSITION_ONLY,
        }
    }
}

/// Options of [`GearB`] (the scene's `[integrator]` table with
/// `kind = "gear_b"`). The default is the note's recommended set: both
/// projections and renormalisation, without the higher-derivative correction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct GearBOptions {
    /// The first corrector coefficient (default 3/16).
    pub c0: FirstCorrector,
    /// Project the quaternion force orthogonal to `Q` (eq 15b; default true).
    pub project_torque: bool,
    /// Project `Q'` orthogonal to `Q` after each step (eq 15a; default true).
    pub project_velocity: bool,
    /// Rescale `Q` to unit norm after each step (default true).
    pub renormalise: bool,
    /// Project `Q''..Q^(5)` onto the derivatives of `|Q|^2 = const`
    /// (default false).
    pub correct_higher_derivatives: bool,
    /// How the higher derivatives are set at t = 0 (default consistent).
    pub startup: Startup,
}

impl TopStep for GearB {
    fn frame(&self) -> &GearFrame {
        &self.frame
    }

    /// One step (a)-(c) of the note plus the switched corrections; the
    /// per-rotor work runs over chunks of rotors across the rayon pool.
    fn step_with<K: TopKind>(
        &mut self,
        potential: &dyn Potential,
        predicted: bool,
        next: &mut dyn FnMut() -> bool,
    ) -> bool {
        let h = self.frame.dt;
        let opts = self.options;
        let coefficients = &self.coefficients;
        // (a): predict (and zero the gradient, as the previous step's last
        // pass did when it predicted).
        if !predicted {
            for_each_rotor_chunk(self.q.as_chunk(), |mut q| q.predict());
            self.gradient.fill(Quat::ZERO);
        }
        // (b): the unconstrained gradient (eq 14) at the predicted Q.
        potential.accumulate_gradient(&self.q.r[0], &mut self.gradient);
        let rotors = (
            self.q.as_chunk(),
            &mut self.gradient[..],
            &mut self.norm_force[..],
            &self.frame.moments[..],
        );
        let predict_next = next();
        for_each_rotor_chunk(rotors, |(mut q, gradient, norm_forces, moments)| {
            for i in 0..moments.len() {
                let q_i = q.r[0][i];
                let force = quaternion_force(&q_i, &gradient[i], opts.project_torque);
                norm_forces[i] = norm_force(&q_i, &force);
                let q_dot = q.r[1][i] * (1.0 / h);
                let accel = acceleration::<K>(&moments[i], &q_i, &q_dot, &force);
                // (c): correct.
                let delta = accel * (0.5 * h * h) - q.r[2][i];
                q.correct(i, coefficients, delta);
            }
            // The switched corrections, each rotor on its own, after the
            // force loop (the same values as rotor by rotor inside it).
            opts.correct_switched(&mut q);
            // The next step's (a).
            if predict_next {
                q.predict();
                gradient.fill(Quat::ZERO);
            }
        });
        predict_next
    }
}

impl GearBOptions {
    /// The switched corrections of the module doc (renormalisation, the
    /// velocity projection, the higher-derivative constraints) on every
    /// rotor of the chunk, after its corrector.
    pub(crate) fn correct_switched(&self, q: &mut NordsieckChunk<'_, Quat, 6>) {
        if self.renormalise {
            for q in q.r[0].iter_mut() {
                *q = *q * (1.0 / q.norm());
            }
        }
        if self.project_velocity || self.correct_higher_derivatives {
            for i in 0..q.r[0].len() {
                let mut r = q.rotor(i);
                if self.project_velocity {
                    enforce_norm_derivative(&mut r, 1);
                }
                if self.correct_higher_derivatives {
                    for k in 2..6 {
                        enforce_norm_derivative(&mut r, k);
                    }
                }
                q.set_rotor(i, &r);
            }
        }
    }
}

impl Default for GearBOptions {
    fn default() -> Self {
        GearBOptions {
            c0: FirstCorrector::VelocityDependent,
            project_torque: true,
            project_velocity: true,
            renormalise: true,
            correct_higher_derivatives: false,
            startup: Startup::Consistent,
        }
    }
}

impl IntegratorOptions for GearBOptions {
    const NAME: &'static str = "gear_b";

    fn build(&self) -> Box<dyn Integrator> {
        Box::new(GearB::new(*self))
    }
}

/// Scheme B: the 6-value second-order Gear corrector for eq 12 (module doc).
#[derive(Clone, Debug)]
pub struct GearB {
    options: GearBOptions,
    coefficients: [f64; 6],
    frame: GearFrame,
    q: Nordsieck<Quat, 6>,
    /// `Q.N` of the last force evaluation, at the (predicted) `Q` where the
    /// force `N` was evaluated, after the projection if on (eq 15b).
    norm_force: Vec<f64>,
    gradient: Vec<Quat>,
}

/// The quaternion force `N = -dV/dQ` (eq 14), projected orthogonal to `Q`
/// when `project` (so that eq 15b holds).
fn quaternion_force(q: &Quat, gradient: &Quat, project: bool) -> Quat {
    let force = -*gradient;
    if project {
        force - *q * (q.dot(&force) / q.norm_squared())
    } else {
        force
    }
}

/// `Q''` of one rotor from the quaternion force `N` (module doc): eq 12 with
/// the body acceleration `(n0/I0, w_b')`, or its spherical-top form.
pub(crate) fn acceleration<K: TopKind>(
    moments: &PrincipalMoments,
    q: &Quat,
    q_dot: &Quat,
    force: &Quat,
) -> Quat {
    if K::SPHERICAL {
        return q_ddot_spherical(q, q_dot, force, moments.inverse.x);
    }
    let force_body = q.conjugate() * *force * (0.5 / q.norm_squared());
    let omega_body = q.omega_body_from_q_dot(q_dot);
    let omega_dot = K::omega_dot_body(moments, &omega_body, &force_body.vector());
    let acceleration_body = Quat::new(
        force_body.scalar() * moments.inverse_mean,
        omega_dot.x,
        omega_dot.y,
        omega_dot.z,
    );
    q_ddot(q, q_dot, &acceleration_body)
}

/// Projects `r_k` along `r_0` so that `sum_{j=0..k} r_j.r_{k-j} = 0`, the k-th
/// time derivative of `|Q|^2 = const` in scaled derivatives (`k >= 1`; for
/// `k = 1` it is the velocity projection).
fn enforce_norm_derivative(r: &mut [Quat; 6], k: usize) {
    let inner: f64 = (1..k).map(|j| r[j].dot(&r[k - j])).sum();
    let f = (r[0].dot(&r[k]) + 0.5 * inner) / r[0].norm_squared();
    r[k] = r[k] - r[0] * f;
}

impl GearB {
    /// A scheme-B integrator with the given options (set up before stepping).
    pub fn new(options: GearBOptions) -> Self {
        GearB {
            options,
            coefficients: second_order_6(options.c0.value()),
            frame: GearFrame::default(),
            q: Nordsieck::zeros(0),
            norm_force: Vec::new(),
            gradient: Vec::new(),
        }
    }
}

impl Default for GearB {
    fn default() -> Self {
        GearB::new(GearBOptions::default())
    }
}

impl Integrator for GearB {
    fn name(&self) -> &'static str {
        GearBOptions::NAME
    }

    fn setup(
        &mut self,
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        let GearStart { frame, derivatives } =
            start(self.options.startup, inertia, potential, initial, None, dt)?;
        self.q = derivatives.q;
        self.gradient = vec![Quat::ZERO; self.q.len()];
        potential.accumulate_gradient(&self.q.r[0], &mut self.gradient);
        self.norm_force = self.q.r[0]
            .iter()
            .zip(&self.gradient)
            .map(|(q, g)| norm_force(q, &quaternion_force(q, g, self.options.project_torque)))
            .collect();
        self.frame = frame;
        Ok(())
    }

    fn step(&mut self, potential: &dyn Potential) {
        self.step_by_top(potential);
    }

    fn steps(&mut self, potential: &dyn Potential, count: u64, go_on: GoOn<'_>) -> u64 {
        self.steps_by_top(potential, count, go_on)
    }

    fn dt(&self) -> f64 {
        self.frame.dt
    }

    fn orientations(&self) -> &[Quat] {
        &self.q.r[0]
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        for ((w, q), r1) in out.iter_mut().zip(&self.q.r[0]).zip(&self.q.r[1]) {
            *w = q.omega_body_from_scaled_q_dot(r1, self.frame.dt);
        }
    }

    fn q_dot(&self, out: &mut [Quat]) {
        for (q_dot, r1) in out.iter_mut().zip(&self.q.r[1]) {
            *q_dot = *r1 * (1.0 / self.frame.dt);
        }
    }

    fn norm_force(&self, out: &mut [f64]) -> bool {
        out.copy_from_slice(&self.norm_force);
        true
    }

    fn checkpoint(&self) -> Vec<f64> {
        let mut out = vec![self.frame.dt];
        self.q.write_flat(&mut out);
        out.extend_from_slice(&self.norm_force);
        out
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        let len = self.q.flat_len() + self.norm_force.len();
        let data = checkpoint_data(state, len)?;
        let rest = self.q.read_flat(data);
        self.norm_force.copy_from_slice(rest);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::rigid_body::{General, Spherical};

    /// `sum_{j=0..k} r_j.r_{k-j}` for `k = 0..5`.
    fn constraint_residuals(r: &[Quat; 6]) -> [f64; 6] {
        std::array::from_fn(|k| (0..=k).map(|j| r[j].dot(&r[k - j])).sum())
    }

    /// The exact scaled derivatives of a free spherical top,
    /// `Q^(k) = Q0*(W/2)^k` with `W = (0, w_b)`: unit norm at all times.
    fn exact_free_spherical(h: f64) -> [Quat; 6] {
        let q0 = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let half_w = Quat::pure(&Vector3::new(0.7, -1.1, 0.9)) * (0.5 * h);
        let mut r = [q0; 6];
        for k in 1..6 {
            r[k] = r[k - 1] * half_w * (1.0 / k as f64);
        }
        r
    }

    /// Perturbs the derivatives of `r` (`r_k` by a fixed quaternion times
    /// `0.1^k`), projects them one after the other and requires every
    /// constraint to hold again, with `Q = r_0` untouched.
    fn assert_constraints_regained(mut r: [Quat; 6]) {
        let q = r[0];
        for (k, x) in r.iter_mut().enumerate().skip(1) {
            *x += Quat::new(0.3, -0.1, 0.2, 0.05) * 0.1f64.powi(k as i32);
        }
        for k in 1..6 {
            enforce_norm_derivative(&mut r, k);
        }
        let residuals = constraint_residuals(&r);
        assert!(
            residuals[1..].iter().all(|x| x.abs() < 1e-15),
            "{residuals:?}"
        );
        assert_eq!(r[0], q);
    }

    /// The higher-derivative correction leaves an exact unit-norm Nordsieck
    /// vector unchanged, and makes a perturbed one satisfy every constraint.
    #[test]
    fn norm_derivative_constraints_are_enforced_and_exact_vectors_kept() {
        let exact = exact_free_spherical(0.1);
        let residuals = constraint_residuals(&exact);
        assert!(
            residuals[1..].iter().all(|x| x.abs() < 1e-15),
            "{residuals:?}"
        );
        let mut r = exact;
        for k in 1..6 {
            enforce_norm_derivative(&mut r, k);
        }
        for (a, b) in r.iter().zip(&exact) {
            assert!((*a - *b).norm() < 1e-16);
        }
        assert_constraints_regained(exact);
    }

    /// The general-top right-hand side reduces to the spherical one for equal
    /// moments, projected or not.
    #[test]
    fn general_right_hand_side_reduces_to_spherical() {
        let m = PrincipalMoments::new(Vector3::repeat(1.7));
        let q = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let q_dot = q.q_dot_from_omega_body(&Vector3::new(0.7, -1.1, 0.9));
        let force = Quat::new(0.4, 1.2, -0.3, 0.8);
        let d = acceleration::<General>(&m, &q, &q_dot, &force)
            - acceleration::<Spherical>(&m, &q, &q_dot, &force);
        assert!(d.norm() < 1e-15, "{d:?}");
    }

    /// The body torque is eq 13 inverted exactly, `(n0, n_b) = Q~*N/(2|Q|^2)`,
    /// also for a non-unit `Q`: at rest (`Q' = 0`, no velocity term, no
    /// gyroscopic term) a force `N = 2 Q*(n0, n_b)` gives
    /// `Q'' = 1/2 Q*(n0/I0, n_b/I)` whatever `|Q|`.
    #[test]
    fn body_torque_inverts_eq13_for_a_non_unit_quaternion() {
        let m = PrincipalMoments::new(Vector3::new(1.3, 2.1, 0.7));
        let q = Quat::new(0.42, -0.7, 0.84, 0.28); // |Q|^2 = 1.4^2 * 0.74
        assert!((q.norm_squared() - 1.0).abs() > 0.4);
        let torque = Quat::new(0.25, -0.6, 0.3, 1.1);
        let force = q * torque * 2.0;
        let expected =
            q * Quat::new(
                torque.scalar() * m.inverse_mean,
                torque.vector().x * m.inverse.x,
                torque.vector().y * m.inverse.y,
                torque.vector().z * m.inverse.z,
            ) * 0.5;
        let d = acceleration::<General>(&m, &q, &Quat::new(0.0, 0.0, 0.0, 0.0), &force) - expected;
        assert!(d.norm() < 1e-15 * expected.norm(), "{d:?}");
    }

    /// The norm-derivative projection holds for a non-unit `Q` too: the
    /// constraints `sum_{j=0..k} r_j.r_{k-j} = 0` are quadratic, so a scaled
    /// exact vector keeps them, and a perturbed scaled one regains them.
    #[test]
    fn norm_derivative_constraints_hold_for_a_non_unit_quaternion() {
        assert_constraints_regained(exact_free_spherical(0.1).map(|x| x * 1.3));
    }
}
