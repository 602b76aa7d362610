//! The `[thermostat]` section (absent: constant energy): read straight into
//! the physics [`ThermostatSpec`], whose option structs carry every option,
//! its default, its check and its documentation. The scene adds what only it
//! knows: the seed of a stochastic thermostat when the table gives none (the
//! seed of a random `[initial]` section, or 63 bits drawn from the
//! operating system; recorded in the run summary), and the integrator, which may refuse
//! the thermostat (`thermostat.kind`).

use super::error::SceneError;
use super::tagged::{read_variant, take_kind, unknown_kind, TaggedError};
use crate::integrators::IntegratorSpec;
use crate::thermostats::ThermostatSpec;
use crate::units::{Dimension, Units};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// `kind = "..."` and the options of that thermostat, checked, with errors
/// naming the option's path inside the table.
fn read_spec(mut table: toml::Table) -> Result<ThermostatSpec, TaggedError> {
    let kind = take_kind(&mut table)?;
    if !ThermostatSpec::KINDS.contains(&kind.as_str()) {
        return Err(unknown_kind(&kind, ThermostatSpec::KINDS));
    }
    let spec = read_variant(table, |options| {
        ThermostatSpec::deserialize_kind(&kind, options)
    })?;
    spec.check()
        .map_err(|e| TaggedError::at(&e.path, e.message))?;
    Ok(spec)
}

/// `read_spec` inside serde (the path travels beside the error).
impl<'de> Deserialize<'de> for ThermostatSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        read_spec(toml::Table::deserialize(deserializer)?).map_err(TaggedError::into_serde)
    }
}

/// The `[thermostat]` table: the [`ThermostatSpec`] it describes, and the
/// table as written (what the run summary records as the scene's
/// definition, keeping out the options it leaves out).
#[derive(Debug, Clone)]
pub struct RawThermostat {
    /// The thermostat and its options, as written (seed not yet resolved).
    pub spec: ThermostatSpec,
    written: toml::Table,
}

impl<'de> Deserialize<'de> for RawThermostat {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let table = toml::Table::deserialize(deserializer)?;
        let spec = read_spec(table.clone()).map_err(TaggedError::into_serde)?;
        Ok(RawThermostat {
            spec,
            written: table,
        })
    }
}

impl Serialize for RawThermostat {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.written.serialize(serializer)
    }
}

/// Validates the section for a run with `integrator` whose random initial
/// state (if any) was drawn with `initial_seed`: the thermostat with its
/// seed resolved.
pub(super) fn thermostat(
    raw: Option<&RawThermostat>,
    integrator: &IntegratorSpec,
    initial_seed: Option<u64>,
) -> Result<Option<ThermostatSpec>, SceneError> {
    let Some(raw) = raw else {
        return Ok(None);
    };
    let spec = match (raw.spec.is_stochastic(), raw.spec.seed()) {
        // A drawn seed has 63 bits, so that it can be written back into a
        // scene (TOML integers are signed 64-bit).
        (true, None) => raw
            .spec
            .seeded(initial_seed.unwrap_or_else(|| rand::random::<u64>() >> 1)),
        _ => raw.spec,
    };
    crate::dynamics::check(integrator, &spec).map_err(|e| SceneError::from(e.at("thermostat")))?;
    Ok(Some(spec))
}

