//! Running a scene: the generic run loop (monomorphised over integrator and
//! potential), the observers it feeds at the intervals it owns, the output
//! files (CSV series, DCD + PDB trajectory, GSD trajectory, JSON summary,
//! checkpoints), and
//! the dispatch from a scene's choices to concrete types.

mod checkpoint;
mod dcd;
mod dispatch;
mod error;
mod gsd;
mod observer;
mod pdb;
mod runner;
mod scene_run;
mod series;
mod summary;
mod trajectory;

pub use checkpoint::{Checkpoint, CheckpointWriter};
pub use dcd::DcdWriter;
pub use dispatch::{execute, potential, with_integrator};
pub use error::RunError;
pub use gsd::{GsdBox, GsdWriter};
pub use observer::{Energies, Needs, Observer, Sample, Scheduled};
pub use pdb::ROTOR_ATOMS;
pub use runner::{run, EnergyReference, RunOptions, RunReport, Stop};
pub use scene_run::{
    run_scene, Outputs, Progress, RunResult, CHECKPOINT_FILE, DCD_FILE, PDB_FILE, SUMMARY_FILE,
};
pub use series::{SeriesObserver, SeriesTable};
pub use summary::{Drift, FinalEnergies, Summary, Versions};
pub use trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver};
