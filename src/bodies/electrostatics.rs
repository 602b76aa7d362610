//! Electrostatics between sites of different bodies: the interface every
//! method shares (site positions and space-frame multipoles in; energy,
//! virial, per-site potential, field and force out, in the convention of
//! the rotors' `SiteFields`: `E = -dV/dmu`), and the sum truncated at a
//! cutoff.
//!
//! The truncated sum is LAMMPS `pair_style lj/cut/dipole/cut`'s: the bare
//! charge and dipole pair energies (the Cartesian tensors of
//! `potential::multipole::kernels`) for site pairs closer than the cutoff,
//! neither shifted nor smoothed, the forces their exact gradients (no
//! impulse at the cutoff). Sites with point quadrupoles take the Cartesian
//! tensors of any order (`crate::potential::multipole::mesh_ewald`'s
//! multi-indices) with the same bare `1/r`. The shifted-force truncation of
//! charges and dipoles (LAMMPS `lj/sf/dipole/sf`) is in
//! [`super::electrostatics_shifted`], the Ewald sums in
//! [`super::electrostatics_ewald`].

use super::electrostatics_shifted::ElectrostaticTruncation;
use super::evaluate::Scope;
use super::neighbours::NeighbourList;
use super::pair_pass::{PairPass, PairTerms};
use super::space::Space;
use crate::checks::{positive, InputError};
use crate::potential::multipole::mesh_ewald::{
    add_source, pair_force, radial_derivatives, Carried, MeshEstimate, MeshParameters, Sources,
    DERIVATIVES, UP_TO,
};
use crate::potential::multipole::{radial_functions, AutoChoice, EwaldParameters};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

pub use crate::potential::multipole::mesh_ewald::SiteResponse;

/// Space-frame multipoles of every site (zero where a site has none).
#[derive(Clone, Debug, Default)]
pub struct SiteMultipoles {
    /// Which multipoles some site carries.
    pub carried: Carried,
    /// Site positions (not necessarily wrapped).
    pub positions: Vec<Vector3<f64>>,
    /// Charges.
    pub charges: Vec<f64>,
    /// Dipoles, space frame.
    pub dipoles: Vec<Vector3<f64>>,
    /// Traceless (Buckingham) quadrupoles, space frame.
    pub quadrupoles: Vec<Matrix3<f64>>,
}

impl SiteMultipoles {
    /// The sites as the sources of a sum (the multipoles no site carries left out).
    pub fn sources(&self) -> Sources<'_> {
        Sources {
            positions: &self.positions,
            charges: self.carried.charges.then_some(&self.charges[..]),
            dipoles: self.carried.dipoles.then_some(&self.dipoles[..]),
            quadrupoles: self.carried.quadrupoles.then_some(&self.quadrupoles[..]),
        }
    }
}

/// A method of electrostatics between sites of different bodies. It fills
/// a [`SiteResponse`]: energy, the atomic virial `sum_pairs r_ij f_ij^T`
/// (the strain derivative at fixed space-frame multipoles), and per site the
/// potential, field `E = -dV/dmu`, conjugate `W = dV/dTheta` and force.
pub trait Electrostatics: Send + Sync + std::fmt::Debug {
    /// The distance within which it reads the pairs of the bodies'
    /// neighbour list (its real-space cutoff); none when it finds its pairs
    /// itself.
    fn pair_cutoff(&self) -> Option<f64>;

    /// The parameters and estimated errors of a mesh sum (none by default).
    fn mesh_parameters(&self) -> Option<(MeshParameters, MeshEstimate)> {
        None
    }

    /// The parameters of a direct Ewald sum (none by default).
    fn ewald_parameters(&self) -> Option<EwaldParameters> {
        None
    }

    /// What `method = "auto"` compared (none by default).
    fn auto_choice(&self) -> Option<&AutoChoice> {
        None
    }

    /// The cutoff and truncation of a sum of charges and dipoles over the
    /// half neighbour list, which the evaluation of a body system then
    /// makes in one pass with the Lennard-Jones term (none by default).
    fn cutoff_pairs(&self) -> Option<(f64, ElectrostaticTruncation)> {
        None
    }

    /// Evaluates the sites' electrostatics into `out` (sized for the
    /// sites), in `scope`: a method may leave the energy and the virial out
    /// for [`Scope::Forces`] where its forces stay the same bits.
    fn evaluate(
        &mut self,
        sites: &SiteMultipoles,
        space: &Space,
        pairs: &NeighbourList,
        out: &mut SiteResponse,
        scope: Scope,
    );
}

/// The sum truncated at a cutoff (LAMMPS `lj/cut/dipole/cut`, or
/// `lj/sf/dipole/sf` shifted-force).
#[derive(Clone, Debug, PartialEq)]
pub struct CutoffSum {
    cutoff: f64,
    truncation: ElectrostaticTruncation,
    /// Whether sites carry quadrupoles (summed through the Cartesian
    /// tensors of any order, over the full view of the neighbour list).
    quadrupoles: bool,
    /// Each site's potential derivatives and half pair virials (sites with quadrupoles).
    derivatives: Vec<[f64; DERIVATIVES]>,
    virials: Vec<Matrix3<f64>>,
    /// The pair pass's buffers (sites without quadrupoles).
    pass: PairPass,
}

