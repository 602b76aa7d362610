//! Start-up of the Gear schemes: the scaled derivatives at t = 0.
//!
//! A Gear method keeps its order only if the stored higher derivatives are
//! consistent with the equations of motion at t = 0. The low orders follow
//! from the equations directly: `Q' = 1/2 Q*(0, w_b)` (eq 10), `w_b'` from
//! Euler's equations with the torque at `Q`, and
//! `Q'' = Q'*Q~*Q' + 1/2 Q*(0, w_b')` (eq 12, corrected). The higher ones
//! ([`Startup::Consistent`]) come from a short accurate integration around
//! t = 0: classical Runge-Kutta (RK4, self-starting) with [`RK4_SUBSTEPS`] = 2
//! substeps `s = h/2` per step `h`, from t = 0 to `+-4h`, gives `Q` and `w_b`
//! at the nine times `j h`, `j = -4..4`; the polynomial of degree 8 through
//! them, in the variable `j`, has coefficients equal to the scaled derivatives
//! `r_k = h^k/k! x^(k)(0)` up to the RK4 error and the aliasing of the Taylor
//! terms of degree >= 9.
//!
//! Cost: `2 * 4 * 2 * 4 + 1 = 65` torque evaluations once per run (two
//! directions, 4 steps `h` each, 2 RK4 substeps of 4 stages each, plus the
//! rates at t = 0), whatever `h` and the number of rotors.
//!
//! Error. RK4's global error has an asymptotic expansion in the substep,
//! `e(t) = s^4 e_4(t) + s^5 e_5(t) + ...` with smooth `e_i`, `e_i(0) = 0`
//! (Hairer, Norsett and Wanner, Solving ODEs I, 2nd ed., Thm II.8.1).
//! Integrating backwards (`s -> -s`) keeps the `s^4` term and flips the `s^5`
//! one, so the samples lie on a smooth perturbed trajectory plus a kink
//! `~ s^5 |t|`. The fit returns the scaled derivatives of the smooth part, an
//! error in `r_k` of relative size `~ (w s)^4` for the fastest frequency `w` of
//! the motion (for a rotation exactly a frequency shift, `k (w s)^4/120`);
//! the kink adds to the even orders the coefficients of `|j|`'s interpolant,
//! `533/420` to `r_2` and `-43/144` to `r_4`, times its size at `t = h`,
//! `~ (w h)(w s)^5/144` (RK4's amplitude error for a rotation). The fit
//! amplifies neither (the rows of the inverse Vandermonde matrix have
//! absolute sums <= 3.3, which also bounds the amplification of rounding).
//! Aliasing puts `r_9` into `r_3` with the factor 820 (`j^9` interpolated on
//! the nine nodes), `~ 2e-3 (w h)^9`, whatever the substeps. All are far below
//! the Gear step's own local error `O((w h)^6)`, but their effect on the
//! global error depends on how each scheme's corrector damps them: the
//! substep count was set by measuring it.
//!
//! Why 2 substeps (measured; 32 would cost 1025 torque evaluations). Gear
//! runs started with `m` substeps were compared with runs
//! started with 256 (64 on the lattice), for schemes A, B and B with the
//! higher-derivative correction, on the free asymmetric top and the dipole in
//! a field (spherical and asymmetric) of the scipy references, the free
//! symmetric top (closed form), the 2 x 2 x 2 multipole cluster of the Gear
//! tests (t = 10, h = 0.0125..0.2) and the 1000-rotor dipole lattice
//! (t = 0.4, h = 0.001..0.016). The start-up's share of the global
//! orientation error falls as `m^-4` to `m^-4.7`. Divided by the Gear error
//! itself (against scipy, the closed form, or scheme A with h = 1/640 on the
//! cluster and 1e-4 on the lattice) it is at most 1.3e-2 for `m = 1`, 2.9e-4
//! for `m = 2` (the lattice at h = 0.016 with the higher-derivative
//! correction, whose own error is the smallest) and 2.2e-5 for `m = 4`, until
//! all reach the rounding level (~1e-13 rad; 32 substeps are within 3e-11 rad
//! of the 256-substep runs everywhere). Two substeps leave every
//! Gear error unchanged to three digits. Seven samples (`+-3h`, degree 6)
//! would save a quarter of the cost but alias `r_7` into `r_3` with the
//! factor 49, which changed Gear errors by up to 20 % at h = 0.2: the nine
//! samples stay.

