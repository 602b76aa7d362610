//! The integrators of body systems, each moving the centres and the
//! orientations with one force-and-torque evaluation per step, and the one
//! choice among them ([`BodyIntegrator`]) a scene's `[integrator]` makes.
//!
//! * [`kicked`]: velocity Verlet for the centres around a rotor
//!   [`crate::integrators::Splitting`]'s kick and rotation, per body:
//!   [`no_squish`] (NO_SQUISH), [`dlm`] (DLM), [`richardson`] (Richardson).
//! * The note's Gear schemes with Gear correctors of the same order for the
//!   centres: [`gear_a`] (scheme A), [`gear_b`] (scheme B), started by
//!   `gear_start`.
//!
//! Thermostats: every integrator carries those its rotor counterpart
//! carries ([`crate::dynamics::check`]: NO_SQUISH and DLM every one,
//! scheme A Nose-Hoover chains (`gear_chains`), scheme B and Richardson
//! none), on the centres and the rotations.

pub mod dlm;
pub mod gear_a;
pub mod gear_b;
mod gear_chains;
mod gear_start;
pub mod kicked;
pub mod no_squish;
pub mod richardson;

pub use dlm::BodyDlm;
pub use gear_a::BodyGearA;
pub use gear_b::BodyGearB;
pub use kicked::BodyKicked;
pub use no_squish::BodyNoSquish;
pub use richardson::BodyRichardson;

use crate::bodies::evaluate::{Evaluation, Scope};
use crate::bodies::system::BodySystem;
use crate::checks::InputError;
use crate::integrators::{IntegratorError, IntegratorSpec};
use crate::thermostats::ThermostatSpec;

/// The integrator of a body system: one variant per algorithm.
#[derive(Clone, Debug)]
pub enum BodyIntegrator {
    /// Velocity Verlet + NO_SQUISH.
    NoSquish(BodyNoSquish),
    /// Velocity Verlet + DLM.
    Dlm(BodyDlm),
    /// Velocity Verlet + Richardson.
    Richardson(BodyRichardson),
    /// Scheme A for centres and rotations.
    GearA(BodyGearA),
    /// Scheme B for centres and rotations.
    GearB(BodyGearB),
}

impl BodyIntegrator {
    /// Refuses the options of `spec` that bodies cannot use (scheme B's
    /// `project_torque = false`; a linear body, which the Gear schemes
    /// refuse, is found when they are set up).
    pub fn check(spec: &IntegratorSpec) -> Result<(), InputError> {
        match spec {
            IntegratorSpec::GearB(options) => BodyGearB::check(options),
            _ => Ok(()),
        }
    }

    /// Refuses the pairs of integrator and thermostat the rotors refuse,
    /// for their reason; the path is relative to the thermostat's table, as
    /// [`crate::dynamics::check`]'s.
    pub fn check_thermostat(
        spec: &IntegratorSpec,
        thermostat: &ThermostatSpec,
    ) -> Result<(), InputError> {
        match crate::dynamics::refusal(spec, thermostat) {
            None => Ok(()),
            Some(reason) => Err(InputError::new(
                "kind",
                format!(
                    "\"{}\" cannot run with integrator {} for bodies ({reason}); use {}",
                    thermostat.name(),
                    spec.name(),
                    crate::dynamics::usable(thermostat)
                ),
            )),
        }
    }

    /// The integrator `spec` names with `thermostat` (none: constant
    /// energy; a pair checked by [`crate::dynamics::check`] and
    /// [`BodyIntegrator::check_thermostat`]), set up on `system` with time
    /// step `dt`; `system` learns whether the dynamics keeps the total
    /// momentum ([`BodySystem::keeps_momentum`]).
    pub fn new(
        spec: &IntegratorSpec,
        thermostat: Option<&ThermostatSpec>,
        system: &mut BodySystem,
        dt: f64,
    ) -> Result<Self, InputError> {
        if let Some(t) = thermostat {
            Self::check_thermostat(spec, t).map_err(|e| e.at("thermostat"))?;
        }
        system.keeps_momentum = thermostat.is_none_or(ThermostatSpec::keeps_momentum);
        let t = thermostat;
        Ok(match *spec {
            IntegratorSpec::NoSquish(o) => {
                Self::NoSquish(BodyNoSquish::with_thermostat(system, dt, o, t)?)
            }
            IntegratorSpec::Dlm(o) => Self::Dlm(BodyDlm::with_thermostat(system, dt, o, t)?),
            IntegratorSpec::Richardson(o) => {
                Self::Richardson(BodyRichardson::with_thermostat(system, dt, o, t)?)
            }
            IntegratorSpec::GearA(o) => {
                let nose_hoover = match t {
                    Some(ThermostatSpec::NoseHoover(chain)) => Some(chain),
                    _ => None,
                };
                Self::GearA(BodyGearA::with_nose_hoover(system, dt, o, nose_hoover)?)
            }
            IntegratorSpec::GearB(o) => Self::GearB(BodyGearB::new(system, dt, o)?),
        })
    }

