//! Start-up of the Gear schemes: the scaled derivatives at t = 0.
//!
//! A Gear method keeps its order only if the stored higher derivatives are
//! consistent with the equations of motion at t = 0. The low orders follow
//! from the equations directly: `Q' = 1/2 Q*(0, w_b)` (eq 10), `w_b'` from
//! Euler's equations with the torque at `Q`, and
//! `Q'' = Q'*Q~*Q' + 1/2 Q*(0, w_b')` (eq 12, corrected). The higher ones
//! ([`Startup::Consistent`]) come from a short accurate integration around
//! t = 0: classical Runge-Kutta (RK4, self-starting) with [`RK4_SUBSTEPS`]
//! substeps per step `h`, from t = 0 to `+-4h`, gives `Q` and `w_b` at the nine
//! times `j h`, `j = -4..4`; the polynomial of degree 8 through them, in the
//! variable `j`, has coefficients equal to the scaled derivatives
//! `r_k = h^k/k! x^(k)(0)` up to the Taylor remainder (aliasing of `r_9`,
//! negligible for `|w| h < 1`) and the RK4 error (`O((h/32)^4)` per unit time).

use super::gear::{GearValue, Nordsieck};
use super::rigid_body::{General, PrincipalMoments, Spherical, TopKind};
use super::setup::{validate_setup, Moments};
use super::torque::{evaluate_torques, torque_body};
use super::{IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::{SMatrix, Vector3};

/// RK4 substeps per Gear step in the start-up integration.
pub const RK4_SUBSTEPS: usize = 32;

/// Half-width of the symmetric sample stencil: samples at `j h`, `|j| <= 4`.
const HALF_WIDTH: usize = 4;
/// Number of samples, and degree + 1 of the fitted polynomial.
const SAMPLES: usize = 2 * HALF_WIDTH + 1;

/// How the scaled derivatives beyond those given directly by the equations
/// of motion (`Q, Q', Q''`, `w_b, w_b'`) are set at t = 0.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Startup {
    /// From an accurate integration around t = 0 and a polynomial fit
    /// (module doc). The default.
    #[default]
    Consistent,
    /// Zero (the naive start, which costs accuracy: see the tests).
    Zeros,
}

/// Scaled derivatives at t = 0, orders 0..=5, of the orientation and of the
/// body angular velocity of every rotor.
pub struct InitialDerivatives {
    /// `h^k/k! Q^(k)(0)`.
    pub q: Nordsieck<Quat, 6>,
    /// `h^k/k! w_b^(k)(0)`.
    pub omega_body: Nordsieck<Vector3<f64>, 6>,
}

/// The time derivatives of the first-order system (eqs 10 and 11 / Euler):
/// writes `Q'` and `w_b'` for every rotor. `torque_space` is scratch.
#[allow(clippy::too_many_arguments)]
fn rates<K: TopKind, P: Potential>(
    moments: &[PrincipalMoments],
    potential: &P,
    q: &[Quat],
    omega_body: &[Vector3<f64>],
    torque_space: &mut [Vector3<f64>],
    q_dot: &mut [Quat],
    omega_dot_body: &mut [Vector3<f64>],
) {
    evaluate_torques(potential, q, torque_space);
    for i in 0..q.len() {
        q_dot[i] = q[i].q_dot_from_omega_body(&omega_body[i]);
        let n_b = torque_body(&q[i], &torque_space[i]);
        omega_dot_body[i] = K::omega_dot_body(&moments[i], &omega_body[i], &n_b);
    }
}

/// The state of all rotors in the start-up integration.
#[derive(Clone)]
struct State {
    q: Vec<Quat>,
    omega_body: Vec<Vector3<f64>>,
}

impl State {
    /// `self + s * rate`.
    fn advanced(&self, rate: &State, s: f64) -> State {
        State {
            q: self
                .q
                .iter()
                .zip(&rate.q)
                .map(|(a, b)| *a + *b * s)
                .collect(),
            omega_body: self
                .omega_body
                .iter()
                .zip(&rate.omega_body)
                .map(|(a, b)| a + b * s)
                .collect(),
        }
    }
}

/// Classical RK4 integration of eqs 10 and Euler's equations (start-up only).
struct Rk4<'a, K, P> {
    moments: &'a [PrincipalMoments],
    potential: &'a P,
    torque_space: Vec<Vector3<f64>>,
    _kind: std::marker::PhantomData<K>,
}

