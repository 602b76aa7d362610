//! The note's experiment: scheme A against scheme B with each of its
//! corrections, for any system of pinned rotors. Each configuration gives one
//! [`Row`]: energy drift and fluctuation, global error and its observed order,
//! the largest stable time step, and the size of the eq 15 zeroth components.

use crate::checks::{finite_and_positive, InputError};
use crate::integrators::{GearAOptions, GearBOptions, IntegratorSpec, RotorState};
use crate::observables::norm_velocity;
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use crate::simulation::{
    run, BlowUpChecks, EnergyHistory, Needs, Observer, RunOptions, Sample, Scheduled, Stop,
};
use std::convert::Infallible;

/// A system of pinned rotors with its initial state.
pub struct System<'a> {
    /// The interactions.
    pub potential: &'a dyn Potential,
    /// One inertia per rotor.
    pub inertia: &'a [Inertia],
    /// The initial orientations and body angular velocities.
    pub initial: &'a [RotorState],
}

/// Run lengths and steps of the experiment (time in the system's units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The base time step (> 0).
    pub dt: f64,
    /// Length of the energy runs at `dt` (drift, fluctuation, eq 15 components).
    pub t_energy: f64,
    /// Time at which the global error is measured, at `dt` and `dt/4`,
    /// against scheme A at `dt / (4 * REFERENCE_REFINEMENT)`.
    pub t_error: f64,
    /// Length of the stability runs.
    pub t_stability: f64,
    /// Energy samples are taken every this many steps (>= 1).
    pub sample_every: u64,
}

impl Settings {
    /// Checks the time step and the run lengths (each finite and > 0), then
    /// the sampling interval (>= 1); the error names the field.
    pub fn check(&self) -> Result<(), InputError> {
        for (path, value) in [
            ("dt", self.dt),
            ("t_energy", self.t_energy),
            ("t_error", self.t_error),
            ("t_stability", self.t_stability),
        ] {
            let _ = finite_and_positive(path, value)?;
        }
        if self.sample_every == 0 {
            return Err(InputError::new("sample_every", "must be >= 1, got 0"));
        }
        Ok(())
    }
}

/// How much finer than the finest measured step the reference run is (its
/// error is then `16^5 ~ 1e6` times smaller for an order-5 scheme).
pub const REFERENCE_REFINEMENT: usize = 16;

/// A run is stable when it stays finite and its total energy stays within
/// this fraction of the initial kinetic energy of its starting value.
pub const STABILITY_ENERGY_FRACTION: f64 = 0.1;

/// Time steps tried for stability: `dt * 2^(k/4)`, `k = 0..=STABILITY_STEPS`.
pub const STABILITY_STEPS: usize = 16;

/// One configuration of the experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// Scheme A with renormalisation.
    A,
    /// Scheme B with these options.
    B(GearBOptions),
}

impl Variant {
    /// The integrator of this configuration.
    pub fn spec(self) -> IntegratorSpec {
        match self {
            Variant::A => IntegratorSpec::GearA(GearAOptions::default()),
            Variant::B(options) => IntegratorSpec::GearB(options),
        }
    }
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Short description of the configuration.
    pub label: String,
    /// The configuration.
    pub variant: Variant,
    /// Least-squares slope of the total energy against time, divided by the
    /// mean kinetic energy (per unit time).
    pub drift: f64,
    /// RMS deviation of the total energy from that straight line, divided by
    /// the mean kinetic energy.
    pub fluctuation: f64,
    /// Largest orientation error (rad) at `t_error` with step `dt`.
    pub global_error: f64,
    /// Observed order from the global errors at `dt` and `dt/4`,
    /// `ln(e(dt) / e(dt/4)) / ln 4`: the least-squares slope over `dt`,
    /// `dt/2`, `dt/4` is this same number (equally spaced in `ln dt`, the
    /// middle point has no weight in the slope), so no run at `dt/2`.
    pub order: f64,
    /// Largest stable step of the scan, or `None` if even `dt` is unstable.
    pub largest_stable_dt: Option<f64>,
    /// Largest `|Q.Q'|` over the energy run (eq 15a).
    pub max_norm_velocity: f64,
    /// Largest `|Q.N|` over the energy run (eq 15b); `None` for scheme A,
    /// which works with body torques.
    pub max_norm_force: Option<f64>,
}

