//! The thermostats sample the canonical distribution `exp(-(K + V)/T)`,
//! proved against exact distributions with fixed seeds at the significance
//! level `ALPHA = 1e-4` (independent replicas, each run long enough to
//! forget its start, so a correct implementation fails one test in 1e4
//! runs), and the same tests reject a temperature, friction or relaxation
//! time wrong by a factor of two every time (p-values below 1e-12).
//!
//! Exact references: body angular velocity components normal with variance
//! `T / I_a` and the kinetic energy of a rotor Gamma(3/2, T) (Maxwell, for
//! any potential); `cos(theta)` of a dipole in a uniform field distributed as
//! `exp(x cos theta)`, `x = mu E / T`, with mean `coth x - 1/x`; the exact
//! autocorrelations of the Ornstein-Uhlenbeck step (`exp(-gamma t)`) and of
//! Bussi's kinetic energy (`exp(-t/tau)`) for a free spherical top. The
//! CDFs are closed forms checked against scipy in
//! `statistics_match_scipy`.

mod thermostat_common;

use nalgebra::Vector3;
use quatrot::integrators::{
    DlmOptions, GearAOptions, IntegratorSpec, NoSquishOptions, RotorState, SphericalTops,
};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::thermostats::{BussiOptions, LangevinOptions, NoseHooverOptions, ThermostatSpec};
use thermostat_common::*;

/// The temperature of the tests (not 1, so that a dropped `T` shows).
const T: f64 = 0.8;
/// Langevin friction (1/time).
const FRICTION: f64 = 2.0;
/// Bussi's relaxation time.
const TAU_BUSSI: f64 = 0.1;
/// The Nose-Hoover period.
const TAU_NH: f64 = 0.2;
/// The time step: `|w| dt ~ 0.03` for `I = 0.1`, where the splitting's bias
/// of the distributions (order `dt^2`, ~1e-3) is far below the tests'
/// resolution (KS distances ~0.03).
const DT: f64 = 0.01;
/// `x = mu E / T` of the dipole tests.
const X: f64 = 2.0;

fn langevin(temperature: f64, friction: f64) -> ThermostatSpec {
    ThermostatSpec::Langevin(LangevinOptions {
        temperature,
        friction,
        seed: None,
    })
}

fn bussi(temperature: f64, tau: f64) -> ThermostatSpec {
    ThermostatSpec::Bussi(BussiOptions {
        temperature,
        tau,
        seed: None,
    })
}

fn nose_hoover(temperature: f64) -> ThermostatSpec {
    ThermostatSpec::NoseHoover(NoseHooverOptions {
        temperature,
        tau: TAU_NH,
        chain: NoseHooverOptions::DEFAULT_CHAIN,
    })
}

/// The integrators a thermostat runs with, by name: NO_SQUISH and DLM with
/// the exact spherical-top flow and with the body-axis sweep.
fn integrators() -> Vec<(&'static str, IntegratorSpec)> {
    let split = SphericalTops::Split;
    vec![
        ("dlm", IntegratorSpec::Dlm(DlmOptions::default())),
        (
            "dlm split",
            IntegratorSpec::Dlm(DlmOptions {
                spherical_tops: split,
            }),
        ),
        (
            "no_squish",
            IntegratorSpec::NoSquish(NoSquishOptions::default()),
        ),
        (
            "no_squish split",
            IntegratorSpec::NoSquish(NoSquishOptions {
                spherical_tops: split,
                ..NoSquishOptions::default()
            }),
        ),
    ]
}

