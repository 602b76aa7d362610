//! `method = "auto"` on sites that are not a lattice: the direct Ewald sum
//! for small systems, PME above the crossover of their cost models
//! (`src/potential/multipole/auto_choice.rs`), the direct sum for
//! accuracies PME cannot reach; each path's sum within the request against
//! the converged direct sum, and the choice recorded (`summary.json`'s
//! `interactions.choice`); PME when the direct sum is too large to build.
//! Lattices keep the FFT path.

mod multipole_support;

use multipole_support::*;
use nalgebra::{Matrix3, Vector3};
use quatrot::potential::multipole::AutoChoice;
use quatrot::potential::{
    Boundary, ExternalFields, MultipolePotential, SumMethod, SumOptions, SumPath,
};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::run::{execute, InteractionsSummary};
use quatrot::scene::{load_text, Overrides};
use quatrot::Quat;
use rand::RngExt;

mod common;

/// The accuracy of the reference sums: the direct sum's truncation below
/// round-off by its estimate.
const CONVERGED: f64 = 1e-15;

/// The Ewald sum at `accuracy` in a conductor, as a scene's boundary gives it.
fn ewald(box_lengths: Vector3<f64>, accuracy: f64) -> Boundary {
    let options = SumOptions {
        accuracy: Some(accuracy),
        ..SumOptions::default()
    };
    Boundary::periodic(box_lengths, &options).expect("a valid sum")
}

/// `cells^3` unit dipoles at simple-cubic sites of unit spacing each moved
/// uniformly within +-0.25 per axis (irregular, as a liquid, no two closer
/// than 0.5: the benchmark's configuration), random orientations; the box edge.
fn jittered_dipoles(cells: usize, seed: u64) -> (Vec<Rotor>, Vec<Quat>, f64) {
    let mut r = rng(seed);
    let rotors: Vec<Rotor> = (0..cells.pow(3))
        .map(|k| {
            let cell = Vector3::new(k % cells, (k / cells) % cells, k / (cells * cells));
            let site = Vector3::from_fn(|a, _| cell[a] as f64 + 0.5 + r.random_range(-0.25..0.25));
            Rotor {
                site,
                inertia: Inertia::Spherical(1.0),
                dipole_body: Some(Vector3::z()),
                quadrupole_body: None,
            }
        })
        .collect();
    let q = rotors.iter().map(|_| random_orientation(&mut r)).collect();
    (rotors, q, cells as f64)
}

fn build(rotors: &[Rotor], edge: f64, accuracy: f64, method: SumMethod) -> MultipolePotential {
    MultipolePotential::with_method(
        rotors,
        ewald(Vector3::repeat(edge), accuracy),
        ExternalFields::NONE,
        method,
    )
    .expect("builds")
}

/// The torques and energy of `p` at `q`.
fn evaluate(p: &MultipolePotential, q: &[Quat]) -> (f64, Vec<Vector3<f64>>) {
    let mut torques = vec![Vector3::zeros(); q.len()];
    let energy = p.evaluate(q, None, Some(&mut torques));
    (energy, torques)
}

/// The RMS torque error of `p` against the converged direct sum, relative
/// to the torque scale `mu^2 n` of unit dipoles at unit density (the scale
/// of the accuracy, `ewald_parameters`), and the energy error relative to
/// `N mu^2 n`.
fn errors(p: &MultipolePotential, rotors: &[Rotor], q: &[Quat], edge: f64) -> (f64, f64) {
    let reference = build(rotors, edge, CONVERGED, SumMethod::Direct);
    let (e0, t0) = evaluate(&reference, q);
    let (e, t) = evaluate(p, q);
    let n = rotors.len() as f64;
    let density = n / edge.powi(3);
    let squares: f64 = t.iter().zip(&t0).map(|(a, b)| (a - b).norm_squared()).sum();
    (
        (squares / n).sqrt() / density,
        (e - e0).abs() / (n * density),
    )
}

