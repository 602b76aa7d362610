//! The energy a run measures its error from, and the energies it computed.

use crate::stats::{energy_drift, EnergyDrift};
use serde::{Deserialize, Serialize};

/// The energy the error is measured from: `error = (E - total) / scale`,
/// `E` the conserved energy (the total energy without a thermostat).
/// `scale` is the initial kinetic energy, or `|E_0|` when the rotors start at
/// rest, or 1 when both vanish.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnergyReference {
    /// `E_0`.
    pub total: f64,
    /// The scale of the relative error.
    pub scale: f64,
}

impl EnergyReference {
    /// The reference of a run starting with these energies.
    pub fn initial(kinetic: f64, total: f64) -> Self {
        let scale = if kinetic > 0.0 {
            kinetic
        } else if total != 0.0 {
            total.abs()
        } else {
            1.0
        };
        EnergyReference { total, scale }
    }

    /// The relative energy error of `total`.
    pub fn error(&self, total: f64) -> f64 {
        (total - self.total) / self.scale
    }
}

/// The energies at every step where a run computed them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EnergyHistory {
    /// The times.
    pub times: Vec<f64>,
    /// The kinetic energies.
    pub kinetic: Vec<f64>,
    /// The conserved energies (the total energies without a thermostat).
    pub total: Vec<f64>,
}

impl EnergyHistory {
    /// Appends the energies at `time`.
    pub fn push(&mut self, time: f64, kinetic: f64, total: f64) {
        self.times.push(time);
        self.kinetic.push(kinetic);
        self.total.push(total);
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// True when no energy was computed.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The drift and fluctuation of the conserved energy relative to the mean
    /// kinetic energy, or to `fallback_scale` when that vanishes
    /// ([`energy_drift`]).
    pub fn drift(&self, fallback_scale: f64) -> EnergyDrift {
        energy_drift(&self.times, &self.total, &self.kinetic, fallback_scale)
    }
}
