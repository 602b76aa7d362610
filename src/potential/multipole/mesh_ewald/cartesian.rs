//! Cartesian derivatives by multi-index: a derivative `d^N` is the exponent
//! triple `N = (n_x, n_y, n_z)`, `|N| = n_x + n_y + n_z <= 5`, numbered by
//! order (`0`: the value; `1..4`: x, y, z; `4..10`: second order; `10..20`:
//! third order; then fourth and fifth). A site's multipoles act as the
//! operator `D = q + mu.grad + 1/3 Theta:grad grad` on its own position
//! (Buckingham quadrupoles), written `sum_E c_E d^E` over the first ten
//! multi-indices ([`source_coefficients`]).
//!
//! Derivatives of a radial function `f(|r|)` through Smith's `B_l`
//! (`B_l = -(1/r) dB_{l-1}/dr`, `B_0 = f`): pairing the indices of `d^N`,
//! `d^N f = sum_k (-1)^(|N| - k) B_(|N| - k) prod_a n_a! / (2^(k_a) k_a!
//! (n_a - 2 k_a)!) r_a^(n_a - 2 k_a)` over `k_a <= n_a / 2`, `k = sum k_a`
//! (the forms `grad f = -r B_1`, `grad grad f = r r^T B_2 - I B_1` of
//! [`crate::potential::multipole::ewald_terms`] and their continuations).

use nalgebra::{Matrix3, Vector3};
use std::sync::OnceLock;

/// Multi-indices of order at most 0, 1, 2, 3, 4, 5.
pub(crate) const UP_TO: [usize; 6] = [1, 4, 10, 20, 35, 56];

/// Number of source coefficients (orders 0 to 2).
pub(crate) const SOURCES: usize = 10;

/// Number of potential derivatives kept per site (orders 0 to 3: the
/// forces on quadrupoles).
pub(crate) const DERIVATIVES: usize = 20;

/// The multi-index tables.
pub(crate) struct Tables {
    /// The exponent triple of each multi-index.
    pub exponents: [[usize; 3]; 56],
    /// The multi-index of `A + E` for `A < DERIVATIVES`, `E < SOURCES`.
    pub sum: [[usize; SOURCES]; DERIVATIVES],
    /// The multi-index of `E + e_a` for `E < SOURCES` (order at most 3).
    pub raise: [[usize; 3]; SOURCES],
    /// `(-1)^|E|` for `E < SOURCES`: a source's operator acts on its own
    /// position, `d/dr_j g(r_i - r_j) = -d/dr_i g(r_i - r_j)`.
    pub parity: [f64; SOURCES],
    /// The recursion step reaching each multi-index ([`radial_derivatives`]).
    steps: [Step; 56],
}

impl Tables {
    /// The tables (built once).
    pub fn get() -> &'static Tables {
        static TABLES: OnceLock<Tables> = OnceLock::new();
        TABLES.get_or_init(|| {
            let mut exponents = [[0; 3]; 56];
            let mut index = [[[usize::MAX; 6]; 6]; 6];
            let mut next = 0;
            for order in 0..=5 {
                for nx in (0..=order).rev() {
                    for ny in (0..=order - nx).rev() {
                        let nz = order - nx - ny;
                        exponents[next] = [nx, ny, nz];
                        index[nx][ny][nz] = next;
                        next += 1;
                    }
                }
            }
            let at = |e: [usize; 3]| index[e[0]][e[1]][e[2]];
            let sum = std::array::from_fn(|a| {
                std::array::from_fn(|e| {
                    let (x, y) = (exponents[a], exponents[e]);
                    at([x[0] + y[0], x[1] + y[1], x[2] + y[2]])
                })
            });
            let raise = std::array::from_fn(|e| {
                std::array::from_fn(|axis| {
                    let mut x = exponents[e];
                    x[axis] += 1;
                    at(x)
                })
            });
            let parity = std::array::from_fn(|e| {
                if exponents[e].iter().sum::<usize>() % 2 == 0 {
                    1.0
                } else {
                    -1.0
                }
            });
            let steps = std::array::from_fn(|n| {
                let x = exponents[n];
                let Some(axis) = x.iter().position(|&m| m > 0) else {
                    return Step::default();
                };
                let mut once = x;
                once[axis] -= 1;
                let mut twice = once;
                twice[axis] = twice[axis].saturating_sub(1);
                Step {
                    axis,
                    once: at(once),
                    twice: at(twice),
                    repeat: once[axis] as f64,
                }
            });
            Tables {
                exponents,
                sum,
                raise,
                parity,
                steps,
            }
        })
    }

    /// The order `|N|` of multi-index `n`.
    pub fn order(&self, n: usize) -> usize {
        self.exponents[n].iter().sum()
    }
}