/// 125 dipoles at 1e-5 take the direct sum, 1,728 at 1e-4 take PME (the
/// model's crossovers are 168 and 116 dipoles, docs/scenes.md); each is
/// within the request against the converged sum, and the choice records
/// both estimates with the cheaper one taken.
#[test]
fn small_systems_take_the_direct_sum_and_large_ones_pme() {
    for (cells, accuracy, path) in [
        (5, 1e-5, SumPath::EwaldDirect),
        (12, 1e-4, SumPath::EwaldPme),
    ] {
        let (rotors, q, edge) = jittered_dipoles(cells, 7);
        let p = build(&rotors, edge, accuracy, SumMethod::Auto);
        assert_eq!(p.sum_path(), path, "{cells}^3 at {accuracy:e}");
        let choice: &AutoChoice = p.auto_choice().expect("the choice is recorded");
        let pme = choice.pme_seconds.expect("PME reaches the accuracy");
        assert_eq!(choice.takes_pme(), path == SumPath::EwaldPme);
        let direct = choice.direct_seconds.expect("the direct sum fits");
        assert_eq!(pme < direct, path == SumPath::EwaldPme, "{choice:?}");
        let (torque, energy) = errors(&p, &rotors, &q, edge);
        println!("{cells}^3 at {accuracy:e}: {choice:?}, RMS torque error {torque:.2e}, energy {energy:.2e}");
        assert!(
            torque <= accuracy && energy <= accuracy,
            "{cells}^3 at {accuracy:e}: torque {torque:e}, energy {energy:e}"
        );
    }
}

/// `cells^3` jittered sites as [`jittered_dipoles`], each carrying a linear
/// unit quadrupole along body z instead of the dipole.
fn jittered_quadrupoles(cells: usize, seed: u64) -> (Vec<Rotor>, f64) {
    let (mut rotors, _, edge) = jittered_dipoles(cells, seed);
    for r in &mut rotors {
        r.dipole_body = None;
        r.quadrupole_body = Some(Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0)));
    }
    (rotors, edge)
}

/// Quadrupoles at 1e-5 take the path measured cheaper on both hosts
/// measured (benchmarks/RESULTS.md, mesh sections of 2026-12-02): 125 the
/// direct sum (1.6 against PME's 9.0 ms per evaluation on the Intel Xeon,
/// 3.0-3.3 against 10.2-10.9 ms on the AMD EPYC), 4,096 PME (116 against
/// 136 ms on the Xeon, alternating; the EPYC's crossover is 730 to 840).
/// Between them the hosts disagree (1,000: PME on the EPYC, 63-66 against
/// 67-72 ms; the direct sum on the Xeon, 36 against 47 ms). Before the
/// models were calibrated per kind, the direct sum was taken up to 13,700
/// quadrupoles.
#[test]
fn quadrupoles_take_the_path_measured_cheaper() {
    for (cells, path) in [(5, SumPath::EwaldDirect), (16, SumPath::EwaldPme)] {
        let (rotors, edge) = jittered_quadrupoles(cells, 11);
        let p = build(&rotors, edge, 1e-5, SumMethod::Auto);
        let choice = p.auto_choice().expect("the choice is recorded");
        assert_eq!(p.sum_path(), path, "{cells}^3 quadrupoles: {choice:?}");
    }
}

/// An accuracy beyond PME's range (the default 1e-12) takes the direct sum
/// whatever the size, the reason naming the refusal; a lattice keeps the
/// FFT lattice sum and "direct" and "pme" make no choice.
#[test]
fn unreachable_accuracies_take_the_direct_sum_and_lattices_the_fft() {
    let (rotors, _, edge) = jittered_dipoles(4, 8);
    let p = build(&rotors, edge, 1e-12, SumMethod::Auto);
    assert_eq!(p.sum_path(), SumPath::EwaldDirect);
    let choice = p.auto_choice().expect("recorded");
    assert_eq!(choice.pme_seconds, None);
    assert!(
        choice
            .reason
            .starts_with("the mesh Ewald sum cannot be used: accuracy: must be from 1e-10 to 1e-2"),
        "{}",
        choice.reason
    );
    for method in [SumMethod::Direct, SumMethod::Pme] {
        assert!(build(&rotors, edge, 1e-4, method).auto_choice().is_none());
    }
    let lattice: Vec<Rotor> = (0..27)
        .map(|k| Rotor {
            site: Vector3::new((k % 3) as f64, ((k / 3) % 3) as f64, (k / 9) as f64),
            ..rotors[0].clone()
        })
        .collect();
    let p = build(&lattice, 3.0, 1e-5, SumMethod::Auto);
    assert_eq!(p.sum_path(), SumPath::EwaldLatticeFft);
    assert!(p.auto_choice().is_none());
}

