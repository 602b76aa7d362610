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

/// The most characters of a scene's name.
const MAX_NAME_CHARS: usize = 100;
/// The most characters of a scene's description.
const MAX_DESCRIPTION_CHARS: usize = 1000;

/// The scene's name (default `scene`): a plain file name, since it names the
/// default output folder and titles the trajectory. Letters, digits, `_`,
/// `-`, `.`, `+` and spaces, starting with a letter, a digit or `_`: no path
/// separator, no `..`, no control character.
fn scene_name(raw: Option<&str>) -> Result<String, SceneError> {
    let Some(name) = raw else {
        return Ok("scene".to_string());
    };
    let plain = name
        .chars()
        .all(|c| c.is_alphanumeric() || "_-.+ ".contains(c))
        && name
            .chars()
            .next()
            .is_some_and(|c| c.is_alphanumeric() || c == '_')
        && !name.contains("..")
        && !name.ends_with([' ', '.'])
        && name.chars().count() <= MAX_NAME_CHARS;
    if !plain {
        return Err(SceneError::field(
            "name",
            format!(
                "must be a plain file name of at most {MAX_NAME_CHARS} characters (letters, digits, _ - . + and spaces, starting with a letter, a digit or _; it names the default output folder), got \"{}\"",
                crate::checks::printable(name, 60)
            ),
        ));
    }
    Ok(name.to_string())
}

/// The scene's description: one line of at most [`MAX_DESCRIPTION_CHARS`]
/// characters, without control characters.
fn description(raw: Option<&str>) -> Result<String, SceneError> {
    let text = raw.unwrap_or_default();
    if text.chars().any(char::is_control) || text.chars().count() > MAX_DESCRIPTION_CHARS {
        return Err(SceneError::field(
            "description",
            format!(
                "must be one line of at most {MAX_DESCRIPTION_CHARS} characters without control characters, got \"{}\"",
                crate::checks::printable(text, 60)
            ),
        ));
    }
    Ok(text.to_string())
}

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
        name: scene_name(raw.name.as_deref())?,
        description: description(raw.description.as_deref())?,
        rotors,
        interactions,
        fields,
        initial,
        seed,
        integrator,
        thermostat,
        dt,
        steps,
        threads: raw.run.threads.unwrap_or_default(),
        record,
    })
}