/// The coefficients `c_E` of `D = q + mu.grad + 1/3 Theta:grad grad`
/// (off-diagonal second derivatives appear twice in `Theta:grad grad`).
pub(crate) fn source_coefficients(
    charge: f64,
    dipole: &Vector3<f64>,
    quadrupole: &Matrix3<f64>,
) -> [f64; SOURCES] {
    let tables = Tables::get();
    std::array::from_fn(|e| {
        let x = tables.exponents[e];
        match tables.order(e) {
            0 => charge,
            1 => dipole[x.iter().position(|&n| n == 1).unwrap_or(0)],
            _ => {
                let mut axes = x
                    .iter()
                    .enumerate()
                    .flat_map(|(a, &n)| std::iter::repeat_n(a, n));
                let (a, b) = (axes.next().unwrap_or(0), axes.next().unwrap_or(0));
                let multiplicity = if a == b { 1.0 } else { 2.0 };
                multiplicity * quadrupole[(a, b)] / 3.0
            }
        }
    })
}

/// `d^N f(r)` for the first `count` multi-indices, `b` holding `B_0..B_5`
/// of `f` at `|r|` (see the module doc); `r = 0` gives the derivatives at
/// the origin of a smooth `f` whose `B_l(0)` are given.
///
/// By the McMurchie-Davidson recursion on `R^n_N = d^N B_n`: with `d_a B_n
/// = -r_a B_(n+1)` and Leibniz's rule, `R^n_(M + e_a) = -(r_a R^(n+1)_M +
/// m_a R^(n+1)_(M - e_a))`, from `R^n_0 = B_n` down to `n = 0` (two
/// multiply-adds per derivative and level: the closed sum of the module doc,
/// which the tests check it against, costs ten times more). `levels` is the
/// caller's scratch (kept across calls: zeroing it per pair cost more than
/// the recursion); the derivatives are `levels[0][..count]`.
pub(crate) fn radial_derivatives(
    r: &Vector3<f64>,
    b: &[f64; 6],
    count: usize,
    levels: &mut RadialLevels,
) {
    let tables = Tables::get();
    let top = tables.order(count - 1);
    // levels[n][N] = R^n_N for |N| <= top - n.
    levels[top][0] = b[top];
    for n in (0..top).rev() {
        let (lower, upper) = levels.split_at_mut(n + 1);
        let (level, above) = (&mut lower[n], &upper[0]);
        level[0] = b[n];
        for (index, step) in tables.steps.iter().enumerate().take(UP_TO[top - n]).skip(1) {
            let mut value = r[step.axis] * above[step.once];
            if step.repeat > 0.0 {
                value += step.repeat * above[step.twice];
            }
            level[index] = -value;
        }
    }
}

/// Adds a source's share to a target's potential derivatives: `d^A phi +=
/// sum_E (-1)^|E| c_E d^(A + E) g` for the first `count` multi-indices `A`,
/// `t` holding the kernel's `d^N g` at `r = r_target - r_source` and `c`
/// the source's first `sources` coefficients.
pub(crate) fn add_source(
    t: &[f64; 56],
    c: &[f64; SOURCES],
    sources: usize,
    count: usize,
    d: &mut [f64; DERIVATIVES],
) {
    let tables = Tables::get();
    for (a, value) in d.iter_mut().enumerate().take(count) {
        *value += (0..sources)
            .map(|e| tables.parity[e] * c[e] * t[tables.sum[a][e]])
            .sum::<f64>();
    }
}

/// The force on a target (coefficients `target`, the first `targets`
/// nonzero) from a source (`source`, the first `sources`), `t` as in
/// [`add_source`] with derivatives up to the order of both plus one: `F_a =
/// -sum_E c_E d^(E + e_a) phi_source`.
pub(crate) fn pair_force(
    t: &[f64; 56],
    target: &[f64; SOURCES],
    targets: usize,
    source: &[f64; SOURCES],
    sources: usize,
) -> Vector3<f64> {
    let tables = Tables::get();
    Vector3::from_fn(|a, _| {
        -(0..targets)
            .map(|e| {
                let raised = tables.raise[e][a];
                target[e]
                    * (0..sources)
                        .map(|f| tables.parity[f] * source[f] * t[tables.sum[raised][f]])
                        .sum::<f64>()
            })
            .sum::<f64>()
    })
}

/// The levels `R^n_N` of [`radial_derivatives`], `n = 0..=5`.
pub(crate) type RadialLevels = [[f64; 56]; 6];

