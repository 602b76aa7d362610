//! One pass over the half neighbour list for the short-range pair terms:
//! Lennard-Jones and the cutoff sum of charges and dipoles together, each
//! pair once, its force added to one site and subtracted from the other
//! (Newton's third law). The truncations are dispatched once per pass, to a
//! kernel monomorphised for them.
//!
//! Threads take contiguous ranges of sites with about equal numbers of
//! pairs, each accumulating into its own block of per-site sums; the blocks
//! are added in range order, so the results are the same bits for a given
//! number of threads (and, with one thread, no block is added at all).

use super::electrostatics::{SiteMultipoles, SiteResponse};
use super::electrostatics_shifted::{ElectrostaticTruncation, ShiftedForceFactors};
use super::lennard_jones::LennardJonesTerm;
use super::neighbours::NeighbourList;
use crate::potential::multipole::{charge_dipole_force, dipole_field, radial, ChargeDipole};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// The terms of a pass: Lennard-Jones with each site's parameters' index
/// (`None` for a site without), and the cutoff sum of charges and dipoles
/// with its cutoff and truncation.
#[derive(Clone, Copy, Debug)]
pub(super) struct PairTerms<'a> {
    pub lennard_jones: Option<(&'a LennardJonesTerm, &'a [Option<u32>])>,
    pub electrostatics: Option<(f64, ElectrostaticTruncation, &'a SiteMultipoles)>,
}

/// The sums of a pass (of one thread's range of sites, before they are
/// added).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PairSums {
    /// The Lennard-Jones energy.
    pub lennard_jones: f64,
    /// The electrostatic energy.
    pub electrostatic: f64,
    /// The atomic virial `sum_pairs r_ij f_ij^T` of both terms.
    pub virial: Matrix3<f64>,
    /// The force on each site, both terms.
    pub force: Vec<Vector3<f64>>,
    /// The electrostatic potential and field at each site (empty without
    /// electrostatics).
    pub potential: Vec<f64>,
    pub field: Vec<Vector3<f64>>,
}

/// The buffers of a pass, reused from one to the next.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PairPass {
    /// One block per thread; the first holds the total after a pass.
    blocks: Vec<PairSums>,
    /// Whether each site carries a charge or a dipole.
    charged: Vec<bool>,
}

impl PairPass {
    /// Sums `terms` over the pairs of `list` at site positions `positions`;
    /// the totals are returned.
    pub(super) fn run(
        &mut self,
        terms: &PairTerms<'_>,
        list: &NeighbourList,
        positions: &[Vector3<f64>],
    ) -> &PairSums {
        let n = positions.len();
        let threads = rayon::current_num_threads().clamp(1, n.max(1));
        self.blocks.resize_with(threads, PairSums::default);
        let electrostatics = terms.electrostatics.is_some();
        for block in &mut self.blocks {
            block.reset(n, electrostatics);
        }
        self.charged.clear();
        if let Some((_, _, m)) = terms.electrostatics {
            let zero = ChargeDipole::default();
            self.charged.extend((0..n).map(|i| charged(m, i) != zero));
        }
        let inputs = Inputs {
            terms,
            list,
            positions,
            charged: &self.charged,
        };
        let blocks = &mut self.blocks;
        use ElectrostaticTruncation as E;
        match terms.electrostatics.map(|(_, t, m)| (t, m.carried.charges)) {
            None => inputs.with_lennard_jones::<NoCharges>(blocks),
            Some((E::Plain, true)) => inputs.with_lennard_jones::<Truncated<Plain, true>>(blocks),
            Some((E::Plain, false)) => inputs.with_lennard_jones::<Truncated<Plain, false>>(blocks),
            Some((E::ShiftedForce, true)) => {
                inputs.with_lennard_jones::<Truncated<ShiftedForceFactors, true>>(blocks)
            }
            Some((E::ShiftedForce, false)) => {
                inputs.with_lennard_jones::<Truncated<ShiftedForceFactors, false>>(blocks)
            }
        }
        let (first, rest) = self.blocks.split_at_mut(1);
        let total = &mut first[0];
        for block in rest.iter() {
            total.lennard_jones += block.lennard_jones;
            total.virial += block.virial;
        }
        if !rest.is_empty() {
            total
                .force
                .par_iter_mut()
                .enumerate()
                .with_min_len(1024)
                .for_each(|(s, f)| rest.iter().for_each(|b| *f += b.force[s]));
            if electrostatics {
                total
                    .field
                    .par_iter_mut()
                    .zip(total.potential.par_iter_mut())
                    .enumerate()
                    .with_min_len(1024)
                    .for_each(|(s, (e, p))| {
                        for b in rest.iter() {
                            *e += b.field[s];
                            *p += b.potential[s];
                        }
                    });
            }
        }
        if let Some((_, _, m)) = terms.electrostatics {
            // Half of each site's charge in its potential and dipole in its field.
            total.electrostatic = (0..n)
                .map(|i| {
                    0.5 * (m.charges[i] * total.potential[i] - m.dipoles[i].dot(&total.field[i]))
                })
                .sum();
        }
        total
    }
}