use super::gear::{GearValue, Nordsieck};
use super::rigid_body::{q_ddot, General, PrincipalMoments, Spherical, TopKind};
use super::rotor_chunks::ROTORS_PER_TASK;
use super::setup_checks::{validate_setup, Moments};
use super::torque::{evaluate_torques, torque_body};
use super::{GoOn, IntegratorError, RotorState};
use crate::checks::named_choices;
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use crate::thermostat_hook::{ChainEquations, CoupledDegrees};
use nalgebra::{SMatrix, Vector3};
use rayon::prelude::*;

/// RK4 substeps per Gear step in the start-up integration (module doc: the
/// measured choice).
pub const RK4_SUBSTEPS: usize = 2;

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

named_choices!(Startup {
    "consistent" => Startup::Consistent,
    "zeros" => Startup::Zeros,
});

/// Scaled derivatives at t = 0, orders 0..=5, of the orientation and of the
/// body angular velocity of every rotor (with the friction of a thermostat
/// chain, if any, integrated with them).
pub struct InitialDerivatives {
    /// `h^k/k! Q^(k)(0)`.
    pub q: Nordsieck<Quat, 6>,
    /// `h^k/k! w_b^(k)(0)`.
    pub omega_body: Nordsieck<Vector3<f64>, 6>,
}

/// The state of all rotors (and of the chain, if any) in the start-up
/// integration, or its rate of change.
#[derive(Clone)]
struct State {
    q: Vec<Quat>,
    omega_body: Vec<Vector3<f64>>,
    /// Chain positions `eta_j` (empty without a chain).
    eta: Vec<f64>,
    /// Chain momenta `p_j` (empty without a chain).
    p: Vec<f64>,
}

/// A state integrated by [`rk4_step`]: a vector space over `f64`.
pub(crate) trait Rk4State: Clone {
    /// `self + s * rate`.
    fn advanced(&self, rate: &Self, s: f64) -> Self;
}

/// `a + s b`, element by element (in parallel, [`ROTORS_PER_TASK`] elements
/// a task: each element as on one thread).
pub(crate) fn axpy<T: GearValue + Send + Sync>(a: &[T], b: &[T], s: f64) -> Vec<T> {
    a.par_iter()
        .zip(b)
        .with_min_len(ROTORS_PER_TASK)
        .map(|(a, b)| *a + *b * s)
        .collect()
}

impl State {
    /// All zeros, shaped as `like`.
    fn zeros_like(like: &State) -> State {
        State {
            q: vec![Quat::ZERO; like.q.len()],
            omega_body: vec![Vector3::zeros(); like.q.len()],
            eta: vec![0.0; like.eta.len()],
            p: vec![0.0; like.p.len()],
        }
    }
}

impl Rk4State for State {
    fn advanced(&self, rate: &State, s: f64) -> State {
        State {
            q: axpy(&self.q, &rate.q, s),
            omega_body: axpy(&self.omega_body, &rate.omega_body, s),
            eta: axpy(&self.eta, &rate.eta, s),
            p: axpy(&self.p, &rate.p, s),
        }
    }
}

