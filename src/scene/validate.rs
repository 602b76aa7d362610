//! From a [`RawScene`] to a typed [`Scene`], section by section (each
//! section's checks live in its file), every error naming the field path and
//! the value (`rotors.sites[3].inertia: must be > 0, got 0`).

use super::bodies::body_scene;
use super::error::SceneError;
use super::fields::fields;
use super::initial::initial;
use super::interactions::interactions;
use super::model::Scene;
use super::raw::{RawBodies, RawRecord, RawRotors, RawScene};
use super::record::{body_record, record, TrajectoryFormat};
use super::rotors::{rotors, Rotors};
use super::run_length::run_length;
use super::thermostat::{in_engine_units, thermostat};
use crate::bodies::BodyIntegrator;
use crate::potential::ExternalFields;
use crate::units::Units;

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
    let raw_rotors = match (&raw.rotors, &raw.bodies) {
        (Some(r), None) => r,
        (None, Some(b)) => return validate_bodies(raw, b),
        (Some(_), Some(_)) => {
            return Err(SceneError::field(
                "bodies",
                "a scene declares [rotors] or [bodies], not both",
            ))
        }
        (None, None) => {
            return Err(SceneError::field(
                "rotors",
                "missing: a scene declares [rotors] or [bodies]",
            ))
        }
    };
    if let Some(field) = [
        ("units", raw.units.is_some_and(|u| u != Units::Reduced)),
        ("body_types", raw.body_types.is_some()),
        ("body_interactions", raw.body_interactions.is_some()),
    ]
    .iter()
    .find_map(|(f, given)| given.then_some(f))
    {
        return Err(SceneError::field(*field, "for scenes of bodies only"));
    }
    let Some(raw_initial) = &raw.initial else {
        return Err(SceneError::field("initial", "missing"));
    };
    let Rotors {
        rotors,
        lattice_box,
    } = rotors(raw_rotors)?;
    let explicit_sites = matches!(raw_rotors, RawRotors::Sites(_));
    let interactions = raw
        .interactions
        .as_ref()
        .map(|i| interactions(i, &rotors, explicit_sites, lattice_box))
        .transpose()?;
    let fields = match &raw.fields {
        Some(f) => fields(f, &rotors, interactions.is_some())?,
        None => ExternalFields::NONE,
    };
    let (initial, seed) = initial(raw_initial, &rotors)?;
    let integrator = raw.integrator.spec;
    let thermostat = thermostat(raw.thermostat.as_ref(), &integrator, seed)?;
    let (dt, steps) = run_length(&raw.run, Units::Reduced)?;
    let record = record(
        raw.record.as_ref().unwrap_or(&RawRecord::default()),
        &integrator,
        &rotors,
    )?;
    Ok(Scene {
        name: scene_name(raw.name.as_deref())?,
        description: description(raw.description.as_deref())?,
        rotors,
        bodies: None,
        units: Units::Reduced,
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

/// Validates a scene of bodies: no rotor section, an integrator that moves
/// bodies with the thermostats it carries for them, only the series of
/// [`BodyQuantity`]s and a GSD trajectory.
///
/// [`BodyQuantity`]: crate::bodies::BodyQuantity
fn validate_bodies(raw: &RawScene, raw_bodies: &RawBodies) -> Result<Scene, SceneError> {
    if let Some(field) = [
        ("interactions", raw.interactions.is_some()),
        ("fields", raw.fields.is_some()),
    ]
    .iter()
    .find_map(|(f, given)| given.then_some(f))
    {
        return Err(SceneError::field(
            *field,
            "for rotors only (bodies interact through [body_interactions])",
        ));
    }
    let integrator = raw.integrator.spec;
    BodyIntegrator::check(&integrator).map_err(|e| e.at("integrator"))?;
    let units = raw.units.unwrap_or_default();
    let (mut bodies, seed) = body_scene(
        raw.body_types.as_ref(),
        raw_bodies,
        raw.body_interactions.as_ref(),
        raw.initial.as_ref(),
        units,
    )?;
    if let Some(t) = &raw.thermostat {
        BodyIntegrator::check_thermostat(&integrator, &t.spec).map_err(|e| e.at("thermostat"))?;
    }
    let thermostat =
        thermostat(raw.thermostat.as_ref(), &integrator, seed)?.map(|t| in_engine_units(t, units));
    let (dt, steps) = run_length(&raw.run, units)?;
    let raw_record = raw.record.clone().unwrap_or_default();
    bodies.series = body_record(&raw_record, &bodies.space)?;
    let no_series = RawRecord {
        series: Vec::new(),
        ..raw_record
    };
    let record = record(&no_series, &integrator, &[])?;
    if record
        .trajectory
        .is_some_and(|t| t.format != TrajectoryFormat::Gsd)
    {
        return Err(SceneError::field(
            "record.trajectory.format",
            "bodies are recorded as GSD only: set format = \"gsd\"",
        ));
    }
    if record.energy_error_threshold.is_some() {
        return Err(SceneError::field(
            "record.energy_error_threshold",
            "not supported for bodies yet",
        ));
    }
    Ok(Scene {
        name: scene_name(raw.name.as_deref())?,
        description: description(raw.description.as_deref())?,
        rotors: Vec::new(),
        bodies: Some(bodies),
        units,
        interactions: None,
        fields: ExternalFields::NONE,
        initial: Vec::new(),
        seed,
        integrator,
        thermostat,
        dt,
        steps,
        threads: raw.run.threads.unwrap_or_default(),
        record,
    })
}
