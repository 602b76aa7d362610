//! Parameters of the mesh Ewald sum of point charges from a requested
//! accuracy, by published estimates of the RMS force error.
//!
//! **Accuracy.** `accuracy` bounds the RMS error of the site forces
//! relative to `F_0 = (Q^2 / N) n^(2/3)`, the force between two sites of the
//! mean square charge `Q^2 / N` at the mean spacing `n^(-1/3)` (`Q^2 = sum
//! q_i^2`, `n = N / V`).
//!
//! **Estimates** (added in quadrature; the real space gets `accuracy / 2`,
//! the mesh `sqrt(3) accuracy / 2`: the real-space estimate falls ~10% short
//! in the tests):
//!
//! * real space (Kolafa & Perram, Mol. Simul. 9, 351 (1992), eq 18):
//!   `dF_r = 2 Q^2 exp(-alpha^2 r_c^2) / sqrt(N r_c V)`, which sets `alpha`
//!   for the cutoff `r_c`;
//! * mesh (Deserno & Holm, J. Chem. Phys. 109, 7694 (1998), eqs 23 and 31,
//!   the closed form for the optimal influence function, per axis with
//!   spacing `h = L / K`): `dF_k = Q^2 (h alpha)^p / L^2 sqrt(alpha L
//!   sqrt(2 pi) sum_(m<p) a_m^(p) (h alpha)^(2m) / N)`, the three axes in
//!   quadrature; each axis takes the smallest `K = 2^a 3^b 5^c` that gives
//!   `dF_k <= accuracy F_0 / (2 MESH_SAFETY)`. The estimate is for
//!   P3M with its optimal influence function; smooth PME's influence
//!   function is not optimal and its error is larger (Ballenegger, Cerda &
//!   Holm, J. Chem. Theory Comput. 8, 936 (2012)): against the converged
//!   sum (the tests, `1e-3` to `1e-6`) the mesh error of smooth PME exceeds
//!   the estimate by up to 3.4x at order 7, 7x (and growing as the accuracy
//!   tightens, beyond 10x at `1e-6`) at order 6 and 60x at order 4, hence
//!   the factor [`MESH_SAFETY`] and order 7 only.
//!
//! Dipoles and quadrupoles (and charges with them): [`super::estimate`].

use super::mesh::mesh_bytes;
use super::parameters::{check_cutoff, MeshParameters};
use crate::potential::multipole::PotentialError;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The accuracies the estimates are trusted for: below, double precision
/// and the asymptotic forms fail; above, the leading orders do not hold.
pub const ACCURACY_RANGE: (f64, f64) = (1e-10, 1e-2);

/// The spline orders whose measured mesh error the estimate with
/// [`MESH_SAFETY`] bounds (module doc).
pub const ESTIMATED_ORDERS: std::ops::RangeInclusive<usize> = 7..=7;

/// The order chosen when none is given.
pub const DEFAULT_ORDER: usize = 7;

/// The factor by which smooth PME's mesh error may exceed the P3M estimate
/// at order 7 (measured up to 3.4; module doc).
pub const MESH_SAFETY: f64 = 10.0;

/// The most mesh points along an axis the choice considers.
const MAX_POINTS_PER_AXIS: usize = 4096;

/// Deserno & Holm's `a_m^(7)` (eq 31), `m < 7`.
const A: [f64; 7] = [
    1.0 / 345600.0,
    3617.0 / 35512320.0,
    745739.0 / 838397952.0,
    56399353.0 / 12773376000.0,
    25091609.0 / 1560084480.0,
    1755948832039.0 / 36229939200000.0,
    4887769399.0 / 37838389248.0,
];

/// The estimated errors of a choice, relative to `F_0` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChargeEstimate {
    /// Real-space part.
    pub real: f64,
    /// Mesh part (three axes in quadrature).
    pub mesh: f64,
}

/// The real-space estimate `dF_r` (absolute).
fn real_error(square_sum: f64, sites: f64, volume: f64, alpha: f64, rc: f64) -> f64 {
    2.0 * square_sum * (-alpha * alpha * rc * rc).exp() / (sites * rc * volume).sqrt()
}

/// The mesh estimate `dF_k` of one axis (absolute).
fn mesh_error(
    square_sum: f64,
    sites: f64,
    alpha: f64,
    order: usize,
    length: f64,
    points: usize,
) -> f64 {
    let ha = length / points as f64 * alpha;
    let sum: f64 = (0..order).map(|m| A[m] * ha.powi(2 * m as i32)).sum();
    square_sum * ha.powi(order as i32) / (length * length)
        * (alpha * length * (2.0 * PI).sqrt() * sum / sites).sqrt()
}