/// One classical RK4 step of `dt` of `y' = rate(y)`.
pub(crate) fn rk4_step<S: Rk4State>(y: &S, dt: f64, mut rate: impl FnMut(&S) -> S) -> S {
    let k1 = rate(y);
    let k2 = rate(&y.advanced(&k1, 0.5 * dt));
    let k3 = rate(&y.advanced(&k2, 0.5 * dt));
    let k4 = rate(&y.advanced(&k3, dt));
    y.advanced(&k1, dt / 6.0)
        .advanced(&k2, dt / 3.0)
        .advanced(&k3, dt / 3.0)
        .advanced(&k4, dt / 6.0)
}

/// The nine states at `j dt`, `j = -4..4`, of `y' = rate(y)` from `y0`
/// at 0, by [`RK4_SUBSTEPS`] RK4 substeps per `dt` (module doc).
pub(crate) fn samples<S: Rk4State>(y0: &S, dt: f64, mut rate: impl FnMut(&S) -> S) -> Vec<S> {
    let mut samples = vec![y0.clone(); SAMPLES];
    for direction in [1.0, -1.0] {
        let substep = direction * dt / RK4_SUBSTEPS as f64;
        let mut y = y0.clone();
        for j in 1..=HALF_WIDTH {
            for _ in 0..RK4_SUBSTEPS {
                y = rk4_step(&y, substep, &mut rate);
            }
            let index = if direction > 0.0 {
                HALF_WIDTH + j
            } else {
                HALF_WIDTH - j
            };
            samples[index] = y.clone();
        }
    }
    samples
}

/// Classical RK4 integration of eqs 10 and Euler's equations, with the
/// chain's friction and equations when there is one (start-up only).
struct Rk4<'a, K> {
    moments: &'a [PrincipalMoments],
    potential: &'a dyn Potential,
    chain: Option<StartChain<'a>>,
    torque_space: Vec<Vector3<f64>>,
    _kind: std::marker::PhantomData<K>,
}

impl<K: TopKind> Rk4<'_, K> {
    /// The time derivatives of the first-order system (eqs 10 and 11 /
    /// Euler, minus the chain's friction `p_1/Q_1 w_b`, and the chain's
    /// equations).
    fn rate(&mut self, y: &State) -> State {
        let mut rate = State::zeros_like(y);
        evaluate_torques(self.potential, &y.q, &mut self.torque_space);
        let (torque_space, moments) = (&self.torque_space, self.moments);
        rate.q
            .par_iter_mut()
            .zip(&mut rate.omega_body)
            .enumerate()
            .with_min_len(ROTORS_PER_TASK)
            .for_each(|(i, (q_dot, w_dot))| {
                *q_dot = y.q[i].q_dot_from_omega_body(&y.omega_body[i]);
                let n_b = torque_body(&y.q[i], &torque_space[i]);
                *w_dot = K::omega_dot_body(&moments[i], &y.omega_body[i], &n_b);
            });
        if let Some(StartChain { chain, coupled }) = self.chain {
            let friction = chain.friction(&y.p);
            for (i, (w_dot, w)) in rate.omega_body.iter_mut().zip(&y.omega_body).enumerate() {
                *w_dot -= coupled.coupled(i, w) * friction;
            }
            let principal: Vec<Vector3<f64>> = self.moments.iter().map(|m| m.moments).collect();
            let kinetic = coupled.kinetic_energy_of(&principal, &y.omega_body);
            chain.rates(&y.p, kinetic, &mut rate.eta, &mut rate.p);
        }
        rate
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
/// the quantity `of` of the nine states (sample `j` at time
/// `(j - 4) h`, as [`samples`] returns them).
pub(crate) fn fit_into<S, T: GearValue>(
    samples: &[S],
    of: impl Fn(&S) -> &Vec<T>,
    from: usize,
    target: &mut Nordsieck<T, 6>,
) {
    let fit = fit_matrix();
    for (k, r_k) in target.r.iter_mut().enumerate().skip(from) {
        for (i, r) in r_k.iter_mut().enumerate() {
            let mut value = T::ZERO;
            for (j, sample) in samples.iter().enumerate() {
                value = value + of(sample)[i] * fit[(k, j)];
            }
            *r = value;
        }
    }
}

/// A thermostat chain integrated with the rotors: its equations and state,
/// and the degrees of freedom it acts on.
#[derive(Clone, Copy, Debug)]
pub struct StartChain<'a> {
    /// The chain (its state at t = 0).
    pub chain: &'a dyn ChainEquations,
    /// The thermostatted degrees of freedom.
    pub coupled: &'a CoupledDegrees,
}

