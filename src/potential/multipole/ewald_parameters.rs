//! The Ewald splitting parameter and the real- and reciprocal-space cutoffs
//! for a requested relative accuracy.
//!
//! **Accuracy.** `accuracy` bounds the truncation error of each site's
//! field `E_i` (and field-gradient conjugate `W_i`) relative to the field
//! scale of the system: `mu n` for the field of dipoles, `mu n^(4/3)` for
//! their gradient, `Theta n^(4/3)` and `Theta n^(5/3)` for quadrupoles, with
//! `n = N / V` the number density and `mu`, `Theta` the largest multipoles
//! (the field of a neighbour at the mean spacing `d = n^(-1/3)`). The energy
//! and the torques, bilinear in the multipoles and these fields, then carry
//! errors of at most `accuracy` times `sum_i (|mu_i|^2 n + |Theta_i|^2 n^(5/3))`
//! and `|mu|^2 n + |Theta|^2 n^(5/3)` up to factors of order one. The
//! estimates are tested against the converged sums (`tests/ewald.rs`).
//!
//! **Estimates** (leading order in `s = alpha r_c` or `s = k_c / (2 alpha)`,
//! integrating the neglected tails with a uniform density; cf. Kolafa &
//! Perram, Mol. Simul. 9, 351 (1992) and Wang & Holm, J. Chem. Phys. 115,
//! 6351 (2001) for dipoles), for a tensor of rank `l` (2: field of a dipole;
//! 3: field of a quadrupole and gradient of a dipole's field; 4: gradient of
//! a quadrupole's field):
//!
//! * real space, `|grad^l erfc(alpha r)/r| ~ (2 alpha^2)^l r^(l-2) exp(-alpha^2 r^2) / (alpha sqrt(pi))`
//!   summed beyond `r_c` with absolute values:
//!   `2 sqrt(pi) 2^l (alpha d)^(l-2) s^(l-1) exp(-s^2)`;
//! * reciprocal space, every neglected mode taken as coherent as a Bragg
//!   peak (`|S(k)| = N |source| k^l` at each reciprocal lattice vector of a
//!   lattice of density `n`): `2^(l+1) / pi (alpha d)^(l+1) s^(l-1) exp(-s^2)`.
//!
//! Each part gets half the accuracy. Then `alpha` minimises the caller's
//! cost model among 200 values from `0.05 / d` to `20 / d`.

use std::f64::consts::PI;

/// The chosen splitting and cutoffs, with the error estimates they meet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EwaldParameters {
    /// The splitting parameter `alpha` (inverse length).
    pub alpha: f64,
    /// The real-space cutoff `r_c` (length).
    pub real_cutoff: f64,
    /// The reciprocal-space cutoff `k_c` (inverse length).
    pub reciprocal_cutoff: f64,
    /// The estimated relative error of the real-space truncation.
    pub real_estimate: f64,
    /// The estimated relative error of the reciprocal-space truncation.
    pub reciprocal_estimate: f64,
}

impl EwaldParameters {
    /// Parameters converged far below round-off for `alpha` (`s = 7` in
    /// both spaces: `exp(-49)`), for reference sums in tests.
    #[cfg(test)]
    pub(crate) fn converged(alpha: f64) -> Self {
        EwaldParameters {
            alpha,
            real_cutoff: 7.0 / alpha,
            reciprocal_cutoff: 14.0 * alpha,
            real_estimate: 0.0,
            reciprocal_estimate: 0.0,
        }
    }
}

/// The tensor ranks the carried multipoles need (2 between dipoles, 3
/// between a dipole and a quadrupole, 4 between quadrupoles).
pub(crate) fn ranks(dipoles: bool, quadrupoles: bool) -> Vec<i32> {
    let mut out = Vec::new();
    if dipoles {
        out.push(2);
    }
    if dipoles && quadrupoles {
        out.push(3);
    }
    if quadrupoles {
        out.push(4);
    }
    out
}

/// The real-space estimate for `s = alpha r_c` (see the module doc).
pub(crate) fn real_estimate(ranks: &[i32], alpha_d: f64, s: f64) -> f64 {
    ranks
        .iter()
        .map(|&l| {
            2.0 * PI.sqrt() * 2f64.powi(l) * alpha_d.powi(l - 2) * s.powi(l - 1) * (-s * s).exp()
        })
        .fold(0.0, f64::max)
}