/// A scene of `rotors` at explicit sites (unit dipoles along body z) in a
/// cubic box of edge `edge`, Ewald at `accuracy` by `method = "auto"`, two
/// DLM steps.
fn irregular_scene(rotors: &[Rotor], edge: f64, accuracy: f64) -> String {
    let sites: Vec<String> = rotors
        .iter()
        .map(|r| {
            format!(
                "{{ position = [{}, {}, {}] }}",
                r.site.x, r.site.y, r.site.z
            )
        })
        .collect();
    format!(
        "version = 1\nname = \"irregular\"\n\
         [rotors]\nkind = \"sites\"\nsites = [{}]\n\
         default = {{ inertia = 1.0, dipole = [0.0, 0.0, 1.0] }}\n\
         [interactions]\nboundary = {{ kind = \"periodic\", accuracy = {accuracy:e}, box = [{edge}, {edge}, {edge}] }}\n\
         [initial]\nkind = \"random\"\nseed = 3\ntemperature = 0.5\n\
         [integrator]\nkind = \"dlm\"\n[run]\ndt = 0.001\nsteps = 2\n",
        sites.join(", ")
    )
}

/// A scene of explicit irregular sites at 1e-6 records the path taken and
/// the choice in `summary.json` (`interactions.choice`: both estimates and
/// the reason), as the potential it builds made it.
#[test]
fn the_summary_records_the_choice() {
    let (rotors, _, edge) = jittered_dipoles(3, 9);
    let text = irregular_scene(&rotors, edge, 1e-6);
    let (raw, scene) = load_text(&text, &Overrides::default()).expect("valid scene");
    let dir = tempfile::tempdir().expect("temporary directory");
    let outputs = common::outputs(Some(dir.path()), false);
    let result = execute(&scene, raw.definition(), &outputs, None, None).expect("runs");
    let written: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("summary.json")).expect("summary written"),
    )
    .expect("JSON");
    let recorded: &InteractionsSummary = result.summary.interactions.as_ref().expect("interacting");
    assert_eq!(
        written["interactions"],
        serde_json::to_value(recorded).expect("JSON")
    );
    let built = build(&rotors, edge, 1e-6, SumMethod::Auto);
    let choice = built.auto_choice().expect("a choice");
    assert_eq!(recorded.path, built.sum_path().as_str());
    let summary = recorded.choice.as_ref().expect("the choice is written");
    assert_eq!(summary.direct_seconds, choice.direct_seconds);
    assert_eq!(summary.pme_seconds, choice.pme_seconds);
    assert_eq!(summary.reason, choice.reason);
    assert_eq!(
        written["interactions"]["choice"]["reason"],
        choice.reason.as_str()
    );
}

/// A direct sum the model prices cheaper but too large to build takes PME
/// (in a run under `--memory-limit 8M`, 125 dipoles at 1e-6: the direct sum
/// needs 12.2 MB, PME 5.8 MB; the model prices the direct sum about 6
/// times cheaper); `summary.json` records why, with no direct estimate.
/// When neither fits (3M), the run is refused before it starts with both
/// reasons, and writes nothing.
#[test]
fn a_direct_sum_too_large_to_build_takes_pme() {
    let (rotors, _, edge) = jittered_dipoles(5, 10);
    let unlimited = build(&rotors, edge, 1e-6, SumMethod::Auto);
    assert_eq!(unlimited.sum_path(), SumPath::EwaldDirect);
    let choice = unlimited.auto_choice().expect("a choice");
    let pme = choice.pme_seconds.expect("PME fits");
    assert!(
        choice.direct_seconds.expect("the direct sum fits") < pme,
        "{choice:?}"
    );
    let dir = tempfile::tempdir().expect("temporary directory");
    let scene = dir.path().join("irregular.toml");
    std::fs::write(&scene, irregular_scene(&rotors, edge, 1e-6)).expect("scene written");
    let run = |limit: &str, out: &str| {
        let out = dir.path().join(out);
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_quatrot"))
            .args(["--memory-limit", limit, "run"])
            .arg(&scene)
            .arg("--out")
            .arg(&out)
            .output()
            .expect("the CLI runs");
        (output, out)
    };
    let (output, out) = run("8M", "fits");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("summary.json")).expect("summary written"),
    )
    .expect("JSON");
    let interactions = &summary["interactions"];
    assert_eq!(interactions["path"], "ewald_pme", "{interactions}");
    assert_eq!(
        interactions["choice"]["direct_seconds"],
        serde_json::Value::Null
    );
    assert_eq!(interactions["choice"]["pme_seconds"], pme);
    let reason = interactions["choice"]["reason"].as_str().expect("a reason");
    assert!(
        reason.starts_with(
            "the direct sum cannot be used: accuracy: the direct Ewald sum of 125 rotors"
        ) && reason.contains("more than the limit"),
        "{reason}"
    );
    let (output, out) = run("3M", "neither");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("the direct Ewald sum of 125 rotors")
            && stderr.contains("; and the mesh Ewald sum cannot be used: accuracy: 1e-6 needs a"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written");
}
