//! An integrator with its thermostat: the one place where a choice of
//! integrator ([`IntegratorSpec`]) and a choice of thermostat
//! ([`ThermostatSpec`]) meet. [`check`] refuses the pairs that cannot run
//! together (a pure function of the two choices, called once, when a scene
//! is validated); [`build`] makes the running `Box<dyn Integrator>` of a
//! checked pair. The integrators and the thermostats know only
//! [`crate::thermostat_hook`], never each other.
//!
//! The integrators of bodies step whole systems and pay one dispatch per
//! step: they take their thermostat as an [`AnyThermostat`], where the
//! rotors' integrators are monomorphised per thermostat ([`build`]).
//!
//! Pairs: NO_SQUISH and DLM carry every thermostat (around or inside their
//! kick-based step); scheme A carries Nose-Hoover chains (integrated with
//! the rotors by its predictor-corrector); scheme B and Richardson carry
//! none.

use crate::checks::InputError;
use crate::integrators::{GearA, Integrator, IntegratorSpec, Kicked, Splitting};
use crate::thermostat_hook::{CoupledDegrees, Nve, SplitDynamics, Thermostat, ThermostatState};
use crate::thermostats::{Bussi, Langevin, NoseHoover, NoseHooverChain, ThermostatSpec};
use nalgebra::Vector3;

/// Why `integrator` cannot carry `thermostat`, if it cannot.
pub(crate) fn refusal(
    integrator: &IntegratorSpec,
    thermostat: &ThermostatSpec,
) -> Option<&'static str> {
    match (integrator, thermostat) {
        (IntegratorSpec::NoSquish(_) | IntegratorSpec::Dlm(_), _)
        | (IntegratorSpec::GearA(_), ThermostatSpec::NoseHoover(_)) => None,
        (IntegratorSpec::GearA(_), _) => Some("a predictor-corrector needs a smooth trajectory"),
        (IntegratorSpec::GearB(_), _) => Some("scheme B has no angular momenta to thermostat"),
        // Neither time reversible nor symplectic: a thermostat's splitting
        // error would not be controlled.
        (IntegratorSpec::Richardson(_), _) => Some("not time reversible"),
    }
}

/// The integrators that carry `thermostat`, as a refusal names them.
pub(crate) fn usable(thermostat: &ThermostatSpec) -> &'static str {
    match thermostat {
        ThermostatSpec::NoseHoover(_) => "no_squish, dlm or gear_a",
        _ => "no_squish or dlm",
    }
}

/// Checks that `integrator` can carry `thermostat` and that a stochastic
/// thermostat has its seed (a scene sets it first). Paths are relative to
/// the thermostat's table: `kind: "bussi" cannot run with integrator gear_b
/// (reason); use ...`, or `seed`.
pub fn check(integrator: &IntegratorSpec, thermostat: &ThermostatSpec) -> Result<(), InputError> {
    if let Some(reason) = refusal(integrator, thermostat) {
        return Err(InputError::new(
            "kind",
            format!(
                "\"{}\" cannot run with integrator {} ({reason}); use {}",
                thermostat.name(),
                integrator.name(),
                usable(thermostat)
            ),
        ));
    }
    if thermostat.is_stochastic() && thermostat.seed().is_none() {
        return Err(InputError::new(
            "seed",
            "must be set (a scene takes the seed of [initial] or draws one)",
        ));
    }
    Ok(())
}

/// The integrator `integrator` with `thermostat` (none: constant energy),
/// set up before stepping. The pair must have passed [`check`] and the
/// thermostat's options their own check (a validated scene's have; other
/// callers use [`try_build`]).
pub fn build(
    integrator: &IntegratorSpec,
    thermostat: Option<&ThermostatSpec>,
) -> Box<dyn Integrator> {
    match (integrator, thermostat) {
        (IntegratorSpec::NoSquish(o), Some(t)) => kicked(*o, t),
        (IntegratorSpec::Dlm(o), Some(t)) => kicked(*o, t),
        (IntegratorSpec::GearA(o), Some(ThermostatSpec::NoseHoover(chain))) => Box::new(
            GearA::with_chain(*o, Box::new(NoseHooverChain::new(chain, 0))),
        ),
        // No thermostat (the pairs `check` refuses never get here).
        (integrator, _) => integrator.build(),
    }
}

/// [`build`] for a pair not yet checked: the thermostat's options
/// ([`ThermostatSpec::check`]) and the pair ([`check`]) first.
pub fn try_build(
    integrator: &IntegratorSpec,
    thermostat: Option<&ThermostatSpec>,
) -> Result<Box<dyn Integrator>, InputError> {
    if let Some(t) = thermostat {
        t.check()?;
        check(integrator, t)?;
    }
    Ok(build(integrator, thermostat))
}

/// The kick-based baseline `options` with `thermostat`.
fn kicked<S: Splitting>(options: S, thermostat: &ThermostatSpec) -> Box<dyn Integrator> {
    // `check` has made sure a stochastic thermostat has its seed.
    let seed = thermostat.seed().unwrap_or_default();
    match *thermostat {
        ThermostatSpec::Langevin(o) => {
            Box::new(Kicked::with_thermostat(options, Langevin::new(o, seed)))
        }
        ThermostatSpec::Bussi(o) => Box::new(Kicked::with_thermostat(options, Bussi::new(o, seed))),
        ThermostatSpec::NoseHoover(o) => {
            Box::new(Kicked::with_thermostat(options, NoseHoover::new(o)))
        }
    }
}

