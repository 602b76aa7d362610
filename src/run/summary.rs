//! The JSON summary of a run: the scene, the seed, the versions, how the
//! pair interactions were summed, the time taken, the final energies and
//! the drift.

use crate::bodies::electrostatics::Electrostatics;
use crate::bodies::{ElectrostaticsOptions, Space};
use crate::potential::multipole::mesh_ewald::{MeshEstimate, MeshParameters};
use crate::potential::multipole::{AutoChoice, EwaldParameters, SumPath};
use crate::potential::{Boundary, MultipolePotential, PeriodicSum, SumKind, Surface};
use crate::scene::{BodyScene, Interactions, Scene, SCENE_VERSION};
use crate::simulation::{Energies, EnergyReference, RunReport, Stop};
use crate::units::UnitNames;
use serde::{Deserialize, Serialize};

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
    /// The conserved energy (runs with a thermostat only; `K + V` otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conserved: Option<f64>,
    /// The relative error of the conserved energy.
    pub error: f64,
}

/// Energy drift over the run.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Drift {
    /// Least-squares slope of the conserved energy (the total energy without
    /// a thermostat) against time, divided by the mean kinetic energy over
    /// the samples (or by the reference scale when that vanishes): relative
    /// drift per unit time.
    pub relative_per_time: f64,
    /// `(E_last - E_0) / scale`.
    pub final_error: f64,
    /// Number of samples in the fit.
    pub samples: usize,
}

/// How a run summed its pair interactions: the boundary as run (defaults
/// filled in), the path the potential took ([`crate::potential::SumPath`])
/// and, for an Ewald sum, the parameters chosen for the accuracy.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct InteractionsSummary {
    /// `"open"` or `"periodic"`.
    pub boundary: String,
    /// The box edges (periodic).
    #[serde(rename = "box")]
    pub box_lengths: Option<[f64; 3]>,
    /// `"ewald"` or `"cutoff"` (periodic).
    pub sum: Option<SumKind>,
    /// The spherical cutoff (`sum = "cutoff"`).
    pub cutoff: Option<f64>,
    /// The requested relative accuracy (`sum = "ewald"`).
    pub accuracy: Option<f64>,
    /// The surroundings (`sum = "ewald"`).
    pub surface: Option<Surface>,
    /// The path taken: `"open_pairs"`, `"cutoff_pairs"`,
    /// `"cutoff_lattice_fft"`, `"ewald_direct"`, `"ewald_lattice_fft"` or
    /// `"ewald_pme"`.
    pub path: String,
    /// The Ewald parameters chosen (`sum = "ewald"`).
    pub ewald: Option<EwaldSummary>,
    /// The cells and the sites per cell of the lattice an FFT path runs on.
    pub lattice: Option<LatticeSummary>,
    /// The parameters of the mesh Ewald sum (path `"ewald_pme"`; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSummary>,
    /// Why `method = "auto"` took the direct Ewald sum or PME on sites that
    /// are not a lattice (absent for every other path and method).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice: Option<ChoiceSummary>,
}

/// What the automatic choice compared ([`AutoChoice`]): each path's
/// estimated seconds per evaluation and the reason.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ChoiceSummary {
    /// The direct Ewald sum's estimated seconds per evaluation (absent
    /// when it is too large to build).
    pub direct_seconds: Option<f64>,
    /// The mesh Ewald sum's (absent when it cannot be built for the request).
    pub pme_seconds: Option<f64>,
    /// Why the path was taken.
    pub reason: String,
}

impl From<&AutoChoice> for ChoiceSummary {
    fn from(c: &AutoChoice) -> Self {
        ChoiceSummary {
            direct_seconds: c.direct_seconds,
            pme_seconds: c.pme_seconds,
            reason: c.reason.clone(),
        }
    }
}

/// The parameters a mesh Ewald sum chose for its accuracy
/// ([`MeshParameters`]), with the error estimates they meet ([`MeshEstimate`]).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct MeshSummary {
    /// The splitting parameter `alpha` (inverse length).
    pub alpha: f64,
    /// The real-space cutoff (length).
    pub real_cutoff: f64,
    /// Mesh points along x, y, z.
    pub grid: [usize; 3],
    /// The B-spline order.
    pub order: usize,
    /// The estimated relative error of the real-space truncation (a bound).
    pub real_estimate: f64,
    /// The estimated relative RMS error of the mesh.
    pub mesh_estimate: f64,
    /// Their sum: the estimated relative error of the sum.
    pub estimated_error: f64,
}

impl From<(MeshParameters, MeshEstimate)> for MeshSummary {
    fn from((p, e): (MeshParameters, MeshEstimate)) -> Self {
        MeshSummary {
            alpha: p.alpha,
            real_cutoff: p.real_cutoff,
            grid: p.grid,
            order: p.order,
            real_estimate: e.real,
            mesh_estimate: e.mesh,
            estimated_error: e.real + e.mesh,
        }
    }
}