/// The configurations of the note's comparison, in table order: a label and a
/// scene `[integrator]` table each, read from `gear_corrections.toml` (the one
/// list, which the Python long runs read too).
pub const CONFIGURATIONS_TOML: &str = include_str!("gear_corrections.toml");

/// The file's layout.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ConfigurationTable {
    configuration: Vec<Configuration>,
}

/// One entry of the file.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Configuration {
    label: String,
    integrator: IntegratorSpec,
}

/// The configurations of the note's comparison ([`CONFIGURATIONS_TOML`]).
pub fn variants() -> Vec<(String, Variant)> {
    // The file is part of the source, parsed by a unit test: not user input.
    let table: ConfigurationTable =
        toml::from_str(CONFIGURATIONS_TOML).expect("gear_corrections.toml parses");
    table
        .configuration
        .into_iter()
        .map(|c| {
            let variant = match c.integrator {
                IntegratorSpec::GearA(options) if options == GearAOptions::default() => Variant::A,
                IntegratorSpec::GearB(options) => Variant::B(options),
                other => panic!(
                    "gear_corrections.toml: {}: not scheme A (default options) or B: {other:?}",
                    c.label
                ),
            };
            (c.label, variant)
        })
        .collect()
}

/// The largest `|Q.Q'|` and `|Q.N|` (eqs 15a, 15b) over the samples of a run.
#[derive(Default)]
struct NormDiagnostics {
    max_norm_velocity: f64,
    max_norm_force: Option<f64>,
}

impl Observer for NormDiagnostics {
    type Error = Infallible;

    fn needs(&self) -> Needs {
        Needs {
            energies: true,
            q_dot: true,
            norm_force: true,
            ..Needs::default()
        }
    }

    /// Samples whose energy is not finite (the run stops there) are left out.
    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), Infallible> {
        if sample.energies.is_some_and(|e| !e.total.is_finite()) {
            return Ok(());
        }
        let q_dot = sample.q_dot.unwrap_or_default();
        for (q, d) in sample.orientations.iter().zip(q_dot) {
            self.max_norm_velocity = self.max_norm_velocity.max(norm_velocity(q, d).abs());
        }
        if let Some(norm_force) = sample.norm_force {
            let worst = norm_force.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            self.max_norm_force = Some(self.max_norm_force.unwrap_or(0.0).max(worst));
        }
        Ok(())
    }
}

/// What one run records: energies every `sample_every` steps and at the
/// end, the eq 15 diagnostics, the final orientations, and whether it stayed
/// finite.
struct Trace {
    final_orientations: Vec<Quat>,
    energies: EnergyHistory,
    norms: NormDiagnostics,
    finite: bool,
}

/// Runs `variant` on `system` to `t_end` with steps of `dt` through the run
/// loop, stopping at the first non-finite sample.
fn trace(variant: Variant, system: &System<'_>, dt: f64, t_end: f64, sample_every: u64) -> Trace {
    let mut t = Trace {
        final_orientations: Vec::new(),
        energies: EnergyHistory::default(),
        norms: NormDiagnostics::default(),
        finite: false,
    };
    let mut integrator = variant.spec().build();
    if integrator
        .setup(system.inertia, system.potential, system.initial, dt)
        .is_err()
    {
        return t;
    }
    let options = RunOptions {
        start_step: 0,
        end_step: (t_end / dt).round() as u64,
        // Checked at the samples only.
        checks: Some(BlowUpChecks {
            every: u64::MAX,
            energy_error_threshold: None,
        }),
        reference: None,
        control: None,
    };
    let mut observers = [Scheduled {
        every: sample_every,
        at_end: true,
        observer: &mut t.norms,
    }];
    let Ok(report) = run(
        integrator.as_mut(),
        system.potential,
        system.inertia,
        &mut observers,
        None,
        &options,
    );
    t.final_orientations = integrator.orientations().to_vec();
    t.energies = report.energy_history;
    t.finite = report.stop == Stop::Completed;
    t
}

