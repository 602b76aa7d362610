//! Cardinal B-splines `M_p` (Essmann et al., J. Chem. Phys. 103, 8577
//! (1995), eqs 4.1-4.4): `M_1` is the indicator of `[0, 1)`, `M_p(u) =
//! u / (p - 1) M_(p-1)(u) + (p - u) / (p - 1) M_(p-1)(u - 1)`, supported on
//! `[0, p]`, `p - 2` times continuously differentiable, with derivatives
//! `M_p^(d)(u) = sum_j (-1)^j C(d, j) M_(p-d)(u - j)`. They interpolate a
//! plane wave on a grid of `K` points: `exp(2 pi i m u / K) ~ b(m) sum_l
//! M_p(u - l) exp(2 pi i m l / K)` with the Euler exponential spline factor
//! `|b(m)|^2 = 1 / |sum_(k=0)^(p-2) M_p(k + 1) exp(2 pi i m k / K)|^2`.

use std::f64::consts::PI;

/// The lowest and highest spline orders.
pub const ORDERS: std::ops::RangeInclusive<usize> = 4..=8;

/// Highest derivative order kept (the forces on quadrupoles).
pub(crate) const MAX_DERIVATIVE: usize = 3;

/// The `p` weights of one site along one axis, and their derivatives:
/// `weight[d][t] = M_p^(d)(w + t)` for the grid point `floor(u) - t`, where
/// `w = u - floor(u)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisWeights {
    pub base: usize,
    pub weight: [[f64; 8]; MAX_DERIVATIVE + 1],
}

impl AxisWeights {
    /// No weights (all zero, base point 0).
    pub const ZERO: Self = AxisWeights {
        base: 0,
        weight: [[0.0; 8]; MAX_DERIVATIVE + 1],
    };

    /// The weights at scaled coordinate `u` in `[0, K)` for order `order`,
    /// derivatives up to `derivatives`.
    pub fn new(u: f64, order: usize, derivatives: usize) -> Self {
        let mut weights = Self::ZERO;
        weights.set(u, order, derivatives);
        weights
    }

    /// Sets the weights of [`Self::new`] in place: rows `0..=derivatives`,
    /// entries `0..order` (the others are left as they were).
    pub fn set(&mut self, u: f64, order: usize, derivatives: usize) {
        let floor = u.floor();
        let w = u - floor;
        // m[t] = M_n(w + t), raised from n = 1 to n = order; only the
        // entries t < n of level n are written and read.
        let mut levels = [[0.0; 8]; 9];
        levels[1][0] = 1.0;
        for n in 2..=order {
            let (lower, upper) = levels.split_at_mut(n);
            let (previous, current) = (&lower[n - 1], &mut upper[0]);
            let scale = 1.0 / (n - 1) as f64;
            for t in 0..n {
                let x = w + t as f64;
                let left = if t < n - 1 { previous[t] } else { 0.0 };
                let right = if t > 0 { previous[t - 1] } else { 0.0 };
                current[t] = (x * left + (n as f64 - x) * right) * scale;
            }
        }
        for (d, row) in self.weight.iter_mut().enumerate().take(derivatives + 1) {
            let lower = &levels[order - d];
            for (t, value) in row.iter_mut().enumerate().take(order) {
                let mut sum = 0.0;
                let mut binomial = 1.0;
                for j in 0..=d.min(t) {
                    let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
                    sum += sign * binomial * lower[t - j];
                    binomial = binomial * (d - j) as f64 / (j + 1) as f64;
                }
                *value = sum;
            }
        }
        self.base = floor as usize;
    }
}