/// Refuses an accuracy outside [`ACCURACY_RANGE`].
pub(super) fn check_accuracy(accuracy: f64) -> Result<(), PotentialError> {
    let (low, high) = ACCURACY_RANGE;
    if !(accuracy >= low && accuracy <= high) {
        return Err(PotentialError::new(
            "accuracy",
            format!(
                "must be from {low:e} to {high:e} for the mesh Ewald sum (what its error \
                 estimates hold for; the default 1e-12 is beyond them), got {}",
                crate::checks::num(accuracy)
            ),
        ));
    }
    Ok(())
}

/// Refuses an accuracy outside [`ACCURACY_RANGE`] and an order outside
/// [`ESTIMATED_ORDERS`]; the order to use.
fn check_request(accuracy: f64, order: Option<usize>) -> Result<usize, PotentialError> {
    check_accuracy(accuracy)?;
    let order = order.unwrap_or(DEFAULT_ORDER);
    if !ESTIMATED_ORDERS.contains(&order) {
        return Err(PotentialError::new(
            "order",
            format!(
                "the error estimate covers orders {} to {} only, got {order}",
                ESTIMATED_ORDERS.start(),
                ESTIMATED_ORDERS.end()
            ),
        ));
    }
    Ok(order)
}

/// The fewest points (from `order` up, at most [`MAX_POINTS_PER_AXIS`])
/// that `fits`, which holds from some count on: doubling (the last step
/// cut to the limit), then bisection between the last count that did not
/// fit and the first that did.
fn smallest_mesh(fits: impl Fn(usize) -> bool, order: usize) -> Option<usize> {
    let (mut lower, mut upper) = (order - 1, order);
    while !fits(upper) {
        if upper >= MAX_POINTS_PER_AXIS {
            return None;
        }
        lower = upper;
        upper = (2 * upper).min(MAX_POINTS_PER_AXIS);
    }
    while upper - lower > 1 {
        let middle = (lower + upper) / 2;
        if fits(middle) {
            upper = middle;
        } else {
            lower = middle;
        }
    }
    Some(upper)
}

