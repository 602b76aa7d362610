//! Finding a scene by built-in name or path, and applying command-line
//! overrides before validation (so their errors name the scene field).

use super::builtin::builtin;
use super::error::SceneError;
use super::model::Scene;
use super::parse::{parse_table, parse_toml};
use super::raw::{RawIntegrator, RawScene};
use super::validate::validate;

/// Values given on the command line (or as Python keywords) that replace the scene's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Replaces `run.dt`.
    pub dt: Option<f64>,
    /// Replaces `run.steps` (and drops `run.time`).
    pub steps: Option<i64>,
    /// Replaces `[integrator]` by this integrator with its default options.
    pub integrator: Option<String>,
    /// Drops `[thermostat]`: the run keeps its energy from the scene's start
    /// (as the schemes that take no thermostat need).
    pub no_thermostat: bool,
}

impl Overrides {
    /// Applies the overrides to a raw scene.
    pub fn apply(&self, raw: &mut RawScene) -> Result<(), SceneError> {
        if let Some(dt) = self.dt {
            raw.run.dt = dt;
        }
        if let Some(steps) = self.steps {
            raw.run.steps = Some(steps);
            raw.run.time = None;
        }
        if let Some(name) = &self.integrator {
            raw.integrator = RawIntegrator::named(name).map_err(|e| {
                let e = e.below("integrator");
                SceneError::field(e.path, e.message)
            })?;
        }
        if self.no_thermostat {
            raw.thermostat = None;
        }
        Ok(())
    }
}

/// Reads the raw scene called `name_or_path`: a path (anything ending in
/// `.toml` or containing a path separator) is read from disk, otherwise a
/// built-in of that name is used, and failing that a file of that name.
pub fn load_raw(name_or_path: &str) -> Result<RawScene, SceneError> {
    let looks_like_path = name_or_path.ends_with(".toml") || name_or_path.contains(['/', '\\']);
    if !looks_like_path {
        if let Some(b) = builtin(name_or_path) {
            return parse_toml(b.toml);
        }
    }
    let path = std::path::Path::new(name_or_path);
    if !path.is_file() {
        return Err(SceneError::NotFound(name_or_path.to_string()));
    }
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
        path: name_or_path.to_string(),
        message: e.to_string(),
    })?;
    parse_toml(&text)
}

/// Loads, overrides and validates a scene by built-in name or path.
pub fn load(name_or_path: &str, overrides: &Overrides) -> Result<(RawScene, Scene), SceneError> {
    let mut raw = load_raw(name_or_path)?;
    overrides.apply(&mut raw)?;
    let scene = validate(&raw)?;
    Ok((raw, scene))
}

/// Validates a scene given as an in-memory table (a Python dict), with overrides.
pub fn load_table(
    table: toml::Table,
    overrides: &Overrides,
) -> Result<(RawScene, Scene), SceneError> {
    let mut raw = parse_table(table)?;
    overrides.apply(&mut raw)?;
    let scene = validate(&raw)?;
    Ok((raw, scene))
}

/// Validates a scene given as TOML text, with overrides.
pub fn load_text(text: &str, overrides: &Overrides) -> Result<(RawScene, Scene), SceneError> {
    let mut raw = parse_toml(text)?;
    overrides.apply(&mut raw)?;
    let scene = validate(&raw)?;
    Ok((raw, scene))
}