impl<K: TopKind, P: Potential> Rk4<'_, K, P> {
    fn rate(&mut self, y: &State) -> State {
        let n = y.q.len();
        let mut rate = State {
            q: vec![Quat::ZERO; n],
            omega_body: vec![Vector3::zeros(); n],
        };
        rates::<K, P>(
            self.moments,
            self.potential,
            &y.q,
            &y.omega_body,
            &mut self.torque_space,
            &mut rate.q,
            &mut rate.omega_body,
        );
        rate
    }

    fn step(&mut self, y: &State, dt: f64) -> State {
        let k1 = self.rate(y);
        let k2 = self.rate(&y.advanced(&k1, 0.5 * dt));
        let k3 = self.rate(&y.advanced(&k2, 0.5 * dt));
        let k4 = self.rate(&y.advanced(&k3, dt));
        y.advanced(&k1, dt / 6.0)
            .advanced(&k2, dt / 3.0)
            .advanced(&k3, dt / 3.0)
            .advanced(&k4, dt / 6.0)
    }
}

/// The inverse of the Vandermonde matrix `V[j][k] = (j - 4)^k`: maps the nine
/// samples to the coefficients of the interpolating polynomial in `j`.
fn fit_matrix() -> SMatrix<f64, SAMPLES, SAMPLES> {
    let v = SMatrix::<f64, SAMPLES, SAMPLES>::from_fn(|j, k| {
        (j as f64 - HALF_WIDTH as f64).powi(k as i32)
    });
    v.try_inverse()
        .expect("a Vandermonde matrix with distinct nodes is invertible")
}

/// Overwrites the orders `from..6` of `target` with the polynomial fit of
/// `samples[j][rotor]` (sample `j` at time `(j - 4) h`).
fn fit_into<T: GearValue>(
    fit: &SMatrix<f64, SAMPLES, SAMPLES>,
    samples: &[Vec<T>],
    from: usize,
    target: &mut Nordsieck<T, 6>,
) {
    for (k, r_k) in target.r.iter_mut().enumerate().skip(from) {
        for (i, r) in r_k.iter_mut().enumerate() {
            let mut value = T::ZERO;
            for (j, sample) in samples.iter().enumerate() {
                value = value + sample[i] * fit[(k, j)];
            }
            *r = value;
        }
    }
}

/// The scaled derivatives at t = 0 for steps of `dt` (module doc). The
/// initial orientations are used as given (the caller normalises them).
pub fn initial_derivatives<K: TopKind, P: Potential>(
    startup: Startup,
    moments: &[PrincipalMoments],
    potential: &P,
    initial: &[RotorState],
    dt: f64,
) -> InitialDerivatives {
    let n = initial.len();
    let y0 = State {
        q: initial.iter().map(|s| s.orientation).collect(),
        omega_body: initial.iter().map(|s| s.omega_body).collect(),
    };
    let mut rk = Rk4::<K, P> {
        moments,
        potential,
        torque_space: vec![Vector3::zeros(); n],
        _kind: std::marker::PhantomData,
    };
    let rate0 = rk.rate(&y0);
    let mut out = InitialDerivatives {
        q: Nordsieck::zeros(n),
        omega_body: Nordsieck::zeros(n),
    };
    if startup == Startup::Consistent {
        let mut samples = vec![y0.clone(); SAMPLES];
        for direction in [1.0, -1.0] {
            let substep = direction * dt / RK4_SUBSTEPS as f64;
            let mut y = y0.clone();
            for j in 1..=HALF_WIDTH {
                for _ in 0..RK4_SUBSTEPS {
                    y = rk.step(&y, substep);
                }
                let index = if direction > 0.0 {
                    HALF_WIDTH + j
                } else {
                    HALF_WIDTH - j
                };
                samples[index] = y.clone();
            }
        }
        let fit = fit_matrix();
        let q_samples: Vec<Vec<Quat>> = samples.iter().map(|s| s.q.clone()).collect();
        let w_samples: Vec<Vec<Vector3<f64>>> =
            samples.iter().map(|s| s.omega_body.clone()).collect();
        fit_into(&fit, &q_samples, 3, &mut out.q);
        fit_into(&fit, &w_samples, 2, &mut out.omega_body);
    }
    // The orders given directly by the equations of motion, exactly.
    for i in 0..n {
        let (q, q_dot) = (y0.q[i], rate0.q[i]);
        let q_ddot = q_dot * q.conjugate() * q_dot + q * Quat::pure(&rate0.omega_body[i]) * 0.5;
        out.q.r[0][i] = q;
        out.q.r[1][i] = q_dot * dt;
        out.q.r[2][i] = q_ddot * (0.5 * dt * dt);
        out.omega_body.r[0][i] = y0.omega_body[i];
        out.omega_body.r[1][i] = rate0.omega_body[i] * dt;
    }
    out
}

