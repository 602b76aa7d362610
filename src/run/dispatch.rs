//! From the scene's choices to concrete types, once, outside the loop: each
//! (integrator, potential) pair is a separate monomorphised run.

use super::error::RunError;
use super::scene_run::{Outputs, Progress, RunResult};
use crate::scene::Scene;
use std::path::Path;

/// Runs a validated scene (`definition` is its raw form, for the summary).
pub fn execute(
    scene: &Scene,
    _definition: serde_json::Value,
    _outputs: &Outputs,
    _restart: Option<&Path>,
    _progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    Err(RunError::Potential(format!(
        "integrator `{}` is not in this build yet",
        scene.integrator.name()
    )))
}
