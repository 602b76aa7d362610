//! The automatic choice (`method = "auto"`) between the direct Ewald sum
//! and smooth PME on sites that are not a lattice: each path's parameters
//! are chosen for the accuracy by its own cost model (the direct sum's
//! real-space pairs and wave vectors, [`super::ewald_parameters::Cost`];
//! PME's pairs, mesh points and spline weights,
//! [`super::mesh_ewald::mesh_cost`]), the two costs are turned into seconds
//! per evaluation by a time per unit of each model, and the cheaper path is
//! taken. An accuracy PME cannot reach (outside
//! [`super::mesh_ewald::ACCURACY_RANGE`], the default 1e-12 among them) or a
//! request it refuses (a box its cutoff does not fit, a mesh over the
//! memory limit) takes the direct sum; a direct sum too large to build (its
//! pair, wave-vector or memory limit) takes PME. When both are refused, the
//! direct sum's refusal is the error, with PME's.
//!
//! The direct model's units become seconds by a time per unit, PME's model
//! is in measured seconds (`mesh_ewald::estimate`'s `MeshCosts`, fitted to
//! forced parameters by `examples/pme_costs.rs`), and each is calibrated
//! per kind of site: the geometric mean of measured CPU time over modelled
//! seconds in the single-thread evaluation times of benchmarks/RESULTS.md's
//! mesh section, its calibration table (2026-12-02 22:11, an idle 2-CPU
//! Intel Xeon; jittered sites at 1e-4 to 1e-6, 125 to 8,000 dipoles in 14
//! cases for each sum, 125 to 2,197 linear quadrupoles in 12). A direct
//! real-space pair is cheap (its geometry is stored once, the sites being
//! fixed) and a PME pair dear (its derivative tensors are computed at each
//! evaluation); a quadrupole's direct pair and wave vector cost about twice
//! a dipole's (higher derivative tensors), which the direct model, counting
//! pairs and wave vectors only, does not see. The hosts differ: the direct
//! sum runs 1.7 times faster against PME on that Xeon than on the AMD
//! EPYC of the calibration before (so the quadrupoles' measured crossover
//! at 1e-5 lies above 2,197 there and at 730 to 840 on the EPYC); the
//! calibration is one host's. The crossovers the models give against the
//! measured ones are in docs/scenes.md.

use super::PotentialError;

/// Seconds per unit of the direct Ewald sum's cost model (a real-space
/// pair, or half a structure-factor product) in one evaluation of dipoles:
/// the 1.23e-8 of the AMD EPYC's calibration times this host's measured
/// over modelled 0.579 (module doc).
pub const DIRECT_SECONDS_PER_UNIT: f64 = 7.12e-9;

/// The direct sum's time per unit with quadrupoles (alone or with dipoles)
/// over that of dipoles: the former 2.2 times 0.524 / 0.579, the
/// quadrupoles' and the dipoles' measured over modelled ratios (module doc).
pub const DIRECT_QUADRUPOLE_FACTOR: f64 = 1.99;

/// The mesh sum's measured over modelled seconds for dipoles (module doc;
/// the model, `mesh_ewald::mesh_cost`, is in seconds): 0.809, range 0.54
/// to 1.02 over the 14 cases.
pub const PME_DIPOLE_CALIBRATION: f64 = 0.809;

/// The mesh sum's measured over modelled seconds for quadrupoles (alone
/// or with dipoles; module doc): 0.708, range 0.40 to 0.94 over the 12
/// cases.
pub const PME_QUADRUPOLE_CALIBRATION: f64 = 0.708;

/// The direct sum's estimated seconds per evaluation of its cost model's
/// `units` for sites with or without `quadrupoles`.
pub(crate) fn direct_seconds(units: f64, quadrupoles: bool) -> f64 {
    let kind = if quadrupoles {
        DIRECT_QUADRUPOLE_FACTOR
    } else {
        1.0
    };
    units * DIRECT_SECONDS_PER_UNIT * kind
}

/// The mesh sum's estimated seconds per evaluation from its cost model's
/// `seconds` for sites with or without `quadrupoles`.
pub(crate) fn pme_seconds(seconds: f64, quadrupoles: bool) -> f64 {
    let kind = if quadrupoles {
        PME_QUADRUPOLE_CALIBRATION
    } else {
        PME_DIPOLE_CALIBRATION
    };
    seconds * kind
}

