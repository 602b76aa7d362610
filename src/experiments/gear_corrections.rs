//! The note's experiment: scheme A against scheme B with each of its
//! corrections, for any system of pinned rotors. Each configuration gives one
//! [`Row`]: energy drift and fluctuation, global error and its observed order,
//! the largest stable time step, and the size of the eq 15 zeroth components.

use crate::integrators::{FirstCorrector, GearA, GearB, GearBOptions, Integrator, RotorState};
use crate::observables::{norm_velocity, total_energy, total_kinetic_energy};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// A system of pinned rotors with its initial state.
pub struct System<'a, P> {
    /// The interactions.
    pub potential: &'a P,
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
    /// Time at which the global error is measured, at `dt`, `dt/2`, `dt/4`,
    /// against scheme A at `dt / (4 * REFERENCE_REFINEMENT)`.
    pub t_error: f64,
    /// Length of the stability runs.
    pub t_stability: f64,
    /// Energy samples are taken every this many steps (>= 1).
    pub sample_every: usize,
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
    /// Order fitted to the global errors at `dt`, `dt/2`, `dt/4`.
    pub order: f64,
    /// Largest stable step of the scan, or `None` if even `dt` is unstable.
    pub largest_stable_dt: Option<f64>,
    /// Largest `|Q.Q'|` over the energy run (eq 15a).
    pub max_q_dot_q_dot: f64,
    /// Largest `|Q.N|` over the energy run (eq 15b); `None` for scheme A,
    /// which works with body torques.
    pub max_q_dot_force: Option<f64>,
}

/// The configurations of the note's comparison.
pub fn variants() -> Vec<(String, Variant)> {
    let none = GearBOptions {
        project_torque: false,
        project_velocity: false,
        renormalise: false,
        ..GearBOptions::default()
    };
    let full = GearBOptions::default();
    vec![
        ("A (renormalised)".into(), Variant::A),
        ("B, no correction".into(), Variant::B(none)),
        (
            "B, renormalisation only".into(),
            Variant::B(GearBOptions {
                renormalise: true,
                ..none
            }),
        ),
        (
            "B, torque only".into(),
            Variant::B(GearBOptions {
                project_torque: true,
                ..none
            }),
        ),
        (
            "B, torque + velocity".into(),
            Variant::B(GearBOptions {
                project_torque: true,
                project_velocity: true,
                ..none
            }),
        ),
        (
            "B, torque + velocity + renormalisation".into(),
            Variant::B(full),
        ),
        (
            "B, all + higher derivatives".into(),
            Variant::B(GearBOptions {
                correct_higher_derivatives: true,
                ..full
            }),
        ),
        (
            "B, all, c0 = 3/20".into(),
            Variant::B(GearBOptions {
                c0: FirstCorrector::PositionOnly,
                ..full
            }),
        ),
    ]
}

/// What one run records.
struct Trace {
    final_orientations: Vec<Quat>,
    times: Vec<f64>,
    energies: Vec<f64>,
    kinetic: Vec<f64>,
    max_q_dot_q_dot: f64,
    max_q_dot_force: Option<f64>,
    finite: bool,
}

