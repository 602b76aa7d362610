//! Scene files: versioned TOML (`version = 1`) describing the rotors, their
//! interactions and fields, the initial conditions, the integrator, the run
//! length and what to record. Text is parsed into raw serde structs
//! ([`raw`]), then validated into a typed [`Scene`] whose errors name the
//! field and the value. The format is documented in `docs/scenes.md`.

mod builtin;
mod error;
mod initial;
mod load;
mod model;
mod parse;
pub mod raw;
mod tagged;
mod validate;

pub use builtin::{builtin, Builtin, BUILTINS};
pub use error::SceneError;
pub use initial::random_states;
pub use load::{load, load_raw, load_table, load_text, Overrides};
pub use model::*;
pub use parse::{parse_table, parse_toml};
pub use validate::{validate, DEFAULT_CHECK_EVERY, DEFAULT_MARKER_LENGTH, SCENE_VERSION};