/// How a multi-index `N` (order at least 1) is reached in the recursion of
/// [`radial_derivatives`]: `N = M + e_axis`, `once = M`, `twice = M -
/// e_axis` (when `repeat = m_axis > 0`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Step {
    axis: usize,
    once: usize,
    twice: usize,
    repeat: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::multipole::ewald_terms::radial_functions;

    /// Every derivative of `erfc(alpha r)/r` up to the fifth order against
    /// central differences of the order below (step 1e-4: truncation
    /// ~1e-8 relative, round-off ~1e-11).
    #[test]
    fn radial_derivatives_are_the_derivatives_of_the_damped_coulomb() {
        let alpha = 0.8;
        let r = Vector3::new(0.9, -0.7, 1.2);
        let tables = Tables::get();
        let at = |x: &Vector3<f64>| {
            let mut levels = [[0.0; 56]; 6];
            radial_derivatives(x, &radial_functions(alpha, x.norm()), 56, &mut levels);
            levels[0]
        };
        let centre = at(&r);
        assert!((centre[0] - libm::erfc(alpha * r.norm()) / r.norm()).abs() < 1e-15);
        let h = 1e-4;
        for (n, &exact) in centre.iter().enumerate().skip(1) {
            let x = tables.exponents[n];
            let axis = x.iter().position(|&m| m > 0).unwrap();
            let mut lower = x;
            lower[axis] -= 1;
            let below = (0..56).find(|&m| tables.exponents[m] == lower).unwrap();
            let step = Vector3::from_fn(|a, _| if a == axis { h } else { 0.0 });
            let fd = (at(&(r + step))[below] - at(&(r - step))[below]) / (2.0 * h);
            assert!(
                (fd - exact).abs() < 1e-7 * (1.0 + exact.abs()),
                "{x:?}: {fd} vs {exact}"
            );
        }
    }

    /// The recursion against the module doc's closed sum over pairings,
    /// `d^N f = sum_k (-1)^(|N| - k) B_(|N| - k) prod_a n_a! / (2^(k_a)
    /// k_a! (n_a - 2 k_a)!) r_a^(n_a - 2 k_a)`, at every order it serves
    /// (`count` of 1 to 56) and at the origin (round-off: sums of a few terms).
    #[test]
    fn radial_derivatives_match_the_closed_sum() {
        let tables = Tables::get();
        let pairings = |n: usize, k: usize| -> f64 {
            let f = |m: usize| (1..=m).map(|v| v as f64).product::<f64>();
            f(n) / (2f64.powi(k as i32) * f(k) * f(n - 2 * k))
        };
        let b = [0.9, -0.4, 1.3, 0.7, -1.1, 0.25];
        for r in [Vector3::new(0.8, -1.3, 0.45), Vector3::zeros()] {
            for &count in &UP_TO {
                let mut levels = [[f64::NAN; 56]; 6];
                radial_derivatives(&r, &b, count, &mut levels);
                for (n, &value) in levels[0].iter().enumerate().take(count) {
                    let [nx, ny, nz] = tables.exponents[n];
                    let mut closed = 0.0;
                    for kx in 0..=nx / 2 {
                        for ky in 0..=ny / 2 {
                            for kz in 0..=nz / 2 {
                                let l = nx + ny + nz - kx - ky - kz;
                                let sign = if l % 2 == 0 { 1.0 } else { -1.0 };
                                closed += sign
                                    * b[l]
                                    * pairings(nx, kx)
                                    * r.x.powi((nx - 2 * kx) as i32)
                                    * pairings(ny, ky)
                                    * r.y.powi((ny - 2 * ky) as i32)
                                    * pairings(nz, kz)
                                    * r.z.powi((nz - 2 * kz) as i32);
                            }
                        }
                    }
                    assert!(
                        (value - closed).abs() < 1e-13 * (1.0 + closed.abs()),
                        "count {count}, {:?} at {r:?}: {value} vs {closed}",
                        tables.exponents[n]
                    );
                }
            }
        }
    }

    /// `D` reproduces `q f + mu.grad f + 1/3 Theta:grad grad f` for
    /// `f = x^2 y + z` (exact polynomial derivatives).
    #[test]
    fn source_coefficients_apply_the_multipole_operator() {
        let tables = Tables::get();
        let (q, mu) = (0.7, Vector3::new(0.2, -0.5, 0.9));
        let theta = Matrix3::new(0.4, 0.3, -0.2, 0.3, -0.1, 0.6, -0.2, 0.6, -0.3);
        let p = Vector3::new(1.5, -0.5, 2.0);
        let derivative = |e: [usize; 3]| match e {
            [0, 0, 0] => p.x * p.x * p.y + p.z,
            [1, 0, 0] => 2.0 * p.x * p.y,
            [0, 1, 0] => p.x * p.x,
            [0, 0, 1] => 1.0,
            [2, 0, 0] => 2.0 * p.y,
            [1, 1, 0] => 2.0 * p.x,
            _ => 0.0,
        };
        let c = source_coefficients(q, &mu, &theta);
        let applied: f64 = (0..SOURCES)
            .map(|e| c[e] * derivative(tables.exponents[e]))
            .sum();
        let hessian = Matrix3::new(
            2.0 * p.y,
            2.0 * p.x,
            0.0,
            2.0 * p.x,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
        );
        let gradient = Vector3::new(2.0 * p.x * p.y, p.x * p.x, 1.0);
        let expected = q * derivative([0, 0, 0]) + mu.dot(&gradient) + theta.dot(&hessian) / 3.0;
        assert!(
            (applied - expected).abs() < 1e-14,
            "{applied} vs {expected}"
        );
    }
}
