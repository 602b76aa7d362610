//! Parameters of the mesh Ewald sum of point multipoles (charges, dipoles,
//! quadrupoles) from a requested accuracy, by an estimate of the aliasing
//! error of smooth PME derived here.
//!
//! **Accuracy.** As for the direct Ewald sum ([`crate::potential::multipole::ewald_parameters`]):
//! the error of the fields the torques need (`E_i` for charges and dipoles,
//! `W_i` for quadrupoles) relative to the field scale `sigma_s n^((s + g +
//! 1) / 3)` of sources of order `s` (0 charge, 1 dipole, 2 quadrupole) and
//! a field of derivative order `g` (1: `E`, 2: `W`), `n = N / V`; here the
//! RMS over the sites, `sigma_s` the RMS multipole.
//!
//! **Real space**: the estimate of the direct Ewald sum for the tensor rank
//! `l = s + g` (`ewald_parameters::real_estimate`, a bound on the tail summed
//! with absolute values), which sets `r_c` for `alpha`; it gets half the
//! accuracy.
//!
//! **Mesh** (derived here; Cerda et al., J. Chem. Phys. 129, 234104 (2008),
//! give the dipolar estimate for P3M's optimal influence function, which
//! smooth PME does not use). A B-spline of order `p` interpolates the plane
//! wave of mode `m` (`|m_a| <= K_a / 2`) with aliases at `m_a + j K_a`
//! whose amplitude relative to the wave is `rho_j = |m_a / (m_a + j K_a)|^p`
//! (the Fourier transform of `M_p`, `(sin(pi m / K) / (pi m / K))^p`); each
//! derivative of the spline (spreading an order-`s` source, gathering an
//! order-`g` field) multiplies the alias by `(m_a + j K_a) / m_a`, so the
//! spreading and the gathering err by `rho_j^(p - s)` and `rho_j^(p - g)`.
//! For sites at random positions with respect to the mesh, the aliases of
//! different sites and modes are incoherent, and the mean square error of a
//! site's field is that of `N` random sources through the Ewald kernel
//! `4 pi exp(-k^2 / 4 alpha^2) / (V k^2)` times `k^(s + g)`, weighted per
//! mode by `eps^2(k) = sum_a sum_(j = +-1, +-2) (rho_j^(2(p - s)) +
//! rho_j^(2(p - g)))`, and by 1 for modes beyond the mesh's Nyquist
//! frequency. As an integral over `k` (`sum_k -> V / (2 pi)^3 int d^3k`):
//!
//! `(dE / (sigma_s n^((l + 1) / 3)))^2 = n^(1 - 2 (l + 1) / 3) / (2 pi)^3
//! int d^3k (4 pi)^2 k^(2 l - 4) exp(-k^2 / 2 alpha^2) eps^2(k)`,
//!
//! by the midpoint rule over `|k_a| < 2 pi / h_a` (twice the Nyquist
//! frequency; beyond, the Gaussian is below `exp(-2 pi^2 / (alpha h)^2)`).
//! The mesh gets half the accuracy. Sites on a lattice are not random with
//! respect to the mesh: their aliases may add coherently; the tests check the
//! estimate on random configurations and on lattices.
//!
//! **Choice.** For each order (the given one, or 4 to 8) and for `alpha d`
//! from 0.5 to 5 (`d = n^(-1/3)`), `r_c` from the real-space estimate, the
//! largest common spacing `h` that meets the mesh estimate, `K_a` the
//! smallest `2^a 3^b 5^c` at least `L_a / h`; the cheapest by the cost model
//! [`cost`] wins. A cutoff longer than half the shortest box side is not
//! used; a request no choice meets is refused.

use super::parameters::MeshParameters;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The estimated errors of a choice, relative to the field scale (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshEstimate {
    /// Real-space part (a bound).
    pub real: f64,
    /// Mesh part (RMS).
    pub mesh: f64,
}

/// Which multipoles the sites carry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Carried {
    /// Point charges.
    pub charges: bool,
    /// Point dipoles.
    pub dipoles: bool,
    /// Point quadrupoles.
    pub quadrupoles: bool,
}