/// `|b(m)|^2` for `m = 0..K` (see the module doc). Where the sum vanishes
/// (odd orders at `m = K / 2`) the mean of the neighbouring values is used,
/// as in Essmann et al.'s reference code.
pub(crate) fn euler_moduli(order: usize, points: usize) -> Vec<f64> {
    let values = AxisWeights::new(0.0, order, 0).weight[0];
    // values[t] = M_p(t); the sum runs over M_p(k + 1), k = 0..p-2.
    let mut moduli: Vec<f64> = (0..points)
        .map(|m| {
            let (mut re, mut im) = (0.0, 0.0);
            for k in 0..order - 1 {
                let phase = 2.0 * PI * (m * k) as f64 / points as f64;
                re += values[k + 1] * phase.cos();
                im += values[k + 1] * phase.sin();
            }
            re * re + im * im
        })
        .collect();
    for m in 0..points {
        if moduli[m] < 1e-14 {
            let neighbour = |j: usize| moduli[j % points];
            moduli[m] = 0.5 * (neighbour(m + points - 1) + neighbour(m + 1));
        }
    }
    moduli.iter().map(|s| 1.0 / s).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed forms of `M_4` (the cubic B-spline: `M_4(u) = u^3 / 6` on
    /// `[0, 1]`, `(-3u^3 + 12u^2 - 12u + 4) / 6` on `[1, 2]`, symmetric
    /// about 2) and its derivatives, and the partition of unity of every
    /// order with vanishing sums of derivatives.
    #[test]
    fn weights_match_closed_forms_and_partition_unity() {
        let w = 0.3;
        let a = AxisWeights::new(5.0 + w, 4, 3);
        assert_eq!(a.base, 5);
        let m4 = |u: f64| -> [f64; 4] {
            if u <= 1.0 {
                [u.powi(3) / 6.0, u * u / 2.0, u, 1.0]
            } else if u <= 2.0 {
                [
                    (-3.0 * u.powi(3) + 12.0 * u * u - 12.0 * u + 4.0) / 6.0,
                    (-9.0 * u * u + 24.0 * u - 12.0) / 6.0,
                    -3.0 * u + 4.0,
                    -3.0,
                ]
            } else {
                let [v, d1, d2, d3] = if 4.0 - u <= 1.0 {
                    let s = 4.0 - u;
                    [s.powi(3) / 6.0, s * s / 2.0, s, 1.0]
                } else {
                    let s = 4.0 - u;
                    [
                        (-3.0 * s.powi(3) + 12.0 * s * s - 12.0 * s + 4.0) / 6.0,
                        (-9.0 * s * s + 24.0 * s - 12.0) / 6.0,
                        -3.0 * s + 4.0,
                        -3.0,
                    ]
                };
                [v, -d1, d2, -d3]
            }
        };
        for t in 0..4 {
            let exact = m4(w + t as f64);
            for (d, exact) in exact.iter().enumerate() {
                assert!((a.weight[d][t] - exact).abs() < 1e-14, "d {d} t {t}");
            }
        }
        for order in ORDERS {
            let a = AxisWeights::new(2.71, order, 3);
            let sums: Vec<f64> = (0..4).map(|d| a.weight[d][..order].iter().sum()).collect();
            assert!((sums[0] - 1.0).abs() < 1e-14, "{order}: {sums:?}");
            for s in &sums[1..] {
                assert!(s.abs() < 1e-12, "{order}: {sums:?}");
            }
        }
    }

    /// The interpolation of eq 4.4 with the moduli: `exp(2 pi i m u / K)`
    /// against `b(m) sum_l M_p(u - l) exp(2 pi i m l / K)` in modulus, for a
    /// low mode (error ~ (m / K)^p).
    #[test]
    fn moduli_make_the_interpolated_plane_wave_unimodular() {
        let (points, m, u) = (32, 2, 7.37);
        for order in ORDERS {
            let a = AxisWeights::new(u, order, 0);
            let (mut re, mut im) = (0.0, 0.0);
            for t in 0..order {
                let l = a.base as f64 - t as f64;
                let phase = 2.0 * PI * m as f64 * l / points as f64;
                re += a.weight[0][t] * phase.cos();
                im += a.weight[0][t] * phase.sin();
            }
            let modulus = ((re * re + im * im) * euler_moduli(order, points)[m]).sqrt();
            assert!((modulus - 1.0).abs() < 1e-4, "order {order}: {modulus}");
        }
    }
}