/// `spec` with its temperature, time constant or friction taken from the
/// scene's `units` into the engine's (the identity in reduced units).
pub(super) fn in_engine_units(spec: ThermostatSpec, units: Units) -> ThermostatSpec {
    let temperature = |t: f64| units.to_internal(t, Dimension::Temperature);
    let time = |t: f64| units.to_internal(t, Dimension::Time);
    match spec {
        ThermostatSpec::Langevin(mut o) => {
            o.temperature = temperature(o.temperature);
            o.friction = units.to_internal(o.friction, Dimension::PerTime);
            ThermostatSpec::Langevin(o)
        }
        ThermostatSpec::Bussi(mut o) => {
            o.temperature = temperature(o.temperature);
            o.tau = time(o.tau);
            ThermostatSpec::Bussi(o)
        }
        ThermostatSpec::NoseHoover(mut o) => {
            o.temperature = temperature(o.temperature);
            o.tau = time(o.tau);
            ThermostatSpec::NoseHoover(o)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{DlmOptions, GearBOptions};
    use crate::thermostats::{LangevinOptions, NoseHooverOptions};

    fn read(text: &str) -> Result<ThermostatSpec, String> {
        crate::scene::parse::parse_value::<RawThermostat>(toml::from_str(text).expect("valid"))
            .map(|r| r.spec)
            .map_err(|e| e.to_string())
    }

    /// In real units a thermostat's temperature (K), time constant (fs) and
    /// friction (1/fs) reach the engine as `k_B T` in kcal/mol and in its
    /// time unit, against LAMMPS `units real`'s constants (`boltz =
    /// 0.0019872067`, 1.2e-6 from the exact value: ERRATA's traps table;
    /// time unit 48.88821 fs); reduced units are left alone.
    #[test]
    fn real_units_convert_the_thermostat_options() {
        let langevin = read("kind = 'langevin'\ntemperature = 300.0\nfriction = 0.01").unwrap();
        let ThermostatSpec::Langevin(o) = in_engine_units(langevin, Units::Real) else {
            panic!("langevin");
        };
        assert!((o.temperature / (300.0 * 0.0019872067) - 1.0).abs() < 2e-6);
        assert!((o.friction / (0.01 * 48.88821) - 1.0).abs() < 1e-6);
        let nose_hoover = read("kind = 'nose_hoover'\ntemperature = 298.0\ntau = 100.0").unwrap();
        let ThermostatSpec::NoseHoover(o) = in_engine_units(nose_hoover, Units::Real) else {
            panic!("nose_hoover");
        };
        assert!((o.tau / (100.0 / 48.88821) - 1.0).abs() < 1e-6);
        assert!((o.temperature / (298.0 * 0.0019872067) - 1.0).abs() < 2e-6);
        assert_eq!(in_engine_units(langevin, Units::Reduced), langevin);
    }

    /// Tables become the physics options; the chain length defaults to 3.
    #[test]
    fn tables_become_the_physics_options() {
        assert_eq!(
            read("kind = 'langevin'\ntemperature = 1.5\nfriction = 2.0\nseed = 4"),
            Ok(ThermostatSpec::Langevin(LangevinOptions {
                temperature: 1.5,
                friction: 2.0,
                seed: Some(4)
            }))
        );
        assert_eq!(
            read("kind = 'nose_hoover'\ntemperature = 1.0\ntau = 0.5"),
            Ok(ThermostatSpec::NoseHoover(NoseHooverOptions {
                temperature: 1.0,
                tau: 0.5,
                chain: NoseHooverOptions::DEFAULT_CHAIN,
            }))
        );
    }

    /// Errors name the option inside the table and the value.
    #[test]
    fn bad_options_name_the_option() {
        assert_eq!(
            read("kind = 'bussi'\ntemperature = 1.0\ntau = 0.0"),
            Err("tau: must be > 0, got 0".to_string())
        );
        assert_eq!(
            read("kind = 'langevin'\ntemperature = -1.0\nfriction = 1.0"),
            Err("temperature: must be >= 0, got -1".to_string())
        );
        assert_eq!(
            read("kind = 'nose_hoover'\ntemperature = 1.0\ntau = 1.0\nchain = 0"),
            Err("chain: must be >= 1, got 0".to_string())
        );
    }

    /// A stochastic thermostat without a seed takes the initial state's;
    /// an integrator that cannot carry the thermostat refuses it.
    #[test]
    fn seed_is_resolved_and_the_integrator_may_refuse() {
        let raw = RawThermostat {
            spec: ThermostatSpec::Langevin(LangevinOptions {
                temperature: 1.0,
                friction: 1.0,
                seed: None,
            }),
            written: toml::Table::new(),
        };
        let dlm = IntegratorSpec::Dlm(DlmOptions::default());
        let spec = thermostat(Some(&raw), &dlm, Some(17)).expect("valid");
        assert_eq!(spec.and_then(|s| s.seed()), Some(17));
        let gear_b = IntegratorSpec::GearB(GearBOptions::default());
        assert_eq!(
            thermostat(Some(&raw), &gear_b, Some(17)).map_err(|e| e.to_string()),
            Err("thermostat.kind: \"langevin\" cannot run with integrator gear_b (scheme B has no angular momenta to thermostat); use no_squish or dlm".to_string())
        );
    }
}
