//! Gear predictor-corrector machinery shared by schemes A and B (Gear 1971,
//! ref 5 of the note), on scaled derivatives (Nordsieck vectors)
//! `r_k = h^k/k! d^k x/dt^k`, `k = 0..N-1`.
//!
//! * **Predict** (a Taylor series): `r_j <- sum_{k >= j} C(k, j) r_k`, done in
//!   place by the Pascal triangle (repeated pairwise additions).
//! * **Correct** an equation of order `m` (1 or 2) with right-hand side `f`
//!   evaluated at the predicted values: `delta = h^m/m! f - r_m`, then
//!   `r_k <- r_k + c_k delta` with the coefficient tables below.
//!
//! Both act on each rotor on its own, so the schemes run them per chunk of
//! rotors ([`NordsieckChunk`]) across the rayon pool.

use super::checkpoint::{read_values, write_values, Components};
use super::rotor_chunks::RotorChunk;
use crate::quaternion::Quat;
use nalgebra::Vector3;
use std::ops::{Add, Mul, Sub};

/// Corrector for first-order equations with 5 stored values (scheme A):
/// `251/720, 1, 11/12, 1/3, 1/24` (Gear's table; the `c_0` of the Adams-Moulton
/// 4-step formula in Nordsieck form).
pub const FIRST_ORDER_5: [f64; 5] = [251.0 / 720.0, 1.0, 11.0 / 12.0, 1.0 / 3.0, 1.0 / 24.0];

/// First corrector coefficient of the 6-value second-order table when the
/// right-hand side depends on the first derivative (as eq 12 does).
pub const C0_VELOCITY_DEPENDENT: f64 = 3.0 / 16.0;

/// First corrector coefficient of the 6-value second-order table for
/// right-hand sides that depend on the position only.
pub const C0_POSITION_ONLY: f64 = 3.0 / 20.0;

/// Corrector for second-order equations with 6 stored values (scheme B):
/// `c0, 251/360, 1, 11/18, 1/6, 1/60`.
pub fn second_order_6(c0: f64) -> [f64; 6] {
    [c0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0]
}

/// A value a Gear recursion acts on (a quaternion or a 3-vector).
pub trait GearValue:
    Components + Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
    /// The zero value.
    const ZERO: Self;
}

impl GearValue for Quat {
    const ZERO: Self = Quat::ZERO;
}

/// A scalar (the variables of a Nose-Hoover chain).
impl GearValue for f64 {
    const ZERO: Self = 0.0;
}

impl GearValue for Vector3<f64> {
    const ZERO: Self = Vector3::new(0.0, 0.0, 0.0);
}

/// The scaled derivatives `r_0..r_{N-1}` of one quantity for every rotor,
/// stored derivative-major (`r[k][rotor]`) so that `r[0]` is the contiguous
/// slice of current values.
#[derive(Clone, Debug, PartialEq)]
pub struct Nordsieck<T, const N: usize> {
    /// `r[k][i] = h^k/k! x_i^(k)`.
    pub r: [Vec<T>; N],
}

impl<T: GearValue, const N: usize> Nordsieck<T, N> {
    /// All zeros, for `n` rotors.
    pub fn zeros(n: usize) -> Self {
        Nordsieck {
            r: std::array::from_fn(|_| vec![T::ZERO; n]),
        }
    }

    /// The number of rotors.
    pub fn len(&self) -> usize {
        self.r[0].len()
    }

    /// True when there are no rotors.
    pub fn is_empty(&self) -> bool {
        self.r[0].is_empty()
    }

    /// All rotors as one chunk, for the per-rotor passes.
    pub fn as_chunk(&mut self) -> NordsieckChunk<'_, T, N> {
        NordsieckChunk {
            r: self.r.each_mut().map(|r_k| r_k.as_mut_slice()),
        }
    }

    /// The Taylor predictor for every rotor ([`NordsieckChunk::predict`]).
    pub fn predict(&mut self) {
        self.as_chunk().predict();
    }

    /// The corrector for rotor `i` ([`NordsieckChunk::correct`]).
    pub fn correct(&mut self, i: usize, coefficients: &[f64; N], delta: T) {
        self.as_chunk().correct(i, coefficients, delta);
    }

    /// The `N` scaled derivatives of rotor `i`.
    pub fn rotor(&self, i: usize) -> [T; N] {
        std::array::from_fn(|k| self.r[k][i])
    }

    /// Overwrites the `N` scaled derivatives of rotor `i`.
    pub fn set_rotor(&mut self, i: usize, values: &[T; N]) {
        self.as_chunk().set_rotor(i, values);
    }

    /// The values of every rotor at the time `t + x h`, `t` the time of
    /// the scaled derivatives (their Taylor polynomial, by Horner's rule),
    /// into `out`.
    pub fn values_at(&self, x: f64, out: &mut [T]) {
        for (i, value) in out.iter_mut().enumerate() {
            *value = self.r.iter().rev().fold(T::ZERO, |acc, r| acc * x + r[i]);
        }
    }

    /// The first `M <= N` scaled derivatives (a lower-order copy).
    pub fn truncated<const M: usize>(&self) -> Nordsieck<T, M> {
        Nordsieck {
            r: std::array::from_fn(|k| self.r[k].clone()),
        }
    }

    /// The length of [`Nordsieck::write_flat`]'s output.
    pub fn flat_len(&self) -> usize {
        N * self.len() * T::LEN
    }

    /// Appends every component, derivative-major.
    pub fn write_flat(&self, out: &mut Vec<f64>) {
        for r_k in &self.r {
            write_values(r_k, out);
        }
    }

    /// Reads back [`Nordsieck::write_flat`]'s output; `data` must hold at
    /// least [`Nordsieck::flat_len`] values. Returns the rest.
    pub fn read_flat<'a>(&mut self, data: &'a [f64]) -> &'a [f64] {
        self.r
            .iter_mut()
            .fold(data, |rest, r_k| read_values(rest, r_k))
    }
}

