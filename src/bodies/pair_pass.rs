//! One pass over the half neighbour list for the short-range pair terms:
//! Lennard-Jones and the cutoff sum of charges and dipoles together, each
//! pair once, its force added to one site and subtracted from the other
//! (Newton's third law). The truncations are dispatched once per pass, to a
//! kernel monomorphised for them. Of each site's listed partners, those
//! within a cutoff are first gathered with their separations in rows
//! (`super::within`), so the kernels take four such pairs per row and no
//! lanes go to the list's skin.
//!
//! A pass for the forces only ([`Scope::Forces`], the steps whose energies
//! and virial nothing reads) is another monomorphisation without the
//! energies' and the virial's sums: the forces are the same bits.
//!
//! Threads take contiguous ranges of sites with about equal numbers of
//! pairs, each accumulating into its own block of per-site sums; the blocks
//! are added in range order, so the results are the same bits for a given
//! number of threads (and, with one thread, no block is added at all).

use super::electrostatics::SiteMultipoles;
use super::electrostatics_shifted::{ChargeDipoles, ElectrostaticTruncation};
use super::evaluate::Scope;
use super::lennard_jones::LennardJonesTerm;
use super::neighbours::NeighbourList;
use super::pair_kernels::{
    react, Bare, ChargeKernel, LennardJones, NoCharges, NoLennardJones, PairKernel, ShiftedForce,
    Truncated,
};
use super::pair_sums::PairSums;
use super::within::Within;
#[cfg(target_arch = "x86_64")]
use crate::lanes::Avx;
use crate::lanes::{Lanes, Path, F4, LANES, V4};
use crate::potential::multipole::ChargeDipole;
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

/// The buffers of a pass, reused from one to the next.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PairPass {
    /// One block per thread; the first holds the total after a pass.
    blocks: Vec<PairSums>,
    /// Each thread's partners within reach of the site it is at.
    within: Vec<Within>,
    /// Whether each site carries a charge or a dipole.
    charged: Vec<bool>,
    /// Each site's Lennard-Jones kind ([`NO_KIND`] without, or without the term).
    kind: Vec<u32>,
    /// The machine code of the pass (the same bits on each).
    path: Path,
}