/// What the automatic choice compared and why it took its path.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoChoice {
    /// The direct Ewald sum's estimated seconds per evaluation (`None` when
    /// it is too large to build: see `reason`).
    pub direct_seconds: Option<f64>,
    /// The mesh Ewald sum's estimated seconds per evaluation (`None` when
    /// it cannot be built for the request: see `reason`).
    pub pme_seconds: Option<f64>,
    /// Why the path was taken, in words.
    pub reason: String,
}

impl AutoChoice {
    /// The comparison of a direct sum estimated at `direct_seconds` per
    /// evaluation with a mesh sum at `pme_seconds`, each or the error that
    /// refused it; both refused is the direct sum's error, PME's appended.
    pub(crate) fn compare(
        direct_seconds: Result<f64, PotentialError>,
        pme_seconds: Result<f64, PotentialError>,
    ) -> Result<Self, PotentialError> {
        let seconds = AutoChoice {
            direct_seconds: direct_seconds.as_ref().ok().copied(),
            pme_seconds: pme_seconds.as_ref().ok().copied(),
            reason: String::new(),
        };
        let reason = match (&direct_seconds, &pme_seconds) {
            (Err(direct), Err(pme)) => {
                return Err(PotentialError::new(
                    direct.path.clone(),
                    format!(
                        "{}; and the mesh Ewald sum cannot be used: {pme}",
                        direct.message
                    ),
                ))
            }
            (Ok(_), Err(pme)) => format!("the mesh Ewald sum cannot be used: {pme}"),
            (Err(direct), Ok(_)) => format!("the direct sum cannot be used: {direct}"),
            (Ok(_), Ok(_)) if seconds.takes_pme() => {
                "the mesh Ewald sum is estimated cheaper than the direct sum".to_string()
            }
            (Ok(_), Ok(_)) => {
                "the direct sum is estimated cheaper than the mesh Ewald sum".to_string()
            }
        };
        Ok(AutoChoice { reason, ..seconds })
    }

    /// Whether the mesh Ewald sum was taken: it can be built, and the
    /// direct sum cannot or is estimated dearer.
    pub fn takes_pme(&self) -> bool {
        match (self.direct_seconds, self.pme_seconds) {
            (_, None) => false,
            (None, Some(_)) => true,
            (Some(direct), Some(pme)) => pme < direct,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cheaper estimate wins; a refused path leaves the other, its
    /// error kept as the reason; both refused is an error naming both.
    #[test]
    fn the_cheaper_path_wins_and_a_refusal_is_the_reason() {
        let refusal = |path: &str| Err(PotentialError::new(path, "too large"));
        let pme = AutoChoice::compare(Ok(1.01), Ok(1.0)).unwrap();
        assert!(pme.takes_pme(), "{pme:?}");
        let direct = AutoChoice::compare(Ok(0.99), Ok(1.0)).unwrap();
        assert!(!direct.takes_pme(), "{direct:?}");
        let tie = AutoChoice::compare(Ok(1.0), Ok(1.0)).unwrap();
        assert!(!tie.takes_pme(), "{tie:?}");
        let (cheaper_pme, cheaper_direct) = (
            "the mesh Ewald sum is estimated cheaper than the direct sum",
            "the direct sum is estimated cheaper than the mesh Ewald sum",
        );
        assert_eq!(pme.reason, cheaper_pme);
        assert_eq!(direct.reason, cheaper_direct);
        assert_eq!(tie.reason, cheaper_direct);
        let refused = AutoChoice::compare(Ok(1e12), refusal("accuracy")).unwrap();
        assert!(!refused.takes_pme());
        assert_eq!(refused.pme_seconds, None);
        assert_eq!(refused.direct_seconds, Some(1e12));
        assert_eq!(
            refused.reason,
            "the mesh Ewald sum cannot be used: accuracy: too large"
        );
        let too_large = AutoChoice::compare(refusal("rotors"), Ok(1e12)).unwrap();
        assert!(too_large.takes_pme(), "{too_large:?}");
        assert_eq!(too_large.direct_seconds, None);
        assert_eq!(too_large.pme_seconds, Some(1e12));
        assert_eq!(
            too_large.reason,
            "the direct sum cannot be used: rotors: too large"
        );
        let both = AutoChoice::compare(refusal("rotors"), refusal("accuracy")).unwrap_err();
        assert_eq!(both.path, "rotors");
        assert_eq!(
            both.message,
            "too large; and the mesh Ewald sum cannot be used: accuracy: too large"
        );
    }
}
