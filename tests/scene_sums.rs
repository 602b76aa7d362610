//! The periodic sums as scenes ask for them: the `[interactions]` boundary
//! read into the Ewald or the truncated sum, run end to end against the
//! closed form of aligned cubic dipole lattices, and `summary.json`
//! recording the path taken and the Ewald parameters chosen.

use nalgebra::Vector3;
use quatrot::potential::multipole::mesh_ewald::ForcedMesh;
use quatrot::potential::{Boundary, PeriodicSum, SumMethod, Surface};
use quatrot::run::{execute, potential, RunResult, SUMMARY_FILE};
use quatrot::scene::{load, load_text, Interactions, Overrides};
use std::f64::consts::PI;

mod common;

/// Lattice sums of ~1e3-1e4 terms whose absolute sum is ~20 times their
/// total, each rounded to ~1e-16, plus the kinetic energy subtracted from the
/// recorded total (the potential energy is recorded as `E - K`): relative to
/// the lattice energy.
const LATTICE_ROUND_OFF: f64 = 1e-13;
/// The default Ewald sum is truncated at the default accuracy (the error of
/// the fields relative to a neighbour's, so of the energy relative to the
/// lattice energy): fcc at 1e-12 is 9e-14 off (measured).
const DEFAULT_ACCURACY: f64 = 1e-12;

/// A lattice of unit dipoles, all along body z, at rest and aligned along
/// space z, with the given boundary table, recording the potential energy
/// at step 0.
fn aligned(lattice: &str, cells: usize, spacing: f64, boundary: &str) -> String {
    format!(
        r#"
version = 1
[rotors]
kind = "lattice"
lattice = "{lattice}"
cells = {cells}
spacing = {spacing}
default = {{ inertia = 0.1, dipole = [0.0, 0.0, 1.0] }}
[interactions]
boundary = {boundary}
[initial]
kind = "uniform"
orientation = [1.0, 0.0, 0.0, 0.0]
omega_body = [0.0, 0.0, 0.0]
[integrator]
kind = "dlm"
[run]
dt = 0.001
steps = 1
[[record.series]]
every = 1
quantities = ["potential_energy"]
"#
    )
}

fn run(text: &str) -> RunResult {
    let (raw, scene) = load_text(text, &Overrides::default()).expect("valid scene");
    execute(&scene, raw.definition(), &common::in_memory(), None, None).expect("runs")
}

/// The potential energy recorded at step 0.
fn first_potential_energy(result: &RunResult) -> f64 {
    result.series[0].values[2]
}

/// A periodic boundary without `sum` is the Ewald sum: the aligned sc, bcc
/// and fcc lattices run from a scene have the Lorentz energy
/// `-(2 pi / 3) n mu^2` per dipole with conducting surroundings (the
/// default) within the default accuracy, and with `surface = "vacuum"` at
/// accuracy 1e-14 that plus `2 pi |M|^2 / (3 V)` (`M = N mu` along z) to
/// round-off.
#[test]
fn aligned_lattices_from_scenes_have_the_closed_form_energies() {
    for (lattice, per_cell, cells) in [("simple_cubic", 1, 4), ("bcc", 2, 3), ("fcc", 4, 3)] {
        let spacing = 1.3;
        let n = (per_cell * cells * cells * cells) as f64;
        let volume = (cells as f64 * spacing).powi(3);
        let lorentz = -(2.0 * PI / 3.0) * (n / volume) * n;
        let surface = 2.0 * PI * n * n / (3.0 * volume);
        for (boundary, expected, tolerance) in [
            ("{ kind = 'periodic' }", lorentz, DEFAULT_ACCURACY),
            (
                "{ kind = 'periodic', sum = 'ewald', surface = 'vacuum', accuracy = 1e-14 }",
                lorentz + surface,
                LATTICE_ROUND_OFF,
            ),
        ] {
            let result = run(&aligned(lattice, cells, spacing, boundary));
            let energy = first_potential_energy(&result);
            assert!(
                (energy - expected).abs() <= tolerance * lorentz.abs(),
                "{lattice} {boundary}: {energy} vs {expected}"
            );
        }
    }
}

