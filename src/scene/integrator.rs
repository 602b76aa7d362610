//! The `[integrator]` section: read straight into the physics
//! [`IntegratorSpec`], whose option structs carry every option, its default,
//! its check and its documentation, and whose list of integrators (and their
//! `kind`s) is the physics' own: nothing here names an integrator.

use super::tagged::{read_variant, take_kind, unknown_kind, TaggedError};
use crate::integrators::IntegratorSpec;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// `kind = "..."` and the options of that integrator, with errors naming the
/// option's path inside the table.
fn read_spec(mut table: toml::Table) -> Result<IntegratorSpec, TaggedError> {
    let kind = take_kind(&mut table)?;
    if !IntegratorSpec::KINDS.contains(&kind.as_str()) {
        return Err(unknown_kind(&kind, IntegratorSpec::KINDS));
    }
    read_variant(table, |options| {
        IntegratorSpec::deserialize_kind(&kind, options)
    })
}

/// `read_spec` inside serde (the path travels beside the error).
impl<'de> Deserialize<'de> for IntegratorSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        read_spec(toml::Table::deserialize(deserializer)?).map_err(TaggedError::into_serde)
    }
}

/// The `[integrator]` table: the [`IntegratorSpec`] it describes, and the
/// table as written (what the run summary records as the scene's definition,
/// keeping out the options it leaves out).
#[derive(Debug, Clone)]
pub struct RawIntegrator {
    /// The integrator and its options.
    pub spec: IntegratorSpec,
    written: toml::Table,
}

impl RawIntegrator {
    /// The table of an integrator with its default options (`kind = name`);
    /// the error's path is below the table.
    pub(super) fn named(name: &str) -> Result<Self, TaggedError> {
        let mut table = toml::Table::new();
        let _ = table.insert("kind".into(), toml::Value::String(name.into()));
        Self::from_table(table)
    }

    fn from_table(table: toml::Table) -> Result<Self, TaggedError> {
        let spec = read_spec(table.clone())?;
        Ok(RawIntegrator {
            spec,
            written: table,
        })
    }
}

impl<'de> Deserialize<'de> for RawIntegrator {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let table = toml::Table::deserialize(deserializer)?;
        RawIntegrator::from_table(table).map_err(TaggedError::into_serde)
    }
}

impl Serialize for RawIntegrator {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.written.serialize(serializer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{GearAOptions, GearBOptions, NoSquishOptions, SphericalTops, Startup};
    use std::num::NonZeroU32;

    fn read(text: &str) -> Result<IntegratorSpec, String> {
        crate::scene::parse::parse_value::<RawIntegrator>(toml::from_str(text).expect("valid"))
            .map(|r| r.spec)
            .map_err(|e| e.to_string())
    }

    /// Options left out take the physics defaults; given ones are read into
    /// the physics types.
    #[test]
    fn tables_become_the_physics_options() {
        assert_eq!(
            read("kind = 'gear_a'"),
            Ok(IntegratorSpec::GearA(GearAOptions::default()))
        );
        assert_eq!(
            read("kind = 'no_squish'\nsubsteps = 10\nspherical_tops = 'split'"),
            Ok(IntegratorSpec::NoSquish(NoSquishOptions {
                substeps: NonZeroU32::new(10).expect("non-zero"),
                spherical_tops: SphericalTops::Split
            }))
        );
        assert_eq!(
            read("kind = 'gear_b'\nstartup = 'zeros'"),
            Ok(IntegratorSpec::GearB(GearBOptions {
                startup: Startup::Zeros,
                ..GearBOptions::default()
            }))
        );
    }

    /// A spec written out (every option, the enums by their scene names)
    /// reads back as itself.
    #[test]
    fn written_specs_read_back() {
        let spec = IntegratorSpec::GearB(GearBOptions {
            c0: crate::integrators::FirstCorrector::PositionOnly,
            startup: Startup::Zeros,
            ..GearBOptions::default()
        });
        let written = toml::to_string(&spec).expect("serialisable");
        assert!(written.contains("c0 = \"3/20\""), "{written}");
        assert_eq!(read(&written), Ok(spec));
        let spec = IntegratorSpec::NoSquish(NoSquishOptions {
            substeps: NoSquishOptions::SUBSTEPS_DL_POLY,
            spherical_tops: SphericalTops::Split,
        });
        assert_eq!(
            read(&toml::to_string(&spec).expect("serialisable")),
            Ok(spec)
        );
    }

    /// Errors name the option (relative to the table) and the value.
    #[test]
    fn bad_options_name_the_option() {
        assert_eq!(
            read("kind = 'no_squish'\nsubsteps = -2"),
            Err("substeps: must be >= 1, got -2".to_string())
        );
        assert_eq!(
            read("kind = 'dlm'\nspherical_tops = 'exactly'"),
            Err("spherical_tops: must be \"exact\" or \"split\", got \"exactly\"".to_string())
        );
        assert_eq!(
            read("kind = 'richardson'\nsubsteps = 1"),
            Err("substeps: unknown field `substeps`, there are no fields".to_string())
        );
        assert_eq!(
            RawIntegrator::named("gear_a").map(|r| r.spec),
            Ok(IntegratorSpec::GearA(GearAOptions::default()))
        );
    }
}
