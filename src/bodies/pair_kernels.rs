//! The kernels of the pair pass: Lennard-Jones (`LennardJones`, plain or
//! shifted against force-shifted, or none) and the charge-dipole pairs of
//! a truncation (`Truncated`, bare or shifted-force, with charges or of
//! dipoles only, or none), each on four pairs in any [`Lanes`], chosen
//! once per pass and monomorphised into its loop.

use super::electrostatics_shifted::{ChargeDipoles, Factors, Plain, ShiftedForceFactors};
use super::lennard_jones::{KindLanes, LennardJonesTerm};
use crate::lanes::{Lanes, LANES, V4};
use nalgebra::Vector3;

/// The Lennard-Jones pairs of a pass.
pub(super) trait PairKernel<'a>: Sync + Sized {
    /// Whether the pass has the term.
    const ON: bool;
    /// The kernel of `term` (`None` if the pass needs the term and has none).
    fn new(term: Option<&'a LennardJonesTerm>) -> Option<Self>;
    /// A site's constants, taken once per site: those of kind `a`.
    type Site<T: Lanes>;
    fn site<T: Lanes>(&self, a: usize) -> Self::Site<T>;
    /// Energies, `-(1/r) du/dr` and 1 for a pair that may overlap (else 0)
    /// of the kind of `site` with kinds `b` at `r2`.
    fn pair<T: Lanes>(&self, site: &Self::Site<T>, b: [usize; LANES], r2: T) -> (T, T, T);
}

pub(super) struct NoLennardJones;

impl PairKernel<'_> for NoLennardJones {
    const ON: bool = false;
    fn new(_: Option<&LennardJonesTerm>) -> Option<Self> {
        Some(NoLennardJones)
    }
    type Site<T: Lanes> = ();
    fn site<T: Lanes>(&self, _: usize) {}
    fn pair<T: Lanes>(&self, _: &(), _: [usize; LANES], _: T) -> (T, T, T) {
        (T::default(), T::default(), T::default())
    }
}

/// The term, force-shifted or not.
pub(super) struct LennardJones<'a, const FORCE_SHIFTED: bool>(&'a LennardJonesTerm);

impl<'a, const FORCE_SHIFTED: bool> PairKernel<'a> for LennardJones<'a, FORCE_SHIFTED> {
    const ON: bool = true;
    fn new(term: Option<&'a LennardJonesTerm>) -> Option<Self> {
        term.map(LennardJones)
    }
    type Site<T: Lanes> = KindLanes<'a, T>;
    #[inline(always)]
    fn site<T: Lanes>(&self, a: usize) -> KindLanes<'a, T> {
        self.0.kind_lanes(a)
    }
    #[inline(always)]
    fn pair<T: Lanes>(&self, site: &KindLanes<'a, T>, b: [usize; LANES], r2: T) -> (T, T, T) {
        self.0.pair_lanes::<T, FORCE_SHIFTED>(site, b, r2)
    }
}

/// Both ends of four charge-dipole pairs: the targets' potentials, fields
/// and forces, and the sources' potentials and fields (their forces are
/// minus the targets'), zero by default.
#[derive(Default)]
pub(super) struct BothEnds<T> {
    pub potential: T,
    pub field: V4<T>,
    pub force: V4<T>,
    pub source_potential: T,
    pub source_field: V4<T>,
}

/// The charge-dipole pairs of a pass.
pub(super) trait ChargeKernel: Sync + Sized {
    /// Whether the pass has the term.
    const ON: bool;
    /// Whether some site carries a charge (if not, the potentials are
    /// left zero: nothing reads them).
    const CHARGES: bool;
    fn new() -> Self;
    /// The pairs of targets at offsets `r` (`r2 = |r|^2`) from sources
    /// (none by default: zero).
    fn pair<T: Lanes>(
        &self,
        _r: &V4<T>,
        _r2: T,
        _cutoff: f64,
        _target: &ChargeDipoles<T>,
        _source: &ChargeDipoles<T>,
    ) -> BothEnds<T> {
        BothEnds::default()
    }
}

/// No charges or dipoles.
pub(super) struct NoCharges;

impl ChargeKernel for NoCharges {
    const ON: bool = false;
    const CHARGES: bool = false;
    fn new() -> Self {
        NoCharges
    }
}

/// A truncation: its radial factors in any lanes.
pub(super) trait Truncation: Sync {
    type Factors<T: Lanes>: Factors<T>;
}

/// The plain truncation (the bare pair terms).
pub(super) struct Bare;

impl Truncation for Bare {
    type Factors<T: Lanes> = Plain<T>;
}

/// The shifted-force truncation.
pub(super) struct ShiftedForce;

impl Truncation for ShiftedForce {
    type Factors<T: Lanes> = ShiftedForceFactors<T>;
}

/// A truncation's pairs, with charges or of dipoles only.
pub(super) struct Truncated<F, const CHARGES: bool>(std::marker::PhantomData<fn() -> F>);

impl<F: Truncation, const CHARGES: bool> ChargeKernel for Truncated<F, CHARGES> {
    const ON: bool = true;
    const CHARGES: bool = CHARGES;
    fn new() -> Self {
        Truncated(std::marker::PhantomData)
    }
    #[inline(always)]
    fn pair<T: Lanes>(
        &self,
        r: &V4<T>,
        r2: T,
        cutoff: f64,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> BothEnds<T> {
        let factors = F::Factors::<T>::new(r2, cutoff);
        if !CHARGES {
            return BothEnds {
                field: factors.dipole_field(r, source),
                force: factors.dipole_force(r, r2, target, source),
                source_field: factors.dipole_field(&-*r, target),
                ..BothEnds::default()
            };
        }
        let ((potential, field), (source_potential, source_field)) =
            (factors.fields(r, source), factors.fields(&-*r, target));
        BothEnds {
            potential,
            field,
            force: factors.force(r, r2, target, source),
            source_potential,
            source_field,
        }
    }
}

/// Newton's third law for a row of pairs: the row's forces `f` on the
/// site taken from its partners `js`, and `r f^T` added to the virial's
/// rows (with `SUMS`). Every lane is taken, with no branch on how many are
/// in use: an unused lane's force is a signed zero (its factor masked to
/// +0.0), and subtracting it leaves a force that is not -0.0 unchanged to
/// the bit; the sums start at +0.0 and a sum or difference rounded to
/// nearest is -0.0 only from a -0.0 operand, so none is.
///
/// # Safety
/// Every partner indexes `force`.
#[inline(always)]
pub(super) unsafe fn react<T: Lanes, const SUMS: bool>(
    f: &V4<T>,
    r: &V4<T>,
    js: &[usize],
    force: &mut [Vector3<f64>],
    virial: &mut [T; 9],
) {
    let forces = f.to_vectors();
    for (&j, fj) in js.iter().zip(forces) {
        // SAFETY: the caller's promise.
        *unsafe { force.get_unchecked_mut(j) } -= fj;
    }
    if !SUMS {
        return;
    }
    let (rs, fs) = ([r.x, r.y, r.z], [f.x, f.y, f.z]);
    for a in 0..3 {
        for b in 0..3 {
            virial[3 * a + b] += rs[a] * fs[b];
        }
    }
}
