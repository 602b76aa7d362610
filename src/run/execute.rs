//! Running a validated scene from its physics objects: its potential and the
//! integrator [`crate::dynamics::build`] makes of its integrator and
//! thermostat.

use super::bodies::run_bodies;
use super::error::RunError;
use super::limits::check_run_limits;
use super::scene_run::{run_scene, thread_record, Outputs, Progress, RunResult, ScenePotential};
use super::summary::InteractionsSummary;
use crate::parallel::{
    automatic_threads, in_pool, on_worker, ThreadCount, ROTORS_PER_THREAD, SITES_PER_THREAD,
};
use crate::potential::multipole::mesh_ewald::ForcedMesh;
use crate::potential::{Boundary, ExternalFields, Free, MultipolePotential, SumMethod};
use crate::scene::{boundary_error, Interactions, Scene};
use std::num::NonZeroUsize;
use std::path::Path;

/// The environment variable that sizes rayon's shared pool.
const RAYON_NUM_THREADS: &str = "RAYON_NUM_THREADS";

/// The potential of a scene: `None` for rotors without interactions or
/// fields (they run with [`Free`]), otherwise the [`MultipolePotential`]
/// (which checks what scene validation cannot cheaply, such as coincident
/// sites, the size of the sums, a lattice for `method = "lattice_fft"`;
/// errors about the boundary name the scene's field).
pub fn potential(scene: &Scene) -> Result<Option<MultipolePotential>, RunError> {
    if scene.interactions.is_none() && scene.fields == ExternalFields::NONE {
        return Ok(None);
    }
    let Interactions {
        boundary,
        method,
        forced,
    } = scene.interactions.unwrap_or(Interactions {
        boundary: Boundary::Open,
        method: SumMethod::Auto,
        forced: ForcedMesh::default(),
    });
    MultipolePotential::with_forced_mesh(&scene.rotors, boundary, scene.fields, method, &forced)
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
/// on a worker of a rayon pool of `outputs.threads` threads when given, else
/// of the scene's `run.threads`, else of the shared pool when
/// `RAYON_NUM_THREADS` sizes it, else of [`automatic_threads`] for its
/// rotors or its moving bodies' sites (`choose_threads`); the count and the reason are
/// recorded in the summary ([`super::Threads`]).
pub fn execute(
    scene: &Scene,
    definition: serde_json::Value,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let (pool, _, _) = choose_threads(scene, outputs.threads);
    let go = move || {
        if let Some(bodies) = &scene.bodies {
            let threads = thread_record(scene, outputs);
            return run_bodies((scene, bodies), definition, outputs, restart, &threads);
        }
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
    };
    match pool {
        Some(count) => in_pool(count, go).map_err(|e| RunError::Threads(e.to_string()))?,
        None => on_worker(go),
    }
}

/// The pool a run of `scene` takes (`None`: the shared pool), who chose it
/// and why: `given` threads, else the scene's `run.threads`, else the shared
/// pool when `RAYON_NUM_THREADS` sizes it, else [`automatic_threads`] for its
/// rotors or its moving bodies' sites.
pub(super) fn choose_threads(
    scene: &Scene,
    given: Option<NonZeroUsize>,
) -> (Option<NonZeroUsize>, &'static str, String) {
    if let Some(count) = given {
        return (Some(count), "given", format!("{count} threads given"));
    }
    if let ThreadCount::Fixed(count) = scene.threads {
        return (
            Some(count),
            "scene",
            format!("run.threads = {count} in the scene"),
        );
    }
    if let Some(value) = std::env::var_os(RAYON_NUM_THREADS).filter(|v| !v.is_empty()) {
        let reason = format!("{RAYON_NUM_THREADS}={}", value.to_string_lossy());
        return (None, RAYON_NUM_THREADS, reason);
    }
    let cores = std::thread::available_parallelism().map_or(1, NonZeroUsize::get);
    let (size, what, per_thread) = match &scene.bodies {
        Some(b) => {
            let sites = b.bodies.iter().map(|body| b.types[body.kind].sites.len());
            (sites.sum(), "body sites", SITES_PER_THREAD)
        }
        None => (scene.rotors.len(), "rotors", ROTORS_PER_THREAD),
    };
    let count = automatic_threads(size, per_thread, cores);
    let reason = format!(
        "{what} {size}, cores {cores}: one thread per {per_thread} {what}, \
         at least 1, at most the cores"
    );
    (Some(count), "automatic", reason)
}
