//! [`FieldSum`]: how a [`super::MultipolePotential`] sums its pair fields,
//! chosen once from the boundary and the way of summing ([`SumMethod`]).

use super::auto_choice::{direct_seconds, pme_seconds, AutoChoice};
use super::ewald::EwaldSum;
use super::lattice_fft::LatticeFft;
use super::lattice_grid::{self, LatticeGrid};
use super::mesh_ewald::{mesh_cost, Carried, ForcedMesh, MeshEstimate, MeshParameters};
use super::mesh_sum::MeshSum;
use super::pairs::{OpenPairs, PairTable};
use super::row_quads::RowQuads;
use super::sum_method::{SumMethod, SumPath};
use super::{Accuracy, Boundary, EwaldParameters, PeriodicSum, PotentialError, SumKind, Surface};
use nalgebra::Vector3;

/// How the pair fields are summed, fixed at construction.
#[derive(Clone, Debug)]
pub(super) enum FieldSum {
    /// Every pair of an open cluster, the geometry computed row by row
    /// (`O(N)` memory).
    Open(OpenPairs),
    /// The pair list of a periodic box truncated at the cutoff.
    Pairs {
        pairs: PairTable,
        /// The dipole pairs regrouped for the quad kernel, when it pays (dipole-only systems).
        row_quads: Option<RowQuads>,
    },
    /// The direct Ewald sum.
    Ewald(Box<EwaldSum>),
    /// The FFT lattice sum (Ewald or truncated).
    LatticeFft(Box<LatticeFft>),
    /// The smooth particle-mesh Ewald sum.
    Mesh(Box<MeshSum>),
}

impl FieldSum {
    /// The sum for `boundary` and `method` (see [`SumMethod`]; the mesh
    /// Ewald sum's parameters `forced` as given, refused with another
    /// method), for the multipole kinds `(dipoles, quadrupoles)` carried,
    /// with what the automatic choice compared when it chose between the
    /// direct Ewald sum and PME ([`AutoChoice`]).
    pub(super) fn build(
        sites: &[Vector3<f64>],
        boundary: Boundary,
        (method, forced): (SumMethod, &ForcedMesh),
        kinds: (bool, bool),
    ) -> Result<(FieldSum, Option<AutoChoice>), PotentialError> {
        method.check_forced(forced)?;
        let pair_sum = |images: (Vector3<f64>, f64)| -> Result<FieldSum, PotentialError> {
            let pairs = PairTable::build(sites, Some(images))?;
            let row_quads = if kinds == (true, false) {
                RowQuads::build(&pairs)
            } else {
                None
            };
            Ok(FieldSum::Pairs { pairs, row_quads })
        };
        let Boundary::Periodic { box_lengths, sum } = boundary else {
            return Ok((Self::open(sites, method)?, None));
        };
        if method == SumMethod::Pme {
            if let Some(mesh) = Self::pme(sites, (box_lengths, sum), forced, kinds)? {
                return Ok((mesh, None));
            }
        }
        if sites.is_empty() {
            let cutoff = match sum {
                PeriodicSum::Cutoff { cutoff } => cutoff,
                PeriodicSum::Ewald { .. } => 0.0,
            };
            return Ok((pair_sum((box_lengths, cutoff))?, None));
        }
        let fft = match method {
            SumMethod::LatticeFft => true,
            SumMethod::Auto => sum.kind() == SumKind::Ewald,
            SumMethod::Direct | SumMethod::Pme => false,
        };
        let density = sites.len() as f64 / box_lengths.product();
        if fft {
            match lattice_grid::detect(sites, &box_lengths) {
                Some(grid) => {
                    let cost = LatticeFft::cost(&grid, &box_lengths);
                    let chosen = sum.choose(density, kinds, cost, &box_lengths)?;
                    let sum = LatticeFft::new(grid, &box_lengths, chosen, kinds)?;
                    return Ok((FieldSum::LatticeFft(Box::new(sum)), None));
                }
                None if method == SumMethod::LatticeFft => {
                    return Err(PotentialError::new(
                        "method",
                        "the FFT lattice sum needs the sites on a lattice of the box \
                         (one grid of cells with the same basis offsets, to round-off); \
                         these sites are not",
                    ));
                }
                None => {}
            }
        }
        let cost = EwaldSum::cost(sites.len(), &box_lengths);
        let chosen = sum.choose(density, kinds, cost, &box_lengths)?;
        match (chosen.sum, chosen.parameters) {
            (PeriodicSum::Ewald { accuracy, surface }, Some(parameters)) => {
                let auto = (method == SumMethod::Auto)
                    .then(|| cost.of(parameters.real_cutoff, parameters.reciprocal_cutoff));
                Self::ewald(
                    sites,
                    box_lengths,
                    (accuracy, surface),
                    (parameters, auto),
                    kinds,
                )
            }
            _ => Ok((pair_sum((box_lengths, chosen.reach))?, None)),
        }
    }

    /// The mesh Ewald sum `method = "pme"` asks for (none without sites).
    fn pme(
        sites: &[Vector3<f64>],
        (box_lengths, sum): (Vector3<f64>, PeriodicSum),
        forced: &ForcedMesh,
        kinds: (bool, bool),
    ) -> Result<Option<FieldSum>, PotentialError> {
        let PeriodicSum::Ewald { accuracy, surface } = sum else {
            return Err(PotentialError::new(
                "method",
                "the mesh Ewald sum needs sum = \"ewald\", got sum = \"cutoff\"",
            ));
        };
        if sites.is_empty() {
            return Ok(None);
        }
        let chosen = MeshSum::choose(sites.len(), &box_lengths, (accuracy, forced), kinds)?;
        let mesh = MeshSum::new(sites, box_lengths, (accuracy, surface), chosen, kinds)?;
        Ok(Some(FieldSum::Mesh(Box::new(mesh))))
    }