/// The scaled derivatives of a run of consecutive rotors, borrowed from a
/// [`Nordsieck`] (index `i` here is the run's `i`-th rotor): the Gear
/// recursions on one task's share of the rotors.
#[derive(Debug)]
pub struct NordsieckChunk<'a, T, const N: usize> {
    /// `r[k][i] = h^k/k! x_i^(k)` for the rotors of the chunk.
    pub r: [&'a mut [T]; N],
}

impl<T: GearValue, const N: usize> NordsieckChunk<'_, T, N> {
    /// The Taylor predictor, in place, by the Pascal triangle, one rotor at
    /// a time (its `N` values stay in registers: one pass over memory).
    pub fn predict(&mut self) {
        for i in 0..self.r[0].len() {
            let mut r = self.rotor(i);
            for j in 0..N - 1 {
                for k in (j..N - 1).rev() {
                    r[k] = r[k] + r[k + 1];
                }
            }
            self.set_rotor(i, &r);
        }
    }

    /// The corrector for rotor `i`: `r_k <- r_k + c_k delta`.
    pub fn correct(&mut self, i: usize, coefficients: &[f64; N], delta: T) {
        for (r_k, c_k) in self.r.iter_mut().zip(coefficients) {
            r_k[i] = r_k[i] + delta * *c_k;
        }
    }

    /// The `N` scaled derivatives of rotor `i`.
    pub fn rotor(&self, i: usize) -> [T; N] {
        std::array::from_fn(|k| self.r[k][i])
    }

    /// Overwrites the `N` scaled derivatives of rotor `i`.
    pub fn set_rotor(&mut self, i: usize, values: &[T; N]) {
        for (r_k, v) in self.r.iter_mut().zip(values) {
            r_k[i] = *v;
        }
    }
}

/// The corrector of a coupled pair of first-order equations `x' = g(y)`,
/// `y' = f` (5 values each, [`FIRST_ORDER_5`]), for rotor `i` of the chunks:
/// `y` first, with its rate `y_dot` at the predicted values, then `x` with
/// `x_dot` of the corrected `y` (the note's steps (d)-(f) of scheme A, where
/// `x = Q`, `y = w_b`; Allen and Tildesley's translational pair `x = r`,
/// `y = v`, `v' = F/m`, `r' = v`).
pub fn correct_pair<X: GearValue, Y: GearValue>(
    x: &mut NordsieckChunk<'_, X, 5>,
    y: &mut NordsieckChunk<'_, Y, 5>,
    i: usize,
    y_dot: Y,
    x_dot: impl Fn(&Y) -> X,
    h: f64,
) {
    let delta_y = y_dot * h - y.r[1][i];
    y.correct(i, &FIRST_ORDER_5, delta_y);
    let delta_x = x_dot(&y.r[0][i]) * h - x.r[1][i];
    x.correct(i, &FIRST_ORDER_5, delta_x);
}

