//! Scene files: versioned TOML (`version = 1`) describing the rotors, their
//! interactions and fields, the initial conditions, the integrator, the run
//! length and what to record. Text is parsed into raw serde structs
//! ([`raw`]; the `[integrator]` table straight into the physics
//! [`crate::integrators::IntegratorSpec`]), then validated into a typed
//! [`Scene`] of physics objects whose errors name the field and the value.
//! One file per section holds its raw types and its checks. The format is
//! documented in `docs/scenes.md`.

mod bodies;
mod body_types;
mod builtin;
mod error;
mod fields;
mod initial;
mod integrator;
mod interactions;
mod load;
mod model;
mod parse;
pub mod raw;
mod record;
mod rotors;
mod run_length;
mod tagged;
mod thermostat;
mod validate;
mod water;

pub use crate::parallel::ThreadCount;
pub use bodies::{body_electrostatics, BodyScene, BodySeries, DEFAULT_SKIN};
pub use body_types::{body_types, RawBodySite, RawBodyType, RawLennardJones};
pub use builtin::{builtin, Builtin, BUILTINS};
pub use error::SceneError;
pub use initial::random_states;
pub use interactions::boundary_error;
pub use load::{load, load_raw, load_table, load_text, Overrides};
pub use model::{Interactions, Scene};
pub use parse::{parse_table, parse_toml, MAX_NESTING};
pub use record::{
    Record, Series, TrajectoryFormat, TrajectorySpec, DEFAULT_CHECK_EVERY, DEFAULT_MARKER_LENGTH,
};
pub use validate::{validate, SCENE_VERSION};
pub use water::WaterModel;