/// The scaled derivatives at t = 0 for steps of `dt` (module doc), with the
/// Nose-Hoover chain `chain` (its masses, and its state at t = 0) integrated
/// with the rotors if given. The initial orientations are used as given (the
/// caller normalises them).
pub fn initial_derivatives<K: TopKind>(
    startup: Startup,
    moments: &[PrincipalMoments],
    potential: &dyn Potential,
    initial: &[RotorState],
    chain: Option<StartChain<'_>>,
    dt: f64,
) -> InitialDerivatives {
    let n = initial.len();
    let y0 = State {
        q: initial.iter().map(|s| s.orientation).collect(),
        omega_body: initial.iter().map(|s| s.omega_body).collect(),
        eta: chain
            .map(|c| c.chain.positions().to_vec())
            .unwrap_or_default(),
        p: chain
            .map(|c| c.chain.momenta().to_vec())
            .unwrap_or_default(),
    };
    let mut rk = Rk4::<K> {
        moments,
        potential,
        chain,
        torque_space: vec![Vector3::zeros(); n],
        _kind: std::marker::PhantomData,
    };
    let rate0 = rk.rate(&y0);
    let mut out = InitialDerivatives {
        q: Nordsieck::zeros(n),
        omega_body: Nordsieck::zeros(n),
    };
    if startup == Startup::Consistent {
        let samples = samples(&y0, dt, |y| rk.rate(y));
        fit_into(&samples, |s| &s.q, 3, &mut out.q);
        fit_into(&samples, |s| &s.omega_body, 2, &mut out.omega_body);
    }
    // The orders given directly by the equations of motion, exactly.
    for i in 0..n {
        let (q, q_dot) = (y0.q[i], rate0.q[i]);
        let acceleration = q_ddot(&q, &q_dot, &Quat::pure(&rate0.omega_body[i]));
        out.q.r[0][i] = q;
        out.q.r[1][i] = q_dot * dt;
        out.q.r[2][i] = acceleration * (0.5 * dt * dt);
        out.omega_body.r[0][i] = y0.omega_body[i];
        out.omega_body.r[1][i] = rate0.omega_body[i] * dt;
    }
    out
}

/// What a Gear scheme keeps from its setup besides its Nordsieck vectors.
#[derive(Clone, Debug, Default)]
pub struct GearFrame {
    /// The time step.
    pub dt: f64,
    /// The principal moments of every rotor.
    pub moments: Vec<PrincipalMoments>,
    /// True when every rotor is a spherical top (the step is then
    /// monomorphised on [`Spherical`], otherwise on [`General`]).
    pub spherical: bool,
}

/// A Gear scheme's step, monomorphised on the kind of top.
pub trait TopStep {
    /// What the scheme kept from its setup.
    fn frame(&self) -> &GearFrame;

    /// One step for rotors of kind `K`: the predictor first unless the
    /// previous step's last pass ran it (`predicted`); that pass ends with
    /// the next step's predictor when `next()` (asked once, before it) says
    /// a step follows. Returns whether it did.
    fn step_with<K: TopKind>(
        &mut self,
        potential: &dyn Potential,
        predicted: bool,
        next: &mut dyn FnMut() -> bool,
    ) -> bool;

    /// [`super::Integrator::step`] ([`Self::steps_by_top`] of one step).
    fn step_by_top(&mut self, potential: &dyn Potential) {
        let _one: u64 = self.steps_by_top(potential, 1, &mut |_| false);
    }

