//! Running a scene: its outputs (CSV series, DCD + PDB or GSD trajectory,
//! JSON summary, checkpoints) as observers of the one run loop of
//! [`crate::simulation`], and the run of a scene from its physics objects.

mod checkpoint;
mod dcd;
mod error;
mod execute;
mod folder;
mod gsd;
mod limits;
mod pdb;
mod resume;
mod scene_run;
mod series;
mod summary;
mod trajectory;

pub use checkpoint::{Checkpoint, CheckpointWriter, Identity};
pub use dcd::{read_header, DcdHeader, DcdWriter};
pub use error::RunError;
pub use execute::{execute, potential, prepare};
pub use folder::{OutputFolder, LOCK_FILE};
pub use gsd::{GsdBox, GsdWriter};
pub use limits::check_run_limits;
pub use pdb::ROTOR_ATOMS;
pub use resume::{AppendAfter, Placement};
pub use scene_run::{
    run_scene, Outputs, Progress, RunResult, CHECKPOINT_FILE, DCD_FILE, PDB_FILE, SUMMARY_FILE,
};
pub use series::{CsvTarget, SeriesObserver, SeriesTable};
pub use summary::{Drift, FinalEnergies, Summary, Versions};
pub use trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver};
