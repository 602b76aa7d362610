//! Schemes A and B on interacting rotors (a pinned 2 x 2 x 2 lattice of
//! dipoles and quadrupoles, `MultipolePotential`), long-run energy conservation, the norm
//! diagnostics of eqs 15a and 15b, restarts and bad input.

mod gear_common;

use gear_common::cluster::cube;
use gear_common::fixtures::{reference, Reference};
use gear_common::*;
use nalgebra::Vector3;
use quatrot::integrators::{
    GearA, GearAOptions, GearB, GearBOptions, Integrator, IntegratorError, RotorState, Startup,
};
use quatrot::observables::{total_energy, total_kinetic_energy};
use quatrot::potential::Potential;
use quatrot::rotor::Inertia;
use quatrot::Quat;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Expected global order of both schemes (see `gear_references.rs`).
const GEAR_ORDER: f64 = 5.0;
/// Allowed distance of a fitted order from the expected one: a fit over a few
/// step sizes carries the higher-order terms.
const ORDER_TOLERANCE: f64 = 0.3;

/// The final orientations of the cluster after t = 5 with `steps` steps.
fn cluster_final<I: Integrator>(mut integrator: I, mixed: bool, steps: usize) -> Vec<Quat> {
    let (cluster, inertia, initial) = cube(mixed);
    final_orientations(&mut integrator, &inertia, &cluster, &initial, 5.0, steps)
}

/// On the interacting cluster (mixed spherical and asymmetric tops) both
/// schemes converge at order 5 to a common limit: the reference is scheme A
/// with 16 times smaller steps than the smallest step of the fit (its error
/// is then ~16^5 ~ 1e6 times smaller), so B's agreement with it is a
/// cross-check between the two formulations.
#[test]
fn cluster_both_schemes_converge_at_order_five_to_a_common_limit() {
    let steps = [100, 200, 400];
    let reference = cluster_final(GearA::default(), true, 16 * 400);
    let dts: Vec<f64> = steps.iter().map(|&s| 5.0 / s as f64).collect();
    let errors_a: Vec<f64> = steps
        .iter()
        .map(|&s| max_angle(&cluster_final(GearA::default(), true, s), &reference))
        .collect();
    let errors_b: Vec<f64> = steps
        .iter()
        .map(|&s| max_angle(&cluster_final(GearB::default(), true, s), &reference))
        .collect();
    for (what, errors) in [("A", &errors_a), ("B", &errors_b)] {
        let order = fitted_order(&dts, errors);
        assert!(
            (order - GEAR_ORDER).abs() < ORDER_TOLERANCE,
            "{what}: order {order:.2} ({errors:?})"
        );
    }
}

/// Energy error relative to the mean kinetic energy: (largest |E(t) - E(0)|,
/// mean kinetic energy) over `t_end` with steps of `dt`.
fn energy_error<I: Integrator, P: Potential>(
    mut integrator: I,
    inertia: &[Inertia],
    potential: &P,
    initial: &[RotorState],
    dt: f64,
    t_end: f64,
) -> f64 {
    let steps = (t_end / dt).round() as usize;
    let mut omega = vec![Vector3::zeros(); initial.len()];
    let (mut e0, mut worst, mut kinetic) = (0.0, 0.0_f64, 0.0);
    run(
        &mut integrator,
        inertia,
        potential,
        initial,
        dt,
        steps,
        |s, i| {
            i.omega_body(&mut omega);
            let e = total_energy(potential, inertia, i.orientations(), &omega);
            kinetic += total_kinetic_energy(inertia, &omega);
            if s == 0 {
                e0 = e;
            }
            worst = worst.max((e - e0).abs());
        },
    );
    worst / (kinetic / (steps + 1) as f64)
}

