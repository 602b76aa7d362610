//! The note's correction experiment (`experiments::gear_corrections`) on a
//! single asymmetric rotor in a uniform field: the table has one row per
//! configuration, the properties that follow from the theory hold in it, and
//! each of its numbers is what its definition gives when the configuration
//! is run here step by step and measured against the scipy reference (the
//! verdicts on the note's claims are reported, not asserted: run with
//! `--nocapture` to see the table).

mod gear_common;

use gear_common::fixtures::{reference, DipoleInField, Reference};
use gear_common::max_angle;
use nalgebra::Vector3;
use quatrot::experiments::gear_corrections::{
    correction_table, variants, Row, Settings, System, Variant, STABILITY_ENERGY_FRACTION,
    STABILITY_STEPS,
};
use quatrot::integrators::{GearBOptions, Integrator};
use quatrot::potential::Potential;
use quatrot::Quat;
use std::sync::OnceLock;

/// Allowed distance of a fitted order from the expected 5: a fit over three
/// step sizes carries the higher-order terms.
const ORDER_TOLERANCE: f64 = 0.3;
/// Rounding level of `Q.N` after the torque projection (|Q|, |N| ~ 1).
const PROJECTED: f64 = 1e-13;

/// Scheme A and every scheme-B configuration with the torque projection are
/// order 5 with `Q.N` at rounding level; without the projection `Q.N` is
/// the norm component of the eq 14 gradient, `-2V` for a dipole, i.e. O(1).
#[test]
fn correction_table_rows_follow_theory() {
    let rows = &table().rows;
    assert_eq!(rows.len(), variants().len());
    for row in rows {
        println!(
            "{:40} drift {:9.2e} fluct {:9.2e} error {:9.2e} order {:5.2} stable dt {:?} |Q.Q'| {:9.2e} |Q.N| {:?}",
            row.label,
            row.drift,
            row.fluctuation,
            row.global_error,
            row.order,
            row.largest_stable_dt,
            row.max_norm_velocity,
            row.max_norm_force
        );
        // Only scheme B stores the quaternion force N of eq 12: scheme A
        // (body torques, eq 15b by construction) reports no `Q.N` at all,
        // not a zero it never computed.
        assert_eq!(
            row.max_norm_force.is_some(),
            matches!(row.variant, Variant::B(_)),
            "{}: |Q.N| {:?}",
            row.label,
            row.max_norm_force
        );
        let projected = match row.variant {
            Variant::A => true,
            Variant::B(options) => options.project_torque,
        };
        if projected {
            assert!(
                (row.order - 5.0).abs() < ORDER_TOLERANCE,
                "{}: order {}",
                row.label,
                row.order
            );
            assert!(
                row.max_norm_force.unwrap_or(0.0) < PROJECTED,
                "{}",
                row.label
            );
        } else {
            assert!(row.max_norm_force.is_some_and(|x| x > 0.1), "{}", row.label);
        }
    }
}

/// The experiment's settings: the reference's time span for the errors.
const SETTINGS: Settings = Settings {
    dt: 0.05,
    t_energy: 200.0,
    t_error: 10.0,
    t_stability: 50.0,
    sample_every: 1,
};

/// The asymmetric dipole in a field (scipy DOP853 reference, rtol 1e-12) and
/// its table, computed once for every test of this file.
struct Table {
    reference: Reference,
    field: DipoleInField,
    rows: Vec<Row>,
}

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        let reference = reference("dipole_field.json", "dipole_asymmetric");
        let field = reference.field.expect("a field case");
        let system = System {
            potential: &field,
            inertia: &[reference.inertia],
            initial: &[reference.initial],
        };
        let rows = correction_table(&system, &SETTINGS);
        Table {
            reference,
            field,
            rows,
        }
    })
}

/// Runs `variant` from the reference's start for `steps` steps of `dt`,
/// calling `observe` after the setup and after each step; false when the
/// setup refuses.
fn run_variant(
    variant: Variant,
    dt: f64,
    steps: usize,
    mut observe: impl FnMut(&dyn Integrator),
) -> bool {
    let t = table();
    let mut integrator = variant.spec().build();
    if integrator
        .setup(&[t.reference.inertia], &t.field, &[t.reference.initial], dt)
        .is_err()
    {
        return false;
    }
    observe(integrator.as_ref());
    for _ in 0..steps {
        integrator.step(&t.field);
        observe(integrator.as_ref());
    }
    true
}