/// The reciprocal-space estimate for `s = k_c / (2 alpha)` (see the module doc).
pub(crate) fn reciprocal_estimate(ranks: &[i32], alpha_d: f64, s: f64) -> f64 {
    ranks
        .iter()
        .map(|&l| 2f64.powi(l + 1) / PI * alpha_d.powi(l + 1) * s.powi(l - 1) * (-s * s).exp())
        .fold(0.0, f64::max)
}

/// The smallest `s` in `[0.5, 30]` with `estimate(s) <= target` (bisection;
/// the estimates decrease for `s >= 0.5` at every `alpha d` used here).
pub(crate) fn solve(estimate: impl Fn(f64) -> f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (0.5, 30.0);
    if estimate(lo) <= target {
        return lo;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if estimate(mid) <= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The work of one evaluation as a function of the cutoffs `(r_c, k_c)`,
/// which the choice of `alpha` minimises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Cost {
    /// The direct sum of `sites` sites in a box of `volume`: its real-space
    /// pairs `N^2 (2 pi / 3) r_c^3 / V` plus `2 N` products per wave vector
    /// of the half space, `V k_c^3 / (12 pi^2)` of them.
    Direct { sites: f64, volume: f64 },
    /// The FFT lattice sum's kernel: for each of `basis_pairs` pairs of
    /// basis offsets, the lattice vectors within `r_c` of a cell of
    /// `cell_volume` and the reciprocal ones within `k_c` at each of the
    /// `spectrum` frequencies.
    LatticeFft {
        basis_pairs: f64,
        cell_volume: f64,
        spectrum: f64,
    },
}

impl Cost {
    /// The cost of the cutoffs `rc`, `kc`.
    pub fn of(&self, rc: f64, kc: f64) -> f64 {
        match *self {
            Cost::Direct { sites: n, volume } => {
                let pairs = n * n * (2.0 * PI / 3.0) * rc.powi(3) / volume;
                let waves = volume * kc.powi(3) / (12.0 * PI * PI);
                pairs + 2.0 * n * waves
            }
            Cost::LatticeFft {
                basis_pairs,
                cell_volume,
                spectrum,
            } => {
                basis_pairs
                    * (4.0 * PI / 3.0 * rc.powi(3) / cell_volume
                        + spectrum * cell_volume * kc.powi(3) / (6.0 * PI * PI))
            }
        }
    }
}

/// The parameters for `accuracy` (in (0, 1)) at number density `density`,
/// for the tensor `ranks` carried, minimising `cost(r_c, k_c)`.
pub(crate) fn choose(
    accuracy: f64,
    density: f64,
    ranks: &[i32],
    cost: impl Fn(f64, f64) -> f64,
) -> EwaldParameters {
    let d = density.cbrt().recip();
    let for_alpha = |alpha: f64| {
        let alpha_d = alpha * d;
        let s_real = solve(|s| real_estimate(ranks, alpha_d, s), 0.5 * accuracy);
        let s_reciprocal = solve(|s| reciprocal_estimate(ranks, alpha_d, s), 0.5 * accuracy);
        EwaldParameters {
            alpha,
            real_cutoff: s_real / alpha,
            reciprocal_cutoff: 2.0 * alpha * s_reciprocal,
            real_estimate: real_estimate(ranks, alpha_d, s_real),
            reciprocal_estimate: reciprocal_estimate(ranks, alpha_d, s_reciprocal),
        }
    };
    const STEPS: usize = 200;
    (0..STEPS)
        .map(|k| for_alpha(0.05 / d * 400f64.powf(k as f64 / (STEPS - 1) as f64)))
        .min_by(|a, b| {
            let (ca, cb) = (
                cost(a.real_cutoff, a.reciprocal_cutoff),
                cost(b.real_cutoff, b.reciprocal_cutoff),
            );
            ca.total_cmp(&cb)
        })
        .expect("at least one alpha")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chosen cutoffs meet the requested accuracy by the estimates, and
    /// a tighter accuracy never shortens a cutoff (for a fixed cost model).
    #[test]
    fn cutoffs_meet_the_estimates_and_grow_with_accuracy() {
        let ranks = ranks(true, true);
        let cost = |rc: f64, kc: f64| rc.powi(3) + 0.3 * kc.powi(3);
        let mut previous: Option<EwaldParameters> = None;
        for accuracy in [1e-4, 1e-8, 1e-12, 1e-15] {
            let p = choose(accuracy, 1.0, &ranks, cost);
            assert!(p.real_estimate <= 0.5 * accuracy * (1.0 + 1e-9));
            assert!(p.reciprocal_estimate <= 0.5 * accuracy * (1.0 + 1e-9));
            if let Some(q) = previous {
                assert!(
                    cost(p.real_cutoff, p.reciprocal_cutoff)
                        >= cost(q.real_cutoff, q.reciprocal_cutoff)
                );
            }
            previous = Some(p);
        }
    }

    /// The interaction tensor between multipoles of orders `l1` and `l2`
    /// (dipole 1, quadrupole 2) has rank `l1 + l2`: the ranks needed are
    /// those of every pair of carried orders, each once, in increasing order.
    #[test]
    fn ranks_are_the_sums_of_the_carried_orders() {
        for (dipoles, quadrupoles) in [(true, false), (false, true), (true, true), (false, false)] {
            let orders: Vec<i32> = [(dipoles, 1), (quadrupoles, 2)]
                .iter()
                .filter_map(|&(carried, l)| carried.then_some(l))
                .collect();
            let mut expected: Vec<i32> = orders
                .iter()
                .flat_map(|l1| orders.iter().map(move |l2| l1 + l2))
                .collect();
            expected.sort_unstable();
            expected.dedup();
            assert_eq!(
                ranks(dipoles, quadrupoles),
                expected,
                "dipoles {dipoles}, quadrupoles {quadrupoles}"
            );
        }
    }

    /// `int_a^inf f` by Simpson's rule over `[a, a + width]` (`f` negligible beyond).
    fn tail(f: impl Fn(f64) -> f64, a: f64, width: f64) -> f64 {
        let m = 20_000;
        let h = width / m as f64;
        let inner: f64 = (1..m)
            .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (f(a) + inner + f(a + width)) * h / 3.0
    }

    /// Each estimate is the leading term in `s` of the tail its derivation
    /// (module doc) integrates, here by quadrature at unit density (`d = 1`,
    /// field scale 1): real space, `4 pi int_rc^inf r^2 (2 alpha^2)^l
    /// r^(l-2) exp(-alpha^2 r^2) / (alpha sqrt(pi)) dr`; reciprocal space,
    /// the Bragg peaks of a lattice of unit density (`4 pi k^2 dk / (2 pi)^3`
    /// of them, each `4 pi exp(-k^2 / 4 alpha^2) k^(l-2)`), `(2 / pi)
    /// int_kc^inf k^l exp(-k^2 / 4 alpha^2) dk`. The next term of the
    /// asymptotic series is `(l - 1) / (2 s^2)` relative, so the two agree to
    /// better than `l / s^2` (5 % for `l = 4`, `s = 9`), and at every `alpha d`.
    #[test]
    fn estimates_are_the_leading_terms_of_their_tail_integrals() {
        for l in [2, 3, 4] {
            for alpha in [0.4, 1.0, 3.0] {
                for s in [6.0, 9.0] {
                    let l_f = l as f64;
                    let bound = l_f / (s * s);
                    let rc = s / alpha;
                    let real = tail(
                        |r| {
                            4.0 * PI
                                * r
                                * r
                                * (2.0 * alpha * alpha).powi(l)
                                * r.powi(l - 2)
                                * (-alpha * alpha * r * r).exp()
                                / (alpha * PI.sqrt())
                        },
                        rc,
                        4.0 / alpha,
                    );
                    let ratio = real_estimate(&[l], alpha, s) / real;
                    assert!(
                        (ratio - 1.0).abs() < bound,
                        "real: l {l}, alpha d {alpha}, s {s}: {ratio}"
                    );
                    let kc = 2.0 * alpha * s;
                    let reciprocal = tail(
                        |k| 2.0 / PI * k.powi(l) * (-k * k / (4.0 * alpha * alpha)).exp(),
                        kc,
                        8.0 * alpha,
                    );
                    let ratio = reciprocal_estimate(&[l], alpha, s) / reciprocal;
                    assert!(
                        (ratio - 1.0).abs() < bound,
                        "reciprocal: l {l}, alpha d {alpha}, s {s}: {ratio}"
                    );
                }
            }
        }
    }
}