    /// The direct Ewald sum of `sites` with `parameters`, or, when `auto`
    /// gives its cost (`method = "auto"`), the cheaper of it and PME by
    /// their cost models, or the one that can be built ([`AutoChoice`]).
    fn ewald(
        sites: &[Vector3<f64>],
        box_lengths: Vector3<f64>,
        (accuracy, surface): (Accuracy, Surface),
        (parameters, auto): (EwaldParameters, Option<f64>),
        kinds: (bool, bool),
    ) -> Result<(FieldSum, Option<AutoChoice>), PotentialError> {
        let Some(direct) = auto else {
            let ewald = EwaldSum::with_parameters(sites, box_lengths, parameters, surface)?;
            return Ok((FieldSum::Ewald(Box::new(ewald)), None));
        };
        let direct = EwaldSum::check_size(sites.len(), &box_lengths, &parameters)
            .map(|_| direct_seconds(direct, kinds.1));
        let free = ForcedMesh::default();
        let mesh = MeshSum::choose(sites.len(), &box_lengths, (accuracy, &free), kinds);
        let pme = mesh.as_ref().map_err(Clone::clone).map(|(p, _)| {
            let costs = Carried {
                charges: false,
                dipoles: kinds.0,
                quadrupoles: kinds.1,
            }
            .costs();
            pme_seconds(mesh_cost(p, sites.len(), &box_lengths, costs), kinds.1)
        });
        let choice = AutoChoice::compare(direct, pme)?;
        let sum = match mesh {
            Ok(mesh) if choice.takes_pme() => FieldSum::Mesh(Box::new(MeshSum::new(
                sites,
                box_lengths,
                (accuracy, surface),
                mesh,
                kinds,
            )?)),
            _ => FieldSum::Ewald(Box::new(EwaldSum::with_parameters(
                sites,
                box_lengths,
                parameters,
                surface,
            )?)),
        };
        Ok((sum, Some(choice)))
    }

    /// Every pair of `sites` in open space; `method` must not be one of
    /// the mesh sums, which need a periodic box.
    fn open(sites: &[Vector3<f64>], method: SumMethod) -> Result<FieldSum, PotentialError> {
        let mesh = match method {
            SumMethod::LatticeFft => Some("the FFT lattice sum"),
            SumMethod::Pme => Some("the mesh Ewald sum"),
            SumMethod::Auto | SumMethod::Direct => None,
        };
        if let Some(name) = mesh {
            return Err(PotentialError::new(
                "method",
                format!("{name} needs a periodic box, got open boundaries"),
            ));
        }
        Ok(FieldSum::Open(OpenPairs::new(sites)?))
    }

    /// Interacting pairs of the pair list, each once (module's
    /// `MultipolePotential::pair_count`).
    pub(super) fn pair_count(&self) -> usize {
        match self {
            FieldSum::Open(pairs) => pairs.len(),
            FieldSum::Pairs { pairs, .. } => pairs.len(),
            FieldSum::Ewald(ewald) => ewald.real_pairs(),
            FieldSum::LatticeFft(_) | FieldSum::Mesh(_) => 0,
        }
    }

    /// Distinct pair geometries stored (the truncated periodic pair list's).
    pub(super) fn geometry_count(&self) -> usize {
        match self {
            FieldSum::Pairs { pairs, .. } => pairs.geometry.len(),
            _ => 0,
        }
    }

    /// The way the pair fields are summed.
    pub(super) fn path(&self) -> SumPath {
        match self {
            FieldSum::Pairs { .. } => SumPath::CutoffPairs,
            FieldSum::Open(_) => SumPath::OpenPairs,
            FieldSum::Ewald(_) => SumPath::EwaldDirect,
            FieldSum::LatticeFft(fft) if fft.parameters().is_some() => SumPath::EwaldLatticeFft,
            FieldSum::LatticeFft(_) => SumPath::CutoffLatticeFft,
            FieldSum::Mesh(_) => SumPath::EwaldPme,
        }
    }

    /// The FFT lattice sum's lattice.
    pub(super) fn lattice(&self) -> Option<&LatticeGrid> {
        match self {
            FieldSum::LatticeFft(fft) => Some(fft.grid()),
            _ => None,
        }
    }

    /// The Ewald parameters of the direct or FFT lattice Ewald sum.
    pub(super) fn ewald_parameters(&self) -> Option<EwaldParameters> {
        match self {
            FieldSum::Ewald(ewald) => Some(ewald.parameters()),
            FieldSum::LatticeFft(fft) => fft.parameters(),
            FieldSum::Pairs { .. } | FieldSum::Open(_) | FieldSum::Mesh(_) => None,
        }
    }

    /// The mesh Ewald sum's parameters and estimated errors.
    pub(super) fn mesh_parameters(&self) -> Option<(MeshParameters, MeshEstimate)> {
        match self {
            FieldSum::Mesh(mesh) => Some(mesh.parameters()),
            _ => None,
        }
    }
}
