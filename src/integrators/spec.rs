//! The choice of an integrator and its options as a value, and the one
//! dispatch from that choice to a running integrator.

use super::{
    DlmOptions, GearAOptions, GearBOptions, Integrator, NoSquishOptions, RichardsonOptions,
};

/// The options of one integrator: its stable name and how to build it.
pub trait IntegratorOptions {
    /// The name used in scene files and checkpoints, e.g. `"gear_a"`.
    const NAME: &'static str;

    /// A new integrator with these options (set up before stepping).
    fn build(&self) -> Box<dyn Integrator>;
}

/// An integrator and its options: the scene's `[integrator]` table, whose
/// `kind` is the variant's [`IntegratorOptions::NAME`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IntegratorSpec {
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
    /// The name used in scene files and checkpoints.
    pub fn name(&self) -> &'static str {
        match self {
            IntegratorSpec::GearA(_) => GearAOptions::NAME,
            IntegratorSpec::GearB(_) => GearBOptions::NAME,
            IntegratorSpec::NoSquish(_) => NoSquishOptions::NAME,
            IntegratorSpec::Dlm(_) => DlmOptions::NAME,
            IntegratorSpec::Richardson(_) => RichardsonOptions::NAME,
        }
    }

    /// True for the integrators that store the quaternion force `N` (and
    /// report `Q.N` through [`Integrator::norm_force`]).
    pub fn stores_quaternion_force(&self) -> bool {
        matches!(self, IntegratorSpec::GearB(_))
    }

    /// A new integrator of this kind and options (set up before stepping).
    pub fn build(&self) -> Box<dyn Integrator> {
        match self {
            IntegratorSpec::GearA(o) => o.build(),
            IntegratorSpec::GearB(o) => o.build(),
            IntegratorSpec::NoSquish(o) => o.build(),
            IntegratorSpec::Dlm(o) => o.build(),
            IntegratorSpec::Richardson(o) => o.build(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variant builds the integrator its name says.
    #[test]
    fn built_integrators_carry_the_spec_name() {
        for spec in [
            IntegratorSpec::GearA(GearAOptions::default()),
            IntegratorSpec::GearB(GearBOptions::default()),
            IntegratorSpec::NoSquish(NoSquishOptions::default()),
            IntegratorSpec::Dlm(DlmOptions::default()),
            IntegratorSpec::Richardson(RichardsonOptions::default()),
        ] {
            assert_eq!(spec.build().name(), spec.name());
        }
    }
}