/// The splitting and the cutoffs an Ewald sum chose for its accuracy
/// ([`EwaldParameters`]), with the error estimates they meet.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct EwaldSummary {
    /// The splitting parameter `alpha` (inverse length).
    pub alpha: f64,
    /// The real-space cutoff (length).
    pub real_cutoff: f64,
    /// The reciprocal-space cutoff (inverse length).
    pub reciprocal_cutoff: f64,
    /// The estimated relative error of the real-space truncation.
    pub real_estimate: f64,
    /// The estimated relative error of the reciprocal-space truncation.
    pub reciprocal_estimate: f64,
    /// Their sum: the estimated relative error of the sum.
    pub estimated_error: f64,
}

/// The lattice of the box an FFT lattice sum runs on.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct LatticeSummary {
    /// Cells along x, y, z.
    pub cells: [usize; 3],
    /// Sites per cell.
    pub basis: usize,
}

impl From<EwaldParameters> for EwaldSummary {
    fn from(p: EwaldParameters) -> Self {
        EwaldSummary {
            alpha: p.alpha,
            real_cutoff: p.real_cutoff,
            reciprocal_cutoff: p.reciprocal_cutoff,
            real_estimate: p.real_estimate,
            reciprocal_estimate: p.reciprocal_estimate,
            estimated_error: p.real_estimate + p.reciprocal_estimate,
        }
    }
}

impl InteractionsSummary {
    /// The record of `interactions` summed by `potential` (built from them).
    pub fn new(interactions: &Interactions, potential: &MultipolePotential) -> Self {
        let mut out = InteractionsSummary {
            boundary: "open".to_string(),
            box_lengths: None,
            sum: None,
            cutoff: None,
            accuracy: None,
            surface: None,
            path: potential.sum_path().as_str().to_string(),
            ewald: potential.ewald_parameters().map(EwaldSummary::from),
            lattice: potential.lattice().map(|grid| LatticeSummary {
                cells: grid.cells,
                basis: grid.basis.len(),
            }),
            mesh: potential.mesh_parameters().map(MeshSummary::from),
            choice: potential.auto_choice().map(ChoiceSummary::from),
        };
        if let Boundary::Periodic { box_lengths, sum } = interactions.boundary {
            out.boundary = "periodic".to_string();
            out.box_lengths = Some(box_lengths.into());
            out.sum = Some(sum.kind());
            match sum {
                PeriodicSum::Cutoff { cutoff } => out.cutoff = Some(cutoff),
                PeriodicSum::Ewald { accuracy, surface } => {
                    out.accuracy = Some(accuracy.get());
                    out.surface = Some(surface);
                }
            }
        }
        out
    }
}

/// What a run of moving bodies ran.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BodiesSummary {
    /// The number of bodies.
    pub count: usize,
    /// Bodies of each type, in type order.
    pub per_type: Vec<usize>,
    /// The number of sites.
    pub sites: usize,
    /// The periodic box's edges (absent in open space).
    #[serde(rename = "box", skip_serializing_if = "Option::is_none")]
    pub box_lengths: Option<[f64; 3]>,
    /// How many times the neighbour list was built.
    pub neighbour_builds: u64,
    /// The electrostatic sum when it is an Ewald sum: its path
    /// (`"ewald_pme"` or `"ewald_direct"`) and parameters (absent for a
    /// cutoff sum).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub electrostatics: Option<BodyElectrostaticsSummary>,
}

/// The Ewald sum of a run of bodies.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BodyElectrostaticsSummary {
    /// The way it is summed: `"ewald_pme"` or `"ewald_direct"`.
    pub path: String,
    /// The accuracy asked for.
    pub accuracy: f64,
    /// The surroundings.
    pub surface: Surface,
    /// The mesh parameters chosen for the accuracy (PME).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSummary>,
    /// The splitting and cutoffs chosen for the accuracy (direct sum).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ewald: Option<EwaldSummary>,
    /// What `method = "auto"` compared (absent for a method given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub choice: Option<ChoiceSummary>,
}

impl BodyElectrostaticsSummary {
    /// The record of the electrostatics `sum` of `bodies` (from
    /// [`crate::bodies::BodySystem::electrostatic_sum`]) when it is an Ewald sum.
    pub fn new(bodies: &BodyScene, sum: Option<&dyn Electrostatics>) -> Option<Self> {
        let (Some(ElectrostaticsOptions::Ewald(o)), Some(sum)) =
            (bodies.interactions.electrostatics, sum)
        else {
            return None;
        };
        let mesh = sum.mesh_parameters().map(MeshSummary::from);
        let path = if mesh.is_some() {
            SumPath::EwaldPme
        } else {
            SumPath::EwaldDirect
        };
        Some(BodyElectrostaticsSummary {
            path: path.as_str().to_string(),
            accuracy: o.accuracy,
            surface: o.surface,
            mesh,
            ewald: sum.ewald_parameters().map(EwaldSummary::from),
            choice: sum.auto_choice().map(ChoiceSummary::from),
        })
    }
}