impl PairSums {
    /// The electrostatic response of the sums (their forces those of the
    /// electrostatics only when the pass had no Lennard-Jones term).
    pub(super) fn fill(&self, out: &mut SiteResponse) {
        out.energy = self.electrostatic;
        out.virial = self.virial;
        out.potential.copy_from_slice(&self.potential);
        out.field.copy_from_slice(&self.field);
        out.force.copy_from_slice(&self.force);
        out.quadrupole_conjugate.fill(Matrix3::zeros());
    }

    /// Zero sums for `n` sites (with the electrostatic ones or not).
    fn reset(&mut self, n: usize, electrostatics: bool) {
        (self.lennard_jones, self.electrostatic) = (0.0, 0.0);
        self.virial = Matrix3::zeros();
        self.force.clear();
        self.force.resize(n, Vector3::zeros());
        let m = if electrostatics { n } else { 0 };
        self.potential.clear();
        self.potential.resize(m, 0.0);
        self.field.clear();
        self.field.resize(m, Vector3::zeros());
    }
}

/// Site `i`'s charge and dipole.
#[inline]
fn charged(m: &SiteMultipoles, i: usize) -> ChargeDipole {
    ChargeDipole {
        charge: m.charges[i],
        dipole: m.dipoles[i],
    }
}

/// What the kernels read.
struct Inputs<'a> {
    terms: &'a PairTerms<'a>,
    list: &'a NeighbourList,
    positions: &'a [Vector3<f64>],
    charged: &'a [bool],
}

impl<'a> Inputs<'a> {
    /// The pass with the charge kernel `C` and the Lennard-Jones kernel of the terms.
    fn with_lennard_jones<C: ChargeKernel>(&self, blocks: &mut [PairSums]) {
        match self.terms.lennard_jones.map(|(t, _)| t.force_shifted()) {
            None if C::ON => self.sum::<NoLennardJones, C>(blocks),
            None => {}
            Some(false) => self.sum::<LennardJones<'_, false>, C>(blocks),
            Some(true) => self.sum::<LennardJones<'_, true>, C>(blocks),
        }
    }

