//! Smooth particle-mesh Ewald (PME) for charges, point dipoles and
//! Buckingham quadrupoles at any sites of an orthorhombic box (Essmann et
//! al., J. Chem. Phys. 103, 8577 (1995); point multipoles as in Sagui,
//! Pedersen & Darden, J. Chem. Phys. 120, 73 (2004)), in the reduced units
//! of the crate (`4 pi eps0 = 1`).
//!
//! Site `i` acts as the operator `D_i = q_i + mu_i.grad + 1/3 Theta_i:grad
//! grad` on its position, and the energy is `V = 1/2 sum_i D_i phi(r_i)`
//! with the potential `phi` of all the other sites and images. Each site's
//! potential derivatives `d^A phi(r_i)` up to the third order are the sum of:
//!
//! * real space: the pairs within `r_c` with the kernel `erfc(alpha r)/r`
//!   (`real_space`, its kernels four pairs at a time in `pair_kernels`);
//! * reciprocal space: `phi(r) = (4 pi / V) sum_(k != 0) exp(-k^2 / 4
//!   alpha^2) / k^2 S(k) exp(i k.r)` with `S(k) = sum_j D_j exp(-i k.r_j)`,
//!   computed on a mesh of `K_x x K_y x K_z` points with B-splines of order
//!   `p` (`bspline`, `spread`, `influence`, `gather`); the
//!   interpolation error falls as `(h / L)^p`;
//! * self: minus each site's own smooth `D_i erf(alpha |r - r_i|) / |r - r_i|`
//!   at `r = r_i` (energy `-alpha q^2 / sqrt(pi) - 2 alpha^3 mu^2 / (3
//!   sqrt(pi)) - 8 alpha^5 Theta:Theta / (45 sqrt(pi))`, the terms of
//!   `crate::potential::multipole::ewald_terms` with charges);
//! * background: a net charge `Q` with its neutralising background,
//!   `phi = -pi Q / (V alpha^2)` (energy `-pi Q^2 / (2 V alpha^2)`);
//! * surface, vacuum only (de Leeuw, Perram & Smith 1980): `V = 2 pi |M|^2
//!   / (3 V)` with `M = sum_i (q_i r_i + mu_i)` over the sites wrapped into
//!   `[0, L_a)`, or for moving molecules over the sites as given, each
//!   molecule whole about its wrapped centre (`MeshEwald::with_whole_molecules`;
//!   with net charge `M` depends on the convention).
//!
//! Then `E_i = -grad phi`, `W_i = 1/3 grad grad phi`, and the force `F_i =
//! -grad_(r_i) V = -D_i grad phi(r_i)` is the exact gradient of the PME
//! energy (the mesh part included), as the tests check by finite
//! differences; the virial `W = -(dV/d eps)^T` under a homogeneous strain
//! of the box and the sites at fixed multipoles is the sum of the
//! real-space pairs' `r_ij f_ij^T`, the reciprocal term of Essmann et al.
//! (eq 2.8) with the multipoles' `-mu_i E_i^T + 2 Theta_i W_i` of the
//! reciprocal fields, the background's `E_bg I` and in vacuum the
//! surface's `E_s I - 4 pi / (3 V) (sum_i q_i r_i) M^T` (none from the
//! self term).
//!
//! **Interface.** [`MeshEwald::new`] builds the mesh, the FFT plans, the
//! influence function and every buffer for a number of sites and a box;
//! [`MeshEwald::evaluate`] takes [`Sources`] (positions, charges, dipoles,
//! quadrupoles: the sites may move between calls) and fills a
//! [`SiteResponse`] (energy; potential, fields and force of every site);
//! every buffer sized by the sites or the mesh is built once (an
//! evaluation allocates only the FFTs' line scratch; the real-space part's
//! per-thread blocks at the first evaluation with a thread count). The
//! spreading (one task per mesh plane) and the gathering are rayon loops
//! whose sums do not depend on the number of threads; the real-space pairs,
//! each visited once, go to one block per thread added in a fixed order:
//! the same bits for a given thread count.
//!
//! **Parameters** from a requested accuracy: [`for_charges`] (Kolafa &
//! Perram; Deserno & Holm) and [`for_multipoles`] (an aliasing estimate of
//! smooth PME derived in `estimate`).
//!
//! **Without the mesh**: [`WaveEwald`], the same terms with the reciprocal
//! part summed over the wave vectors (the direct Ewald sum of moving
//! sites, cheaper than a mesh for small systems), its parameters by
//! [`for_waves`].

mod accuracy;
mod bspline;
mod cartesian;
mod damped;
mod estimate;
mod gather;
mod influence;
mod mesh;
mod pair_kernels;
mod parameters;
mod real_space;
mod search;
mod site_terms;
mod sites;
mod spread;
mod waves;

pub use accuracy::{
    for_charges, ChargeEstimate, ACCURACY_RANGE, DEFAULT_ORDER, ESTIMATED_ORDERS, MESH_SAFETY,
};
pub use bspline::ORDERS;
pub(crate) use cartesian::{add_source, pair_force, radial_derivatives, DERIVATIVES, UP_TO};
pub(crate) use damped::ErfcTable;
pub use estimate::{mesh_cost, Carried, MeshCosts, MeshEstimate};
pub use mesh::MeshEwald;
pub use parameters::{ForcedMesh, MeshParameters};
pub(crate) use real_space::per_site;
pub use search::{for_multipoles, for_multipoles_forced, for_multipoles_with_skin};
pub use sites::{SiteResponse, Sources};
pub use waves::{for_waves, WaveEwald};

#[cfg(test)]
pub(crate) mod tests;
