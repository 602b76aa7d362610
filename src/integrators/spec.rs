//! The choice of an integrator and its options as a value, and the one
//! dispatch from that choice to a running integrator. The list of
//! integrators is written once, in the `integrator_spec!` invocation below:
//! it makes the enum, its names, its dispatch and the reading of its options.

use super::{
    DlmOptions, GearAOptions, GearBOptions, Integrator, NoSquishOptions, RichardsonOptions,
};
use serde::{Deserialize, Deserializer, Serialize};

/// The options of one integrator: its stable name and how to build it.
pub trait IntegratorOptions {
    /// The name used in scene files (`kind`) and checkpoints, e.g. `"gear_a"`.
    const NAME: &'static str;

    /// A new integrator with these options, without a thermostat (constant
    /// energy), set up before stepping.
    fn build(&self) -> Box<dyn Integrator>;
}

/// Defines [`IntegratorSpec`] from its variants, each a newtype around an
/// [`IntegratorOptions`] type.
macro_rules! integrator_spec {
    ($($(#[$doc:meta])* $variant:ident($options:ty)),+ $(,)?) => {
        /// An integrator and its options: the scene's `[integrator]` table,
        /// whose `kind` is the variant's [`IntegratorOptions::NAME`] (also
        /// when written: the variant's name in snake case, tested).
        #[derive(Clone, Copy, Debug, PartialEq, Serialize)]
        #[serde(tag = "kind", rename_all = "snake_case")]
        pub enum IntegratorSpec {
            $($(#[$doc])* $variant($options)),+
        }

        impl IntegratorSpec {
            /// The name of every integrator, in the order of the variants.
            pub const KINDS: &'static [&'static str] = &[$(<$options>::NAME),+];

            /// The name used in scene files and checkpoints.
            pub fn name(&self) -> &'static str {
                match self {
                    $(IntegratorSpec::$variant(_) => <$options>::NAME),+
                }
            }

            /// A new integrator of this kind and options without a
            /// thermostat (constant energy), set up before stepping: the one
            /// dispatch from a choice to an integrator
            /// ([`crate::dynamics::build`] adds a thermostat).
            pub fn build(&self) -> Box<dyn Integrator> {
                match self {
                    $(IntegratorSpec::$variant(o) => o.build()),+
                }
            }

            /// Reads the options of the integrator called `kind` (one of
            /// [`IntegratorSpec::KINDS`]) from `deserializer`.
            pub fn deserialize_kind<'de, D: Deserializer<'de>>(
                kind: &str,
                deserializer: D,
            ) -> Result<Self, D::Error> {
                $(if kind == <$options>::NAME {
                    return <$options>::deserialize(deserializer).map(IntegratorSpec::$variant);
                })+
                Err(serde::de::Error::unknown_variant(kind, Self::KINDS))
            }
        }
    };
}

integrator_spec! {
    /// Scheme A (coupled first-order Gear pair).
    GearA(GearAOptions),
    /// Scheme B (second-order Gear on `Q`) and its corrections.
    GearB(GearBOptions),
    /// NO_SQUISH.
    NoSquish(NoSquishOptions),
    /// The Dullweber-Leimkuhler-McLachlan splitting.
    Dlm(DlmOptions),
    /// The Richardson-iterated quaternion update of LAMMPS.
    Richardson(RichardsonOptions),
}

impl IntegratorSpec {
    /// True for the integrators that store the quaternion force `N` (and
    /// report `Q.N` through [`Integrator::norm_force`]).
    pub fn stores_quaternion_force(&self) -> bool {
        matches!(self, IntegratorSpec::GearB(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variant builds the integrator its name says, and the names are
    /// listed in the order of the variants.
    #[test]
    fn built_integrators_carry_the_spec_name() {
        let specs = [
            IntegratorSpec::GearA(GearAOptions::default()),
            IntegratorSpec::GearB(GearBOptions::default()),
            IntegratorSpec::NoSquish(NoSquishOptions::default()),
            IntegratorSpec::Dlm(DlmOptions::default()),
            IntegratorSpec::Richardson(RichardsonOptions::default()),
        ];
        for (spec, kind) in specs.iter().zip(IntegratorSpec::KINDS) {
            let built = spec.build();
            assert_eq!(built.name(), spec.name());
            assert_eq!(spec.name(), *kind);
            let written = serde_json::to_value(spec).expect("serialisable");
            assert_eq!(written["kind"], *kind);
        }
    }
}
