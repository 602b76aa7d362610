//! Running a validated scene from its physics objects: its potential and the
//! integrator [`crate::dynamics::build`] makes of its integrator and
//! thermostat.

use super::error::RunError;
use super::limits::check_run_limits;
use super::scene_run::{run_scene, Outputs, Progress, RunResult, ScenePotential};
use super::summary::InteractionsSummary;
use crate::parallel::on_worker;
use crate::potential::{Boundary, ExternalFields, Free, MultipolePotential, SumMethod};
use crate::scene::{boundary_error, Interactions, Scene};
use std::path::Path;

/// The potential of a scene: `None` for rotors without interactions or
/// fields (they run with [`Free`]), otherwise the [`MultipolePotential`]
/// (which checks what scene validation cannot cheaply, such as coincident
/// sites, the size of the sums, a lattice for `method = "lattice_fft"`;
/// errors about the boundary name the scene's field).
pub fn potential(scene: &Scene) -> Result<Option<MultipolePotential>, RunError> {
    if scene.interactions.is_none() && scene.fields == ExternalFields::NONE {
        return Ok(None);
    }
    let Interactions { boundary, method } = scene.interactions.unwrap_or(Interactions {
        boundary: Boundary::Open,
        method: SumMethod::Auto,
    });
    MultipolePotential::with_method(&scene.rotors, boundary, scene.fields, method)
        .map(Some)
        .map_err(|e| match boundary_error(&e) {
            Some(scene_error) => RunError::Scene(scene_error),
            None => RunError::Potential(e.to_string()),
        })
}

/// Everything `run` checks before its first step, without running: the
/// sizes and ranges of the run ([`check_run_limits`], series and frames kept
/// in memory when `keep`) and the potential (built, which checks what scene
/// validation cannot cheaply, such as coincident sites). Returns the
/// potential.
pub fn prepare(scene: &Scene, keep: bool) -> Result<Option<MultipolePotential>, RunError> {
    check_run_limits(scene, keep)?;
    potential(scene)
}

/// Runs a validated scene (`definition` is its raw form, for the summary)
/// on a worker of the rayon pool.
pub fn execute(
    scene: &Scene,
    definition: serde_json::Value,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    on_worker(|| {
        let built = prepare(scene, outputs.keep)?;
        let interactions = scene
            .interactions
            .as_ref()
            .zip(built.as_ref())
            .map(|(i, p)| InteractionsSummary::new(i, p));
        let potential = match &built {
            Some(p) => ScenePotential {
                potential: p,
                interactions: interactions.as_ref(),
            },
            None => ScenePotential::plain(&Free),
        };
        let mut integrator = crate::dynamics::build(&scene.integrator, scene.thermostat.as_ref());
        run_scene(
            scene,
            definition,
            integrator.as_mut(),
            potential,
            outputs,
            restart,
            progress,
        )
    })
}