impl CutoffSum {
    /// The sum over pairs closer than `cutoff` (> 0) of sites carrying
    /// `carried`, truncated by `truncation` (shifted-force refuses
    /// quadrupoles, naming `truncation`).
    pub fn new(
        cutoff: f64,
        truncation: ElectrostaticTruncation,
        carried: Carried,
    ) -> Result<Self, InputError> {
        if truncation == ElectrostaticTruncation::ShiftedForce && carried.quadrupoles {
            return Err(InputError::new(
                "truncation",
                "\"shifted_force\" truncates charges and dipoles only, and sites carry quadrupoles",
            ));
        }
        Ok(CutoffSum {
            cutoff: positive(cutoff).map_err(|e| e.at("cutoff"))?,
            truncation,
            quadrupoles: carried.quadrupoles,
            derivatives: Vec::new(),
            virials: Vec::new(),
            pass: PairPass::default(),
        })
    }
}

/// The pairs within bodies of an Ewald sum: the sites of each body, the
/// body of each site, and the splitting `alpha`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Exclusions<'a> {
    pub bodies: &'a [std::ops::Range<usize>],
    pub site_body: &'a [u32],
    pub alpha: f64,
}

/// `B_0..B_5` of a radial kernel at a distance.
pub(super) type RadialKernel<'a> = dyn Fn(f64) -> [f64; 6] + Sync + 'a;

/// Adds to every site's potential derivatives `derivatives` (and to its
/// half of the pair virials, `virials`) the pairs of `pairs` closer than
/// `cutoff` through the radial kernel whose `B_0..B_5` at `r` are
/// `kernel(r)` (the bare `1/r` of a cutoff sum, `erfc(alpha r) / r` of
/// Ewald's real space), then, with `exclusions`, subtracts within each body
/// (`exclusions(i)` the range of site `i`'s body) the smooth part
/// `erf(alpha r) / r` that a reciprocal-space sum put there.
pub(super) fn add_pairs(
    sites: &SiteMultipoles,
    pairs: &NeighbourList,
    (cutoff, kernel): (f64, &RadialKernel<'_>),
    exclusions: Option<Exclusions<'_>>,
    (derivatives, virials): (&mut [[f64; DERIVATIVES]], &mut [Matrix3<f64>]),
) {
    let sources = sites.sources();
    let order = sources.order();
    // Up to the field gradients (the quadrupoles' conjugates) at least.
    let field_order = (order + 1).max(2);
    let (count, needed) = (UP_TO[field_order], UP_TO[field_order + order]);
    let cutoff2 = cutoff * cutoff;
    derivatives
        .par_iter_mut()
        .zip(virials.par_iter_mut())
        .enumerate()
        .with_min_len(64)
        .for_each(|(i, (d, w))| {
            *w = Matrix3::zeros();
            let target = sources.coefficients(i);
            let mut t = [[0.0; 56]; 6];
            let mut pair = |r: Vector3<f64>, b: &[f64; 6], j: usize| {
                radial_derivatives(&r, b, needed, &mut t);
                let source = sources.coefficients(j);
                add_source(&t[0], &source, UP_TO[order], count, d);
                let f = pair_force(&t[0], &target, UP_TO[order], &source, UP_TO[order]);
                *w += r * f.transpose() * 0.5;
            };
            for (j, r) in pairs.separations(i, &sites.positions) {
                if r.norm_squared() < cutoff2 {
                    pair(r, &kernel(r.norm()), j);
                }
            }
            if let Some(Exclusions {
                bodies,
                site_body,
                alpha,
            }) = exclusions
            {
                for j in bodies[site_body[i] as usize].clone().filter(|&j| j != i) {
                    let r = sites.positions[i] - sites.positions[j];
                    let (bare, damped): ([f64; 6], [f64; 6]) = (
                        radial_functions(0.0, r.norm()),
                        radial_functions(alpha, r.norm()),
                    );
                    // -erf(alpha r) / r = erfc(alpha r) / r - 1 / r.
                    pair(r, &std::array::from_fn(|l| damped[l] - bare[l]), j);
                }
            }
        });
}

impl Electrostatics for CutoffSum {
    fn pair_cutoff(&self) -> Option<f64> {
        Some(self.cutoff)
    }

    fn cutoff_pairs(&self) -> Option<(f64, ElectrostaticTruncation)> {
        (!self.quadrupoles).then_some((self.cutoff, self.truncation))
    }

    fn evaluate(
        &mut self,
        sites: &SiteMultipoles,
        _space: &Space,
        pairs: &NeighbourList,
        out: &mut SiteResponse,
        scope: Scope,
    ) {
        let n = sites.positions.len();
        if self.quadrupoles {
            // The Cartesian tensors of any order (the pair pass's charge-dipole kernels are LAMMPS's).
            self.derivatives.clear();
            self.derivatives.resize(n, [0.0; DERIVATIVES]);
            self.virials.resize(n, Matrix3::zeros());
            let kernel = |r: f64| radial_functions(0.0, r);
            add_pairs(
                sites,
                pairs,
                (self.cutoff, &kernel),
                None,
                (&mut self.derivatives, &mut self.virials),
            );
            out.fill(&sites.sources(), &self.derivatives);
            out.virial = self.virials.iter().sum();
            return;
        }
        let terms = PairTerms {
            lennard_jones: None,
            electrostatics: Some((self.cutoff, self.truncation, sites)),
        };
        self.pass
            .run(&terms, pairs, &sites.positions, scope)
            .fill(out);
    }
}