/// The smallest `2^a 3^b 5^c` at least `n`.
pub(super) fn fft_size(n: usize) -> usize {
    (n..)
        .find(|&k| {
            let mut m = k;
            for p in [2, 3, 5] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .unwrap_or(n)
}

/// The parameters for point charges `charges` in `box_lengths` at relative
/// force accuracy `accuracy`, with real-space cutoff `real_cutoff` and
/// spline order `order` (default [`DEFAULT_ORDER`]). Refuses (naming the
/// field) an accuracy outside [`ACCURACY_RANGE`], an order the estimate does
/// not cover, a cutoff the box does not fit, charges all zero, and meshes
/// over the memory limit.
pub fn for_charges(
    accuracy: f64,
    charges: &[f64],
    box_lengths: &Vector3<f64>,
    real_cutoff: f64,
    order: Option<usize>,
) -> Result<(MeshParameters, ChargeEstimate), PotentialError> {
    let order = check_request(accuracy, order)?;
    let sites = charges.len() as f64;
    let square_sum: f64 = charges.iter().map(|q| q * q).sum();
    if !(square_sum > 0.0 && square_sum.is_finite()) {
        return Err(PotentialError::new(
            "charges",
            format!("need a finite nonzero sum of squares, got {square_sum}"),
        ));
    }
    let volume = box_lengths.product();
    check_cutoff(real_cutoff, box_lengths)?;
    let scale = square_sum / sites * (sites / volume).powf(2.0 / 3.0);
    let target = accuracy * scale / 2.0;
    // exp(-alpha^2 r_c^2) = target sqrt(N r_c V) / (2 Q^2)
    let ratio = target * (sites * real_cutoff * volume).sqrt() / (2.0 * square_sum);
    let alpha = if ratio < 1.0 {
        (-ratio.ln()).sqrt() / real_cutoff
    } else {
        // Any splitting meets the real-space target: the mean spacing's.
        1.0 / (volume / sites).cbrt()
    };
    let per_axis = target / MESH_SAFETY;
    let mut grid = [0; 3];
    for (a, points) in grid.iter_mut().enumerate() {
        let length = box_lengths[a];
        let fits = |k: usize| mesh_error(square_sum, sites, alpha, order, length, k) <= per_axis;
        let upper = smallest_mesh(fits, order).ok_or_else(|| {
            PotentialError::new(
                "accuracy",
                format!(
                    "{accuracy} needs more than {MAX_POINTS_PER_AXIS} mesh points along axis {a} \
                     (splitting {alpha:.4}, order {order}): ask for less, or a longer real_cutoff"
                ),
            )
        })?;
        *points = fft_size(upper);
    }
    crate::memory::check("accuracy", mesh_bytes(grid)).map_err(|e| {
        PotentialError::new(
            "accuracy",
            format!(
                "{accuracy} needs a {}x{}x{} mesh: {}",
                grid[0], grid[1], grid[2], e.message
            ),
        )
    })?;
    let parameters = MeshParameters {
        alpha,
        real_cutoff,
        grid,
        order,
    };
    let mesh = (0..3)
        .map(|a| mesh_error(square_sum, sites, alpha, order, box_lengths[a], grid[a]).powi(2))
        .sum::<f64>()
        .sqrt();
    let estimate = ChargeEstimate {
        real: real_error(square_sum, sites, volume, alpha, real_cutoff) / scale,
        mesh: mesh / scale,
    };
    Ok((parameters, estimate))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The search finds the fewest fitting points from `order` up to the
    /// limit, for every spline order 4 to 8: before session 36 it doubled
    /// past the limit unless the order times a power of two hit it (at the
    /// charges' order 7: 3,584, then 7,168 > 4,096, so meshes of 3,585 to
    /// 4,096 points that fit were refused), and bisected below the order
    /// when the order itself fit (found by `make mutants`: `>` with `>=` at
    /// the limit survived). Each test of a count is an error estimate, so
    /// the search takes at most two per doubling of the count (doubling,
    /// then bisection), 2 log2(4096 / 4) + 2 = 22 (a search stepping by 2
    /// instead of doubling, which `make mutants` left alive, finds the same
    /// counts with hundreds).
    #[test]
    fn the_mesh_search_finds_every_count_up_to_the_limit() {
        for order in 4..=8 {
            for first in [
                order,
                order + 1,
                37,
                1000,
                2561,
                3585,
                4095,
                MAX_POINTS_PER_AXIS,
            ] {
                let tests = std::cell::Cell::new(0);
                let found = smallest_mesh(
                    |k| {
                        tests.set(tests.get() + 1);
                        k >= first
                    },
                    order,
                );
                assert_eq!(found, Some(first), "order {order}, fits from {first}");
                assert!(
                    tests.get() <= 22,
                    "order {order}, fits from {first}: {} tests",
                    tests.get()
                );
            }
            assert_eq!(smallest_mesh(|k| k > MAX_POINTS_PER_AXIS, order), None);
            assert_eq!(smallest_mesh(|_| true, order), Some(order));
        }
    }

    /// LAMMPS's `estimated absolute RMS force accuracy` of `pppm` with forced
    /// parameters (`fixtures/pppm_estimates_lammps.json`, by `make fixtures`):
    /// the same two estimates, evaluated by LAMMPS from its own copy of the
    /// formulas and of Deserno & Holm's `a_m^(7)`, as `sqrt(dF_r^2 +
    /// dF_k^2)` with `dF_k` the axes in quadrature over `sqrt(3)`; printed
    /// to 8 digits. The cases reach `h alpha` from 0.2 to 1.7 (every
    /// `a_m` weighs in some) and one where the real space dominates.
    #[test]
    fn the_estimates_are_those_lammps_prints() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/fixtures/pppm_estimates_lammps.json"
        );
        let fixture: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).expect(path)).expect("JSON");
        let cases = fixture["cases"].as_array().expect("cases");
        assert_eq!(cases.len(), 8);
        for case in cases {
            let number = |key: &str| case[key].as_f64().expect(key);
            let list = |key: &str| -> Vec<f64> {
                case[key]
                    .as_array()
                    .expect(key)
                    .iter()
                    .map(|v| v.as_f64().expect(key))
                    .collect()
            };
            let (box_, mesh) = (list("box"), list("mesh"));
            let (square_sum, sites) = (number("square_sum"), number("sites"));
            let (alpha, cutoff) = (number("alpha"), number("cutoff"));
            let volume: f64 = box_.iter().product();
            let real = real_error(square_sum, sites, volume, alpha, cutoff);
            let axes: f64 = box_
                .iter()
                .zip(&mesh)
                .map(|(&l, &k)| mesh_error(square_sum, sites, alpha, 7, l, k as usize).powi(2))
                .sum();
            let ours = real.hypot((axes / 3.0).sqrt());
            let lammps = number("lammps_absolute_rms_force_accuracy");
            assert!(
                ((ours - lammps) / lammps).abs() < 2e-7,
                "case {case}: ours {ours:e}, LAMMPS {lammps:e}"
            );
        }
    }
}