/// The largest rotation angle between corresponding orientations (radians),
/// `PI` when either is not a finite non-zero quaternion.
fn max_angle(a: &[Quat], b: &[Quat]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| match (p.try_normalize(), q.try_normalize()) {
            (Some(p), Some(q)) => p.angle_to(&q),
            _ => std::f64::consts::PI,
        })
        .fold(0.0, f64::max)
}

fn is_stable(variant: Variant, system: &System<'_>, dt: f64, t_end: f64) -> bool {
    let t = trace(variant, system, dt, t_end, 1);
    let Some((&e0, &k0)) = t.energies.total.first().zip(t.energies.kinetic.first()) else {
        return false;
    };
    t.finite
        && t.energies
            .total
            .iter()
            .all(|e| (e - e0).abs() <= STABILITY_ENERGY_FRACTION * k0)
}

/// The table: one row per configuration of [`variants`].
pub fn correction_table(system: &System<'_>, settings: &Settings) -> Vec<Row> {
    let dts = [settings.dt, settings.dt / 4.0];
    let reference = trace(
        Variant::A,
        system,
        dts[1] / REFERENCE_REFINEMENT as f64,
        settings.t_error,
        u64::MAX,
    )
    .final_orientations;
    variants()
        .into_iter()
        .map(|(label, variant)| {
            let energy = trace(
                variant,
                system,
                settings.dt,
                settings.t_energy,
                settings.sample_every,
            );
            let drift = energy.energies.drift(0.0);
            let errors: Vec<f64> = dts
                .iter()
                .map(|&dt| {
                    let t = trace(variant, system, dt, settings.t_error, u64::MAX);
                    if t.finite {
                        max_angle(&t.final_orientations, &reference)
                    } else {
                        f64::NAN
                    }
                })
                .collect();
            let order = (errors[0] / errors[1]).ln() / (dts[0] / dts[1]).ln();
            let largest_stable_dt = (0..=STABILITY_STEPS)
                .map(|k| settings.dt * 2f64.powf(k as f64 / 4.0))
                .take_while(|&dt| is_stable(variant, system, dt, settings.t_stability))
                .last();
            Row {
                label,
                variant,
                drift: if energy.finite {
                    drift.relative_per_time
                } else {
                    f64::NAN
                },
                fluctuation: if energy.finite {
                    drift.relative_fluctuation
                } else {
                    f64::NAN
                },
                global_error: errors[0],
                order,
                largest_stable_dt,
                max_norm_velocity: energy.norms.max_norm_velocity,
                max_norm_force: energy.norms.max_norm_force,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The time step and each run length must be finite and > 0, the
    /// sampling interval >= 1; the first bad one is named.
    #[test]
    fn settings_refuse_a_time_that_is_not_positive() {
        let good = Settings {
            dt: 0.02,
            t_energy: 1.0,
            t_error: 0.5,
            t_stability: 0.5,
            sample_every: 1,
        };
        assert_eq!(good.check(), Ok(()));
        let bad = Settings { dt: 0.0, ..good };
        assert_eq!(
            bad.check().unwrap_err().to_string(),
            "dt: must be finite and > 0, got 0"
        );
        let bad = Settings {
            t_stability: f64::INFINITY,
            ..good
        };
        assert_eq!(
            bad.check().unwrap_err().to_string(),
            "t_stability: must be finite and > 0, got inf"
        );
        let bad = Settings {
            sample_every: 0,
            ..good
        };
        assert_eq!(
            bad.check().unwrap_err().to_string(),
            "sample_every: must be >= 1, got 0"
        );
    }
}