impl Carried {
    /// The measured costs of the mesh sum's work for these sites: those of
    /// the dearest kind carried (quadrupoles take the general kernel, dipoles
    /// the unrolled kernel of charges and dipoles, charges alone their own).
    pub fn costs(&self) -> MeshCosts {
        if self.quadrupoles {
            QUADRUPOLE_COSTS
        } else if self.dipoles {
            DIPOLE_COSTS
        } else {
            CHARGE_COSTS
        }
    }

    /// The pairs `(s, g)` of source order and field order (module doc).
    pub(crate) fn orders(&self) -> Vec<(i32, i32)> {
        let sources: Vec<i32> = [(self.charges, 0), (self.dipoles, 1), (self.quadrupoles, 2)]
            .iter()
            .filter_map(|&(c, s)| c.then_some(s))
            .collect();
        let fields: Vec<i32> = [(self.charges || self.dipoles, 1), (self.quadrupoles, 2)]
            .iter()
            .filter_map(|&(c, g)| c.then_some(g))
            .collect();
        sources
            .iter()
            .flat_map(|&s| fields.iter().map(move |&g| (s, g)))
            .collect()
    }
}

/// The factor by which the mesh error of charges exceeds the estimate:
/// measured against the converged sum on 648 random charges (one third
/// -0.8476, two thirds 0.4238) at accuracies 1e-4 to 1e-6, up to 2.8 at
/// order 8, 2.1 at 7, 1.9 at 6, 1.6 at 4, 1.04 at 5 (2026-11-28); without
/// it the sums of charged bodies missed their request by up to 1.4x
/// (`validation/checks/pme_references.py`). Dipoles and quadrupoles stay
/// within their estimate (the tests: 0.03 to 0.42 of the request).
const CHARGE_MESH_SAFETY: f64 = 3.0;

/// Midpoints per axis of the quadrature over `[0, 2 pi / h_a)`.
const POINTS: usize = 32;

/// The mesh estimate (module doc) of the orders `orders` for `alpha`, mesh
/// spacings `h`, spline order `p` and density `n`: the largest over the pairs.
pub(crate) fn mesh_estimate(
    orders: &[(i32, i32)],
    alpha: f64,
    h: &[f64; 3],
    p: usize,
    n: f64,
) -> f64 {
    let mut largest: f64 = 0.0;
    for &(s, g) in orders {
        let l = s + g;
        // Per axis: k_a, exp(-k_a^2 / 2 alpha^2), the alias weight (None beyond Nyquist).
        let axis: Vec<[(f64, f64, Option<f64>); POINTS]> = h
            .iter()
            .map(|&h| {
                std::array::from_fn(|i| {
                    let u = (i as f64 + 0.5) / POINTS as f64;
                    let k = 2.0 * PI * u / h;
                    let alias = (u < 0.5).then(|| {
                        [-2.0, -1.0, 1.0, 2.0]
                            .iter()
                            .map(|j| {
                                let rho = (u / (u + j)).abs();
                                rho.powi(2 * (p as i32 - s)) + rho.powi(2 * (p as i32 - g))
                            })
                            .sum()
                    });
                    (k, (-k * k / (2.0 * alpha * alpha)).exp(), alias)
                })
            })
            .collect();
        // k^(2 l - 4) as `k2^(l - 2)`, l from 1 to 4, without a call to powi per mode.
        let power = |k2: f64| match l - 2 {
            -1 => 1.0 / k2,
            0 => 1.0,
            1 => k2,
            _ => k2 * k2,
        };
        let mut sum = 0.0;
        for &(kx, gx, ex) in &axis[0] {
            for &(ky, gy, ey) in &axis[1] {
                for &(kz, gz, ez) in &axis[2] {
                    let eps = match (ex, ey, ez) {
                        (Some(x), Some(y), Some(z)) => x + y + z,
                        _ => 1.0,
                    };
                    let k2 = kx * kx + ky * ky + kz * kz;
                    sum += power(k2) * gx * gy * gz * eps;
                }
            }
        }
        let cell: f64 = h.iter().map(|h| 2.0 * PI / (h * POINTS as f64)).product();
        let integral = 8.0 * (4.0 * PI).powi(2) * sum * cell;
        let square = n.powf(1.0 - 2.0 * (l + 1) as f64 / 3.0) / (2.0 * PI).powi(3) * integral;
        let safety = if s == 0 { CHARGE_MESH_SAFETY } else { 1.0 };
        largest = largest.max(safety * square.sqrt());
    }
    largest
}

