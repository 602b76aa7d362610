//! From the scene's choices to concrete types, once, outside the loop: each
//! (integrator, potential) pair is a separate monomorphised run.

use super::error::RunError;
use super::scene_run::{run_scene, Outputs, Progress, RunResult};
use crate::integrators::free_rotation::SphericalTops;
use crate::integrators::{
    Dlm, FirstCorrector, GearA, GearAOptions, GearB, GearBOptions, NoSquish, Richardson, Startup,
};
use crate::parallel::on_worker;
use crate::potential::{Boundary, ExternalFields, Free, MultipolePotential, Potential};
use crate::scene::{
    BoundaryChoice, GearBC0, GearStartup, IntegratorChoice, Scene, SphericalTopRotation,
};
use std::num::NonZeroUsize;
use std::path::Path;

/// The potential of a scene: `None` for rotors without interactions or
/// fields (they run with [`Free`]), otherwise the [`MultipolePotential`]
/// (which checks what scene validation cannot cheaply, such as coincident sites).
pub fn potential(scene: &Scene) -> Result<Option<MultipolePotential>, RunError> {
    let fields = ExternalFields {
        field: scene.fields.uniform,
        field_gradient: scene.fields.gradient,
    };
    if scene.interactions.is_none() && fields == ExternalFields::NONE {
        return Ok(None);
    }
    let boundary = match (scene.interactions.map(|i| i.boundary), scene.box_lengths) {
        (Some(BoundaryChoice::Periodic { cutoff }), Some(box_lengths)) => {
            Boundary::periodic_cutoff(box_lengths, cutoff)
        }
        _ => Boundary::Open,
    };
    MultipolePotential::new(&scene.rotors, boundary, fields)
        .map(Some)
        .map_err(|e| RunError::Potential(e.to_string()))
}

/// Runs a validated scene (`definition` is its raw form, for the summary).
pub fn execute(
    scene: &Scene,
    definition: serde_json::Value,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    on_worker(|| match potential(scene)? {
        None => with_integrator(scene, definition, &Free, outputs, restart, progress),
        Some(p) => with_integrator(scene, definition, &p, outputs, restart, progress),
    })
}

fn startup(s: GearStartup) -> Startup {
    match s {
        GearStartup::Consistent => Startup::Consistent,
        GearStartup::Zeros => Startup::Zeros,
    }
}

fn spherical(s: SphericalTopRotation) -> SphericalTops {
    match s {
        SphericalTopRotation::Exact => SphericalTops::Exact,
        SphericalTopRotation::Split => SphericalTops::Split,
    }
}

/// Runs a validated scene with the given potential (built by the caller from
/// the scene, possibly wrapped, e.g. to count evaluations in the benchmarks)
/// and the integrator the scene chooses.
pub fn with_integrator<P: Potential>(
    scene: &Scene,
    definition: serde_json::Value,
    potential: &P,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    match scene.integrator {
        IntegratorChoice::GearA {
            renormalise,
            startup: s,
        } => {
            let integrator = GearA::new(GearAOptions {
                renormalise,
                startup: startup(s),
            });
            run_scene(
                scene, definition, integrator, potential, outputs, restart, progress,
            )
        }
        IntegratorChoice::GearB {
            c0,
            project_torque,
            project_velocity,
            renormalise,
            correct_higher_derivatives,
            startup: s,
        } => {
            let integrator = GearB::new(GearBOptions {
                c0: match c0 {
                    GearBC0::ThreeSixteenths => FirstCorrector::VelocityDependent,
                    GearBC0::ThreeTwentieths => FirstCorrector::PositionOnly,
                },
                project_torque,
                project_velocity,
                renormalise,
                correct_higher_derivatives,
                startup: startup(s),
            });
            run_scene(
                scene, definition, integrator, potential, outputs, restart, progress,
            )
        }
        IntegratorChoice::NoSquish {
            substeps,
            spherical_tops,
        } => {
            let substeps = NonZeroUsize::new(substeps as usize).unwrap_or(NonZeroUsize::MIN);
            let integrator = NoSquish::new(substeps, spherical(spherical_tops));
            run_scene(
                scene, definition, integrator, potential, outputs, restart, progress,
            )
        }
        IntegratorChoice::Dlm { spherical_tops } => {
            let integrator = Dlm::new(spherical(spherical_tops));
            run_scene(
                scene, definition, integrator, potential, outputs, restart, progress,
            )
        }
        IntegratorChoice::Richardson => run_scene(
            scene,
            definition,
            Richardson::new(),
            potential,
            outputs,
            restart,
            progress,
        ),
    }
}
