//! The choice of a thermostat and its options as a value (the scene's
//! `[thermostat]` table), and the building of a kick-based baseline with it.

use super::{Bussi, BussiOptions, Langevin, LangevinOptions, NoseHoover, NoseHooverOptions};
use crate::checks::InputError;
use crate::integrators::{Integrator, Kicked, Splitting};
use serde::{Deserialize, Deserializer, Serialize};

/// A thermostat and its options: the scene's `[thermostat]` table, whose
/// `kind` is the variant's name in snake case.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ThermostatSpec {
    /// Langevin dynamics per principal axis ([`Langevin`]).
    Langevin(LangevinOptions),
    /// Stochastic velocity rescaling ([`Bussi`]).
    Bussi(BussiOptions),
    /// Nose-Hoover chains ([`NoseHoover`]; scheme A integrates them too).
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

    /// The refusal of an integrator that cannot carry this thermostat:
    /// `kind: "bussi" cannot run with integrator gear_b (reason); use ...`.
    pub fn refused(&self, integrator: &str, reason: &str) -> InputError {
        let usable = match self {
            ThermostatSpec::NoseHoover(_) => "no_squish, dlm or gear_a",
            _ => "no_squish or dlm",
        };
        InputError::new(
            "kind",
            format!(
                "\"{}\" cannot run with integrator {integrator} ({reason}); use {usable}",
                self.name()
            ),
        )
    }
}

/// The kick-based baseline `options` with `thermostat` (or none): the
/// thermostat's checks apply.
pub fn build_kicked<S: Splitting>(
    options: S,
    thermostat: Option<&ThermostatSpec>,
) -> Result<Box<dyn Integrator>, InputError> {
    Ok(match thermostat {
        None => Box::new(Kicked::new(options)),
        Some(ThermostatSpec::Langevin(o)) => {
            Box::new(Kicked::with_thermostat(options, Langevin::new(*o)?))
        }
        Some(ThermostatSpec::Bussi(o)) => {
            Box::new(Kicked::with_thermostat(options, Bussi::new(*o)?))
        }
        Some(ThermostatSpec::NoseHoover(o)) => {
            Box::new(Kicked::with_thermostat(options, NoseHoover::new(*o)?))
        }
    })
}
