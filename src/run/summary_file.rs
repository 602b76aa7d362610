//! The summary file of a run (`summary.json`): written when the run starts
//! (status "running"), after each checkpoint (with its step), on an error
//! ("failed", with the error) and at the end; on a restart that appends to
//! an earlier run's files, the earlier summary is kept under another name.

use super::checkpoint::CheckpointWriter;
use super::error::RunError;
use super::folder::{write_atomically, SUMMARY_FILE};
use super::resume::{kept_summary_name, Placement};
use super::summary::{InteractionsSummary, Summary, Threads};
use crate::scene::Scene;
use crate::simulation::{CheckpointSink, EnergyHistory, EnergyReference, RunReport, Stop};
use std::path::{Path, PathBuf};

/// Keeps the summary of the earlier run that a restart appends to under
/// another name (done once the outputs are open, so that a restart refused
/// before leaves the folder as it was).
pub(super) fn keep_earlier_summary(
    files: Option<(&Path, &Placement)>,
    start_step: u64,
) -> Result<(), RunError> {
    if let Some((dir, Placement::Append(_))) = files {
        let summary = dir.join(SUMMARY_FILE);
        if summary.exists() {
            let kept = kept_summary_name(dir, start_step);
            std::fs::rename(&summary, &kept).map_err(|e| RunError::io(&kept, e))?;
        }
    }
    Ok(())
}

/// Status of the summary of a run that stopped on an error.
const FAILED: &str = "failed";

/// The error `error` of a run, after rewriting the summary written at its
/// start (`running`, brought to its last checkpoint) with status [`FAILED`]
/// and the error. A summary that cannot be written either (a full disk)
/// keeps saying "running"; the run's own error is the one reported.
pub(super) fn record_failure(running: Option<(PathBuf, Summary)>, error: RunError) -> RunError {
    if let Some((path, mut summary)) = running {
        summary.status = FAILED;
        summary.message = Some(error.to_string());
        let _ = write_summary(&path, &summary);
    }
    error
}

/// `summary` with where the outputs went (`files`: the folder and the
/// placement), written there.
pub(super) fn placed(
    mut summary: Summary,
    files: Option<(&Path, &Placement)>,
) -> Result<Summary, RunError> {
    summary.outputs = files.map(|(_, placement)| placement.as_str());
    if let Some((dir, _)) = files {
        write_summary(&dir.join(SUMMARY_FILE), &summary)?;
    }
    Ok(summary)
}

/// What a killed run leaves: a summary saying "running" (written in the
/// folder of `files`, and its path), rewritten after each checkpoint with
/// the checkpoint's step.
pub(super) fn running_summary(
    scene: &Scene,
    definition: &serde_json::Value,
    interactions: Option<&InteractionsSummary>,
    start: (u64, &Threads),
    files: Option<(&Path, &Placement)>,
) -> Result<Option<(PathBuf, Summary)>, RunError> {
    let Some((dir, _)) = files else {
        return Ok(None);
    };
    let summary = in_progress(scene, definition, interactions.cloned(), start);
    Ok(Some((dir.join(SUMMARY_FILE), placed(summary, files)?)))
}

/// Status of the summary of a run in progress (or killed).
const RUNNING: &str = "running";

/// The summary of a run of `scene` from `start_step` that has not ended:
/// status [`RUNNING`], no energies yet.
pub(super) fn in_progress(
    scene: &Scene,
    definition: &serde_json::Value,
    interactions: Option<InteractionsSummary>,
    (start_step, threads): (u64, &Threads),
) -> Summary {
    let report = RunReport {
        stop: Stop::Completed,
        last_step: start_step,
        reference: None,
        last_energies: None,
        energy_history: EnergyHistory::default(),
        wall_seconds: 0.0,
    };
    let mut summary = Summary::new(
        scene,
        definition.clone(),
        interactions,
        &report,
        (start_step, threads),
    );
    summary.status = RUNNING;
    summary
}

/// Writes `summary` to `path` atomically (readers, and a run killed
/// meanwhile, see the old file or the new one).
pub(super) fn write_summary(path: &Path, summary: &Summary) -> Result<(), RunError> {
    let text = serde_json::to_string_pretty(summary).map_err(|e| RunError::io(path, e))?;
    write_atomically(path, (text + "\n").as_bytes(), false)
}

/// Checkpoints, each followed by the summary in progress (status
/// [`RUNNING`]) brought to the checkpoint's step, so that a killed run's
/// summary names the checkpoint to restart from.
pub(super) struct SummaryAfterCheckpoint {
    pub(super) checkpoint: CheckpointWriter,
    pub(super) summary: Option<(PathBuf, Summary)>,
}

impl CheckpointSink for SummaryAfterCheckpoint {
    type Error = RunError;

    fn write(
        &mut self,
        step: u64,
        state: &[f64],
        reference: Option<EnergyReference>,
    ) -> Result<(), RunError> {
        self.checkpoint.write(step, state, reference)?;
        if let Some((path, summary)) = &mut self.summary {
            summary.last_step = step;
            summary.initial_energy = reference;
            write_summary(path, summary)?;
        }
        Ok(())
    }
}