/// The total energy `1/2 w.I w + V`, written out here from the principal
/// moments and the field.
fn total_energy(integrator: &dyn Integrator) -> f64 {
    let t = table();
    let mut w = [Vector3::zeros()];
    integrator.omega_body(&mut w);
    let kinetic = 0.5 * w[0].dot(&t.reference.inertia.principal().component_mul(&w[0]));
    kinetic + t.field.energy(integrator.orientations())
}

/// The orientation of `variant` at `t_error` with steps of `dt`; `None`
/// for a run that left finite numbers.
fn final_orientation(variant: Variant, dt: f64) -> Option<Quat> {
    let steps = (SETTINGS.t_error / dt).round() as usize;
    let mut last = Quat::IDENTITY;
    assert!(run_variant(variant, dt, steps, |i| last = i.orientations()[0]));
    last.is_finite().then_some(last)
}

/// The table's steps for the errors and the order fit.
const ERROR_STEPS: [f64; 3] = [SETTINGS.dt, SETTINGS.dt / 2.0, SETTINGS.dt / 4.0];

/// The table's global error of each configuration is its error against the
/// scipy reference to within the error of the table's own reference run
/// (scheme A at `dt / 64`; the triangle inequality), that error measured
/// here against scipy too. A run that blows up has no error (NaN).
#[test]
fn global_errors_are_the_errors_against_scipy() {
    let t = table();
    let scipy = *t.reference.orientations.last().expect("samples");
    let reference = final_orientation(Variant::A, SETTINGS.dt / 64.0).expect("stable");
    // The angle's rounding (|Q| ~ 1).
    let bound = reference.angle_to(&scipy) + 1e-15;
    for row in &t.rows {
        match final_orientation(row.variant, SETTINGS.dt) {
            None => assert!(row.global_error.is_nan(), "{}: blew up here", row.label),
            Some(q) => {
                let error = max_angle(&[q], &[scipy]);
                assert!(
                    (row.global_error - error).abs() <= bound,
                    "{}: table {:e}, against scipy {error:e}, bound {bound:e}",
                    row.label,
                    row.global_error
                );
            }
        }
    }
}

/// The table's order, from its errors at `dt` and `dt/4`, is the
/// least-squares slope of `ln error` against `ln dt` over `dt`, `dt/2`,
/// `dt/4` (its doc: the middle point of three equally spaced in `ln dt` has
/// no weight), each error against scheme A at `dt / 64`, as recomputed here
/// from runs of each step, to rounding (planted: the second step `4 dt`
/// moves it by 1e-2).
#[test]
fn orders_are_the_fits_of_the_errors_at_three_steps() {
    let reference = final_orientation(Variant::A, SETTINGS.dt / 64.0).expect("stable");
    for row in &table().rows {
        let errors: Vec<f64> = ERROR_STEPS
            .iter()
            .map(|&dt| {
                final_orientation(row.variant, dt)
                    .map_or(f64::NAN, |q| max_angle(&[q], &[reference]))
            })
            .collect();
        let order = gear_common::fitted_order(&ERROR_STEPS, &errors);
        if order.is_nan() {
            assert!(row.order.is_nan(), "{}: a step blew up here", row.label);
        } else {
            assert!(
                (row.order - order).abs() <= 1e-9,
                "{}: table order {}, recomputed {order}",
                row.label,
                row.order
            );
        }
    }
}

