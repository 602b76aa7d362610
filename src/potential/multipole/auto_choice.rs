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
//! memory limit) takes the direct sum.
//!
//! The times per unit are the geometric means of measured time over
//! modelled cost in the single-thread evaluation times of
//! benchmarks/RESULTS.md's mesh section (2026-11-28, jittered dipoles at
//! 1e-5) from 512 to 2,197 sites, where the choice is close (the model's
//! crossover is then 1,040 dipoles, the measured one 908). A direct
//! real-space pair is cheap (its geometry is stored once, the sites being
//! fixed) and a PME pair dear (its derivative tensors are computed at each
//! evaluation), hence the two scales. The
//! crossover they give, and its measurement at other accuracies, are in
//! docs/scenes.md.

use super::PotentialError;

/// Seconds per unit of the direct Ewald sum's cost model (a real-space
/// pair, or half a structure-factor product) in one evaluation.
pub const DIRECT_SECONDS_PER_UNIT: f64 = 1.6e-8;

/// Seconds per unit of the mesh Ewald sum's cost model (a real-space pair
/// of the general kernel and its equivalents for the mesh and the splines)
/// in one evaluation. Since 2026-11-29 the unit of the mesh sum's constants
/// (`mesh_ewald::estimate`): each is its measured seconds
/// (`examples/pme_costs.rs`, 2026-11-29, a loaded 2-CPU Xeon) over this
/// one, kept from the fit above, so that a modelled cost is that run's
/// seconds while [`DIRECT_SECONDS_PER_UNIT`] is still the fit of
/// 2026-11-28.
pub const PME_SECONDS_PER_UNIT: f64 = 5.4e-7;

/// What the automatic choice compared and why it took its path.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoChoice {
    /// The direct Ewald sum's estimated seconds per evaluation.
    pub direct_seconds: f64,
    /// The mesh Ewald sum's estimated seconds per evaluation (`None` when
    /// it cannot be built for the request: see `reason`).
    pub pme_seconds: Option<f64>,
    /// Why the path was taken, in words.
    pub reason: String,
}

impl AutoChoice {
    /// The comparison of a direct sum estimated at `direct_seconds` per
    /// evaluation with a mesh sum at `pme_seconds`, or with the error that
    /// refused the mesh sum.
    pub(crate) fn compare(direct_seconds: f64, pme_seconds: Result<f64, PotentialError>) -> Self {
        match pme_seconds {
            Ok(pme_seconds) => {
                let reason = if pme_seconds < direct_seconds {
                    "the mesh Ewald sum is estimated cheaper than the direct sum"
                } else {
                    "the direct sum is estimated cheaper than the mesh Ewald sum"
                };
                AutoChoice {
                    direct_seconds,
                    pme_seconds: Some(pme_seconds),
                    reason: reason.to_string(),
                }
            }
            Err(e) => AutoChoice {
                direct_seconds,
                pme_seconds: None,
                reason: format!("the mesh Ewald sum cannot be used: {e}"),
            },
        }
    }

    /// Whether the mesh Ewald sum was taken.
    pub fn takes_pme(&self) -> bool {
        self.pme_seconds
            .is_some_and(|pme| pme < self.direct_seconds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cheaper estimate wins; a refused mesh sum leaves the direct sum,
    /// its error kept as the reason.
    #[test]
    fn the_cheaper_path_wins_and_a_refusal_is_the_reason() {
        let pme = AutoChoice::compare(1.01, Ok(1.0));
        assert!(pme.takes_pme(), "{pme:?}");
        let direct = AutoChoice::compare(0.99, Ok(1.0));
        assert!(!direct.takes_pme(), "{direct:?}");
        let refused = AutoChoice::compare(1e12, Err(PotentialError::new("accuracy", "too tight")));
        assert!(!refused.takes_pme());
        assert_eq!(refused.pme_seconds, None);
        assert_eq!(
            refused.reason,
            "the mesh Ewald sum cannot be used: accuracy: too tight"
        );
    }
}
