//! The scene file as written: serde structs that mirror the TOML (or JSON)
//! exactly, with `deny_unknown_fields` everywhere and internally tagged enums
//! (`kind = "..."`) of struct variants. Each section's types live in the
//! section's file; [`super::validate()`] turns a [`RawScene`] into a typed
//! [`super::Scene`].

use serde::{Deserialize, Serialize};

pub use super::bodies::{
    RawBodies, RawBody, RawBodyElectrostatics, RawBodyEwald, RawBodyInteractions,
    RawElectrostaticCutoff, RawGivenBodies, RawLatticeBodies, RawLennardJonesOptions,
    RawRandomBodies,
};
pub use super::body_types::RawBodyType;
pub use super::fields::RawFields;
pub use super::initial::{RawExplicitInitial, RawInitial, RawRandomInitial, RawUniformInitial};
pub use super::integrator::RawIntegrator;
pub use super::interactions::{RawBoundary, RawInteractions, RawOpen, RawPeriodic, SumKind};
pub use super::record::{RawRecord, RawSeries, RawTrajectory};
pub use super::rotors::{
    RawInertia, RawLattice, RawOverride, RawRotorProps, RawRotors, RawSite, RawSites,
};
pub use super::run_length::RawRun;
pub use super::thermostat::RawThermostat;

/// A whole scene file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    /// The format version (must be [`super::SCENE_VERSION`]).
    pub version: i64,
    /// Short name.
    pub name: Option<String>,
    /// One line of text.
    pub description: Option<String>,
    /// The unit system (default reduced).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<crate::units::Units>,
    /// `[rotors]` (a scene declares rotors or bodies).
    pub rotors: Option<RawRotors>,
    /// `[[body_types]]` (scenes of bodies).
    pub body_types: Option<Vec<RawBodyType>>,
    /// `[bodies]`.
    pub bodies: Option<RawBodies>,
    /// `[body_interactions]`.
    pub body_interactions: Option<RawBodyInteractions>,
    /// `[interactions]`.
    pub interactions: Option<RawInteractions>,
    /// `[fields]`.
    pub fields: Option<RawFields>,
    /// `[initial]` (rotors: required; given bodies: absent).
    pub initial: Option<RawInitial>,
    /// `[integrator]`.
    pub integrator: RawIntegrator,
    /// `[thermostat]` (absent: constant energy).
    pub thermostat: Option<RawThermostat>,
    /// `[run]`.
    pub run: RawRun,
    /// `[record]`.
    pub record: Option<RawRecord>,
}

impl RawScene {
    /// The scene as JSON without the keys left out (for run summaries).
    pub fn definition(&self) -> serde_json::Value {
        fn strip_nulls(value: &mut serde_json::Value) {
            match value {
                serde_json::Value::Object(map) => {
                    map.retain(|_, v| !v.is_null());
                    map.values_mut().for_each(strip_nulls);
                }
                serde_json::Value::Array(items) => items.iter_mut().for_each(strip_nulls),
                _ => {}
            }
        }
        let mut value = serde_json::to_value(self).unwrap_or_default();
        strip_nulls(&mut value);
        value
    }
}