/// The built-in dipole lattice is summed by Ewald (conducting surroundings,
/// accuracy 1e-12, the automatic path), and `dipole_lattice_sc_cutoff` is
/// the same scene with the truncated sum it had before (cutoff 3.1).
#[test]
fn the_builtin_lattice_is_ewald_and_its_cutoff_variant_the_same_system_truncated() {
    let (_, ewald) = load("dipole_lattice_sc", &Overrides::default()).expect("built-in");
    let (_, cutoff) = load("dipole_lattice_sc_cutoff", &Overrides::default()).expect("built-in");
    let box_lengths = Vector3::repeat(10.0);
    assert_eq!(
        ewald.interactions,
        Some(Interactions {
            boundary: Boundary::periodic_ewald(box_lengths),
            method: SumMethod::Auto,
            forced: ForcedMesh::default(),
        })
    );
    assert_eq!(
        cutoff.interactions,
        Some(Interactions {
            boundary: Boundary::periodic_cutoff(box_lengths, 3.1),
            method: SumMethod::Auto,
            forced: ForcedMesh::default(),
        })
    );
    assert_eq!(
        (&ewald.rotors, &ewald.initial, ewald.integrator, ewald.dt),
        (
            &cutoff.rotors,
            &cutoff.initial,
            cutoff.integrator,
            cutoff.dt
        )
    );
    assert_eq!(
        (ewald.steps, &ewald.record, ewald.seed),
        (cutoff.steps, &cutoff.record, cutoff.seed)
    );
}

