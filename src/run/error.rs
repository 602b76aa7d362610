//! The one error type of the run layer.

use crate::integrators::IntegratorError;
use crate::scene::SceneError;

/// Why a run could not start, continue or write its outputs. A blow-up is
/// not an error: it is a [`crate::simulation::Stop`] of a run whose outputs
/// are valid.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The integrator could not be set up or restored.
    #[error(transparent)]
    Integrator(#[from] IntegratorError),
    /// The potential could not be built from the scene.
    #[error("potential: {0}")]
    Potential(String),
    /// Writing or reading an output file failed.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
    /// The output folder is in use by another run.
    #[error("{dir}: the output folder is in use by {holder} (one run per folder; choose another with --out or out_dir)")]
    Locked {
        /// The folder.
        dir: String,
        /// Who holds its lock.
        holder: String,
    },
    /// A checkpoint does not belong to this scene.
    #[error("checkpoint {path}: {message}")]
    Checkpoint {
        /// The checkpoint file.
        path: String,
        /// Why it does not fit.
        message: String,
    },
}

impl RunError {
    /// An I/O error on `path`.
    pub fn io(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        RunError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}