impl BodiesSummary {
    /// The summary of `bodies` (`per_type` of each type) after
    /// `neighbour_builds` builds, with the record of its Ewald sum
    /// (`BodyElectrostaticsSummary::new`).
    pub fn new(
        per_type: &[usize],
        bodies: &BodyScene,
        neighbour_builds: u64,
        electrostatics: Option<BodyElectrostaticsSummary>,
    ) -> Self {
        BodiesSummary {
            count: bodies.bodies.len(),
            per_type: per_type.to_vec(),
            sites: bodies
                .bodies
                .iter()
                .map(|b| bodies.types[b.kind].sites.len())
                .sum(),
            box_lengths: match bodies.space {
                Space::Periodic(l) => Some(l.into()),
                Space::Open => None,
            },
            neighbour_builds,
            electrostatics,
        }
    }
}

/// How many threads a run used and why.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Threads {
    /// The size of the rayon pool the run loop ran in.
    pub count: usize,
    /// Who chose it: `"given"` (`--threads`, Python's `threads=`),
    /// `"scene"` (its `run.threads`), `"RAYON_NUM_THREADS"` (the
    /// environment) or `"automatic"` (from the
    /// number of rotors or of moving bodies' sites,
    /// [`crate::parallel::automatic_threads`]).
    pub chosen: &'static str,
    /// The rule or the setting that gave the count.
    pub reason: String,
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
    /// The seed of a stochastic thermostat (runs with one only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thermostat_seed: Option<u64>,
    /// What produced the outputs.
    pub versions: Versions,
    /// The integrator's name.
    pub integrator: String,
    /// The number of rotors.
    pub rotors: usize,
    /// How the pair interactions were summed (`None` without interactions).
    pub interactions: Option<InteractionsSummary>,
    /// The time step.
    pub dt: f64,
    /// The first step of this run (0, or the checkpoint's).
    pub start_step: u64,
    /// The step the run ended at.
    pub last_step: u64,
    /// "completed", "blew_up" or "interrupted"; "failed" (with the error
    /// as `message`) when the run stopped on an error, such as a write that
    /// failed; "running" in the file of a run that has not ended (written
    /// at its start and after each checkpoint: what a killed run leaves).
    pub status: &'static str,
    /// The blow-up message (step and rotor), if any.
    pub message: Option<String>,
    /// Wall-clock seconds of the run loop.
    pub wall_seconds: f64,
    /// The threads the run used.
    pub threads: Threads,
    /// The energy reference.
    pub initial_energy: Option<EnergyReference>,
    /// The last energies computed.
    pub final_energies: Option<FinalEnergies>,
    /// The energy drift, when energies were computed at two steps or more.
    pub drift: Option<Drift>,
    /// The bodies of a scene of bodies (absent for rotors).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<BodiesSummary>,
    /// The units of the outputs (absent: reduced units).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub units: Option<UnitNames>,
    /// How the files were written: `"new"`, `"appended"` to an earlier
    /// run's, or `"new_folder"` (a restart whose folder held files that do
    /// not end at the checkpoint); absent when no file was written.
    pub outputs: Option<&'static str>,
}

/// The drift of the run's conserved energy (the total energy without a
/// thermostat), relative to the mean kinetic energy over the samples (or to
/// the reference scale when that vanishes).
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
    /// The summary of `report` for `scene` (whose raw form is `definition`),
    /// whose pair interactions were summed as `interactions` says, run on
    /// `threads`.
    pub fn new(
        scene: &Scene,
        definition: serde_json::Value,
        interactions: Option<InteractionsSummary>,
        report: &RunReport,
        (start_step, threads): (u64, &Threads),
    ) -> Self {
        let final_energies = report
            .last_energies
            .map(|(step, e): (u64, Energies)| FinalEnergies {
                step,
                kinetic: e.kinetic,
                potential: e.potential,
                total: e.total,
                conserved: scene.thermostat.is_some().then_some(e.conserved),
                error: e.error,
            });
        Summary {
            scene: scene.name.clone(),
            description: scene.description.clone(),
            definition,
            seed: scene.seed,
            thermostat_seed: scene.thermostat.as_ref().and_then(|t| t.seed()),
            versions: Versions {
                quatrot: env!("CARGO_PKG_VERSION"),
                scene_format: SCENE_VERSION,
            },
            integrator: scene.integrator.name().to_string(),
            rotors: scene.rotors.len(),
            interactions,
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
            threads: threads.clone(),
            initial_energy: report.reference,
            final_energies,
            drift: drift(report),
            bodies: None,
            units: None,
            outputs: None,
        }
    }
}