/// The largest stable step is the last of `dt * 2^(k/4)`, k = 0, 1, ..., 16,
/// before the first at which a run of `t_stability` leaves finite numbers
/// or moves the total energy from its start by more than
/// `STABILITY_ENERGY_FRACTION` of the initial kinetic energy, as checked
/// here step by step (planted: every run stable, none stable, the energy
/// bound reversed, the grid `dt + 2^(k/4)`).
#[test]
fn the_largest_stable_step_is_the_definitions() {
    let stable = |variant: Variant, dt: f64| {
        let steps = (SETTINGS.t_stability / dt).round() as usize;
        let (mut start, mut ok) = (None, true);
        let set_up = run_variant(variant, dt, steps, |i| {
            let e = total_energy(i);
            let (e0, bound) = *start.get_or_insert_with(|| {
                let k0 = e - table().field.energy(i.orientations());
                (e, STABILITY_ENERGY_FRACTION * k0)
            });
            ok &= e.is_finite() && (e - e0).abs() <= bound;
        });
        set_up && ok
    };
    let mut seen_unstable = false;
    for row in &table().rows {
        let grid = |k: usize| SETTINGS.dt * 2f64.powf(k as f64 / 4.0);
        let first_unstable = (0..=STABILITY_STEPS).find(|&k| !stable(row.variant, grid(k)));
        seen_unstable |= first_unstable.is_some();
        let expected = match first_unstable {
            Some(0) => None,
            Some(k) => Some(grid(k - 1)),
            None => Some(grid(STABILITY_STEPS)),
        };
        assert_eq!(row.largest_stable_dt, expected, "{}", row.label);
    }
    assert!(
        seen_unstable,
        "no configuration has a largest stable step below 16 dt: the scan tests nothing"
    );
}

/// `max |Q.Q'|` over the energy run (eq 15a): at rounding level where `Q'`
/// is kept orthogonal to `Q` (scheme A, whose `Q'` is eq 10 of its `w`, and
/// scheme B with the velocity projection), the size of the truncation error
/// without it; the same number as `Q.Q'` from the integrator's own `Q'` at
/// every step of the run here.
#[test]
fn the_largest_norm_velocity_is_that_of_the_run() {
    const ROUNDING: f64 = 1e-13;
    for row in &table().rows {
        let steps = (SETTINGS.t_energy / SETTINGS.dt).round() as usize;
        // The table's run stops at its first sample of non-finite energy.
        let (mut largest, mut finite): (f64, bool) = (0.0, true);
        assert!(run_variant(row.variant, SETTINGS.dt, steps, |i| {
            finite &= total_energy(i).is_finite();
            if finite {
                let mut q_dot = [Quat::IDENTITY];
                i.q_dot(&mut q_dot);
                largest = largest.max(i.orientations()[0].dot(&q_dot[0]).abs());
            }
        }));
        assert_eq!(row.max_norm_velocity, largest, "{}", row.label);
        let kept = match row.variant {
            Variant::A => true,
            Variant::B(GearBOptions {
                project_velocity, ..
            }) => project_velocity,
        };
        if kept {
            assert!(largest < ROUNDING, "{}: {largest:e}", row.label);
        } else {
            assert!(largest > 1e3 * ROUNDING, "{}: {largest:e}", row.label);
        }
    }
}

/// The configurations read from `gear_corrections.toml` (the list the Python
/// long runs read too) are the note's: scheme A, then scheme B with no
/// correction, each correction added in the note's order, every correction
/// with the higher derivatives corrected too, and every correction with
/// c0 = 3/20.
#[test]
fn configuration_file_gives_the_notes_configurations() {
    use quatrot::integrators::{FirstCorrector, GearBOptions};
    let none = GearBOptions {
        project_torque: false,
        project_velocity: false,
        renormalise: false,
        ..GearBOptions::default()
    };
    let full = GearBOptions::default();
    assert!(full.project_torque && full.project_velocity && full.renormalise);
    assert!(!full.correct_higher_derivatives);
    let expected = vec![
        ("A (renormalised)", Variant::A),
        ("B, no correction", Variant::B(none)),
        (
            "B, renormalisation only",
            Variant::B(GearBOptions {
                renormalise: true,
                ..none
            }),
        ),
        (
            "B, torque only",
            Variant::B(GearBOptions {
                project_torque: true,
                ..none
            }),
        ),
        (
            "B, torque + velocity",
            Variant::B(GearBOptions {
                project_torque: true,
                project_velocity: true,
                ..none
            }),
        ),
        ("B, torque + velocity + renormalisation", Variant::B(full)),
        (
            "B, all + higher derivatives",
            Variant::B(GearBOptions {
                correct_higher_derivatives: true,
                ..full
            }),
        ),
        (
            "B, all, c0 = 3/20",
            Variant::B(GearBOptions {
                c0: FirstCorrector::PositionOnly,
                ..full
            }),
        ),
    ];
    let found = variants();
    let found: Vec<(&str, Variant)> = found.iter().map(|(l, v)| (l.as_str(), *v)).collect();
    assert_eq!(found, expected);
}
