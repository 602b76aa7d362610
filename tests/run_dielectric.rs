//! The dielectric constant of a recorded run (`run::dielectric_of_run`):
//! the ideal dipolar gas limit from synthetic series against the closed
//! form, the formula and volume taken from the run's summary, the
//! temperature from its recorded column, the same result from the output
//! files as from the run in memory, and the refusals.

use nalgebra::Vector3;
use quatrot::potential::Surface;
use quatrot::run::{
    dielectric_of_run, dipole_series, execute, read_run, InteractionsSummary, SeriesTable,
};
use quatrot::scene::raw::SumKind;
use quatrot::scene::{load_text, Overrides};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;

mod common;

/// How far the estimate may be from the closed form, in its own standard
/// errors (two-sided 6e-5 for a normal estimate).
const Z: f64 = 4.0;
/// The blocking error against the exact standard error of the ideal gas
/// (the blocking estimate scatters by ~1 % at 20000 frames; a factor 2
/// fails).
const ERROR_TOLERANCE: f64 = 0.10;

fn ewald(box_lengths: [f64; 3], surface: Surface) -> InteractionsSummary {
    InteractionsSummary {
        boundary: "periodic".to_string(),
        box_lengths: Some(box_lengths),
        sum: Some(SumKind::Ewald),
        cutoff: None,
        accuracy: Some(1e-12),
        surface: Some(surface),
        path: "ewald_lattice_fft".to_string(),
        ewald: None,
        lattice: None,
        mesh: None,
        choice: None,
    }
}

/// A series `observables` of `M` and `temperature` per frame, as a run
/// records it.
fn series(dipoles: &[Vector3<f64>], temperatures: &[f64]) -> SeriesTable {
    let columns = ["step", "time", "M_x", "M_y", "M_z", "temperature"];
    let values = dipoles
        .iter()
        .zip(temperatures)
        .enumerate()
        .flat_map(|(k, (m, t))| [k as f64, k as f64, m.x, m.y, m.z, *t])
        .collect();
    SeriesTable {
        name: "observables".to_string(),
        columns: columns.map(str::to_string).to_vec(),
        values,
    }
}

/// The ideal dipolar gas: `N` independent dipoles of moment `mu`, uniformly
/// oriented in every frame (seed 5), in a box of volume `V`, the recorded
/// temperature fluctuating around `T` (+-20 %, mean exactly `T`). The run's
/// dielectric constant takes the conducting formula from an Ewald summary
/// with conducting surroundings, the vacuum one from vacuum surroundings,
/// `V` from the box and `T` from the column: `eps - 1 = 4 pi n mu^2 / (3 T)`
/// and `(eps - 1)/(eps + 2) = 4 pi n mu^2 / (9 T)`, within `Z` errors, the
/// errors within `ERROR_TOLERANCE` of the exact one
/// (`Var |M|^2 = 2/3 N (N - 1) mu^4`).
#[test]
fn ideal_dipolar_gas_from_a_recorded_series() {
    let (n, frames, mu, temperature) = (64, 20_000, 1.2, 1.5);
    let box_lengths = [10.0, 8.0, 6.25];
    let volume: f64 = box_lengths.iter().product();
    let mut rng = ChaCha20Rng::seed_from_u64(5);
    let dipoles: Vec<Vector3<f64>> = (0..frames)
        .map(|_| {
            (0..n)
                .map(|_| {
                    let v = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
                    v / v.norm() * mu
                })
                .sum()
        })
        .collect();
    let temperatures: Vec<f64> = (0..frames)
        .map(|k| temperature * (1.0 + if k % 2 == 0 { 0.2 } else { -0.2 }))
        .collect();
    let table = series(&dipoles, &temperatures);
    let nf = n as f64;
    let y = 4.0 * PI * nf * mu * mu / (9.0 * volume * temperature);
    let y_error = y * (2.0 / 3.0 * nf * (nf - 1.0)).sqrt() / nf / (frames as f64).sqrt();
    for (surface, exact, exact_error) in [
        (Surface::Conducting, 1.0 + 3.0 * y, 3.0 * y_error),
        (
            Surface::Vacuum,
            (1.0 + 2.0 * y) / (1.0 - y),
            3.0 * y_error / (1.0 - y).powi(2),
        ),
    ] {
        let eps = dielectric_of_run(Some(&ewald(box_lengths, surface)), &table, None)
            .expect("a formula applies");
        assert!(
            (eps.epsilon - exact).abs() < Z * eps.error,
            "{surface:?}: {} +- {} vs {exact}",
            eps.epsilon,
            eps.error
        );
        assert!(
            (eps.error / exact_error - 1.0).abs() < ERROR_TOLERANCE,
            "{surface:?}: error {} vs {exact_error}",
            eps.error
        );
        // A temperature given overrides the column.
        let at_twice = dielectric_of_run(
            Some(&ewald(box_lengths, surface)),
            &table,
            Some(2.0 * temperature),
        )
        .expect("a formula applies");
        if surface == Surface::Conducting {
            assert!(((at_twice.epsilon - 1.0) / (eps.epsilon - 1.0) - 0.5).abs() < 1e-12);
        }
    }
}