    /// One step.
    pub fn step(&mut self, system: &mut BodySystem) {
        self.step_read(system, true);
    }

    /// One step, `read` saying whether [`Self::evaluated`] will be asked
    /// for the state it ends on: the kick-based integrators then evaluate
    /// in full, else for the forces only ([`Scope::Forces`]); the Gear
    /// schemes always for the forces only, since they evaluate at the
    /// predicted configuration and [`Self::evaluated`] evaluates afresh.
    pub fn step_read(&mut self, system: &mut BodySystem, read: bool) {
        let scope = if read { Scope::Full } else { Scope::Forces };
        match self {
            Self::NoSquish(i) => i.step_in(system, scope),
            Self::Dlm(i) => i.step_in(system, scope),
            Self::Richardson(i) => i.step_in(system, scope),
            Self::GearA(i) => i.step_in(system, Scope::Forces),
            Self::GearB(i) => i.step_in(system, Scope::Forces),
        }
    }

    /// The thermostat's share of the conserved energy (0 without one).
    pub fn thermostat_energy(&self) -> f64 {
        match self {
            Self::NoSquish(i) => i.thermostat_energy(),
            Self::Dlm(i) => i.thermostat_energy(),
            Self::Richardson(i) => i.thermostat_energy(),
            Self::GearA(i) => i.thermostat_energy(),
            Self::GearB(_) => 0.0,
        }
    }

    /// The state of `system` and of the integrator for a checkpoint, laid
    /// out as `[system][integrator]`: the bodies and the neighbour list
    /// (`BodySystem::write_checkpoint`), then the integrator's own (the
    /// splittings' momenta, the Gear schemes' scaled derivatives). A
    /// thermostat of bodies appends its state after the integrator's (as
    /// the rotors' integrators do, `ThermostatState::write_checkpoint`).
    pub fn checkpoint(&self, system: &BodySystem) -> Vec<f64> {
        let mut out = Vec::new();
        system.write_checkpoint(&mut out);
        match self {
            Self::NoSquish(i) => i.write_checkpoint(&mut out),
            Self::Dlm(i) => i.write_checkpoint(&mut out),
            Self::Richardson(i) => i.write_checkpoint(&mut out),
            Self::GearA(i) => i.write_checkpoint(&mut out),
            Self::GearB(i) => i.write_checkpoint(&mut out),
        }
        out
    }

    /// Restores `system` and the integrator (set up on a system of the
    /// same bodies, types and options) from [`BodyIntegrator::checkpoint`]'s
    /// output, refusing one of another length. The run then goes on bit
    /// for bit as the one that wrote it.
    pub fn restore(
        &mut self,
        system: &mut BodySystem,
        state: &[f64],
    ) -> Result<(), IntegratorError> {
        let rest = system.read_checkpoint(state)?;
        let rest = match self {
            Self::NoSquish(i) => i.read_checkpoint(system, rest),
            Self::Dlm(i) => i.read_checkpoint(system, rest),
            Self::Richardson(i) => i.read_checkpoint(system, rest),
            Self::GearA(i) => i.read_checkpoint(rest),
            Self::GearB(i) => i.read_checkpoint(rest),
        }?;
        if rest.is_empty() {
            Ok(())
        } else {
            Err(IntegratorError::BadCheckpoint(format!(
                "{} values left over after the state of the bodies and the integrator",
                rest.len()
            )))
        }
    }

    /// The evaluation at the current state of `system`: the splittings'
    /// own (their step ends on it); the Gear schemes evaluate only at the
    /// predicted configuration, so the state is evaluated into `scratch`
    /// (an evaluation a run pays only at the steps it records).
    pub fn evaluated<'a>(
        &'a self,
        system: &mut BodySystem,
        scratch: &'a mut Evaluation,
    ) -> &'a Evaluation {
        match self {
            Self::NoSquish(i) => i.evaluation(),
            Self::Dlm(i) => i.evaluation(),
            Self::Richardson(i) => i.evaluation(),
            Self::GearA(_) | Self::GearB(_) => {
                system.evaluate(scratch);
                scratch
            }
        }
    }
}