/// Spherical, symmetric and asymmetric tops.
fn tops() -> [(&'static str, Inertia); 3] {
    [
        ("spherical", Inertia::Spherical(0.1)),
        (
            "symmetric",
            Inertia::Principal(Vector3::new(0.1, 0.1, 0.25)),
        ),
        (
            "asymmetric",
            Inertia::Principal(Vector3::new(0.1, 0.15, 0.25)),
        ),
    ]
}

/// The first sample of every rotor of every replica, and their inertia.
fn first_samples(runs: &[Samples], system: &System) -> (Vec<RotorState>, Vec<Inertia>) {
    let states = runs.iter().flat_map(|s| s[0].clone()).collect();
    let inertia = runs
        .iter()
        .flat_map(|_| system.rotors.iter().map(|r| r.inertia))
        .collect();
    (states, inertia)
}

/// p-values of the Maxwell tests at temperature `t`: angular velocity
/// components (KS against the normal), kinetic energy per rotor (KS against
/// Gamma(3/2)), and the mean kinetic energy `3T/2` (z test, variance
/// `3 T^2 / 2` per rotor).
fn maxwell_p_values(states: &[RotorState], inertia: &[Inertia], t: f64) -> [f64; 3] {
    let omega = scaled_omega(states, inertia, t);
    let kinetic = scaled_kinetic(states, inertia, t);
    let n = kinetic.len() as f64;
    let mean = kinetic.iter().sum::<f64>() / n;
    [
        ks_test(&omega, normal_cdf),
        ks_test(&kinetic, gamma_three_halves_cdf),
        two_sided_p((mean - 1.5) / (1.5 / n).sqrt()),
    ]
}

/// p-values of the dipole tests at `x`: `cos(theta)` (KS against the exact
/// CDF) and its mean (z test, exact variance `1 - 2 L(x)/x - L(x)^2`).
fn dipole_p_values(states: &[RotorState], x: f64) -> [f64; 2] {
    let c = cosines(states, &Vector3::z(), &Vector3::z());
    let n = c.len() as f64;
    let mean = c.iter().sum::<f64>() / n;
    let l = langevin_function(x);
    let variance = 1.0 - 2.0 * l / x - l * l;
    [
        ks_test(&c, |v| dipole_cos_cdf(v, x)),
        two_sided_p((mean - l) / (variance / n).sqrt()),
    ]
}

fn assert_pass(what: &str, p: &[f64]) {
    println!("{what}: p-values {}", show(p));
    assert!(p.iter().all(|&p| p > ALPHA), "{what}: p-values {}", show(p));
}

fn show(p: &[f64]) -> String {
    p.iter()
        .map(|x| format!("{x:.3e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn assert_rejected(what: &str, p: &[f64]) {
    println!("{what} (wrong by two): p-values {}", show(p));
    assert!(
        p.iter().all(|&p| p < WRONG_BY_TWO_P),
        "{what}: p-values {}",
        show(p)
    );
}

/// The replica counts and run lengths of the Maxwell tests on free rotors:
/// 2000 rotors (6000 components; KS critical distance 0.029 at `ALPHA`),
/// from `T/4` for 5 time units (the kinetic energy relaxes as
/// `exp(-2 gamma t)` with Langevin, `exp(-t/tau)` with Bussi: `e^-20`, `e^-50`).
const FREE: Replicas = Replicas {
    count: 2000,
    initial_temperature: 0.25 * T,
    dt: DT,
    steps: 500,
    lag: 0,
};

/// Langevin and Bussi on free spherical, symmetric and asymmetric tops,
/// with every integrator: Maxwell angular velocities and Gamma kinetic
/// energies. (Nose-Hoover is left out: free rotors couple only through the
/// chain, which does not make them ergodic.)
#[test]
fn langevin_and_bussi_free_rotors_are_maxwell() {
    for (thermostat, spec) in [
        ("langevin", langevin(T, FRICTION)),
        ("bussi", bussi(T, TAU_BUSSI)),
    ] {
        for (integrator, ispec) in integrators() {
            for (top, inertia) in tops() {
                let system = System::free(inertia);
                let runs = run_replicas(&system, &ispec, &spec, FREE, 11);
                let (states, inertia) = first_samples(&runs, &system);
                let p = maxwell_p_values(&states, &inertia, T);
                assert_pass(&format!("{thermostat} {integrator} {top}"), &p);
            }
        }
    }
}

/// A dipole `|mu| = 1` along body axis 3 in the field `E = x T` along z.
fn dipole(inertia: Inertia) -> System {
    System::dipole_in_field(inertia, Vector3::z(), Vector3::z() * (X * T))
}

/// Langevin on a dipole in a uniform field (spherical and asymmetric tops,
/// every integrator): `cos(theta)` and its mean are exact, and the angular
/// velocities Maxwell. 2000 replicas from uniform orientations at `T`, 10
/// time units (the libration, frequency ~4.5, is damped at the rate gamma).
#[test]
fn langevin_dipole_in_field_follows_boltzmann() {
    let replicas = Replicas {
        count: 2000,
        initial_temperature: T,
        dt: DT,
        steps: 1000,
        lag: 0,
    };
    for (integrator, ispec) in integrators() {
        for (top, inertia) in [tops()[0], tops()[2]] {
            let system = dipole(inertia);
            let runs = run_replicas(&system, &ispec, &langevin(T, FRICTION), replicas, 21);
            let (states, inertia) = first_samples(&runs, &system);
            let what = format!("langevin {integrator} {top} dipole");
            assert_pass(&what, &dipole_p_values(&states, X));
            assert_pass(&what, &maxwell_p_values(&states, &inertia, T));
        }
    }
}

/// `x = mu E / T` of the harmonic libration: the dipole stays within about
/// `x^-1/2 = 0.03` rad of the field, where `-mu E cos(theta)` is harmonic
/// to a relative `1/x`.
const X_HARMONIC: f64 = 1000.0;

/// The z-test p-value of the mean of `samples` against `mean`, each sample
/// of variance `variance`.
fn mean_p_value(samples: &[f64], mean: f64, variance: f64) -> f64 {
    let n = samples.len() as f64;
    let measured = samples.iter().sum::<f64>() / n;
    println!(
        "mean {measured:.4} against {mean:.4} +- {:.4}",
        (variance / n).sqrt()
    );
    two_sided_p((measured - mean) / (variance / n).sqrt())
}

/// Langevin's step (B A O A B) and Bussi's (its rescaling where the O step
/// acts) leave the orientations of a harmonic libration exact at any `dt`,
/// but their momenta after the last half kick, where the kinetic temperature
/// is read, are low by `(w0 dt / 2)^2` (issue 41's water: T_rot 1.2 % low at
/// 2 fs). Closed form for a harmonic oscillator of frequency `w0` (mass 1,
/// `a = (w0 dt/2)^2`): from one action in mid-step to the next the map is
/// position Verlet (A B B A), which keeps `w0^2 q^2 / (1 - a) + p^2`, and
/// the action keeps `p` exactly Maxwell (Bussi: their summed kinetic
/// energy), so in mid-step `<p^2> = T`, `<q^2> = T (1 - a) / w0^2`; the last
/// A and B take that to velocity Verlet's invariant `w0^2 q^2 + p^2 / (1 -
/// a)`: at the full step `<q^2> = T / w0^2` exact, `<p^2> = T (1 - a)`.
/// A thermostat acting on the full-step momenta instead (Bussi before session
/// 26) keeps `<p^2> = T` there and makes the orientations hot, `<w0^2 q^2> =
/// T / (1 - a)`: measured 1.315 +- 0.021 against 4/3 at `w0 dt = 1`, the
/// canonical 1 rejected at p = 1e-50 (ERRATA.md, traps).
/// A spherical top (`I = 0.1`) with a dipole in the field `E = x T`,
/// `x = 1000`, librates about the two axes normal to the dipole at
/// `w0 = sqrt(mu E / I)`; at `w0 dt = 1`: `I w_k^2 / T` has mean 3/4 on
/// those axes (not 1: rejected) and 1 on the spin about the dipole (no
/// torque: Langevin's O step alone, exact; Bussi leaves the conserved spin
/// at its Maxwell start), and `x (1 - cos(theta))` its exact mean
/// `x (1 - L(x))` (not the `1 / (1 - a)` of a full-step thermostat:
/// rejected). 4000 replicas, 600 steps (Langevin: 300 e-folds of the
/// friction `w0 / 2`; Bussi: 60 relaxation times) from uniform
/// orientations, every integrator (Bussi: those whose flow keeps the spin).
#[test]
fn mid_step_thermostats_keep_a_libration_exact_and_read_its_full_step_kinetic_temperature_low_by_w0_dt_over_2_squared(
) {
    let inertia = 0.1;
    let field = X_HARMONIC * T;
    let w0 = (field / inertia).sqrt();
    let replicas = Replicas {
        count: 4000,
        initial_temperature: T,
        dt: 1.0 / w0,
        steps: 600,
        lag: 0,
    };
    let deficit = 0.25; // (w0 dt / 2)^2
    let system = System::dipole_in_field(
        Inertia::Spherical(inertia),
        Vector3::z(),
        Vector3::z() * field,
    );
    // Bussi with the exact spherical-top flows only, as `global_pairs`: the
    // body-axis sweep does not conserve the spin it leaves out.
    let all = integrators();
    let pairs = [
        ("langevin", langevin(T, 0.5 * w0), all.clone()),
        ("bussi", bussi(T, TAU_BUSSI), vec![all[0], all[2]]),
    ];
    for (thermostat, spec, integrators) in pairs {
        for (integrator, ispec) in integrators {
            let runs = run_replicas(&system, &ispec, &spec, replicas, 61);
            let (states, _) = first_samples(&runs, &system);
            let scaled = |k: usize| {
                states
                    .iter()
                    .map(move |s| inertia * s.omega_body[k].powi(2) / T)
            };
            let libration: Vec<f64> = scaled(0).chain(scaled(1)).collect();
            let spin: Vec<f64> = scaled(2).collect();
            let c = cosines(&states, &Vector3::z(), &Vector3::z());
            let depth: Vec<f64> = c.iter().map(|c| X_HARMONIC * (1.0 - c)).collect();
            let l = langevin_function(X_HARMONIC);
            let x2 = X_HARMONIC * X_HARMONIC;
            let what = format!("{thermostat} {integrator} harmonic libration");
            let expected = 1.0 - deficit;
            let hot = 1.0 / expected;
            assert_pass(
                &what,
                &[
                    mean_p_value(&libration, expected, 2.0 * expected * expected),
                    mean_p_value(&spin, 1.0, 2.0),
                    mean_p_value(
                        &depth,
                        X_HARMONIC * (1.0 - l),
                        x2 * (1.0 - 2.0 * l / X_HARMONIC - l * l),
                    ),
                ],
            );
            assert_rejected(
                &what,
                &[
                    mean_p_value(&libration, 1.0, 2.0 * expected * expected),
                    // The depth of two harmonic librations is exponential:
                    // variance = mean^2.
                    mean_p_value(&depth, hot, hot * hot),
                ],
            );
        }
    }
}

/// Bussi and Nose-Hoover with DLM and NO_SQUISH at [`DT`], and Nose-Hoover
/// with scheme A at `DT/2`: scheme A's explicit predictor-corrector is
/// stable only while `dt |p_j / Q_j|` of every thermostat stays below about
/// 0.2, and with `tau = 20 dt` one replica in 1000 of this test crossed that
/// (the chain's upper momenta oscillating with alternating signs, then
/// diverging); at `tau = 40 dt` none did.
fn global_pairs() -> Vec<(
    &'static str,
    ThermostatSpec,
    &'static str,
    IntegratorSpec,
    f64,
)> {
    let mut out = Vec::new();
    for (thermostat, spec) in [
        ("bussi", bussi(T, TAU_BUSSI)),
        ("nose_hoover", nose_hoover(T)),
    ] {
        for (integrator, ispec) in [integrators()[0], integrators()[2]] {
            out.push((thermostat, spec, integrator, ispec, DT));
        }
    }
    out.push((
        "nose_hoover",
        nose_hoover(T),
        "gear_a",
        IntegratorSpec::GearA(GearAOptions::default()),
        0.5 * DT,
    ));
    out
}

/// The global thermostats (and scheme A with Nose-Hoover) on an asymmetric
/// dipole in a field (one rotor per replica, ergodic through its chaotic
/// libration): `cos(theta)` exact and
/// the angular velocities Maxwell. 1000 replicas from uniform orientations
/// at `T`, 50 time units.
#[test]
fn bussi_and_nose_hoover_asymmetric_dipole_follows_boltzmann() {
    let replicas = Replicas {
        count: 1000,
        initial_temperature: T,
        dt: DT,
        steps: 5000,
        lag: 0,
    };
    let system = dipole(tops()[2].1);
    for (thermostat, spec, integrator, ispec, dt) in global_pairs() {
        let replicas = Replicas {
            dt,
            steps: (50.0 / dt).round() as usize,
            ..replicas
        };
        let runs = run_replicas(&system, &ispec, &spec, replicas, 31);
        let (states, inertia) = first_samples(&runs, &system);
        let what = format!("{thermostat} {integrator} asymmetric dipole");
        assert_pass(&what, &dipole_p_values(&states, X));
        assert_pass(&what, &maxwell_p_values(&states, &inertia, T));
    }
}

/// Eight dipoles on asymmetric tops on a cube of side 1 in a weak field
/// (every rotor interacts, and no spin is conserved, so every component is
/// thermostatted): each thermostat (with DLM and NO_SQUISH, and scheme A for
/// Nose-Hoover) gives Maxwell angular velocities (exact for any potential in
/// the canonical ensemble: momenta are independent of the orientations and of
/// each other). 500 replicas (4000 rotors), 20 time units from `T/2`. (On
/// spherical tops the spins about the dipoles are conserved and Bussi and
/// Nose-Hoover leave them at their start:
/// `tests/thermostat_dynamics.rs::global_thermostats_leave_the_conserved_spins_alone`.)
fn cluster() -> System {
    let mut system = System::dipole_in_field(tops()[2].1, Vector3::z(), Vector3::z() * 0.5);
    let template = system.rotors[0].clone();
    system.rotors = (0..8)
        .map(|k| Rotor {
            site: Vector3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64),
            ..template.clone()
        })
        .collect();
    system
}

const CLUSTER: Replicas = Replicas {
    count: 500,
    initial_temperature: 0.5 * T,
    dt: DT,
    steps: 2000,
    lag: 0,
};

#[test]
fn every_thermostat_gives_maxwell_momenta_in_an_interacting_cluster() {
    let system = cluster();
    for (thermostat, spec) in [
        ("langevin", langevin(T, FRICTION)),
        ("bussi", bussi(T, TAU_BUSSI)),
        ("nose_hoover", nose_hoover(T)),
    ] {
        let mut pairs = vec![integrators()[0], integrators()[2]];
        if thermostat == "nose_hoover" {
            pairs.push(("gear_a", IntegratorSpec::GearA(GearAOptions::default())));
        }
        for (integrator, ispec) in pairs {
            let runs = run_replicas(&system, &ispec, &spec, CLUSTER, 41);
            let (states, inertia) = first_samples(&runs, &system);
            let what = format!("{thermostat} {integrator} cluster");
            assert_pass(&what, &maxwell_p_values(&states, &inertia, T));
        }
    }
}

/// A temperature wrong by a factor of two fails every test: each thermostat
/// run at `2T` and judged against `T` (free rotors for Langevin and Bussi,
/// the dipole in a field for Langevin, the cluster for Nose-Hoover).
#[test]
fn temperature_wrong_by_two_is_rejected() {
    let dlm = IntegratorSpec::Dlm(DlmOptions::default());
    let free = System::free(tops()[2].1);
    for (thermostat, spec) in [
        ("langevin", langevin(2.0 * T, FRICTION)),
        ("bussi", bussi(2.0 * T, TAU_BUSSI)),
    ] {
        let runs = run_replicas(&free, &dlm, &spec, FREE, 51);
        let (states, inertia) = first_samples(&runs, &free);
        assert_rejected(thermostat, &maxwell_p_values(&states, &inertia, T));
    }
    let system = dipole(tops()[0].1);
    let replicas = Replicas {
        count: 2000,
        initial_temperature: T,
        dt: DT,
        steps: 1000,
        lag: 0,
    };
    let runs = run_replicas(&system, &dlm, &langevin(2.0 * T, FRICTION), replicas, 52);
    let (states, _) = first_samples(&runs, &system);
    assert_rejected("langevin dipole", &dipole_p_values(&states, X));
    let system = cluster();
    let runs = run_replicas(&system, &dlm, &nose_hoover(2.0 * T), CLUSTER, 53);
    let (states, inertia) = first_samples(&runs, &system);
    assert_rejected(
        "nose_hoover cluster",
        &maxwell_p_values(&states, &inertia, T),
    );
}

/// The regression slope of the second samples on the first, pooled, with
/// its p-value against `expected` (z test with the robust standard error).
fn lag_p_value(x: &[f64], y: &[f64], expected: f64) -> f64 {
    let (slope, error) = slope_with_error(x, y);
    two_sided_p((slope - expected) / error)
}

/// The relaxation of a thermostat whose time constant is `name` = `value`,
/// over a lag of one time constant: the samples `pairs(value)` (second on
/// first) have the slope `exp(-1)`, and those of twice the value are
/// rejected.
fn assert_one_e_fold(name: &str, value: f64, pairs: impl Fn(f64) -> (Vec<f64>, Vec<f64>)) {
    let expected = (-1.0f64).exp();
    let (x, y) = pairs(value);
    assert_pass(name, &[lag_p_value(&x, &y, expected)]);
    let (x, y) = pairs(2.0 * value);
    assert_rejected(&format!("{name} x 2"), &[lag_p_value(&x, &y, expected)]);
}

/// The friction: for a free spherical top with the exact flow only the O
/// step changes `w_b`, so `w_b(t + s) = exp(-gamma s) w_b(t) + noise`
/// exactly. 2000 replicas at equilibrium, lag `s = 1/gamma`: the slope
/// matches `exp(-1)` and rejects a friction wrong by a factor of two.
#[test]
fn langevin_friction_sets_the_exact_decay() {
    let system = System::free(Inertia::Spherical(0.1));
    let dlm = IntegratorSpec::Dlm(DlmOptions::default());
    let replicas = Replicas {
        count: 2000,
        initial_temperature: T,
        dt: DT,
        steps: 10,
        lag: (1.0 / FRICTION / DT).round() as usize,
    };
    let pairs = |friction: f64| {
        let runs = run_replicas(&system, &dlm, &langevin(T, friction), replicas, 61);
        let component = |k: usize| -> Vec<f64> {
            runs.iter()
                .flat_map(|s| (0..3).map(move |a| s[k][0].omega_body[a]))
                .collect()
        };
        (component(0), component(1))
    };
    assert_one_e_fold("friction", FRICTION, pairs);
}

/// Bussi's relaxation time: for a free spherical top with the exact flow
/// only the rescaling changes `K`, whose exact conditional mean is
/// `K(t + s) = exp(-s/tau) K(t) + (1 - exp(-s/tau)) 3T/2`. 2000 replicas at
/// equilibrium, lag `s = tau`: the slope matches `exp(-1)` and rejects a
/// `tau` wrong by a factor of two.
#[test]
fn bussi_tau_sets_the_exact_relaxation() {
    let system = System::free(Inertia::Spherical(0.1));
    let dlm = IntegratorSpec::Dlm(DlmOptions::default());
    let replicas = Replicas {
        count: 2000,
        initial_temperature: T,
        dt: DT,
        steps: 10,
        lag: (TAU_BUSSI / DT).round() as usize,
    };
    let pairs = |tau: f64| {
        let runs = run_replicas(&system, &dlm, &bussi(T, tau), replicas, 71);
        let inertia = [system.rotors[0].inertia];
        let kinetic = |k: usize| -> Vec<f64> {
            runs.iter()
                .map(|s| scaled_kinetic(&s[k], &inertia, T)[0])
                .collect()
        };
        (kinetic(0), kinetic(1))
    };
    assert_one_e_fold("tau", TAU_BUSSI, pairs);
}

/// A dipole on a spherical top keeps its spin about the dipole (no torque
/// about it); the global thermostats leave that spin alone
/// ([`quatrot::thermostat_hook::CoupledDegrees`]). Scaling it with the rest
/// kept the ratio of the spin to the conserved field component `L_z`, and the
/// rotor never reached the canonical distribution (`cos(theta)` p-values
/// ~1e-27 at 4000 replicas). Now `cos(theta)` and the angular velocities are
/// exact, as for the asymmetric top (DLM and scheme A; NO_SQUISH shares the
/// thermostat's code with DLM).
#[test]
fn global_thermostats_thermalise_a_spherical_dipole() {
    let replicas = Replicas {
        count: 1000,
        initial_temperature: T,
        dt: DT,
        steps: 5000,
        lag: 0,
    };
    let system = dipole(tops()[0].1);
    let pairs = global_pairs().into_iter().filter(|p| p.2 != "no_squish");
    for (thermostat, spec, integrator, ispec, dt) in pairs {
        let replicas = Replicas {
            dt,
            steps: (50.0 / dt).round() as usize,
            ..replicas
        };
        let runs = run_replicas(&system, &ispec, &spec, replicas, 91);
        let (states, inertia) = first_samples(&runs, &system);
        let what = format!("{thermostat} {integrator} spherical dipole");
        assert_pass(&what, &dipole_p_values(&states, X));
        assert_pass(&what, &maxwell_p_values(&states, &inertia, T));
    }
}

/// The closed-form statistics against scipy 1.17.1 (values printed by
/// `scipy.stats`): `kstwobign.sf(1.0) = 0.26999967167735456`,
/// `kstwobign.sf(1.95) = 0.00099591084288358`, `kstwo.sf(0.035, 4000) =
/// 1.0811e-4`, `gamma.cdf(0.7, 1.5) = 0.2944652687959088`,
/// `gamma.cdf(2.3, 1.5) = 0.7964579183206351`, `norm.cdf(-1.3) =
/// 0.09680048458561036`, `2 norm.sf(4) = 6.334248366623973e-05`.
#[test]
fn statistics_match_scipy() {
    let close = |a: f64, b: f64, tol: f64| assert!((a - b).abs() <= tol * b.abs(), "{a} vs {b}");
    close(kolmogorov_tail(1.0), 0.26999967167735456, 1e-12);
    close(kolmogorov_tail(1.95), 0.00099591084288358, 1e-10);
    // Stephens' correction is within 3 % of the exact finite-n tail here.
    close(ks_p_value(0.035, 4000), 1.0811454099820793e-4, 0.03);
    close(gamma_three_halves_cdf(0.7), 0.2944652687959088, 1e-14);
    close(gamma_three_halves_cdf(2.3), 0.7964579183206351, 1e-14);
    close(normal_cdf(-1.3), 0.09680048458561036, 1e-14);
    close(two_sided_p(4.0), 6.334248366623973e-05, 1e-12);
    // The dipole CDF: its ends, and the derivative exp(x c) x / (2 sinh x).
    close(dipole_cos_cdf(1.0, X), 1.0, 1e-15);
    assert_eq!(dipole_cos_cdf(-1.0, X), 0.0);
    let h = 1e-6;
    let density = (dipole_cos_cdf(0.3 + h, X) - dipole_cos_cdf(0.3 - h, X)) / (2.0 * h);
    close(density, (X * 0.3).exp() * X / (2.0 * X.sinh()), 1e-8);
}
