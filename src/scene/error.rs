//! The one error type of the scene layer.

/// Why a scene could not be read or validated. Every message names the
/// field (as a path such as `rotors.sites[3].inertia`) and the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid TOML (or JSON).
    #[error("syntax: {0}")]
    Syntax(String),
    /// A field is unknown, missing, of the wrong type, or has a bad value.
    #[error("{path}: {message}")]
    Field { path: String, message: String },
    /// No built-in scene of that name and no such file.
    #[error("no built-in scene or file named `{0}` (`quatrot scenes` lists the built-ins)")]
    NotFound(String),
    /// The file exists but could not be read.
    #[error("{path}: cannot read: {message}")]
    Io { path: String, message: String },
}

impl SceneError {
    /// A bad value at `path`.
    pub fn field(path: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError::Field {
            path: path.into(),
            message: message.into(),
        }
    }
}