/// The estimated seconds of one evaluation: `N n (2 pi / 3) r_c^3` pairs,
/// [`MESH_POINT_SECONDS`] per mesh point and `log2` of the point count (the
/// FFTs both ways and the influence function), `p^3` spline points per site
/// (spreading and gathering) and the per-site work, each at its measured
/// cost (`costs`).
pub(crate) fn cost(
    (sites, density): (f64, f64),
    rc: f64,
    grid: [usize; 3],
    order: usize,
    costs: MeshCosts,
) -> f64 {
    let points: f64 = grid.iter().map(|&k| k as f64).product();
    costs.pair * sites * density * (2.0 * PI / 3.0) * rc.powi(3)
        + MESH_POINT_SECONDS * points * points.log2()
        + costs.spline_point * sites * (order as f64).powi(3)
        + costs.site * sites
}

/// `cost` of the sum of `sites` sites in `box_lengths` with `parameters`
/// at `costs`, in seconds per evaluation: what the automatic choices weigh
/// against the direct sum.
pub fn mesh_cost(
    parameters: &MeshParameters,
    sites: usize,
    box_lengths: &Vector3<f64>,
    costs: MeshCosts,
) -> f64 {
    let n = sites.max(1) as f64;
    cost(
        (n, n / box_lengths.product()),
        parameters.real_cutoff,
        parameters.grid,
        parameters.order,
        costs,
    )
}

/// The seconds of the mesh sum's work per unit for one kind of site, one
/// thread: least-squares fits of `t = t_pair P + t_mesh M log2 M + t_spline
/// N p^3 + t_site N` to the evaluation times of `examples/pme_costs.rs`
/// (forced parameters, median process CPU time; 2026-12-02, an idle 2-CPU
/// Intel Xeon), `P = N n (2 pi / 3) r_c^3` the model's pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshCosts {
    /// A real-space pair, the search included.
    pub pair: f64,
    /// A site's spline point (`p^3` of them per site).
    pub spline_point: f64,
    /// A site's work that no parameter changes (wrapping, the cell list,
    /// the self terms, the forces): not weighed by the choice of
    /// parameters, but by the automatic choice against the direct sum.
    pub site: f64,
}

/// 12,000 random charges at 100.2 per unit volume, forces without the
/// field gradient (15 cases, meshes 40^3 to 200^3, residual 2.8 %).
const CHARGE_COSTS: MeshCosts = MeshCosts {
    pair: 25.9e-9,
    spline_point: 1.76e-9,
    site: 297e-9,
};

/// 4,096 random unit dipoles at density 0.8, forces and torques (15
/// cases, meshes 16^3 to 160^3, residual 6 %).
const DIPOLE_COSTS: MeshCosts = MeshCosts {
    pair: 35.3e-9,
    spline_point: 2.36e-9,
    site: 468e-9,
};

/// 4,096 random linear quadrupoles at density 0.8 on the general kernel
/// (15 cases, residual 0.6 %).
const QUADRUPOLE_COSTS: MeshCosts = MeshCosts {
    pair: 336e-9,
    spline_point: 3.33e-9,
    site: 961e-9,
};

/// The cost of a mesh point (times `log2` of the point count), from the
/// charges' fit: per unit it grows with the mesh (0.6 ns below 48^3, 1.0
/// to 1.3 ns from 100^3 to 200^3, out of cache), and the fit over meshes
/// up to 200^3 prices the large meshes that dominate a sum's cost.
const MESH_POINT_SECONDS: f64 = 1.19e-9;
