//! From a [`RawScene`] to a typed [`Scene`], section by section (each
//! section's checks live in its file), every error naming the field path and
//! the value (`rotors.sites[3].inertia: must be > 0, got 0`).

use super::error::SceneError;
use super::fields::fields;
use super::initial::initial;
use super::interactions::interactions;
use super::model::Scene;
use super::raw::{RawRecord, RawRotors, RawScene};
use super::record::record;
use super::rotors::{rotors, Rotors};
use super::run_length::run_length;
use super::thermostat::thermostat;
use crate::potential::ExternalFields;

/// The only scene format version this build reads.
pub const SCENE_VERSION: i64 = 1;

/// Validates a whole scene.
pub fn validate(raw: &RawScene) -> Result<Scene, SceneError> {
    if raw.version != SCENE_VERSION {
        return Err(SceneError::field(
            "version",
            format!(
                "unsupported version {} (this quatrot reads version {SCENE_VERSION})",
                raw.version
            ),
        ));
    }
    let Rotors {
        rotors,
        lattice_box,
    } = rotors(&raw.rotors)?;
    let explicit_sites = matches!(raw.rotors, RawRotors::Sites(_));
    let interactions = raw
        .interactions
        .as_ref()
        .map(|i| interactions(i, &rotors, explicit_sites, lattice_box))
        .transpose()?;
    let fields = match &raw.fields {
        Some(f) => fields(f, &rotors, interactions.is_some())?,
        None => ExternalFields::NONE,
    };
    let (initial, seed) = initial(&raw.initial, &rotors)?;
    let integrator = raw.integrator.spec;
    let thermostat = thermostat(raw.thermostat.as_ref(), &integrator, seed)?;
    let (dt, steps) = run_length(&raw.run)?;
    let record = record(
        raw.record.as_ref().unwrap_or(&RawRecord::default()),
        &integrator,
        &rotors,
    )?;
    Ok(Scene {
        name: raw.name.clone().unwrap_or_else(|| "scene".to_string()),
        description: raw.description.clone().unwrap_or_default(),
        rotors,
        interactions,
        fields,
        initial,
        seed,
        integrator,
        thermostat,
        dt,
        steps,
        record,
    })
}
