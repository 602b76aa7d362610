//! The charge kernel of Ewald's real space, `erfc(alpha r) / r` and its
//! first radial function, with `erfc` from a table instead of a libm call.
//!
//! `erfc(x) = exp(-x^2) erfcx(x)`: the scaled `erfcx` is smooth and slowly
//! varying, so on each of the intervals `[k / 8, (k + 1) / 8)` of `[0, 8)`
//! it is its Chebyshev interpolant of degree 8 (built once from libm's
//! `erfc(x) exp(x^2)` at the Chebyshev nodes, then written in powers of
//! the interval's local variable `t` in `[-1, 1]` and evaluated by
//! Horner), and the `exp(-x^2)` is the one the radial function `B_1`
//! needs anyway: one `exp` per pair instead of libm `erfc`'s two plus the
//! `exp`. Relative error against libm below `1e-14` for `x < 6`
//! (interpolation below `3e-15`; the rest is `exp`'s rounding of `x^2`,
//! which the former kernel's `exp(-x^2)` has too), the tests check it; at
//! `x >= 8` (`erfc < 1.2e-29`) libm's `erfc`.

use crate::lanes::{Lanes, LANES};
use std::f64::consts::PI;
use std::ops::{Add, Div, Mul};
use std::sync::OnceLock;

/// Intervals per unit of `x`.
const PER_UNIT: usize = 8;

/// Intervals of the table (`[0, INTERVALS / PER_UNIT)`).
const INTERVALS: usize = 8 * PER_UNIT;

/// The interpolant's degree; its `DEGREE + 1` Chebyshev nodes per interval.
const DEGREE: usize = 8;

/// The power coefficients of `erfcx` on each interval, in its local `t`.
pub(crate) struct ErfcTable {
    coefficients: [[f64; DEGREE + 1]; INTERVALS],
}