/// Long run (t = 1000, 40 000 steps) of a dipole in a field, spherical and
/// asymmetric: neither Gear scheme is symplectic, so the energy drifts
/// secularly, at a rate set by the local error `O(h^6)` per step, i.e.
/// `O(h^5)` per unit time. Asserted: (1) the relative energy error at
/// `dt = 0.025` is below the a-priori level `(|w|max dt)^5 |w|max t` with
/// `|w|max = 2` (`6e-4`; measured ~2e-5 for A and ~3e-5 for B); (2) halving
/// `dt` divides it by `2^5` within the order tolerance.
#[test]
fn long_run_energy_drift_is_small_and_fifth_order() {
    const T_END: f64 = 1000.0;
    const OMEGA_MAX: f64 = 2.0;
    let dts = [0.05, 0.025];
    let bound = (OMEGA_MAX * dts[1]).powi(5) * OMEGA_MAX * T_END;
    for name in ["dipole_spherical", "dipole_asymmetric"] {
        let r: Reference = reference("dipole_field.json", name);
        let field = r.field.expect("a field case");
        let errors = |scheme: &str| -> Vec<f64> {
            dts.iter()
                .map(|&dt| match scheme {
                    "A" => energy_error(
                        GearA::default(),
                        &[r.inertia],
                        &field,
                        &[r.initial],
                        dt,
                        T_END,
                    ),
                    _ => energy_error(
                        GearB::default(),
                        &[r.inertia],
                        &field,
                        &[r.initial],
                        dt,
                        T_END,
                    ),
                })
                .collect()
        };
        for scheme in ["A", "B"] {
            let e = errors(scheme);
            let order = fitted_order(&dts, &e);
            assert!(
                e[1] < bound,
                "{name} {scheme}: energy error {:.2e} > {bound:.2e}",
                e[1]
            );
            assert!(
                (order - GEAR_ORDER).abs() < ORDER_TOLERANCE,
                "{name} {scheme}: drift order {order:.2}"
            );
        }
    }
}

/// `| |Q| - 1 |` of scheme A at `t = 250, 500, 750, 1000` (a dipole in a
/// field, asymmetric top) with steps of `dt`.
fn scheme_a_norm_errors(renormalise: bool, dt: f64) -> Vec<f64> {
    const T_END: f64 = 1000.0;
    let r = reference("dipole_field.json", "dipole_asymmetric");
    let field = r.field.expect("a field case");
    let steps = (T_END / dt).round() as usize;
    let mut errors = Vec::new();
    let mut integrator = GearA::new(GearAOptions {
        renormalise,
        ..Default::default()
    });
    run(
        &mut integrator,
        &[r.inertia],
        &field,
        &[r.initial],
        dt,
        steps,
        |s, i| {
            if s > 0 && s % (steps / 4) == 0 {
                errors.push((i.orientations()[0].norm() - 1.0).abs());
            }
        },
    );
    errors
}

/// `Q/|Q|` is unit to the rounding of the sum of squares, the square root and
/// the division: a few ulps.
const UNIT_ROUND_OFF: f64 = 4.0 * f64::EPSILON;

/// Scheme A's `renormalise` switch: on, `|Q|` stays 1 to round-off over a
/// long run; off, the corrector's truncation error moves `|Q|` a little each
/// step in the same direction (eq 15a holds for the corrected `Q'`, not for
/// the Taylor-predicted `Q`), so `|Q| - 1` grows linearly in time (its values
/// at t = 500 and 1000 in the ratio 2) and is fifth order in `dt` like the
/// local error per unit time (measured 8.1e-5 at dt = 0.05, 2.5e-6 at 0.025).
#[test]
fn scheme_a_norm_drifts_without_renormalisation() {
    // Relative departure of e(1000)/e(500) from 2 allowed: the drift rate
    // follows the rotor's quasi-periodic motion, averaged over 500 time units.
    const LINEAR_GROWTH_TOLERANCE: f64 = 0.1;
    let dts = [0.05, 0.025];
    for dt in dts {
        let kept = scheme_a_norm_errors(true, dt);
        assert!(
            kept.iter().all(|e| *e <= UNIT_ROUND_OFF),
            "renormalised, dt = {dt}: {kept:?}"
        );
    }
    let drift: Vec<Vec<f64>> = dts
        .iter()
        .map(|&dt| scheme_a_norm_errors(false, dt))
        .collect();
    for (dt, e) in dts.iter().zip(&drift) {
        assert!(e[0] > 1e3 * UNIT_ROUND_OFF, "dt = {dt}: no drift ({e:?})");
        let growth = e[3] / e[1];
        assert!(
            (growth / 2.0 - 1.0).abs() < LINEAR_GROWTH_TOLERANCE,
            "dt = {dt}: |Q| - 1 not linear in t ({e:?})"
        );
    }
    let finals: Vec<f64> = drift.iter().map(|e| e[3]).collect();
    let order = fitted_order(&dts, &finals);
    assert!(
        (order - GEAR_ORDER).abs() < ORDER_TOLERANCE,
        "norm drift order {order:.2} ({finals:?})"
    );
}