/// No formula for a truncated sum, an open cluster or a run without
/// interactions; a series without `M`, or without a temperature when none
/// is given, is named.
#[test]
fn refusals_name_what_is_missing() {
    let m = [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 1.0, 0.0)];
    let table = series(&m, &[1.0, 1.0]);
    let mut cutoff = ewald([4.0; 3], Surface::Conducting);
    (cutoff.sum, cutoff.surface, cutoff.accuracy, cutoff.cutoff) =
        (Some(SumKind::Cutoff), None, None, Some(1.5));
    let err = |i: Option<&InteractionsSummary>, t: &SeriesTable, temperature| {
        dielectric_of_run(i, t, temperature)
            .unwrap_err()
            .to_string()
    };
    assert!(err(Some(&cutoff), &table, None).starts_with(
        "boundary: cutoff: no fluctuation formula applies to a plain spherical cutoff"
    ));
    let open = InteractionsSummary {
        boundary: "open".to_string(),
        box_lengths: None,
        sum: None,
        cutoff: None,
        accuracy: None,
        surface: None,
        path: "open_pairs".to_string(),
        ewald: None,
        lattice: None,
        mesh: None,
        choice: None,
    };
    assert!(err(Some(&open), &table, None).starts_with("boundary: open: no fluctuation formula"));
    assert_eq!(
        err(None, &table, None),
        "boundary: the run has no pair interactions, so no boundary gives a fluctuation formula"
    );
    let conducting = ewald([4.0; 3], Surface::Conducting);
    let mut without_m = table.clone();
    without_m.columns[2] = "kinetic_energy".to_string();
    assert_eq!(
        err(Some(&conducting), &without_m, None),
        "series: `observables` records no total dipole (add \"M\" to its quantities)"
    );
    let mut without_t = table.clone();
    without_t.columns[5] = "norm_error".to_string();
    assert_eq!(
        err(Some(&conducting), &without_t, None),
        "temperature: give it, or record \"temperature\" in the series `observables` with \"M\""
    );
    assert!(dielectric_of_run(Some(&conducting), &without_t, Some(1.0)).is_ok());
    // Found by the analysis fuzz (issue 37): the run's total dipoles were
    // named `dipoles`, an argument of another function.
    let mut huge = table.clone();
    huge.values[2] = f64::INFINITY;
    assert_eq!(
        err(Some(&conducting), &huge, None),
        "series `observables`: M[0]: must be finite"
    );
    huge.values[2] = 1e200;
    assert_eq!(
        err(Some(&conducting), &huge, None),
        "series `observables`: M: |M|^2 overflows float64: the dipoles are too large"
    );
    assert!(err(Some(&conducting), &table, Some(1e-320)).starts_with(
        "interactions.box, temperature: 4 pi / (9 V T) overflows float64 (V = 64, T = 1e-320)"
    ));
    assert_eq!(
        dipole_series(&[without_m.clone()], None)
            .unwrap_err()
            .to_string(),
        "series: no series of the run records the total dipole (add \"M\" to a series' quantities)"
    );
    let mut other = table.clone();
    other.name = "other".to_string();
    assert_eq!(
        dipole_series(&[table.clone(), other.clone()], None)
            .unwrap_err()
            .to_string(),
        "series: several series record \"M\" (observables, other): name one"
    );
    assert_eq!(
        dipole_series(&[table.clone(), other], Some("other"))
            .expect("named")
            .name,
        "other"
    );
}

