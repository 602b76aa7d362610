//! The one error type of the run layer.

use crate::checks::printable;
use crate::integrators::IntegratorError;

/// The most characters of a path or message shown.
const SHOWN: usize = 300;
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
    #[error("potential: {}", printable(.0, SHOWN))]
    Potential(String),
    /// Writing or reading an output file failed.
    #[error("{}: {}", printable(.path, SHOWN), printable(.message, SHOWN))]
    Io {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
    /// The output folder is in use by another run.
    #[error(
        "{}: the output folder is in use by {holder} (one run per folder; choose another with --out or out_dir)",
        printable(.dir, SHOWN)
    )]
    Locked {
        /// The folder.
        dir: String,
        /// Who holds its lock.
        holder: String,
    },
    /// The pool of threads for the run could not be started.
    #[error("threads: {}", printable(.0, SHOWN))]
    Threads(String),
    /// A checkpoint does not belong to this scene.
    #[error("checkpoint {}: {}", printable(.path, SHOWN), printable(.message, SHOWN))]
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
