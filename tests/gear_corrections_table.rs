//! The note's correction experiment (`experiments::gear_corrections`) on a
//! single asymmetric rotor in a uniform field: the table has one row per
//! configuration, and the properties that follow from the theory hold in it
//! (the verdicts on the note's claims are reported, not asserted: run with
//! `--nocapture` to see the table).

mod gear_common;

use gear_common::fixtures::reference;
use quatrot::experiments::gear_corrections::{
    correction_table, variants, Settings, System, Variant,
};

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
    let r = reference("dipole_field.json", "dipole_asymmetric");
    let field = r.field.expect("a field case");
    let system = System {
        potential: &field,
        inertia: &[r.inertia],
        initial: &[r.initial],
    };
    let settings = Settings {
        dt: 0.05,
        t_energy: 200.0,
        t_error: 10.0,
        t_stability: 50.0,
        sample_every: 1,
    };
    let rows = correction_table(&system, &settings);
    assert_eq!(rows.len(), variants().len());
    for row in &rows {
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