/// Largest |Q.Q'| and |Q.N| (eqs 15a, 15b) over a cluster run of scheme B.
fn norm_diagnostics(options: GearBOptions) -> (f64, f64) {
    let (cluster, inertia, initial) = cube(false);
    let mut q_dot = vec![Quat::ZERO; initial.len()];
    let mut q_n = vec![0.0; initial.len()];
    let (mut worst_qq, mut worst_qn) = (0.0_f64, 0.0_f64);
    run(
        &mut GearB::new(options),
        &inertia,
        &cluster,
        &initial,
        0.02,
        500,
        |_, i| {
            i.q_dot(&mut q_dot);
            assert!(i.norm_force(&mut q_n));
            for ((q, qd), qn) in i.orientations().iter().zip(&q_dot).zip(&q_n) {
                worst_qq = worst_qq.max(q.dot(qd).abs());
                worst_qn = worst_qn.max(qn.abs());
            }
        },
    );
    (worst_qq, worst_qn)
}

/// Rounding level of the projected quantities (|Q| ~ 1, |Q'| and |N| ~ 1).
const PROJECTED: f64 = 1e-13;

/// With the note's projections on, `Q.Q'` and `Q.N` stay at the rounding
/// level; without them, `Q.N` is the large norm component of the unprojected
/// eq 14 gradient (`Q.dV/dQ = 2V` for dipoles) and `Q.Q'` grows.
#[test]
fn projections_keep_eq15_zeroth_components_at_rounding_level() {
    let (qq, qn) = norm_diagnostics(GearBOptions::default());
    assert!(
        qq < PROJECTED && qn < PROJECTED,
        "projected: Q.Q' {qq:.2e}, Q.N {qn:.2e}"
    );
    let (qq, qn) = norm_diagnostics(GearBOptions {
        project_torque: false,
        project_velocity: false,
        ..Default::default()
    });
    assert!(
        qq > 1e3 * PROJECTED && qn > 1e-2,
        "unprojected: Q.Q' {qq:.2e}, Q.N {qn:.2e}"
    );
}

/// A checkpoint taken mid-run and restored into a freshly set-up integrator
/// reproduces the continuation bit for bit; one of another length is
/// refused, one of another `dt` is left to the run's identity check.
#[test]
fn checkpoint_restore_is_bit_exact() {
    fn check<I: Integrator>(make: impl Fn() -> I) {
        let (cluster, inertia, initial) = cube(true);
        let mut first = make();
        first
            .setup(&inertia, &cluster, &initial, 0.03)
            .expect("valid");
        for _ in 0..37 {
            first.step(&cluster);
        }
        let saved = first.checkpoint();
        for _ in 0..25 {
            first.step(&cluster);
        }
        let mut second = make();
        second
            .setup(&inertia, &cluster, &initial, 0.03)
            .expect("valid");
        second.restore(&saved).expect("matching checkpoint");
        for _ in 0..25 {
            second.step(&cluster);
        }
        assert_eq!(first.orientations(), second.orientations());
        assert_eq!(first.checkpoint(), second.checkpoint());
        assert!(matches!(
            second.restore(&saved[1..]),
            Err(IntegratorError::BadCheckpoint(_))
        ));
        // dt is compared once on a restart, by the checkpoint's identity
        // (tests/outputs_and_restarts.rs), not again by the Gear layout.
        let mut other_dt = make();
        other_dt
            .setup(&inertia, &cluster, &initial, 0.01)
            .expect("valid");
        assert_eq!(other_dt.restore(&saved), Ok(()));
    }
    check(GearA::default);
    check(GearB::default);
}