impl ErfcTable {
    /// The table (built at the first call).
    pub fn get() -> &'static ErfcTable {
        static TABLE: OnceLock<ErfcTable> = OnceLock::new();
        TABLE.get_or_init(ErfcTable::build)
    }

    fn build() -> ErfcTable {
        let n = DEGREE + 1;
        let nodes: Vec<f64> = (0..n)
            .map(|j| (PI * (j as f64 + 0.5) / n as f64).cos())
            .collect();
        // The power coefficients of the Chebyshev polynomials T_0..T_DEGREE.
        let mut chebyshev = [[0.0; DEGREE + 1]; DEGREE + 1];
        chebyshev[0][0] = 1.0;
        chebyshev[1][1] = 1.0;
        for k in 2..=DEGREE {
            for m in 0..=DEGREE {
                let raised = if m > 0 { chebyshev[k - 1][m - 1] } else { 0.0 };
                chebyshev[k][m] = 2.0 * raised - chebyshev[k - 2][m];
            }
        }
        let coefficients = std::array::from_fn(|interval| {
            let centre = (interval as f64 + 0.5) / PER_UNIT as f64;
            let half_width = 0.5 / PER_UNIT as f64;
            let values: Vec<f64> = nodes
                .iter()
                .map(|t| {
                    let x = centre + half_width * t;
                    libm::erfc(x) * (x * x).exp()
                })
                .collect();
            let mut power = [0.0; DEGREE + 1];
            for (k, row) in chebyshev.iter().enumerate() {
                let weight = if k == 0 { 1.0 } else { 2.0 } / n as f64;
                let c: f64 = values
                    .iter()
                    .zip(&nodes)
                    .map(|(v, t)| v * (k as f64 * t.acos()).cos())
                    .sum::<f64>()
                    * weight;
                for (p, r) in power.iter_mut().zip(row) {
                    *p += c * r;
                }
            }
            power
        });
        ErfcTable { coefficients }
    }

    /// `(erfc(x), exp(-x^2))` for `x >= 0`.
    #[inline]
    pub fn erfc_gauss(&self, x: f64) -> (f64, f64) {
        let gauss = (-x * x).exp();
        let scaled = x * PER_UNIT as f64;
        if scaled >= INTERVALS as f64 {
            return (libm::erfc(x), gauss);
        }
        let k = scaled as usize;
        let t = 2.0 * (scaled - k as f64) - 1.0;
        let sum = horner(|m| self.coefficients[k][m], t);
        (gauss * sum, gauss)
    }

    /// [`Self::erfc_gauss`] in four lanes, each lane's bits those of the
    /// scalar function (the same operations in the same order; `exp` and,
    /// beyond the table, `erfc` by libm for each lane).
    #[inline(always)]
    pub fn erfc_gauss_lanes<T: Lanes>(&self, x: T) -> (T, T) {
        let gauss = T::from_array((-x * x).to_array().map(f64::exp));
        let scaled = x * PER_UNIT as f64;
        let intervals = scaled.to_array().map(|s| s as usize);
        let beyond = intervals.map(|k| k >= INTERVALS);
        let rows = intervals.map(|k| &self.coefficients[k.min(INTERVALS - 1)]);
        let start = T::from_array(intervals.map(|k| k as f64));
        let t = (scaled - start) * 2.0 - T::splat(1.0);
        let sum = horner(|m| T::from_array(rows.map(|c| c[m])), t);
        let erfc = gauss * sum;
        if !beyond.contains(&true) {
            return (erfc, gauss);
        }
        let (mut lanes, xs) = (erfc.to_array(), x.to_array());
        for l in 0..LANES {
            if beyond[l] {
                lanes[l] = libm::erfc(xs[l]);
            }
        }
        (T::from_array(lanes), gauss)
    }

    /// Smith's radial functions `B_0..B_(L-1)` of `erfc(alpha r) / r` (the
    /// recursion of `crate::potential::multipole::ewald_terms::radial_functions`)
    /// at `r^2 = distance_squared`, `alpha > 0`.
    #[inline]
    pub fn radial<const L: usize>(&self, alpha: f64, distance_squared: f64) -> [f64; L] {
        let r = distance_squared.sqrt();
        let (erfc, gauss) = self.erfc_gauss(alpha * r);
        recursion(erfc, gauss, (r, distance_squared), alpha, |x| x)
    }

    /// [`Self::radial`] in four lanes, each lane's bits the scalar
    /// function's.
    #[inline(always)]
    pub fn radial_lanes<T: Lanes, const L: usize>(
        &self,
        alpha: f64,
        distance_squared: T,
    ) -> [T; L] {
        let r = distance_squared.sqrt();
        let (erfc, gauss) = self.erfc_gauss_lanes(r * alpha);
        recursion(erfc, gauss, (r, distance_squared), alpha, T::splat)
    }
}

/// `c(8) t^8 + ... + c(0)` by Horner's rule.
#[inline(always)]
fn horner<T: Copy + Add<Output = T> + Mul<Output = T>>(c: impl Fn(usize) -> T, t: T) -> T {
    let mut sum = c(DEGREE);
    for m in (0..DEGREE).rev() {
        sum = sum * t + c(m);
    }
    sum
}

