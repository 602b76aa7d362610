//! The JSON summary of a run: the scene, the seed, the versions, the time
//! taken, the final energies and the drift.

use crate::scene::{Scene, SCENE_VERSION};
use crate::simulation::{Energies, EnergyReference, RunReport, Stop};
use serde::Serialize;

/// Versions of what produced the outputs.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Versions {
    /// The crate's version.
    pub quatrot: &'static str,
    /// The scene format version read.
    pub scene_format: i64,
}

/// Energies at the last step they were computed.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FinalEnergies {
    /// The step.
    pub step: u64,
    /// `K`.
    pub kinetic: f64,
    /// `V`.
    pub potential: f64,
    /// `K + V`.
    pub total: f64,
    /// The relative energy error.
    pub error: f64,
}

/// Energy drift over the run.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Drift {
    /// Least-squares slope of the total energy against time, divided by the
    /// mean kinetic energy over the samples (or by the reference scale when
    /// that vanishes): relative drift per unit time.
    pub relative_per_time: f64,
    /// `(E_last - E_0) / scale`.
    pub final_error: f64,
    /// Number of samples in the fit.
    pub samples: usize,
}

/// The summary written to `summary.json` and returned to Python.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Summary {
    /// The scene's name.
    pub scene: String,
    /// The scene's description.
    pub description: String,
    /// The scene as run (after command-line overrides), as JSON.
    pub definition: serde_json::Value,
    /// The seed of the random initial state, if any.
    pub seed: Option<u64>,
    /// What produced the outputs.
    pub versions: Versions,
    /// The integrator's name.
    pub integrator: String,
    /// The number of rotors.
    pub rotors: usize,
    /// The time step.
    pub dt: f64,
    /// The first step of this run (0, or the checkpoint's).
    pub start_step: u64,
    /// The step the run ended at.
    pub last_step: u64,
    /// "completed", "blew_up" or "interrupted".
    pub status: &'static str,
    /// The blow-up message (step and rotor), if any.
    pub message: Option<String>,
    /// Wall-clock seconds of the run loop.
    pub wall_seconds: f64,
    /// The energy reference.
    pub initial_energy: Option<EnergyReference>,
    /// The last energies computed.
    pub final_energies: Option<FinalEnergies>,
    /// The energy drift, when energies were computed at two steps or more.
    pub drift: Option<Drift>,
    /// How the files were written: `"new"`, `"appended"` to an earlier
    /// run's, or `"new_folder"` (a restart whose folder held files that do
    /// not end at the checkpoint); absent when no file was written.
    pub outputs: Option<&'static str>,
}

/// The drift of the run's total energy, relative to the mean kinetic
/// energy over the samples (or to the reference scale when that vanishes).
fn drift(report: &RunReport) -> Option<Drift> {
    let reference = report.reference?;
    let (_, last) = report.last_energies?;
    let history = &report.energy_history;
    if history.len() < 2 {
        return None;
    }
    Some(Drift {
        relative_per_time: history.drift(reference.scale).relative_per_time,
        final_error: last.error,
        samples: history.len(),
    })
}

impl Summary {
    /// The summary of `report` for `scene` (whose raw form is `definition`).
    pub fn new(
        scene: &Scene,
        definition: serde_json::Value,
        report: &RunReport,
        start_step: u64,
    ) -> Self {
        let final_energies = report
            .last_energies
            .map(|(step, e): (u64, Energies)| FinalEnergies {
                step,
                kinetic: e.kinetic,
                potential: e.potential,
                total: e.total,
                error: e.error,
            });
        Summary {
            scene: scene.name.clone(),
            description: scene.description.clone(),
            definition,
            seed: scene.seed,
            versions: Versions {
                quatrot: env!("CARGO_PKG_VERSION"),
                scene_format: SCENE_VERSION,
            },
            integrator: scene.integrator.name().to_string(),
            rotors: scene.rotors.len(),
            dt: scene.dt,
            start_step,
            last_step: report.last_step,
            status: match report.stop {
                Stop::Completed => "completed",
                Stop::BlewUp { .. } => "blew_up",
                Stop::Interrupted { .. } => "interrupted",
            },
            message: report.stop.message(),
            wall_seconds: report.wall_seconds,
            initial_energy: report.reference,
            final_energies,
            drift: drift(report),
            outputs: None,
        }
    }
}