impl PairPass {
    /// Sums `terms` over the pairs of `list` at site positions `positions`
    /// (in `scope`: without the energies and the virial, left NaN, for
    /// [`Scope::Forces`]); the totals are returned.
    pub(super) fn run(
        &mut self,
        terms: &PairTerms<'_>,
        list: &NeighbourList,
        positions: &[Vector3<f64>],
        scope: Scope,
    ) -> &PairSums {
        let n = positions.len();
        let threads = rayon::current_num_threads().clamp(1, n.max(1));
        self.blocks.resize_with(threads, PairSums::default);
        self.within.resize_with(threads, Within::default);
        let electrostatics = terms.electrostatics.is_some();
        for block in &mut self.blocks {
            block.reset(n, electrostatics);
        }
        self.site_tables(terms, n);
        let inputs = Inputs {
            terms,
            list,
            positions,
            charged: &self.charged,
            kind: &self.kind,
            one_kind: self.kind.iter().all(|&k| k == self.kind[0] && k != NO_KIND),
            all_charged: self.charged.iter().all(|&c| c),
            lengths: list.image_lengths(),
            path: self.path,
        };
        let blocks = (&mut self.blocks[..], &mut self.within[..]);
        match scope {
            Scope::Full => inputs.with_charges::<true>(blocks),
            Scope::Forces => inputs.with_charges::<false>(blocks),
        }
        let (first, rest) = self.blocks.split_at_mut(1);
        let total = &mut first[0];
        for block in rest.iter() {
            total.lennard_jones += block.lennard_jones;
            total.overlaps += block.overlaps;
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
        if scope == Scope::Forces {
            (total.lennard_jones, total.electrostatic) = (f64::NAN, f64::NAN);
            total.overlaps = f64::NAN;
            total.virial = Matrix3::repeat(f64::NAN);
        } else if let Some((_, _, m)) = terms.electrostatics {
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

impl PairPass {
    /// Swaps the last pass's forces on the sites with `forces` (the next
    /// pass clears what it is given back: no copy).
    pub(super) fn swap_forces(&mut self, forces: &mut Vec<Vector3<f64>>) {
        std::mem::swap(&mut self.blocks[0].force, forces);
    }

    /// The pass's per-site tables for `n` sites: whether each is charged,
    /// its Lennard-Jones kind.
    fn site_tables(&mut self, terms: &PairTerms<'_>, n: usize) {
        self.charged.clear();
        if let Some((_, _, m)) = terms.electrostatics {
            let zero = ChargeDipole::default();
            self.charged.extend((0..n).map(|i| charged(m, i) != zero));
        }
        self.kind.clear();
        if let Some((_, kinds)) = terms.lennard_jones {
            self.kind.extend(kinds.iter().map(|k| k.unwrap_or(NO_KIND)));
        } else {
            self.kind.resize(n, NO_KIND);
        }
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
    /// Each site's Lennard-Jones kind, [`NO_KIND`] for none.
    kind: &'a [u32],
    /// Whether every site has the same Lennard-Jones kind (then the lanes
    /// take no kinds) and whether every site is charged.
    one_kind: bool,
    all_charged: bool,
    /// The box lengths of the list's image counts (zero in open space).
    lengths: Vector3<f64>,
    path: Path,
}

/// A site without Lennard-Jones.
const NO_KIND: u32 = u32::MAX;

/// Each thread's block of sums and its scratch of partners within reach.
type Blocks<'b> = (&'b mut [PairSums], &'b mut [Within]);

impl<'a> Inputs<'a> {
    /// The pass with the charge kernel of the terms (the energies and the
    /// virial summed with `SUMS`).
    fn with_charges<const SUMS: bool>(&self, blocks: Blocks<'_>) {
        use ElectrostaticTruncation as E;
        match self
            .terms
            .electrostatics
            .map(|(_, t, m)| (t, m.carried.charges))
        {
            None => self.with_lennard_jones::<NoCharges, SUMS>(blocks),
            Some((E::Plain, true)) => {
                self.with_lennard_jones::<Truncated<Bare, true>, SUMS>(blocks)
            }
            Some((E::Plain, false)) => {
                self.with_lennard_jones::<Truncated<Bare, false>, SUMS>(blocks)
            }
            Some((E::ShiftedForce, true)) => {
                self.with_lennard_jones::<Truncated<ShiftedForce, true>, SUMS>(blocks)
            }
            Some((E::ShiftedForce, false)) => {
                self.with_lennard_jones::<Truncated<ShiftedForce, false>, SUMS>(blocks)
            }
        }
    }

    /// The pass with the charge kernel `C` and the Lennard-Jones kernel of the terms.
    fn with_lennard_jones<C: ChargeKernel, const SUMS: bool>(&self, blocks: Blocks<'_>) {
        match self.terms.lennard_jones.map(|(t, _)| t.force_shifted()) {
            None if C::ON => self.sum::<NoLennardJones, C, SUMS>(blocks),
            None => {}
            Some(false) => self.sum::<LennardJones<'_, false>, C, SUMS>(blocks),
            Some(true) => self.sum::<LennardJones<'_, true>, C, SUMS>(blocks),
        }
    }

    /// The pass with the kernels `L` and `C`, one range of sites per block.
    fn sum<L: PairKernel<'a>, C: ChargeKernel, const SUMS: bool>(
        &self,
        (blocks, within): Blocks<'_>,
    ) {
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
            self.range::<L, C, SUMS>(0..n, (&mut blocks[0], &mut within[0]));
        } else {
            blocks
                .par_iter_mut()
                .zip(within.par_iter_mut())
                .enumerate()
                .for_each(|(k, out)| self.range::<L, C, SUMS>(bounds[k]..bounds[k + 1], out));
        }
    }

    /// [`Inputs::lanes`] on the pass's [`Path`]: in AVX registers (with
    /// AVX-512 VL's 32 or AVX2's 16) where the CPU has them, else in arrays
    /// (the same bits: the lanes round as the scalar operations do).
    fn range<L: PairKernel<'a>, C: ChargeKernel, const SUMS: bool>(
        &self,
        sites: std::ops::Range<usize>,
        out: (&mut PairSums, &mut Within),
    ) {
        #[cfg(target_arch = "x86_64")]
        match self.path {
            Path::Avx512 if Path::Avx512.runs() => {
                // SAFETY: the CPU has AVX-512 VL and AVX2, checked just above.
                return unsafe { self.lanes_avx512::<L, C, SUMS>(sites, out) };
            }
            Path::Avx512 | Path::Avx2 if Path::Avx2.runs() => {
                // SAFETY: the CPU has AVX2, checked just above.
                return unsafe { self.lanes_avx2::<L, C, SUMS>(sites, out) };
            }
            _ => {}
        }
        self.lanes::<F4, L, C, SUMS>(sites, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl")]
    fn lanes_avx512<L: PairKernel<'a>, C: ChargeKernel, const SUMS: bool>(
        &self,
        sites: std::ops::Range<usize>,
        out: (&mut PairSums, &mut Within),
    ) {
        self.lanes::<Avx, L, C, SUMS>(sites, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn lanes_avx2<L: PairKernel<'a>, C: ChargeKernel, const SUMS: bool>(
        &self,
        sites: std::ops::Range<usize>,
        out: (&mut PairSums, &mut Within),
    ) {
        self.lanes::<Avx, L, C, SUMS>(sites, out);
    }

    /// The pairs listed under the sites of `sites` into `out`, those
    /// within a cutoff four at a time (each site's kept in `near` first):
    /// each site's force, field and potential, and with `SUMS` the energy
    /// and the virial, summed in four lanes, added up at the end.
    #[inline(always)]
    fn lanes<T: Lanes, L: PairKernel<'a>, C: ChargeKernel, const SUMS: bool>(
        &self,
        sites: std::ops::Range<usize>,
        (out, near): (&mut PairSums, &mut Within),
    ) {
        let Some(lj) = L::new(self.terms.lennard_jones.map(|t| t.0)) else {
            return;
        };
        let (coulomb_cutoff, multipoles) = match self.terms.electrostatics {
            Some((cutoff, _, m)) => (cutoff, Some(m)),
            None => (0.0, None),
        };
        let coulomb = C::new();
        let charges = (&coulomb, coulomb_cutoff);
        let (lj_cutoff2, coulomb_cutoff2, reach2) = self.squared_cutoffs::<T>();
        let kind = self.kind;
        self.check_sites(out);
        near.path = self.path;
        // Which lanes a chunk of `n` pairs uses, at `n - 1`.
        let listed: [T; LANES] = std::array::from_fn(|n| T::mask(std::array::from_fn(|l| l <= n)));
        let (mut lj_energy, mut overlaps) = (T::default(), T::default());
        // The virial's components, row by row.
        let mut virial = [T::default(); 9];
        for i in sites {
            let a = kind[i];
            let target = match multipoles {
                Some(m) if C::ON && self.charged[i] => Some(ChargeDipoles::splat(&charged(m, i))),
                _ => None,
            };
            if (!L::ON || a == NO_KIND) && target.is_none() {
                continue;
            }
            // Site `i`'s Lennard-Jones constants (any kind's where it has none: unused).
            let lj_i = lj.site::<T>(if a == NO_KIND { 0 } else { a as usize });
            let (mut force_i, mut field_i, mut potential_i) =
                (V4::<T>::default(), V4::<T>::default(), T::default());
            let (x, run) = (&self.positions[i], self.list.half_run(i));
            near.collect(x, run, self.positions, &self.lengths, reach2);
            for start in (0..near.count()).step_by(LANES) {
                // Unused lanes repeat the last pair, their results dropped.
                let n = (near.count() - start).min(LANES);
                let listed = listed[n - 1];
                let (js, r, r2) = near.row::<T>(start);
                let mut f = V4::<T>::default();
                if L::ON && a != NO_KIND {
                    let within = r2.lt(lj_cutoff2).keep(listed);
                    let (u, f_over_r, core) =
                        self.lennard_jones_pairs(&lj, (&lj_i, a, &js), r2, within);
                    if SUMS {
                        lj_energy += u;
                        overlaps += core;
                    }
                    f = r * f_over_r;
                }
                if let (Some(t), Some(m)) = (&target, multipoles) {
                    let within = r2.lt(coulomb_cutoff2).keep(listed);
                    let sums = (&mut field_i, &mut potential_i);
                    let chunk = (&r, r2, within, &js[..n]);
                    // SAFETY: every partner is a site (`check_sites`).
                    f += unsafe {
                        self.charge_pairs::<T, C, SUMS>(charges, chunk, (t, m), sums, out)
                    };
                }
                force_i += f;
                // SAFETY: every partner is a site (`check_sites`).
                unsafe { react::<T, SUMS>(&f, &r, &js, &mut out.force, &mut virial) };
            }
            out.force[i] += force_i.total();
            if target.is_some() {
                out.add_field::<T, SUMS>(i, field_i, potential_i);
            }
        }
        out.lennard_jones = lj_energy.total();
        out.overlaps = overlaps.total();
        out.virial = Matrix3::from_fn(|a, b| virial[3 * a + b].total());
    }

    /// The squared cutoffs of the pass's Lennard-Jones and charge-dipole
    /// terms (zero for a term it lacks) in lanes, and the larger: the
    /// pairs beyond both are not kept.
    fn squared_cutoffs<T: Lanes>(&self) -> (T, T, f64) {
        let lj = self.terms.lennard_jones.map_or(0.0, |(t, _)| t.cutoff());
        let coulomb = self.terms.electrostatics.map_or(0.0, |(c, _, _)| c);
        let (lj2, coulomb2) = (lj * lj, coulomb * coulomb);
        (T::splat(lj2), T::splat(coulomb2), lj2.max(coulomb2))
    }

    /// The Lennard-Jones energies, `-(1/r) du/dr` and overlap marks of
    /// site kind `a` (its constants `site`) with the partners `js` at `r2`,
    /// zero outside the lanes `within` of the cutoff and for partners
    /// without Lennard-Jones.
    #[inline(always)]
    fn lennard_jones_pairs<T: Lanes, L: PairKernel<'a>>(
        &self,
        lj: &L,
        (site, a, js): (&L::Site<T>, u32, &[usize; LANES]),
        r2: T,
        mut within: T,
    ) -> (T, T, T) {
        // With one kind, every site's is `a`.
        let mut b = [a as usize; LANES];
        if !self.one_kind {
            // SAFETY: the partners are sites (checked before the rows).
            let kinds = js.map(|j| *unsafe { self.kind.get_unchecked(j) });
            within = within.keep(T::mask(kinds.map(|b| b != NO_KIND)));
            b = kinds.map(|b| if b == NO_KIND { 0 } else { b as usize });
        }
        let (u, f_over_r, core) = lj.pair(site, b, r2);
        (u.keep(within), f_over_r.keep(within), core.keep(within))
    }

    /// The charge-dipole pairs of target `t` with the partners `js` (the
    /// first lanes) at separations `r` within the lanes `within` of the
    /// cutoff: the target's field and (with `SUMS`) potential added to
    /// `sums`, the partners' to `out`; the forces on the target returned.
    ///
    /// # Safety
    /// Every partner indexes the multipoles, the pass's tables and `out`'s
    /// per-site sums.
    #[inline(always)]
    unsafe fn charge_pairs<T: Lanes, C: ChargeKernel, const SUMS: bool>(
        &self,
        (coulomb, cutoff): (&C, f64),
        (r, r2, mut within, js): (&V4<T>, T, T, &[usize]),
        (t, m): (&ChargeDipoles<T>, &SiteMultipoles),
        (field_i, potential_i): (&mut V4<T>, &mut T),
        out: &mut PairSums,
    ) -> V4<T> {
        // SAFETY (of every unchecked access below): the caller's promise.
        let lanes: [usize; LANES] = std::array::from_fn(|l| js[l.min(js.len() - 1)]);
        let source = ChargeDipoles {
            charge: match C::CHARGES {
                true => T::from_array(lanes.map(|j| *unsafe { m.charges.get_unchecked(j) })),
                false => T::default(),
            },
            dipole: V4::gather(lanes.map(|j| unsafe { m.dipoles.get_unchecked(j) })),
        };
        if !self.all_charged {
            let charged = lanes.map(|j| *unsafe { self.charged.get_unchecked(j) });
            within = within.keep(T::mask(charged));
        }
        let pair = coulomb.pair(r, r2, cutoff, t, &source);
        *field_i += pair.field.keep(within);
        if C::CHARGES && SUMS {
            *potential_i += pair.potential.keep(within);
            let source_potential = pair.source_potential.keep(within).to_array();
            for (l, &j) in js.iter().enumerate() {
                *unsafe { out.potential.get_unchecked_mut(j) } += source_potential[l];
            }
        }
        let source_field = pair.source_field.keep(within).to_vectors();
        for (l, &j) in js.iter().enumerate() {
            *unsafe { out.field.get_unchecked_mut(j) } += source_field[l];
        }
        pair.force.keep(within)
    }

    /// The partners of the kept rows are sites ([`Within`]'s promise), so
    /// they index the per-site arrays that the rows read and write, all of
    /// one entry per site: checked here once, not at every partner.
    fn check_sites(&self, out: &PairSums) {
        let n = self.positions.len();
        let electrostatic = self.terms.electrostatics.map_or([n; 5], |(_, _, m)| {
            let sums = [out.potential.len(), out.field.len()];
            [
                m.charges.len(),
                m.dipoles.len(),
                self.charged.len(),
                sums[0],
                sums[1],
            ]
        });
        let lengths = [out.force.len(), self.kind.len()]
            .into_iter()
            .chain(electrostatic);
        assert!(
            lengths.into_iter().all(|l| l == n),
            "per-site arrays of the pass's sites"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::lennard_jones::{LennardJonesOptions, Mixing, Truncation};
    use crate::bodies::site::LennardJones as Parameters;
    use crate::bodies::space::Space;
    use crate::potential::multipole::mesh_ewald::Carried;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Energies of a direct double loop agree with the pass to this
    /// relative round-off (sums of ~1e4 terms in another order).
    const ROUND_OFF: f64 = 1e-12;

    /// 500 dipolar Lennard-Jones sites, one per body, on a jittered cubic
    /// lattice in a periodic box at density 0.8: positions, multipoles
    /// (charged or not), the term and its kinds.
    fn fluid(charges: bool) -> (SiteMultipoles, LennardJonesTerm, Vec<Option<u32>>, Space) {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (side, spacing) = (8, (1.0f64 / 0.8).cbrt());
        let space = Space::Periodic(Vector3::repeat(side as f64 * spacing));
        let mut sites = SiteMultipoles {
            carried: Carried {
                charges,
                dipoles: true,
                quadrupoles: false,
            },
            ..SiteMultipoles::default()
        };
        for k in 0..side * side * side {
            let cell = Vector3::new(k % side, (k / side) % side, k / (side * side));
            let jitter = Vector3::from_fn(|_, _| 0.2 * (rng.random::<f64>() - 0.5));
            sites
                .positions
                .push(cell.map(|c| c as f64 * spacing) + jitter);
            let mu = Vector3::from_fn(|_, _| rng.random::<f64>() - 0.5);
            sites.dipoles.push(mu.normalize());
            let q = if charges { 0.5 - (k % 2) as f64 } else { 0.0 };
            sites.charges.push(q);
        }
        let options = LennardJonesOptions {
            cutoff: 2.5,
            truncation: Truncation::Shifted,
            mixing: Mixing::LorentzBerthelot,
        };
        let parameters = vec![Parameters {
            epsilon: 1.0,
            sigma: 1.0,
        }];
        let term = LennardJonesTerm::new(options, parameters).unwrap();
        let kinds = vec![Some(0); sites.positions.len()];
        (sites, term, kinds, space)
    }

    /// Every output of the kernels of four pairs, lane by lane.
    fn kernel_outputs<T: Lanes, K: ChargeKernel>(
        term: &LennardJonesTerm,
        r: &[Vector3<f64>; LANES],
        target: &ChargeDipole,
        sources: &[ChargeDipole; LANES],
    ) -> Vec<[f64; LANES]> {
        let r = V4::<T>::gather(std::array::from_fn(|l| &r[l]));
        let r2 = r.dot(&r);
        let source = ChargeDipoles {
            charge: T::from_array(sources.map(|s| s.charge)),
            dipole: V4::gather(std::array::from_fn(|l| &sources[l].dipole)),
        };
        let pair = K::new().pair(&r, r2, 2.5, &ChargeDipoles::splat(target), &source);
        let (u, f_over_r, _) = term.pair_lanes::<T, false>(&term.kind_lanes(0), [0; LANES], r2);
        let (u_fs, f_fs, _) = term.pair_lanes::<T, true>(&term.kind_lanes(0), [0; LANES], r2);
        let mut out = vec![
            u,
            f_over_r,
            u_fs,
            f_fs,
            pair.potential,
            pair.source_potential,
        ];
        for v in [pair.field, pair.force, pair.source_field] {
            out.extend([v.x, v.y, v.z]);
        }
        out.into_iter().map(T::to_array).collect()
    }

    /// The kernels give the same bits in AVX registers as in arrays (the
    /// pass takes either, by the CPU), for every truncation with and
    /// without charges, and the Lennard-Jones lanes are the scalar pair's
    /// bits.
    #[test]
    fn avx_and_array_lanes_give_the_same_bits() {
        let (sites, term, _, _) = fluid(true);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..50 {
            let r: [Vector3<f64>; LANES] =
                std::array::from_fn(|_| Vector3::from_fn(|_, _| 4.0 * rng.random::<f64>() - 2.0));
            let sources: [ChargeDipole; LANES] =
                std::array::from_fn(|_| charged(&sites, rng.random_range(0..sites.charges.len())));
            let target = charged(&sites, 0);
            let array = kernel_outputs::<F4, Truncated<Bare, true>>(&term, &r, &target, &sources);
            for l in 0..LANES {
                let (u, f_over_r) = term.pair(0, 0, r[l].norm_squared());
                assert_eq!((array[0][l], array[1][l]), (u, f_over_r), "lane {l}");
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                let bits = |o: Vec<[f64; LANES]>| -> Vec<[u64; LANES]> {
                    o.into_iter().map(|x| x.map(f64::to_bits)).collect()
                };
                macro_rules! same {
                    ($($kernel:ty),*) => {$(
                        assert_eq!(
                            bits(kernel_outputs::<F4, $kernel>(&term, &r, &target, &sources)),
                            bits(kernel_outputs::<Avx, $kernel>(&term, &r, &target, &sources)),
                            stringify!($kernel)
                        );
                    )*};
                }
                same!(
                    Truncated<Bare, true>,
                    Truncated<Bare, false>,
                    Truncated<ShiftedForce, true>,
                    Truncated<ShiftedForce, false>
                );
            }
        }
    }

    /// Every machine path this CPU has ([`Path`]: the AVX2 code with
    /// AVX-512 VL's registers, the AVX2 code, arrays) gives the pass the
    /// same bits (debug-printed sums: every bit of every value), with and
    /// without charges, for both truncations of the electrostatics and of
    /// Lennard-Jones (shifted against force-shifted), in full and forces
    /// only, with one kind and with two (mixed) and sites without any (every
    /// seventh): each kernel and each choice of the rows, on 500 sites;
    /// and the two kinds' energy is a direct loop's over all pairs.
    #[test]
    fn every_path_gives_the_same_bits() {
        let paths = Path::available();
        assert_eq!(paths.last(), Some(&Path::Arrays));
        for charges in [false, true] {
            let (sites, one_kind, kinds, space) = fluid(charges);
            let n = sites.positions.len();
            let mut list = NeighbourList::new(2.5, 0.3).unwrap().half_only();
            list.build(&sites.positions, &(0..n as u32).collect::<Vec<_>>(), &space);
            let options = LennardJonesOptions {
                cutoff: 2.5,
                truncation: Truncation::ForceShifted,
                mixing: Mixing::LorentzBerthelot,
            };
            let two =
                [(1.0, 1.0), (0.7, 1.2)].map(|(epsilon, sigma)| Parameters { epsilon, sigma });
            let two_kinds = LennardJonesTerm::new(options, two.to_vec()).unwrap();
            let mixed: Vec<Option<u32>> = (0..n)
                .map(|i| (i % 7 != 0).then_some((i % 2) as u32))
                .collect();
            // The two kinds' energy against a direct loop over all pairs
            // with the scalar pair (each kind's own row of the table).
            let mut direct = 0.0;
            for i in 0..n {
                for j in i + 1..n {
                    let r = space.minimum_image(sites.positions[i] - sites.positions[j]);
                    if let (Some(a), Some(b), true) = (mixed[i], mixed[j], r.norm() < 2.5) {
                        direct += two_kinds.pair(a as usize, b as usize, r.norm_squared()).0;
                    }
                }
            }
            let only_lj = PairTerms {
                lennard_jones: Some((&two_kinds, &mixed)),
                electrostatics: None,
            };
            let mut pass = PairPass::default();
            let lj = pass
                .run(&only_lj, &list, &sites.positions, Scope::Full)
                .lennard_jones;
            assert!(
                (lj - direct).abs() < ROUND_OFF * direct.abs(),
                "{lj} {direct}"
            );
            for (term, kinds) in [(&one_kind, &kinds), (&two_kinds, &mixed)] {
                for truncation in [
                    ElectrostaticTruncation::Plain,
                    ElectrostaticTruncation::ShiftedForce,
                ] {
                    let terms = PairTerms {
                        lennard_jones: Some((term, kinds)),
                        electrostatics: Some((2.5, truncation, &sites)),
                    };
                    for scope in [Scope::Full, Scope::Forces] {
                        let sums: Vec<String> = paths
                            .iter()
                            .map(|&path| {
                                let mut pass = PairPass {
                                    path,
                                    ..PairPass::default()
                                };
                                format!("{:?}", pass.run(&terms, &list, &sites.positions, scope))
                            })
                            .collect();
                        for (path, s) in paths.iter().zip(&sums) {
                            assert_eq!(s, &sums[0], "{path:?}, charges {charges}, {scope:?}");
                        }
                    }
                }
            }
        }
    }

    /// With 1, 2 and 3 threads the pass gives the same bits twice, the
    /// forces of each count agree with one thread's to round-off and add
    /// up to zero (Newton's third law), and the energies are those of a
    /// direct loop over all pairs (written out here: the bare dipole-dipole
    /// energy `(mu_i.mu_j - 3 (mu_i.r^)(mu_j.r^)) / r^3`, Coulomb's `q_i q_j
    /// / r`, and `q_i` in the potential `mu_j.r / r^3` of `mu_j` plus `mu_i`
    /// in the field `q_j r / r^3` of `q_j`, `r = x_i - x_j`).
    #[test]
    fn threads_reproduce_their_bits_and_the_direct_sums() {
        for charges in [false, true] {
            let (sites, term, kinds, space) = fluid(charges);
            let n = sites.positions.len();
            let mut list = NeighbourList::new(2.5, 0.3).unwrap().half_only();
            list.build(&sites.positions, &(0..n as u32).collect::<Vec<_>>(), &space);
            let terms = PairTerms {
                lennard_jones: Some((&term, &kinds)),
                electrostatics: Some((2.5, ElectrostaticTruncation::Plain, &sites)),
            };
            let (mut lj, mut coulomb) = (0.0, 0.0);
            for i in 0..n {
                for j in i + 1..n {
                    let r = space.minimum_image(sites.positions[i] - sites.positions[j]);
                    let d = r.norm();
                    if d >= 2.5 {
                        continue;
                    }
                    lj += term.pair(0, 0, d * d).0;
                    let (mu_i, mu_j) = (sites.dipoles[i], sites.dipoles[j]);
                    let (q_i, q_j) = (sites.charges[i], sites.charges[j]);
                    coulomb += (mu_i.dot(&mu_j) - 3.0 * mu_i.dot(&r) * mu_j.dot(&r) / (d * d))
                        / d.powi(3)
                        + q_i * q_j / d
                        + (q_i * mu_j.dot(&r) - q_j * mu_i.dot(&r)) / d.powi(3);
                }
            }
            let one = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| {
                    PairPass::default()
                        .run(&terms, &list, &sites.positions, Scope::Full)
                        .clone()
                })
            };
            let single = one(1);
            for threads in [1, 2, 3] {
                let sums = one(threads);
                assert_eq!(sums, one(threads), "{threads} threads, charges {charges}");
                assert!(
                    (sums.lennard_jones - lj).abs() < ROUND_OFF * lj.abs(),
                    "{threads}"
                );
                assert!(
                    (sums.electrostatic - coulomb).abs() < ROUND_OFF * coulomb.abs(),
                    "{threads}: {} {coulomb}",
                    sums.electrostatic
                );
                let scale = single.force.iter().map(|f| f.norm()).fold(0.0, f64::max);
                let total: Vector3<f64> = sums.force.iter().sum();
                assert!(total.norm() < 1e-10 * scale, "{threads}: {total}");
                for (f, g) in sums.force.iter().zip(&single.force) {
                    assert!((f - g).norm() < ROUND_OFF * scale, "{threads}");
                }
            }
        }
    }
}