/// `summary.json` records the boundary as run, the path the potential took
/// and, for Ewald sums, the parameters the potential chose (read back from
/// the file; the estimated error within the accuracy asked): the FFT path
/// on the built-in lattice, the pair list for its cutoff variant, the direct
/// Ewald sum when `method = "direct"` and on sites that are not a lattice,
/// the truncated sum by FFT when `method = "lattice_fft"`, the mesh Ewald
/// sum and its mesh when `method = "pme"`, every pair of an open cluster.
#[test]
fn the_summary_records_the_sum_path_and_the_ewald_parameters() {
    let base = quatrot::scene::builtin("dipole_lattice_sc")
        .expect("built-in")
        .toml;
    let with_boundary = |boundary: &str| {
        base.replace(
            r#"boundary = { kind = "periodic", sum = "ewald" }"#,
            &format!("boundary = {boundary}"),
        )
    };
    let cases = [
        ("{ kind = 'periodic' }", "ewald_lattice_fft"),
        (
            "{ kind = 'periodic', sum = 'ewald', accuracy = 1e-6, method = 'direct', surface = 'vacuum' }",
            "ewald_direct",
        ),
        (
            "{ kind = 'periodic', sum = 'cutoff', cutoff = 3.1 }",
            "cutoff_pairs",
        ),
        (
            "{ kind = 'periodic', sum = 'cutoff', cutoff = 2.5, method = 'lattice_fft' }",
            "cutoff_lattice_fft",
        ),
        (
            "{ kind = 'periodic', sum = 'ewald', accuracy = 1e-4, method = 'pme' }",
            "ewald_pme",
        ),
    ];
    let dir = tempfile::tempdir().expect("temporary directory");
    for (boundary, path) in cases {
        let text = with_boundary(boundary).replace("steps = 500", "steps = 2");
        let (raw, scene) = load_text(&text, &Overrides::default()).expect("valid");
        let outputs = common::outputs(Some(dir.path()), false);
        let result = execute(&scene, raw.definition(), &outputs, None, None).expect("runs");
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(SUMMARY_FILE)).expect("summary written"),
        )
        .expect("JSON");
        let recorded = serde_json::to_value(&result.summary.interactions).expect("JSON");
        assert_eq!(summary["interactions"], recorded, "{boundary}");
        assert_eq!(recorded["path"], path, "{boundary}");
        assert_eq!(recorded["boundary"], "periodic");
        assert_eq!(recorded["box"], serde_json::json!([10.0, 10.0, 10.0]));
        let built = potential(&scene).expect("builds").expect("interacts");
        let Some(Interactions {
            boundary: Boundary::Periodic { sum, .. },
            ..
        }) = scene.interactions
        else {
            panic!("periodic")
        };
        let in_memory = result.summary.interactions.as_ref().expect("interacting");
        // The mesh record is written for the PME path only: the other
        // summaries keep their bytes.
        assert_eq!(
            recorded.get("mesh").is_some(),
            path == "ewald_pme",
            "{boundary}"
        );
        match sum {
            PeriodicSum::Ewald { accuracy, .. } if path == "ewald_pme" => {
                let (p, e) = built.mesh_parameters().expect("mesh parameters");
                let mesh = in_memory.mesh.expect("mesh parameters recorded");
                assert_eq!(
                    (mesh.alpha, mesh.real_cutoff, mesh.grid, mesh.order),
                    (p.alpha, p.real_cutoff, p.grid, p.order)
                );
                assert_eq!((mesh.real_estimate, mesh.mesh_estimate), (e.real, e.mesh));
                assert!(mesh.estimated_error <= accuracy.get(), "{boundary}");
                assert!(recorded["ewald"].is_null());
                assert_eq!(recorded["mesh"]["grid"], serde_json::json!(p.grid));
            }
            PeriodicSum::Ewald { accuracy, surface } => {
                let p = built.ewald_parameters().expect("Ewald parameters");
                let ewald = in_memory.ewald.expect("Ewald parameters recorded");
                assert_eq!(
                    (ewald.alpha, ewald.real_cutoff, ewald.reciprocal_cutoff),
                    (p.alpha, p.real_cutoff, p.reciprocal_cutoff)
                );
                assert_eq!(
                    (ewald.real_estimate, ewald.reciprocal_estimate),
                    (p.real_estimate, p.reciprocal_estimate)
                );
                assert_eq!(
                    ewald.estimated_error,
                    p.real_estimate + p.reciprocal_estimate
                );
                assert!(ewald.estimated_error <= accuracy.get(), "{boundary}");
                assert_eq!(in_memory.accuracy, Some(accuracy.get()));
                assert_eq!(in_memory.surface, Some(surface));
                assert_eq!(recorded["surface"], surface.as_str());
                assert_eq!(recorded["sum"], "ewald");
            }
            PeriodicSum::Cutoff { cutoff } => {
                assert!(recorded["ewald"].is_null());
                assert_eq!(in_memory.cutoff, Some(cutoff));
                assert_eq!(recorded["sum"], "cutoff");
            }
        }
        let on_lattice = path.ends_with("lattice_fft");
        assert_eq!(!recorded["lattice"].is_null(), on_lattice, "{boundary}");
        if on_lattice {
            assert_eq!(
                recorded["lattice"]["cells"],
                serde_json::json!([10, 10, 10])
            );
            assert_eq!(recorded["lattice"]["basis"], 1);
        }
        if let PeriodicSum::Ewald { surface, .. } = sum {
            assert_eq!(
                surface == Surface::Vacuum,
                boundary.contains("vacuum"),
                "{boundary}"
            );
        }
    }
    let irregular = r#"
version = 1
[rotors]
kind = "sites"
default = { inertia = 1.0, dipole = [0.0, 0.0, 1.0] }
sites = [{ position = [0.0, 0.0, 0.0] }, { position = [1.23456789, 0.3, 0.7] }]
[interactions]
boundary = { kind = "periodic", box = [3.0, 3.0, 3.0] }
[initial]
kind = "random"
seed = 3
temperature = 1.0
[integrator]
kind = "dlm"
[run]
dt = 0.001
steps = 2
"#;
    let summary = run(irregular).summary;
    let recorded = summary.interactions.expect("interacting");
    assert_eq!(recorded.path, "ewald_direct");
    assert!(recorded.ewald.is_some());
    let open = irregular.replace(
        r#"{ kind = "periodic", box = [3.0, 3.0, 3.0] }"#,
        r#"{ kind = "open" }"#,
    );
    let recorded = run(&open).summary.interactions.expect("interacting");
    assert_eq!(
        (recorded.boundary.as_str(), recorded.path.as_str()),
        ("open", "open_pairs")
    );
    assert!(recorded.ewald.is_none() && recorded.box_lengths.is_none());
}
