//! The way of summing a periodic system ([`SumMethod`], the option
//! `method`) and the way a potential took ([`SumPath`]). A new way (a mesh)
//! is a variant of each, checked against the sum it needs where the sum is
//! built (`field_sum.rs`).

use super::mesh_ewald::ForcedMesh;
use super::PotentialError;
use crate::checks::named_choices;

/// Which way of summing a periodic system is wanted. [`SumMethod::Auto`]
/// (what [`super::MultipolePotential::new`] uses) takes the FFT lattice sum for an
/// Ewald sum whose sites are a lattice of the box (detected: see
/// [`crate::potential::multipole::LatticeGrid`]; vacancies and mixed
/// multipoles included), for other sites the cheaper of the direct Ewald
/// sum and the mesh Ewald sum by their cost models ([`super::AutoChoice`]:
/// the direct sum below a crossover size, PME above, the direct sum for
/// accuracies PME cannot reach), and the pair list for a truncated sum (bit
/// for bit the sum of earlier versions).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SumMethod {
    /// The fastest path that is exact for the sites (the default).
    #[default]
    Auto,
    /// The pair list (truncated) or the direct Ewald sum, even on a lattice.
    Direct,
    /// The FFT lattice sum (Ewald, or the truncated sum, which it equals to
    /// round-off): an error when the sites are not a lattice of the box.
    LatticeFft,
    /// The smooth particle-mesh Ewald sum ([`super::mesh_ewald`]), on any
    /// sites: an error with a truncated sum or open boundaries.
    Pme,
}

named_choices!(SumMethod {
    "auto" => SumMethod::Auto,
    "direct" => SumMethod::Direct,
    "lattice_fft" => SumMethod::LatticeFft,
    "pme" => SumMethod::Pme,
});

impl SumMethod {
    /// Refuses parameters of the mesh Ewald sum `forced` with a way of
    /// summing other than [`SumMethod::Pme`], naming the first forced.
    pub fn check_forced(self, forced: &ForcedMesh) -> Result<(), PotentialError> {
        match forced.first_forced() {
            Some(name) if self != SumMethod::Pme => Err(PotentialError::new(
                name,
                format!(
                    "forces a parameter of the mesh Ewald sum: only with method = \"pme\", got \
                     method = \"{}\"",
                    self.as_str()
                ),
            )),
            _ => Ok(()),
        }
    }
}

/// The way a potential sums its pair fields (see [`super::MultipolePotential::sum_path`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SumPath {
    /// Every pair of an open cluster.
    OpenPairs,
    /// The truncated periodic sum over the pair list.
    CutoffPairs,
    /// The truncated periodic sum by FFT on the lattice.
    CutoffLatticeFft,
    /// The direct Ewald sum (real-space pairs and structure factors).
    EwaldDirect,
    /// The Ewald sum by FFT on the lattice.
    EwaldLatticeFft,
    /// The smooth particle-mesh Ewald sum.
    EwaldPme,
}

impl SumPath {
    /// A short name, as written in summaries: `"open_pairs"`, `"cutoff_pairs"`,
    /// `"cutoff_lattice_fft"`, `"ewald_direct"`, `"ewald_lattice_fft"`, `"ewald_pme"`.
    pub fn as_str(self) -> &'static str {
        match self {
            SumPath::OpenPairs => "open_pairs",
            SumPath::CutoffPairs => "cutoff_pairs",
            SumPath::CutoffLatticeFft => "cutoff_lattice_fft",
            SumPath::EwaldDirect => "ewald_direct",
            SumPath::EwaldLatticeFft => "ewald_lattice_fft",
            SumPath::EwaldPme => "ewald_pme",
        }
    }
}