fn trace<I: Integrator, P: Potential>(
    mut integrator: I,
    system: &System<P>,
    dt: f64,
    t_end: f64,
    sample_every: usize,
) -> Trace {
    let n = system.initial.len();
    let steps = (t_end / dt).round() as usize;
    let mut omega = vec![Vector3::zeros(); n];
    let mut q_dot = vec![Quat::ZERO; n];
    let mut q_n = vec![0.0; n];
    let mut t = Trace {
        final_orientations: Vec::new(),
        times: Vec::new(),
        energies: Vec::new(),
        kinetic: Vec::new(),
        max_q_dot_q_dot: 0.0,
        max_q_dot_force: None,
        finite: true,
    };
    if integrator
        .setup(system.inertia, system.potential, system.initial, dt)
        .is_err()
    {
        t.finite = false;
        return t;
    }
    for step in 0..=steps {
        if step > 0 {
            integrator.step(system.potential);
        }
        if step % sample_every.max(1) != 0 && step != steps {
            continue;
        }
        let q = integrator.orientations();
        integrator.omega_body(&mut omega);
        integrator.q_dot(&mut q_dot);
        let energy = total_energy(system.potential, system.inertia, q, &omega);
        if !energy.is_finite() {
            t.finite = false;
            break;
        }
        t.times.push(step as f64 * dt);
        t.energies.push(energy);
        t.kinetic.push(total_kinetic_energy(system.inertia, &omega));
        for (qi, qd) in q.iter().zip(&q_dot) {
            t.max_q_dot_q_dot = t.max_q_dot_q_dot.max(norm_velocity(qi, qd).abs());
        }
        if integrator.norm_force(&mut q_n) {
            let worst = q_n.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            t.max_q_dot_force = Some(t.max_q_dot_force.unwrap_or(0.0).max(worst));
        }
    }
    t.final_orientations = integrator.orientations().to_vec();
    t
}

fn trace_variant<P: Potential>(
    variant: Variant,
    system: &System<P>,
    dt: f64,
    t_end: f64,
    sample_every: usize,
) -> Trace {
    match variant {
        Variant::A => trace(GearA::default(), system, dt, t_end, sample_every),
        Variant::B(options) => trace(GearB::new(options), system, dt, t_end, sample_every),
    }
}

/// Least-squares line `y = a + b x`: returns `(b, rms residual)`.
fn line_fit(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let rss: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    (slope, (rss / n).sqrt())
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

fn is_stable<P: Potential>(variant: Variant, system: &System<P>, dt: f64, t_end: f64) -> bool {
    let t = trace_variant(variant, system, dt, t_end, 1);
    let Some((&e0, &k0)) = t.energies.first().zip(t.kinetic.first()) else {
        return false;
    };
    t.finite
        && t.energies
            .iter()
            .all(|e| (e - e0).abs() <= STABILITY_ENERGY_FRACTION * k0)
}

/// The table: one row per configuration of [`variants`].
pub fn correction_table<P: Potential>(system: &System<P>, settings: &Settings) -> Vec<Row> {
    let dts = [settings.dt, settings.dt / 2.0, settings.dt / 4.0];
    let reference = trace(
        GearA::default(),
        system,
        dts[2] / REFERENCE_REFINEMENT as f64,
        settings.t_error,
        usize::MAX,
    )
    .final_orientations;
    variants()
        .into_iter()
        .map(|(label, variant)| {
            let energy = trace_variant(
                variant,
                system,
                settings.dt,
                settings.t_energy,
                settings.sample_every,
            );
            let mean_kinetic =
                energy.kinetic.iter().sum::<f64>() / energy.kinetic.len().max(1) as f64;
            let (slope, rms) = line_fit(&energy.times, &energy.energies);
            let errors: Vec<f64> = dts
                .iter()
                .map(|&dt| {
                    let t = trace_variant(variant, system, dt, settings.t_error, usize::MAX);
                    if t.finite {
                        max_angle(&t.final_orientations, &reference)
                    } else {
                        f64::NAN
                    }
                })
                .collect();
            let log_dts: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
            let log_errors: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
            let order = line_fit(&log_dts, &log_errors).0;
            let largest_stable_dt = (0..=STABILITY_STEPS)
                .map(|k| settings.dt * 2f64.powf(k as f64 / 4.0))
                .take_while(|&dt| is_stable(variant, system, dt, settings.t_stability))
                .last();
            Row {
                label,
                variant,
                drift: if energy.finite {
                    slope / mean_kinetic
                } else {
                    f64::NAN
                },
                fluctuation: if energy.finite {
                    rms / mean_kinetic
                } else {
                    f64::NAN
                },
                global_error: errors[0],
                order,
                largest_stable_dt,
                max_q_dot_q_dot: energy.max_q_dot_q_dot,
                max_q_dot_force: energy.max_q_dot_force,
            }
        })
        .collect()
}