/// A thermostat chosen at run time (none, or one of
/// [`crate::thermostats`]) as one type.
#[derive(Clone, Debug)]
pub enum AnyThermostat {
    /// None: constant energy.
    Nve(Nve),
    /// [`Langevin`].
    Langevin(Langevin),
    /// [`Bussi`].
    Bussi(Bussi),
    /// [`NoseHoover`].
    NoseHoover(NoseHoover),
}

/// `$body` with `$t` bound to the thermostat inside `$value`, whichever it is.
macro_rules! each_thermostat {
    ($value:expr, $t:ident => $body:expr) => {
        match $value {
            AnyThermostat::Nve($t) => $body,
            AnyThermostat::Langevin($t) => $body,
            AnyThermostat::Bussi($t) => $body,
            AnyThermostat::NoseHoover($t) => $body,
        }
    };
}

impl AnyThermostat {
    /// `thermostat` (none: [`Nve`]), whose pairing has passed [`check`] (a
    /// stochastic thermostat has its seed).
    pub fn new(thermostat: Option<&ThermostatSpec>) -> Self {
        let seed = thermostat
            .and_then(ThermostatSpec::seed)
            .unwrap_or_default();
        match thermostat {
            None => AnyThermostat::Nve(Nve),
            Some(ThermostatSpec::Langevin(o)) => AnyThermostat::Langevin(Langevin::new(*o, seed)),
            Some(ThermostatSpec::Bussi(o)) => AnyThermostat::Bussi(Bussi::new(*o, seed)),
            Some(ThermostatSpec::NoseHoover(o)) => AnyThermostat::NoseHoover(NoseHoover::new(*o)),
        }
    }
}

impl Thermostat for AnyThermostat {
    type State = dyn ThermostatState;

    fn setup(&mut self, moments: &[Vector3<f64>], degrees: &CoupledDegrees, dt: f64) {
        each_thermostat!(self, t => t.setup(moments, degrees, dt));
    }

    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D) {
        each_thermostat!(self, t => t.step(dynamics));
    }

    fn state(&self) -> &(dyn ThermostatState + 'static) {
        each_thermostat!(self, t => {
            let state: &dyn ThermostatState = t.state();
            state
        })
    }

    fn state_mut(&mut self) -> &mut (dyn ThermostatState + 'static) {
        each_thermostat!(self, t => {
            let state: &mut dyn ThermostatState = t.state_mut();
            state
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{
        DlmOptions, GearAOptions, GearBOptions, NoSquishOptions, RichardsonOptions,
    };
    use crate::thermostats::{BussiOptions, LangevinOptions, NoseHooverOptions};

    /// NO_SQUISH and DLM carry all three thermostats, scheme A only the
    /// Nose-Hoover chain, scheme B and Richardson none (the pairs the
    /// thermostats' docs state); an accepted pair builds the integrator
    /// its name says.
    #[test]
    fn pairs_are_accepted_as_documented() {
        let integrators = [
            IntegratorSpec::GearA(GearAOptions::default()),
            IntegratorSpec::GearB(GearBOptions::default()),
            IntegratorSpec::NoSquish(NoSquishOptions::default()),
            IntegratorSpec::Dlm(DlmOptions::default()),
            IntegratorSpec::Richardson(RichardsonOptions::default()),
        ];
        let thermostats = [
            ThermostatSpec::Langevin(LangevinOptions {
                temperature: 1.0,
                friction: 1.0,
                seed: Some(1),
            }),
            ThermostatSpec::Bussi(BussiOptions {
                temperature: 1.0,
                tau: 1.0,
                seed: Some(1),
            }),
            ThermostatSpec::NoseHoover(NoseHooverOptions {
                temperature: 1.0,
                tau: 1.0,
                chain: NoseHooverOptions::DEFAULT_CHAIN,
            }),
        ];
        let accepted = |i: &str, t: &str| {
            matches!(i, "no_squish" | "dlm") || (i, t) == ("gear_a", "nose_hoover")
        };
        for i in &integrators {
            for t in &thermostats {
                let result = try_build(i, Some(t));
                assert_eq!(result.is_ok(), accepted(i.name(), t.name()), "{i:?} {t:?}");
                match result {
                    Ok(built) => assert_eq!(built.name(), i.name()),
                    Err(e) => assert_eq!(e.path, "kind"),
                }
            }
        }
    }

    /// A stochastic thermostat without a seed is refused naming `seed`.
    #[test]
    fn an_unseeded_stochastic_thermostat_is_refused() {
        let unseeded = ThermostatSpec::Bussi(BussiOptions {
            temperature: 1.0,
            tau: 1.0,
            seed: None,
        });
        let dlm = IntegratorSpec::Dlm(DlmOptions::default());
        let error = check(&dlm, &unseeded).expect_err("no seed");
        assert_eq!(error.path, "seed");
        assert!(check(&dlm, &unseeded.seeded(3)).is_ok());
    }
}