    /// [`super::Integrator::steps`], each step on [`Spherical`] when every rotor
    /// is a spherical top and on [`General`] otherwise: the predictor of
    /// each step after the first runs in the previous step's last pass.
    fn steps_by_top(&mut self, potential: &dyn Potential, count: u64, go_on: GoOn<'_>) -> u64 {
        let mut taken = 0;
        let mut predicted = false;
        loop {
            taken += 1;
            let mut next = || taken < count && go_on(taken);
            predicted = if self.frame().spherical {
                self.step_with::<Spherical>(potential, predicted, &mut next)
            } else {
                self.step_with::<General>(potential, predicted, &mut next)
            };
            if !predicted {
                return taken;
            }
        }
    }
}

/// What a Gear scheme's setup computes from its arguments.
pub struct GearStart {
    /// The step, the principal moments and the kind of top.
    pub frame: GearFrame,
    /// The scaled derivatives at t = 0, from the normalised initial states.
    pub derivatives: InitialDerivatives,
}

/// The shared setup of the Gear schemes: validates the arguments (every moment
/// must be > 0, since the schemes divide by each) and computes the scaled
/// derivatives at t = 0 for steps of `dt`, with the chain `chain` if given.
pub fn start(
    startup: Startup,
    inertia: &[Inertia],
    potential: &dyn Potential,
    initial: &[RotorState],
    chain: Option<StartChain<'_>>,
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
        initial_derivatives::<Spherical>(startup, &moments, potential, &valid.initial, chain, dt)
    } else {
        initial_derivatives::<General>(startup, &moments, potential, &valid.initial, chain, dt)
    };
    Ok(GearStart {
        frame: GearFrame {
            dt,
            moments,
            spherical,
        },
        derivatives,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::Free;

    /// Agreement of the fitted scaled derivatives with the exact ones for the
    /// spherical test below (`h |w|/2 = 0.04`, `s = h/2`; module doc): the
    /// frequency shift puts `4e-14` into `r_3`, the kink `2.5e-13` into `r_4`
    /// (one substep would put `8e-12` there), rounding ~1e-14.
    const FIT_TOLERANCE: f64 = 1e-12;
    /// Rounding in the fitted derivatives: samples of unit norm after at most
    /// 8 RK4 steps (~10 eps), times the fit's row sums (<= 3.3), with margin.
    const FIT_ROUNDING: f64 = 1e-13;
    /// Factor on the error model of the module doc (frequency shift, kink,
    /// aliasing) for a top whose motion combines two frequencies, bounded by
    /// their sum `w`.
    const MODEL_SAFETY: f64 = 2.0;
    /// The kink's share of each order: the coefficients of the degree-8
    /// interpolant of `|j|` on `j = -4..4` (exact fractions, module doc).
    const KINK: [f64; 6] = [0.0, 0.0, 533.0 / 420.0, 0.0, 43.0 / 144.0, 0.0];

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
        let consistent = initial_derivatives::<Spherical>(
            Startup::Consistent,
            &moments,
            &Free,
            &initial,
            None,
            h,
        );
        let general =
            initial_derivatives::<General>(Startup::Consistent, &moments, &Free, &initial, None, h);
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
            initial_derivatives::<Spherical>(Startup::Zeros, &moments, &Free, &initial, None, h);
        for (k, e) in exact.iter().enumerate() {
            let expected = if k <= 2 { *e } else { Quat::ZERO };
            assert!(
                (zeros.q.r[k][0] - expected).norm() < 1e-15,
                "zeros, Q order {k}"
            );
        }
    }

    /// `x^k/k!`.
    fn scaled_power(x: f64, k: usize) -> f64 {
        (1..=k).fold(1.0, |p, j| p * x / j as f64)
    }

    /// The allowed error of `r_k` (module doc's error model) for a motion of
    /// amplitude `size` and frequencies summing to at most `w`, step `h`.
    fn model_tolerance(size: f64, w: f64, h: f64, k: usize) -> f64 {
        let s = h / RK4_SUBSTEPS as f64;
        let shift = k as f64 * (s * w).powi(4) / 120.0 * scaled_power(h * w, k);
        let kink = KINK[k] * h * w * (s * w).powi(5) / 144.0;
        let aliasing = 820.0 * scaled_power(h * w, 9);
        MODEL_SAFETY * size * (shift + kink + aliasing) + FIT_ROUNDING
    }

    /// Free symmetric top `I1 = I2 != I3` in closed form:
    /// `Q(t) = exp(t A) Q0 exp(t B)` with the pure quaternions
    /// `A = (0, L_s/(2 I1))` (precession about the space-fixed angular
    /// momentum) and `B = (0, -Omega e3/2)`, `Omega = (I3 - I1) w3/I1`, so
    /// `r_k = sum_j (hA)^j/j! Q0 (hB)^(k-j)/(k-j)!`; and
    /// `w1 + i w2 = (w1 + i w2)(0) exp(i Omega t)` with `w3` constant, so
    /// `r_k` of `w_b` is `(h Omega)^k/k!` times `(w1, w2)` turned by `k` right
    /// angles. The consistent start-up matches both, the orders given by the
    /// equations to rounding and the fitted ones within the error model, at
    /// `|w| h ~ 0.2` where the model's terms are far above rounding.
    #[test]
    fn consistent_startup_matches_free_symmetric_top_closed_form() {
        let (i1, i3) = (1.0, 2.5);
        let q0 = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let w = Vector3::new(0.7, -1.1, 0.9);
        let h = 0.1;
        let l_space = q0.body_to_space(&Vector3::new(i1 * w.x, i1 * w.y, i3 * w.z));
        let omega = (i3 - i1) / i1 * w.z;
        let a = Quat::pure(&(l_space * (0.5 * h / i1)));
        let b = Quat::pure(&Vector3::new(0.0, 0.0, -0.5 * omega * h));
        let powers = |x: Quat| {
            let mut p = [Quat::IDENTITY; 6];
            for k in 1..6 {
                p[k] = p[k - 1] * x * (1.0 / k as f64);
            }
            p
        };
        let (a_k, b_k) = (powers(a), powers(b));
        let moments = [PrincipalMoments::new(Vector3::new(i1, i1, i3))];
        let initial = [RotorState {
            orientation: q0,
            omega_body: w,
        }];
        let d =
            initial_derivatives::<General>(Startup::Consistent, &moments, &Free, &initial, None, h);
        let w_q = a.norm() / h + b.norm() / h;
        let mut perpendicular = Vector3::new(w.x, w.y, 0.0);
        for k in 0..6 {
            let exact = (0..=k).fold(Quat::ZERO, |sum, j| sum + a_k[j] * q0 * b_k[k - j]);
            let error = (d.q.r[k][0] - exact).norm();
            let tolerance = if k < 3 {
                FIT_ROUNDING
            } else {
                model_tolerance(1.0, w_q, h, k)
            };
            assert!(
                error < tolerance,
                "Q order {k}: {error:.2e} > {tolerance:.2e}"
            );
            let exact = perpendicular * scaled_power(omega * h, k)
                + Vector3::new(0.0, 0.0, if k == 0 { w.z } else { 0.0 });
            let error = (d.omega_body.r[k][0] - exact).norm();
            let tolerance = if k < 2 {
                FIT_ROUNDING
            } else {
                model_tolerance(perpendicular.norm(), omega.abs(), h, k)
            };
            assert!(
                error < tolerance,
                "w order {k}: {error:.2e} > {tolerance:.2e}"
            );
            perpendicular = Vector3::new(-perpendicular.y, perpendicular.x, 0.0);
        }
    }
}