/// What a Gear scheme's setup computes from its arguments.
pub struct GearStart {
    /// The principal moments of every rotor.
    pub moments: Vec<PrincipalMoments>,
    /// True when every rotor is a spherical top (the step is then
    /// monomorphised on [`Spherical`], otherwise on [`General`]).
    pub spherical: bool,
    /// The scaled derivatives at t = 0, from the normalised initial states.
    pub derivatives: InitialDerivatives,
}

/// The shared setup of the Gear schemes: validates the arguments (every moment
/// must be > 0, since the schemes divide by each) and computes the scaled
/// derivatives at t = 0 for steps of `dt`.
pub fn start<P: Potential>(
    startup: Startup,
    inertia: &[Inertia],
    potential: &P,
    initial: &[RotorState],
    dt: f64,
) -> Result<GearStart, IntegratorError> {
    let valid = validate_setup(inertia, initial, dt, Moments::Positive)?;
    let moments: Vec<PrincipalMoments> = valid
        .moments
        .into_iter()
        .map(PrincipalMoments::new)
        .collect();
    let spherical = inertia.iter().all(Inertia::is_spherical);
    let derivatives = if spherical {
        initial_derivatives::<Spherical, P>(startup, &moments, potential, &valid.initial, dt)
    } else {
        initial_derivatives::<General, P>(startup, &moments, potential, &valid.initial, dt)
    };
    Ok(GearStart {
        moments,
        spherical,
        derivatives,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::Free;

    /// Agreement of the fitted scaled derivatives with the exact ones: RK4
    /// error `~ (h/32)^4 |w|^5 4h` plus rounding amplified by the fit (~1e3 eps).
    const FIT_TOLERANCE: f64 = 1e-12;

    /// For a free spherical top, `Q^(k) = Q0*(W/2)^k` and `w_b` is constant:
    /// the consistent start-up recovers these up to the fifth derivative, and
    /// the zero start-up keeps only the orders given by the equations.
    #[test]
    fn consistent_startup_recovers_exact_free_spherical_derivatives() {
        let q0 = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let w = Vector3::new(0.7, -1.1, 0.9);
        let h = 0.05;
        let initial = [RotorState {
            orientation: q0,
            omega_body: w,
        }];
        let moments = [PrincipalMoments::new(Vector3::repeat(1.3))];
        let half_w = Quat::pure(&w) * (0.5 * h);
        let mut exact = [q0; 6];
        for k in 1..6 {
            exact[k] = exact[k - 1] * half_w * (1.0 / k as f64);
        }
        let consistent =
            initial_derivatives::<Spherical, _>(Startup::Consistent, &moments, &Free, &initial, h);
        let general =
            initial_derivatives::<General, _>(Startup::Consistent, &moments, &Free, &initial, h);
        for d in [&consistent, &general] {
            for (k, e) in exact.iter().enumerate() {
                assert!((d.q.r[k][0] - *e).norm() < FIT_TOLERANCE, "Q order {k}");
            }
            assert_eq!(d.omega_body.r[0][0], w);
            for k in 1..6 {
                assert!(d.omega_body.r[k][0].norm() < FIT_TOLERANCE, "w order {k}");
            }
        }
        let zeros =
            initial_derivatives::<Spherical, _>(Startup::Zeros, &moments, &Free, &initial, h);
        for (k, e) in exact.iter().enumerate() {
            let expected = if k <= 2 { *e } else { Quat::ZERO };
            assert!(
                (zeros.q.r[k][0] - expected).norm() < 1e-15,
                "zeros, Q order {k}"
            );
        }
    }
}
