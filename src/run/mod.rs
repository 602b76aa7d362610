//! Running a scene: its outputs (CSV series, DCD + PDB or GSD trajectory,
//! JSON summary, checkpoints) as observers of the one run loop of
//! [`crate::simulation`], the run of a scene from its physics objects, and
//! what is computed from a run's recorded outputs (its dielectric constant).

mod bodies;
mod body_outputs;
mod checkpoint;
mod dcd;
mod dielectric;
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
mod summary_file;
mod trajectory;

pub use checkpoint::{Checkpoint, CheckpointWriter, Identity};
pub use dcd::{read_header, DcdHeader, DcdWriter};
pub use dielectric::{dielectric_of_run, dipole_series, read_run};
pub use error::RunError;
pub use execute::{execute, potential, prepare};
pub use folder::{
    OutputFolder, CHECKPOINT_FILE, DCD_FILE, GSD_FILE, LOCK_FILE, PDB_FILE, SUMMARY_FILE,
};
pub use gsd::{BodyFrame, BodyTypes, GsdBox, GsdWriter};
pub use limits::check_run_limits;
pub use pdb::ROTOR_ATOMS;
pub use resume::{AppendAfter, Placement};
pub use scene_run::{run_scene, Outputs, Progress, RunResult, ScenePotential};
pub use series::{CsvTarget, SeriesObserver, SeriesTable};
pub use summary::{
    BodiesSummary, ChoiceSummary, Drift, EwaldSummary, FinalEnergies, InteractionsSummary,
    LatticeSummary, MeshSummary, Summary, Threads, Versions,
};
pub use trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver, GSD_OPEN_MARGIN};
