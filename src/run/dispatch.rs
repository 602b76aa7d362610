//! From the scene's choices to concrete types, once, outside the loop: each
//! (integrator, potential) pair is a separate monomorphised run.

use super::error::RunError;
use super::scene_run::{run_scene, Outputs, Progress, RunResult};
use crate::integrators::{
    DlmOptions, FirstCorrector, GearAOptions, GearBOptions, IntegratorSpec, NoSquishOptions,
    RichardsonOptions, SphericalTops, Startup,
};
use crate::parallel::on_worker;
use crate::potential::{Boundary, ExternalFields, Free, MultipolePotential, Potential};
use crate::scene::{
    BoundaryChoice, GearBC0, GearStartup, IntegratorChoice, Scene, SphericalTopRotation,
};
use std::num::NonZeroU32;
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
        (Some(BoundaryChoice::Periodic { cutoff }), Some(box_lengths)) => Boundary::Periodic {
            box_lengths,
            cutoff,
        },
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
pub fn with_integrator(
    scene: &Scene,
    definition: serde_json::Value,
    potential: &dyn Potential,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let spec = match scene.integrator {
        IntegratorChoice::GearA {
            renormalise,
            startup: s,
        } => IntegratorSpec::GearA(GearAOptions {
            renormalise,
            startup: startup(s),
        }),
        IntegratorChoice::GearB {
            c0,
            project_torque,
            project_velocity,
            renormalise,
            correct_higher_derivatives,
            startup: s,
        } => IntegratorSpec::GearB(GearBOptions {
            c0: match c0 {
                GearBC0::ThreeSixteenths => FirstCorrector::VelocityDependent,
                GearBC0::ThreeTwentieths => FirstCorrector::PositionOnly,
            },
            project_torque,
            project_velocity,
            renormalise,
            correct_higher_derivatives,
            startup: startup(s),
        }),
        IntegratorChoice::NoSquish {
            substeps,
            spherical_tops,
        } => IntegratorSpec::NoSquish(NoSquishOptions {
            substeps: NonZeroU32::new(substeps).unwrap_or(NonZeroU32::MIN),
            spherical_tops: spherical(spherical_tops),
        }),
        IntegratorChoice::Dlm { spherical_tops } => IntegratorSpec::Dlm(DlmOptions {
            spherical_tops: spherical(spherical_tops),
        }),
        IntegratorChoice::Richardson => IntegratorSpec::Richardson(RichardsonOptions {}),
    };
    run_scene(
        scene,
        definition,
        &mut *spec.build(),
        potential,
        outputs,
        restart,
        progress,
    )
}
