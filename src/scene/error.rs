//! The one error type of the scene layer.

use crate::checks::{printable, InputError};

/// The most characters of a field path a message shows.
const PATH_CHARS: usize = 160;
/// The most characters of a message's text (the value quoted in it
/// included) shown.
const MESSAGE_CHARS: usize = 400;

/// Why a scene could not be read or validated. Every message names the
/// field (as a path such as `rotors.sites[3].inertia`) and the offending value;
/// what it quotes from the input is shown without control characters and
/// cut to an excerpt.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid TOML (or JSON).
    #[error("syntax: {}", printable(.0, MESSAGE_CHARS))]
    Syntax(String),
    /// A field is unknown, missing, of the wrong type, or has a bad value.
    #[error("{}: {}", printable(.path, PATH_CHARS), printable(.message, MESSAGE_CHARS))]
    Field {
        /// Where, e.g. `rotors.sites[3].inertia`.
        path: String,
        /// What is wrong, with the value found.
        message: String,
    },
    /// No built-in scene of that name and no such file.
    #[error(
        "no built-in scene or file named `{}` (`quatrot scenes` lists the built-ins)",
        printable(.0, PATH_CHARS)
    )]
    NotFound(String),
    /// The file exists but could not be read.
    #[error(
        "{}: cannot read: {}",
        printable(.path, PATH_CHARS),
        printable(.message, MESSAGE_CHARS)
    )]
    Io {
        /// The file.
        path: String,
        /// Why it could not be read.
        message: String,
    },
}

impl SceneError {
    /// A bad value at `path`.
    pub fn field(path: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError::Field {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The error of a physics check, its path renamed to the scene's: the
    /// first entry `(physics, scene)` of `names` whose physics name starts the
    /// path (followed by nothing, `[` or `.`) is replaced by the scene path.
    pub fn renamed(e: InputError, names: &[(&str, &str)]) -> Self {
        let path = names
            .iter()
            .find_map(|(physics, scene)| {
                let rest = e.path.strip_prefix(physics)?;
                (rest.is_empty() || rest.starts_with(['[', '.'])).then(|| format!("{scene}{rest}"))
            })
            .unwrap_or(e.path);
        SceneError::Field {
            path,
            message: e.message,
        }
    }
}

/// A physics check's error whose path is already the scene's.
impl From<InputError> for SceneError {
    fn from(e: InputError) -> Self {
        SceneError::Field {
            path: e.path,
            message: e.message,
        }
    }
}