/// `B_0 = erfc(alpha r) / r` and `B_l = ((2 l - 1) B_(l-1) + (2 alpha^2)^l
/// exp(-alpha^2 r^2) / (alpha sqrt(pi))) / r^2` (Smith's recursion), from
/// `erfc` and `gauss = exp(-alpha^2 r^2)`, scalars or lanes (`splat` a
/// constant).
#[inline(always)]
fn recursion<T, const L: usize>(
    erfc: T,
    gauss: T,
    (r, distance_squared): (T, T),
    alpha: f64,
    splat: impl Fn(f64) -> T,
) -> [T; L]
where
    T: Copy + Add<Output = T> + Mul<Output = T> + Div<Output = T>,
{
    let inv_r2 = splat(1.0) / distance_squared;
    let mut b = [splat(0.0); L];
    b[0] = erfc / r;
    let mut gauss = gauss / splat(alpha * PI.sqrt());
    for l in 1..L {
        gauss = gauss * splat(2.0 * alpha * alpha);
        b[l] = (splat((2 * l - 1) as f64) * b[l - 1] + gauss) * inv_r2;
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::multipole::ewald_terms::radial_functions;

    /// Relative error of the tabulated `erfc` against libm's for `x < 6`
    /// (`exp`'s rounding of `x^2` makes `~x^2 1.1e-16`, plus the
    /// interpolation's `3e-15`).
    const ERFC_RELATIVE: f64 = 1e-14;

    /// `erfc` matches libm's on a fine sweep of `[0, 6)`, the interval ends
    /// included, and at and beyond the table's end.
    #[test]
    fn tabulated_erfc_matches_libm() {
        let table = ErfcTable::get();
        let mut worst: f64 = 0.0;
        for i in 0..60_000 {
            let x = i as f64 * 1e-4;
            let (erfc, gauss) = table.erfc_gauss(x);
            worst = worst.max((erfc / libm::erfc(x) - 1.0).abs());
            assert_eq!(gauss, (-x * x).exp());
        }
        assert!(worst < ERFC_RELATIVE, "{worst:e}");
        for x in [7.9999, 8.0, 9.5, 27.0] {
            let erfc = table.erfc_gauss(x).0;
            assert!((erfc / libm::erfc(x) - 1.0).abs() < 1e-13 || erfc == libm::erfc(x));
        }
    }

    /// Reference values of `erfc` from scipy.special.erfc (scipy 1.17.1):
    /// the table does not only agree with the libm it was built from.
    #[test]
    fn tabulated_erfc_matches_published_values() {
        let table = ErfcTable::get();
        for (x, expected) in [
            (0.5, 0.4795001221869535),
            (1.0, 0.15729920705028516),
            (2.5, 0.00040695201744495886),
            (4.0, 1.541725790028002e-08),
            (5.5, 7.357847917974398e-15),
        ] {
            let erfc = table.erfc_gauss(x).0;
            assert!(
                (erfc / expected - 1.0).abs() < ERFC_RELATIVE,
                "{x}: {erfc:e}"
            );
        }
    }

    /// Each lane of `radial_lanes` holds the bits of the scalar `radial`
    /// (in arrays and, where the CPU has AVX2, in AVX registers), lanes
    /// beyond the table's end (libm's `erfc`) mixed with lanes inside it.
    #[test]
    fn radial_lanes_are_the_scalar_radial() {
        fn check<T: Lanes>() {
            let table = ErfcTable::get();
            let alpha = 1.3;
            for start in 0..400 {
                // alpha r = x: lane 0 from 0.01 to 8.7, the others beyond the table.
                let x: [f64; LANES] =
                    std::array::from_fn(|l| 0.01 + 0.0217 * start as f64 + 7.9 * l as f64);
                let r2 = x.map(|x| (x / alpha) * (x / alpha));
                let lanes = table.radial_lanes::<T, 4>(alpha, T::from_array(r2));
                for (l, &r2) in r2.iter().enumerate() {
                    let scalar = table.radial::<4>(alpha, r2);
                    for k in 0..4 {
                        assert_eq!(
                            lanes[k].to_array()[l].to_bits(),
                            scalar[k].to_bits(),
                            "r^2 {r2} B_{k}"
                        );
                    }
                }
            }
        }
        check::<crate::lanes::F4>();
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            check::<crate::lanes::Avx>();
        }
    }

    /// `radial` is the general kernel's `B_0..B_2` to the same bound.
    #[test]
    fn radial_is_the_general_kernel() {
        let table = ErfcTable::get();
        let alpha = 0.37;
        for i in 1..2000 {
            let r = i as f64 * 3e-3 / alpha;
            let fast = table.radial::<3>(alpha, r * r);
            let general = radial_functions::<3>(alpha, r);
            for l in 0..3 {
                assert!(
                    (fast[l] / general[l] - 1.0).abs() < ERFC_RELATIVE,
                    "r {r} l {l}"
                );
            }
        }
    }
}
