//! Checkpoint files: the integrator's complete state at a step, stored as the
//! bit patterns of its floats (JSON; serde_json's default float parsing is
//! not correctly rounded, so no float is stored as a decimal), with
//! what is needed to check that it belongs to the scene it is restarted with.

use super::error::RunError;
use crate::simulation::{CheckpointSink, EnergyReference};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag written in every checkpoint.
const FORMAT: &str = "quatrot-checkpoint-1";

/// The contents of a checkpoint file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Checkpoint {
    /// The format tag, `quatrot-checkpoint-1`.
    pub format: String,
    /// The scene's name.
    pub scene: String,
    /// The integrator's name.
    pub integrator: String,
    /// The thermostat's kind, if the run has one (its state is part of
    /// `state_bits`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermostat: Option<String>,
    /// The number of rotors.
    pub rotors: usize,
    /// `dt.to_bits()`: a restart must use the same time step exactly.
    pub dt_bits: u64,
    /// The step of the state.
    pub step: u64,
    /// Bits of the reference energy `(total, scale)`, if one was computed.
    pub reference_bits: Option<[u64; 2]>,
    /// `f64::to_bits` of [`crate::integrators::Integrator::checkpoint`].
    pub state_bits: Vec<u64>,
}

impl Checkpoint {
    /// Reads a checkpoint file.
    pub fn read(path: &Path) -> Result<Checkpoint, RunError> {
        let text = std::fs::read_to_string(path).map_err(|e| RunError::io(path, e))?;
        let checkpoint: Checkpoint =
            serde_json::from_str(&text).map_err(|e| RunError::Checkpoint {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
        if checkpoint.format != FORMAT {
            return Err(RunError::Checkpoint {
                path: path.display().to_string(),
                message: format!("format `{}`, expected `{FORMAT}`", checkpoint.format),
            });
        }
        Ok(checkpoint)
    }

    /// Checks that the checkpoint fits a run of `rotors` rotors with this
    /// integrator, thermostat and time step.
    pub fn check(
        &self,
        path: &Path,
        integrator: &str,
        thermostat: Option<&str>,
        rotors: usize,
        dt: f64,
    ) -> Result<(), RunError> {
        let mismatch = |what: &str, here: String, there: String| RunError::Checkpoint {
            path: path.display().to_string(),
            message: format!("{what} is {here} in the scene but {there} in the checkpoint"),
        };
        if self.integrator != integrator {
            return Err(mismatch(
                "the integrator",
                integrator.to_string(),
                self.integrator.clone(),
            ));
        }
        if self.thermostat.as_deref() != thermostat {
            let name = |t: Option<&str>| t.unwrap_or("none").to_string();
            return Err(mismatch(
                "the thermostat",
                name(thermostat),
                name(self.thermostat.as_deref()),
            ));
        }
        if self.rotors != rotors {
            return Err(mismatch(
                "the number of rotors",
                rotors.to_string(),
                self.rotors.to_string(),
            ));
        }
        if self.dt_bits != dt.to_bits() {
            return Err(mismatch(
                "dt",
                dt.to_string(),
                f64::from_bits(self.dt_bits).to_string(),
            ));
        }
        Ok(())
    }

    /// The reference energy of the run.
    pub fn reference(&self) -> Option<EnergyReference> {
        self.reference_bits.map(|[total, scale]| EnergyReference {
            total: f64::from_bits(total),
            scale: f64::from_bits(scale),
        })
    }

    /// The integrator state.
    pub fn state(&self) -> Vec<f64> {
        self.state_bits.iter().map(|&b| f64::from_bits(b)).collect()
    }
}

/// Writes checkpoints of one run to one file, replacing it atomically.
#[derive(Clone, Debug)]
pub struct CheckpointWriter {
    /// The checkpoint file.
    pub path: PathBuf,
    /// The scene's name.
    pub scene: String,
    /// The integrator's name.
    pub integrator: String,
    /// The thermostat's kind, if any.
    pub thermostat: Option<String>,
    /// The number of rotors.
    pub rotors: usize,
    /// The time step.
    pub dt: f64,
}

impl CheckpointSink for CheckpointWriter {
    type Error = RunError;

    /// Writes the state at `step` (to a temporary file, then renamed).
    fn write(
        &mut self,
        step: u64,
        state: &[f64],
        reference: Option<EnergyReference>,
    ) -> Result<(), RunError> {
        let checkpoint = Checkpoint {
            format: FORMAT.to_string(),
            scene: self.scene.clone(),
            integrator: self.integrator.clone(),
            thermostat: self.thermostat.clone(),
            rotors: self.rotors,
            dt_bits: self.dt.to_bits(),
            step,
            reference_bits: reference.map(|r| [r.total.to_bits(), r.scale.to_bits()]),
            state_bits: state.iter().map(|x| x.to_bits()).collect(),
        };
        let text = serde_json::to_string(&checkpoint).map_err(|e| RunError::io(&self.path, e))?;
        let partial = self.path.with_extension("json.partial");
        std::fs::write(&partial, text).map_err(|e| RunError::io(&partial, e))?;
        std::fs::rename(&partial, &self.path).map_err(|e| RunError::io(&self.path, e))
    }
}