    /// The pass with the kernels `L` and `C`, one range of sites per block.
    fn sum<L: PairKernel<'a>, C: ChargeKernel>(&self, blocks: &mut [PairSums]) {
        let n = self.positions.len();
        let (threads, pairs) = (blocks.len(), self.list.pairs());
        // The first site with at least `k pairs / threads` pairs before it.
        let bound = |k: usize| {
            let before = k * pairs / threads;
            let (mut lo, mut hi) = (0, n);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if self.list.half_start(mid) < before {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let bounds: Vec<usize> = (0..=threads)
            .map(|k| if k == threads { n } else { bound(k) })
            .collect();
        if threads == 1 {
            self.range::<L, C>(0..n, &mut blocks[0]);
        } else {
            blocks
                .par_iter_mut()
                .enumerate()
                .for_each(|(k, block)| self.range::<L, C>(bounds[k]..bounds[k + 1], block));
        }
    }

    /// The pairs listed under the sites of `sites` into `out`.
    #[inline(always)]
    fn range<L: PairKernel<'a>, C: ChargeKernel>(
        &self,
        sites: std::ops::Range<usize>,
        out: &mut PairSums,
    ) {
        let Some(lj) = L::new(self.terms.lennard_jones.map(|t| t.0)) else {
            return;
        };
        let (lj_cutoff2, kind) = self
            .terms
            .lennard_jones
            .map_or((0.0, &[][..]), |(t, kind)| (t.cutoff() * t.cutoff(), kind));
        let (coulomb_cutoff, multipoles) = match self.terms.electrostatics {
            Some((cutoff, _, m)) => (cutoff, Some(m)),
            None => (0.0, None),
        };
        let (coulomb, coulomb_cutoff2) = (C::new(), coulomb_cutoff * coulomb_cutoff);
        let mut lj_energy = 0.0;
        // The virial's components, row by row (nalgebra's outer product
        // costs several times these nine products).
        let mut virial = [0.0; 9];
        for i in sites {
            let a = if L::ON { kind[i] } else { None };
            let target = match multipoles {
                Some(m) if C::ON && self.charged[i] => Some(charged(m, i)),
                _ => None,
            };
            if a.is_none() && target.is_none() {
                continue;
            }
            let (mut force_i, mut field_i, mut potential_i) =
                (Vector3::zeros(), Vector3::zeros(), 0.0);
            for (j, r) in self.list.half_pairs(i, self.positions) {
                let r2 = r.norm_squared();
                let mut f = Vector3::zeros();
                if let (true, Some(a), Some(b)) =
                    (r2 < lj_cutoff2, a, kind.get(j).copied().flatten())
                {
                    let (u, f_over_r) = lj.pair(a as usize, b as usize, r2);
                    lj_energy += u;
                    f = r * f_over_r;
                }
                if let (true, Some(t), Some(m)) = (r2 < coulomb_cutoff2, &target, multipoles) {
                    if self.charged[j] {
                        let s = charged(m, j);
                        let pair = coulomb.pair(&r, r2, coulomb_cutoff, t, &s);
                        field_i += pair.field;
                        out.field[j] += pair.source_field;
                        if C::CHARGES {
                            potential_i += pair.potential;
                            out.potential[j] += pair.source_potential;
                        }
                        f += pair.force;
                    }
                }
                force_i += f;
                out.force[j] -= f;
                for a in 0..3 {
                    for b in 0..3 {
                        virial[3 * a + b] += r[a] * f[b];
                    }
                }
            }
            out.force[i] += force_i;
            if target.is_some() {
                out.potential[i] += potential_i;
                out.field[i] += field_i;
            }
        }
        out.lennard_jones = lj_energy;
        out.virial = Matrix3::from_row_slice(&virial);
    }
}

/// The Lennard-Jones pair of a pass.
trait PairKernel<'a>: Sync + Sized {
    /// Whether the pass has the term.
    const ON: bool;
    /// The kernel of `term` (`None` if the pass needs the term and has none).
    fn new(term: Option<&'a LennardJonesTerm>) -> Option<Self>;
    /// Energy and `-(1/r) du/dr` of kinds `a`, `b` at `r2` within the cutoff.
    fn pair(&self, a: usize, b: usize, r2: f64) -> (f64, f64);
}

struct NoLennardJones;

impl PairKernel<'_> for NoLennardJones {
    const ON: bool = false;
    fn new(_: Option<&LennardJonesTerm>) -> Option<Self> {
        Some(NoLennardJones)
    }
    fn pair(&self, _: usize, _: usize, _: f64) -> (f64, f64) {
        (0.0, 0.0)
    }
}

/// The term, force-shifted or not.
struct LennardJones<'a, const FORCE_SHIFTED: bool>(&'a LennardJonesTerm);

impl<'a, const FORCE_SHIFTED: bool> PairKernel<'a> for LennardJones<'a, FORCE_SHIFTED> {
    const ON: bool = true;
    fn new(term: Option<&'a LennardJonesTerm>) -> Option<Self> {
        term.map(LennardJones)
    }
    #[inline(always)]
    fn pair(&self, a: usize, b: usize, r2: f64) -> (f64, f64) {
        self.0.pair_of::<FORCE_SHIFTED>(a, b, r2)
    }
}

/// Both ends of a charge-dipole pair: the target's potential, field and
/// force, and the source's potential and field (its force is minus the
/// target's).
struct BothEnds {
    potential: f64,
    field: Vector3<f64>,
    force: Vector3<f64>,
    source_potential: f64,
    source_field: Vector3<f64>,
}