/// A run of the built-in Ewald lattice recording `M` and the temperature:
/// the dielectric constant from its output files (summary.json and the CSV)
/// is the one from the run in memory, bit for bit, and the fluctuation
/// formula of `analysis` applied by hand (V = 1000, T the mean recorded
/// temperature, conducting); the truncated variant is refused.
#[test]
fn a_run_from_its_files_and_from_memory() {
    let base = quatrot::scene::builtin("dipole_lattice_sc")
        .expect("built-in")
        .toml
        .replace("steps = 500", "steps = 60");
    let record = "\n[[record.series]]\nname = \"polarization\"\nevery = 2\nquantities = [\"M\", \"M2\", \"temperature\"]\n";
    let dir = tempfile::tempdir().expect("dir");
    let (raw, scene) = load_text(&format!("{base}{record}"), &Overrides::default()).expect("valid");
    let outputs = common::outputs(Some(dir.path()), true);
    let result = execute(&scene, raw.definition(), &outputs, None, None).expect("runs");
    // The built-in's own `energies` series records M too (every 10 steps):
    // with two, the series must be named.
    assert!(dipole_series(&result.series, None)
        .unwrap_err()
        .message
        .starts_with("several series record \"M\" (energies, polarization)"));
    let in_memory = dielectric_of_run(
        result.summary.interactions.as_ref(),
        dipole_series(&result.series, Some("polarization")).expect("named"),
        None,
    )
    .expect("conducting Ewald");
    let (interactions, tables) = read_run(dir.path()).expect("outputs readable");
    assert_eq!(tables.len(), 2);
    let from_files = dielectric_of_run(
        interactions.as_ref(),
        dipole_series(&tables, Some("polarization")).expect("named"),
        None,
    )
    .expect("conducting Ewald");
    assert_eq!(from_files, in_memory);
    let table = dipole_series(&tables, Some("polarization")).expect("named");
    let rows: Vec<&[f64]> = table.values.chunks(table.columns.len()).collect();
    let m: Vec<Vector3<f64>> = rows
        .iter()
        .map(|r| Vector3::new(r[2], r[3], r[4]))
        .collect();
    let t = rows.iter().map(|r| r[6]).sum::<f64>() / rows.len() as f64;
    for (r, m) in rows.iter().zip(&m) {
        assert!((r[5] - m.norm_squared()).abs() <= 1e-12 * r[5]);
    }
    let by_hand = quatrot::analysis::dielectric_constant(
        &m,
        1000.0,
        t,
        quatrot::analysis::DielectricBoundary::Conducting,
    )
    .expect("formula");
    assert_eq!(by_hand, in_memory);

    let cutoff = base.replace(
        r#"boundary = { kind = "periodic", sum = "ewald" }"#,
        r#"boundary = { kind = "periodic", sum = "cutoff", cutoff = 3.1 }"#,
    );
    let (raw, scene) =
        load_text(&format!("{cutoff}{record}"), &Overrides::default()).expect("valid");
    let result = execute(&scene, raw.definition(), &outputs, None, None).expect("runs");
    let refused = dielectric_of_run(
        result.summary.interactions.as_ref(),
        dipole_series(&result.series, Some("polarization")).expect("named"),
        None,
    )
    .unwrap_err();
    assert_eq!(refused.path, "boundary");
}
