//! The choice of a thermostat and its options as a value (the scene's
//! `[thermostat]` table).

use super::{BussiOptions, LangevinOptions, NoseHooverOptions};
use crate::checks::InputError;
use serde::{Deserialize, Deserializer, Serialize};

/// A thermostat and its options: the scene's `[thermostat]` table, whose
/// `kind` is the variant's name in snake case.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ThermostatSpec {
    /// Langevin dynamics per principal axis ([`super::Langevin`]).
    Langevin(LangevinOptions),
    /// Stochastic velocity rescaling ([`super::Bussi`]).
    Bussi(BussiOptions),
    /// Nose-Hoover chains ([`super::NoseHoover`]; scheme A integrates them too).
    NoseHoover(NoseHooverOptions),
}

impl ThermostatSpec {
    /// The name of every thermostat, in the order of the variants.
    pub const KINDS: &'static [&'static str] = &["langevin", "bussi", "nose_hoover"];

    /// The name used in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            ThermostatSpec::Langevin(_) => Self::KINDS[0],
            ThermostatSpec::Bussi(_) => Self::KINDS[1],
            ThermostatSpec::NoseHoover(_) => Self::KINDS[2],
        }
    }

    /// Checks the options (paths relative to the table: `temperature`, ...).
    pub fn check(&self) -> Result<(), InputError> {
        match self {
            ThermostatSpec::Langevin(o) => o.check(),
            ThermostatSpec::Bussi(o) => o.check(),
            ThermostatSpec::NoseHoover(o) => o.check(),
        }
    }

    /// True for the thermostats that draw random numbers (and need a seed).
    pub fn is_stochastic(&self) -> bool {
        !matches!(self, ThermostatSpec::NoseHoover(_))
    }

    /// Whether it keeps the total momentum of bodies that move (Bussi and
    /// Nose-Hoover scale the velocities about the centre of mass; Langevin
    /// kicks every centre on its own), so that `T_trans` counts `3N - 3`
    /// degrees of freedom rather than `3N`.
    pub fn keeps_momentum(&self) -> bool {
        !matches!(self, ThermostatSpec::Langevin(_))
    }

    /// The seed of a stochastic thermostat, if set.
    pub fn seed(&self) -> Option<u64> {
        match self {
            ThermostatSpec::Langevin(o) => o.seed,
            ThermostatSpec::Bussi(o) => o.seed,
            ThermostatSpec::NoseHoover(_) => None,
        }
    }

    /// The same thermostat with its seed set to `seed` if it draws random
    /// numbers and has none.
    pub fn seeded(self, seed: u64) -> Self {
        match self {
            ThermostatSpec::Langevin(o) => ThermostatSpec::Langevin(LangevinOptions {
                seed: o.seed.or(Some(seed)),
                ..o
            }),
            ThermostatSpec::Bussi(o) => ThermostatSpec::Bussi(BussiOptions {
                seed: o.seed.or(Some(seed)),
                ..o
            }),
            nose_hoover => nose_hoover,
        }
    }

    /// Reads the options of the thermostat called `kind` (one of
    /// [`ThermostatSpec::KINDS`]) from `deserializer`.
    pub fn deserialize_kind<'de, D: Deserializer<'de>>(
        kind: &str,
        deserializer: D,
    ) -> Result<Self, D::Error> {
        match kind {
            "langevin" => LangevinOptions::deserialize(deserializer).map(ThermostatSpec::Langevin),
            "bussi" => BussiOptions::deserialize(deserializer).map(ThermostatSpec::Bussi),
            "nose_hoover" => {
                NoseHooverOptions::deserialize(deserializer).map(ThermostatSpec::NoseHoover)
            }
            _ => Err(serde::de::Error::unknown_variant(kind, Self::KINDS)),
        }
    }
}