/// The charge-dipole pair of a pass.
trait ChargeKernel: Sync + Sized {
    /// Whether the pass has the term.
    const ON: bool;
    /// Whether some site carries a charge (if not, the potentials are
    /// left zero: nothing reads them).
    const CHARGES: bool;
    fn new() -> Self;
    /// The pair of a target at offset `r` (`r2 = |r|^2` within `cutoff`)
    /// from a source.
    fn pair(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        cutoff: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> BothEnds;
}

/// No charges or dipoles.
struct NoCharges;

impl ChargeKernel for NoCharges {
    const ON: bool = false;
    const CHARGES: bool = false;
    fn new() -> Self {
        NoCharges
    }
    fn pair(
        &self,
        _: &Vector3<f64>,
        _: f64,
        _: f64,
        _: &ChargeDipole,
        _: &ChargeDipole,
    ) -> BothEnds {
        BothEnds {
            potential: 0.0,
            field: Vector3::zeros(),
            force: Vector3::zeros(),
            source_potential: 0.0,
            source_field: Vector3::zeros(),
        }
    }
}

/// The radial factors of a truncation at one distance, and what a pair
/// takes from them.
trait Factors {
    fn new(r2: f64, cutoff: f64) -> Self;
    /// The potential and field at offset `r` from a source.
    fn fields(&self, r: &Vector3<f64>, source: &ChargeDipole) -> (f64, Vector3<f64>);
    /// The force on a target at offset `r` from a source.
    fn force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64>;
    /// [`Factors::fields`]' field of a source without charge.
    fn dipole_field(&self, r: &Vector3<f64>, source: &ChargeDipole) -> Vector3<f64> {
        self.fields(r, source).1
    }
    /// [`Factors::force`] of sites without charges.
    fn dipole_force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        self.force(r, r2, target, source)
    }
}

/// A truncation's pair, with charges or of dipoles only.
struct Truncated<F, const CHARGES: bool>(std::marker::PhantomData<fn() -> F>);

impl<F: Factors, const CHARGES: bool> ChargeKernel for Truncated<F, CHARGES> {
    const ON: bool = true;
    const CHARGES: bool = CHARGES;
    fn new() -> Self {
        Truncated(std::marker::PhantomData)
    }
    #[inline(always)]
    fn pair(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        cutoff: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> BothEnds {
        let factors = F::new(r2, cutoff);
        if !CHARGES {
            return BothEnds {
                potential: 0.0,
                field: factors.dipole_field(r, source),
                force: factors.dipole_force(r, r2, target, source),
                source_potential: 0.0,
                source_field: factors.dipole_field(&-r, target),
            };
        }
        let ((potential, field), (source_potential, source_field)) =
            (factors.fields(r, source), factors.fields(&-r, target));
        BothEnds {
            potential,
            field,
            force: factors.force(r, r2, target, source),
            source_potential,
            source_field,
        }
    }
}

/// The bare pair (LAMMPS `lj/cut/dipole/cut`): the radial functions of
/// `1/r`.
struct Plain([f64; 5]);

impl Factors for Plain {
    #[inline(always)]
    fn new(r2: f64, _: f64) -> Self {
        Plain(radial(0.0, r2.sqrt()))
    }
    #[inline(always)]
    fn fields(&self, r: &Vector3<f64>, s: &ChargeDipole) -> (f64, Vector3<f64>) {
        let b = &self.0;
        (
            s.charge * b[0] + s.dipole.dot(r) * b[1],
            r * (s.charge * b[1]) + dipole_field(r, b, &s.dipole),
        )
    }
    #[inline(always)]
    fn force(
        &self,
        r: &Vector3<f64>,
        _: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        charge_dipole_force(r, &self.0, target, source)
    }
    #[inline(always)]
    fn dipole_field(&self, r: &Vector3<f64>, source: &ChargeDipole) -> Vector3<f64> {
        dipole_field(r, &self.0, &source.dipole)
    }
    /// `charge_dipole_force` with zero charges.
    #[inline(always)]
    fn dipole_force(
        &self,
        r: &Vector3<f64>,
        _: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        let (b, mu_t, mu_s) = (&self.0, &target.dipole, &source.dipole);
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        r * (mu_t.dot(mu_s) * b[2] - t_r * s_r * b[3]) + (mu_t * s_r + mu_s * t_r) * b[2]
    }
}

/// The shifted-force pair (LAMMPS `lj/sf/dipole/sf`).
impl Factors for ShiftedForceFactors {
    #[inline(always)]
    fn new(r2: f64, cutoff: f64) -> Self {
        ShiftedForceFactors::new(r2, cutoff)
    }
    #[inline(always)]
    fn fields(&self, r: &Vector3<f64>, source: &ChargeDipole) -> (f64, Vector3<f64>) {
        ShiftedForceFactors::fields(self, r, source)
    }
    #[inline(always)]
    fn force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        ShiftedForceFactors::force(self, r, r2, target, source)
    }
}