impl<T: Send, const N: usize> RotorChunk for NordsieckChunk<'_, T, N> {
    fn rotors(&self) -> usize {
        self.r[0].len()
    }

    /// Every `r_k` cut at `mid`.
    fn split_at_rotor(self, mid: usize) -> (Self, Self) {
        let mut left = self.r;
        let right = std::array::from_fn(|k| {
            let (head, tail) = std::mem::take(&mut left[k]).split_at_mut(mid);
            left[k] = head;
            tail
        });
        (NordsieckChunk { r: left }, NordsieckChunk { r: right })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The predictor is the exact Taylor shift of a polynomial of degree N-1:
    /// for x(t) = t^4 with h = 1, r_k = C(4, k) t^(4-k), shifted from t = 2 to 3.
    #[test]
    fn predictor_shifts_polynomials_exactly() {
        let binom = [1.0, 4.0, 6.0, 4.0, 1.0];
        let scaled = |t: f64| -> [Vector3<f64>; 5] {
            std::array::from_fn(|k| Vector3::repeat(binom[k] * t.powi(4 - k as i32)))
        };
        let mut n = Nordsieck::<Vector3<f64>, 5>::zeros(1);
        n.set_rotor(0, &scaled(2.0));
        n.predict();
        assert_eq!(n.rotor(0), scaled(3.0));
    }

    /// `values_at` evaluates the Taylor polynomial: for x(t) = t^4 with
    /// h = 1 stored at t = 2, the values at t = 2 + x are (2 + x)^4,
    /// exactly (dyadic x).
    #[test]
    fn values_at_evaluates_the_taylor_polynomial() {
        let binom = [1.0, 4.0, 6.0, 4.0, 1.0];
        let mut n = Nordsieck::<f64, 5>::zeros(2);
        let scaled: [f64; 5] = std::array::from_fn(|k| binom[k] * 2f64.powi(4 - k as i32));
        n.set_rotor(1, &scaled);
        let mut out = [f64::NAN; 2];
        for x in [-1.0, -0.5, 0.0, 0.25] {
            n.values_at(x, &mut out);
            assert_eq!(out, [0.0, (2.0 + x).powi(4)], "x = {x}");
        }
    }

    /// Global error at t = 5 of the 6-value second-order method on
    /// `y'' = a y' + b y` (`y = Re exp(z t)`, `z^2 = a z + b`), from exact
    /// scaled derivatives, with `n` steps.
    fn linear_error(a: f64, b: f64, c0: f64, n: usize) -> f64 {
        let z = nalgebra::Complex::new(0.5 * a, 0.0)
            + (nalgebra::Complex::new(0.25 * a * a + b, 0.0)).sqrt();
        let (t_end, h) = (5.0, 5.0 / n as f64);
        let coefficients = second_order_6(c0);
        let mut y = Nordsieck::<Vector3<f64>, 6>::zeros(1);
        let mut factor = 1.0;
        for k in 0..6 {
            y.r[k][0] = Vector3::repeat(z.powi(k as i32).re * factor);
            factor *= h / (k + 1) as f64;
        }
        for _ in 0..n {
            y.predict();
            let f = y.r[1][0] * (a / h) + y.r[0][0] * b;
            let delta = f * (0.5 * h * h) - y.r[2][0];
            y.correct(0, &coefficients, delta);
        }
        (y.r[0][0].x - (z * t_end).exp().re).abs()
    }

    /// With a velocity-dependent right-hand side (as eq 12) both `c0` give
    /// global order 5, so `c0` does not set the order of scheme B; with a
    /// position-only one, `3/20` reaches order 6 (steps h = 0.025, 0.0125).
    #[test]
    fn second_order_table_is_fifth_order_with_velocity_dependence_for_both_c0() {
        let order = |a: f64, c0: f64| {
            let (e1, e2) = (
                linear_error(a, -1.0, c0, 200),
                linear_error(a, -1.0, c0, 400),
            );
            (e1 / e2).log2()
        };
        for (a, c0, expected) in [
            (0.0, C0_POSITION_ONLY, 6.0),
            (-0.5, C0_POSITION_ONLY, 5.0),
            (-0.5, C0_VELOCITY_DEPENDENT, 5.0),
        ] {
            let p = order(a, c0);
            assert!(
                (p - expected).abs() < 0.3,
                "a = {a}, c0 = {c0}: order {p:.2}"
            );
        }
    }

    /// A chunk has as many rotors as its values, and the per-rotor passes
    /// cut it into tasks of `ROTORS_PER_TASK` rotors with every derivative
    /// cut at the same rotor (a chunk that reported no rotors would run as
    /// one task, on one thread).
    #[test]
    fn chunks_count_their_rotors_and_cut_every_derivative_together() {
        use super::super::rotor_chunks::{for_each_rotor_chunk, ROTORS_PER_TASK};
        let n = 2 * ROTORS_PER_TASK + 5;
        let mut y = Nordsieck::<f64, 3>::zeros(n);
        for (k, r_k) in y.r.iter_mut().enumerate() {
            for (i, value) in r_k.iter_mut().enumerate() {
                *value = (k * n + i) as f64;
            }
        }
        assert_eq!(y.as_chunk().rotors(), n);
        let sizes = std::sync::Mutex::new(Vec::new());
        for_each_rotor_chunk(y.as_chunk(), |chunk| {
            let first = chunk.r[0][0] as usize;
            for (k, r_k) in chunk.r.iter().enumerate() {
                assert_eq!(r_k[0], (k * n + first) as f64, "derivative {k}");
            }
            sizes.lock().expect("not poisoned").push(chunk.rotors());
        });
        let mut sizes = sizes.into_inner().expect("not poisoned");
        sizes.sort();
        assert_eq!(sizes, [5, ROTORS_PER_TASK, ROTORS_PER_TASK]);
    }

    /// The flat round trip is exact.
    #[test]
    fn flat_round_trip() {
        let mut n = Nordsieck::<Quat, 3>::zeros(2);
        n.r[2][1] = Quat::new(1.0, 2.0, 3.0, 4.0);
        let mut flat = Vec::new();
        n.write_flat(&mut flat);
        assert_eq!(flat.len(), n.flat_len());
        let mut m = Nordsieck::<Quat, 3>::zeros(2);
        assert!(m.read_flat(&flat).is_empty());
        assert_eq!(m, n);
    }
}