/// Bad setups are errors naming the problem, never panics.
#[test]
fn bad_setup_is_an_error() {
    fn check<I: Integrator>(mut integrator: I) {
        let (cluster, mut inertia, mut initial) = cube(false);
        assert_eq!(
            integrator.setup(&inertia, &cluster, &initial, 0.0),
            Err(IntegratorError::BadTimeStep(0.0))
        );
        assert!(matches!(
            integrator.setup(&inertia[..3], &cluster, &initial, 0.01),
            Err(IntegratorError::Unsupported { rotor: 3, .. })
        ));
        inertia[2] = Inertia::Principal(Vector3::new(1.0, 0.0, 2.0));
        assert!(matches!(
            integrator.setup(&inertia, &cluster, &initial, 0.01),
            Err(IntegratorError::Unsupported { rotor: 2, .. })
        ));
        inertia[2] = Inertia::Spherical(1.0);
        initial[5].orientation = Quat::ZERO;
        assert!(matches!(
            integrator.setup(&inertia, &cluster, &initial, 0.01),
            Err(IntegratorError::Unsupported { rotor: 5, .. })
        ));
    }
    check(GearA::default());
    check(GearB::default());
}

/// Torque evaluations of a consistent start-up, as documented in
/// `src/integrators/startup.rs` (and quoted in RESULTS.md's text): two
/// directions of 4 steps, 2 RK4 substeps of 4 stages each, plus the rates
/// at t = 0.
const CONSISTENT_STARTUP_EVALUATIONS: usize = 2 * 4 * 2 * 4 + 1;

/// Counts the calls of the wrapped potential that compute forces.
struct CountingForces<'a, P> {
    inner: &'a P,
    calls: AtomicUsize,
}

impl<P: Potential> Potential for CountingForces<'_, P> {
    fn energy(&self, q: &[Quat]) -> f64 {
        self.inner.energy(q)
    }
    fn accumulate_gradient(&self, q: &[Quat], g: &mut [Quat]) {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.accumulate_gradient(q, g)
    }
    fn accumulate_torques(&self, q: &[Quat], t: &mut [Vector3<f64>]) {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.accumulate_torques(q, t)
    }
    fn energy_and_gradient(&self, q: &[Quat], g: &mut [Quat]) -> f64 {
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.inner.energy_and_gradient(q, g)
    }
}

/// The consistent start-up of both schemes costs the documented number of
/// force evaluations, the zero start-up one (the rates at t = 0), and each
/// step one more; scheme B's setup adds one gradient for its `Q.N`
/// diagnostic at t = 0.
#[test]
fn startup_costs_the_documented_force_evaluations() {
    fn count<I: Integrator>(mut integrator: I, steps: usize) -> usize {
        let (cluster, inertia, initial) = cube(true);
        let counting = CountingForces {
            inner: &cluster,
            calls: AtomicUsize::new(0),
        };
        run(
            &mut integrator,
            &inertia,
            &counting,
            &initial,
            0.05,
            steps,
            |_, _| {},
        );
        counting.calls.load(Ordering::Relaxed)
    }
    let steps = 3;
    for startup in [Startup::Consistent, Startup::Zeros] {
        let expected = match startup {
            Startup::Consistent => CONSISTENT_STARTUP_EVALUATIONS,
            Startup::Zeros => 1,
        };
        let a = GearA::new(GearAOptions {
            startup,
            ..Default::default()
        });
        let b = GearB::new(GearBOptions {
            startup,
            ..Default::default()
        });
        assert_eq!(count(a, steps), expected + steps, "A {startup:?}");
        assert_eq!(count(b, steps), expected + 1 + steps, "B {startup:?}");
    }
}
