//! Checkpoints and restarts of runs of moving bodies (issue 39, item 6
//! "restart bit for bit", and its Bad input paragraph): a run stopped at a
//! checkpoint and restarted writes the files of the uninterrupted run byte
//! for byte, for every integrator on both built-ins; an interrupted run
//! leaves whole outputs and a checkpoint its restart continues; a
//! checkpoint is refused by another scene or when damaged, naming what
//! differs; a blow-up names the step and the bodies.

use quatrot::run::{
    execute, Checkpoint, Outputs, Placement, RunResult, CHECKPOINT_FILE, GSD_FILE, SUMMARY_FILE,
};
use quatrot::scene::{load_text, Overrides, Scene};
use quatrot::simulation::{Control, Stop};
use std::path::Path;
use std::sync::Arc;

mod common;

/// The body integrators, as a scene's `[integrator]` names them.
const INTEGRATORS: [&str; 5] = ["no_squish", "dlm", "richardson", "gear_a", "gear_b"];

/// The built-in scenes of bodies.
const BUILTINS: [&str; 2] = ["stockmayer_fluid", "lewis_wahnstrom_otp"];

/// The summary's fields that differ between a restarted run and the
/// uninterrupted one: the wall time, the step the run started at, the
/// drift (fitted to the energies the run itself computed) and how the
/// files were placed.
const RUN_FIELDS: [&str; 4] = ["wall_seconds", "start_step", "drift", "outputs"];

/// The built-in `name` with a series every 5 steps, checkpoints every 10,
/// and a GSD frame every 10 steps if `gsd` (none otherwise).
fn text(name: &str, gsd: bool) -> String {
    let toml = common::builtin_at_constant_energy(name);
    let toml = toml
        .replace(
            "[[record.series]]",
            "[record]\ncheckpoint_every = 10\n\n[[record.series]]",
        )
        .replace("every = 100\n", "every = 15\n")
        .replace("every = 10\n", "every = 5\n")
        .replace("every = 15\n", "every = 10\n");
    match (gsd, toml.find("[record.trajectory]")) {
        (false, Some(at)) => toml[..at].to_string(),
        _ => toml,
    }
}

/// The scene `text` with `integrator` (default options) for `steps` steps.
fn scene(text: &str, integrator: &str, steps: i64) -> Scene {
    let overrides = Overrides {
        steps: Some(steps),
        integrator: Some(integrator.to_string()),
        ..Overrides::default()
    };
    load_text(text, &overrides).expect("valid").1
}

fn run_in(dir: &Path, scene: &Scene, restart: Option<&Path>) -> RunResult {
    let outputs = common::outputs(Some(dir), false);
    execute(scene, serde_json::Value::Null, &outputs, restart, None).expect("runs")
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The summary in the folder `dir`.
fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&read(&dir.join(SUMMARY_FILE))).expect("JSON")
}

/// The step of the last row of `series.csv` in the folder `dir`, which
/// ends with a whole row.
fn last_row(dir: &Path) -> u64 {
    let csv = String::from_utf8(read(&dir.join("series.csv"))).expect("text");
    assert!(csv.ends_with('\n'), "a partial row");
    let row = csv.lines().last().expect("rows");
    row.split(',')
        .next()
        .and_then(|s| s.parse().ok())
        .expect("a step")
}

/// The summary at `path` without the fields of [`RUN_FIELDS`].
fn summary_without_run_fields(path: &Path) -> serde_json::Value {
    let mut summary: serde_json::Value = serde_json::from_slice(&read(path)).expect("JSON");
    for field in RUN_FIELDS {
        let _ = summary
            .as_object_mut()
            .expect("an object")
            .remove(field)
            .unwrap_or_else(|| panic!("no {field} in the summary"));
    }
    summary
}

/// For every integrator on both built-ins: 20 steps, then a restart from
/// the checkpoint at step 20 to step 30, appends to the series and leaves
/// the series, the last checkpoint (the whole state, bit for bit: centres,
/// images, velocities, orientations, angular momenta, the integrator's
/// momenta or Gear derivatives, the neighbour list's positions and builds)
/// and the summary (but for the fields a restart changes) byte for byte
/// those of one run of 30 steps.
#[test]
fn a_restart_continues_every_integrator_bit_for_bit() {
    for name in BUILTINS {
        let text = text(name, false);
        for integrator in INTEGRATORS {
            let (full, split) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
            let _ = run_in(full.path(), &scene(&text, integrator, 30), None);
            let _ = run_in(split.path(), &scene(&text, integrator, 20), None);
            let checkpoint = split.path().join(CHECKPOINT_FILE);
            assert_eq!(Checkpoint::read(&checkpoint).expect("valid").step, 20);
            let rest = run_in(
                split.path(),
                &scene(&text, integrator, 30),
                Some(&checkpoint),
            );
            let case = format!("{name}, {integrator}");
            assert!(
                matches!(rest.written, Some((_, Placement::Append(_)))),
                "{case}: {:?}",
                rest.written
            );
            assert_eq!(rest.stop, Stop::Completed, "{case}");
            for file in ["series.csv", CHECKPOINT_FILE] {
                assert!(
                    read(&split.path().join(file)) == read(&full.path().join(file)),
                    "{case}: {file} differs"
                );
            }
            assert_eq!(
                summary_without_run_fields(&split.path().join(SUMMARY_FILE)),
                summary_without_run_fields(&full.path().join(SUMMARY_FILE)),
                "{case}"
            );
            assert!(split.path().join("summary.until-20.json").is_file());
        }
    }
}

/// The thermostats' state goes into a body checkpoint too (after the
/// splitting's momenta or the Gear derivatives): with each thermostat, on
/// both built-ins, every integrator that carries it (NO_SQUISH and DLM
/// each, scheme A Nose-Hoover) restarted at step 20 writes the series and
/// the last checkpoint of one run of 30 steps byte for byte (Langevin's and
/// Bussi's noise streams, the Nose-Hoover chains and the heat they record
/// included).
#[test]
fn a_restart_with_a_thermostat_continues_bit_for_bit() {
    let thermostats = [
        (
            "kind = \"langevin\"\ntemperature = 1.0\nfriction = 2.0\nseed = 5",
            &["no_squish", "dlm"][..],
        ),
        (
            "kind = \"bussi\"\ntemperature = 1.0\ntau = 0.05\nseed = 5",
            &["no_squish", "dlm"][..],
        ),
        (
            "kind = \"nose_hoover\"\ntemperature = 1.0\ntau = 0.1",
            &["no_squish", "dlm", "gear_a"][..],
        ),
    ];
    for name in BUILTINS {
        for (thermostat, integrators) in thermostats {
            let text = format!("{}\n[thermostat]\n{thermostat}\n", text(name, false));
            for &integrator in integrators {
                let (full, split) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
                let _ = run_in(full.path(), &scene(&text, integrator, 30), None);
                let _ = run_in(split.path(), &scene(&text, integrator, 20), None);
                let checkpoint = split.path().join(CHECKPOINT_FILE);
                let rest = run_in(
                    split.path(),
                    &scene(&text, integrator, 30),
                    Some(&checkpoint),
                );
                let case = format!("{name}, {integrator}, {thermostat}");
                assert_eq!(rest.stop, Stop::Completed, "{case}");
                for file in ["series.csv", CHECKPOINT_FILE] {
                    assert!(
                        read(&split.path().join(file)) == read(&full.path().join(file)),
                        "{case}: {file} differs"
                    );
                }
            }
        }
    }
}

/// A run recording a GSD trajectory restarts into a new folder (a GSD file
/// is never appended to, as for rotors), whose trajectory starts at the
/// first frame after the checkpoint and whose series and last checkpoint
/// are the uninterrupted run's from there on.
#[test]
fn a_restart_with_a_trajectory_writes_a_new_folder_that_goes_on_bit_for_bit() {
    let text = text("stockmayer_fluid", true);
    let (full, split) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let _ = run_in(full.path(), &scene(&text, "gear_b", 30), None);
    let _ = run_in(split.path(), &scene(&text, "gear_b", 20), None);
    let rest = run_in(
        split.path(),
        &scene(&text, "gear_b", 30),
        Some(&split.path().join(CHECKPOINT_FILE)),
    );
    let Some((dir, Placement::NewFolder { reason, .. })) = &rest.written else {
        panic!("a new folder, got {:?}", rest.written);
    };
    assert_eq!(dir, &split.path().join("restart-20"));
    assert!(
        reason.contains("a GSD trajectory is not continued"),
        "{reason}"
    );
    assert!(dir.join(GSD_FILE).is_file());
    assert_eq!(
        read(&dir.join(CHECKPOINT_FILE)),
        read(&full.path().join(CHECKPOINT_FILE))
    );
    let full_rows = String::from_utf8(read(&full.path().join("series.csv"))).unwrap();
    let new_rows = String::from_utf8(read(&dir.join("series.csv"))).unwrap();
    let tail: Vec<&str> = full_rows.lines().skip(1 + 20 / 5).collect();
    assert_eq!(new_rows.lines().skip(1).collect::<Vec<_>>(), tail);
}

/// A run stopped from another thread (as the CLI's signal handler and
/// Python's Ctrl-C do) ends at the end of a step with whole CSV rows, a
/// summary saying "interrupted" at that step and a checkpoint there; its
/// restart appends, and the series and the last checkpoint are then those
/// of the uninterrupted run, byte for byte.
#[test]
fn an_interrupted_run_of_bodies_ends_cleanly_and_its_restart_continues_bit_for_bit() {
    const STEPS: i64 = 300;
    let text = text("stockmayer_fluid", false);
    for integrator in ["no_squish", "gear_a"] {
        let (full, cut) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let _ = run_in(full.path(), &scene(&text, integrator, STEPS), None);
        let control = Arc::new(Control::new());
        let outputs = Outputs {
            dir: Some(cut.path().to_path_buf()),
            keep: false,
            control: Some(Arc::clone(&control)),
            threads: None,
        };
        let watcher = {
            let control = Arc::clone(&control);
            std::thread::spawn(move || {
                while control.step() < 13 {
                    std::thread::yield_now();
                }
                control.request_stop();
            })
        };
        let long = scene(&text, integrator, STEPS);
        let result = execute(&long, serde_json::Value::Null, &outputs, None, None).expect("runs");
        watcher.join().expect("the watcher");
        let Stop::Interrupted { step } = result.stop else {
            panic!("{integrator}: interrupted, got {:?}", result.stop);
        };
        assert!((13..STEPS as u64).contains(&step), "{integrator}: {step}");
        let summary = summary(cut.path());
        assert_eq!(summary["status"], "interrupted");
        assert_eq!(summary["last_step"], step);
        assert_eq!(last_row(cut.path()), step / 5 * 5, "{integrator}");
        let checkpoint = cut.path().join(CHECKPOINT_FILE);
        assert_eq!(Checkpoint::read(&checkpoint).expect("valid").step, step);
        let rest = run_in(cut.path(), &long, Some(&checkpoint));
        assert!(matches!(rest.written, Some((_, Placement::Append(_)))));
        for file in ["series.csv", CHECKPOINT_FILE] {
            assert!(
                read(&cut.path().join(file)) == read(&full.path().join(file)),
                "{integrator}: {file} differs"
            );
        }
    }
}

/// A checkpoint of a run of bodies is refused by a scene with another
/// number of bodies, other body types, another integrator, by a scene of
/// rotors, and when it is edited or its state has the wrong length, each
/// message saying what is wrong; nothing is written then.
#[test]
fn checkpoints_of_bodies_are_refused_by_other_scenes_and_when_damaged() {
    let text = text("stockmayer_fluid", false);
    let dir = tempfile::tempdir().unwrap();
    let _ = run_in(dir.path(), &scene(&text, "dlm", 10), None);
    let path = dir.path().join(CHECKPOINT_FILE);
    let restart = |scene: &Scene, path: &Path| {
        let out = tempfile::tempdir().unwrap();
        let outputs = common::outputs(Some(out.path()), false);
        let e = execute(scene, serde_json::Value::Null, &outputs, Some(path), None)
            .expect_err("refused")
            .to_string();
        assert!(!out.path().join(SUMMARY_FILE).exists(), "{e}");
        e
    };
    let expect = |scene: &Scene, path: &Path, message: &str| {
        assert_eq!(
            restart(scene, path),
            format!("checkpoint {}: {message}", path.display())
        );
    };
    expect(
        &scene(&text.replace("counts = [256]", "counts = [500]"), "dlm", 20),
        &path,
        "the number of bodies is 500 in the scene but 256 in the checkpoint",
    );
    expect(
        &scene(&text.replace("mass = 1.0", "mass = 1.5"), "dlm", 20),
        &path,
        "the body types (body_types: mass, inertia, sites) or the bodies' types \
         differ from those of the checkpoint's run",
    );
    expect(
        &scene(&text.replace("skin = 0.3", "skin = 0.4"), "dlm", 20),
        &path,
        "the box and the interactions of the bodies (bodies.box, body_interactions) \
         differ from those of the checkpoint's run",
    );
    let other = restart(&scene(&text, "no_squish", 20), &path);
    assert!(
        other.contains("the integrator is {\"kind\":\"no_squish\"")
            && other.contains("in the scene but {\"kind\":\"dlm\""),
        "{other}"
    );
    let rotors = common::scene_with(
        &common::two_rotors("dlm", 0.002, 20, ""),
        &common::steps(20),
    )
    .1;
    expect(
        &rotors,
        &path,
        "the scene is of rotors but the checkpoint of bodies",
    );
    let same = scene(&text, "dlm", 20);
    let original = std::fs::read_to_string(&path).unwrap();
    let edited = dir.path().join("edited.json");
    std::fs::write(&edited, original.replace("\"step\":10", "\"step\":11")).unwrap();
    assert!(restart(&same, &edited).contains("damaged or edited"));
    let mut short = Checkpoint::read(&path).expect("valid");
    let _ = short.state_bits.pop();
    short.seal();
    std::fs::write(&edited, serde_json::to_string(&short).unwrap()).unwrap();
    expect(
        &same,
        &edited,
        "the bodies' momenta: expected 768 values, only 767 left",
    );
}

/// A run whose time step is far too long for the liquid blows up: the run
/// stops at a blow-up check with a message naming the step, the two bodies
/// and their sites, deep inside their core; the series are kept up to the
/// step before, and the summary records the blow-up with the message.
#[test]
fn a_blow_up_of_bodies_names_the_step_and_the_bodies() {
    let text = text("stockmayer_fluid", false).replace("[record]\n", "[record]\ncheck_every = 1\n");
    let dir = tempfile::tempdir().unwrap();
    let overrides = Overrides {
        dt: Some(0.05),
        steps: Some(400),
        ..Overrides::default()
    };
    let scene = load_text(&text, &overrides).expect("valid").1;
    let result = run_in(dir.path(), &scene, None);
    let Stop::BlewUp {
        step,
        rotor,
        reason,
    } = &result.stop
    else {
        panic!("a blow-up, got {:?}", result.stop);
    };
    let message = result.summary.message.clone().expect("a message");
    assert!(
        message.starts_with(&format!(
            "blew up at step {step}, body {rotor}: site 0 of body {rotor} and site 0 of body "
        )),
        "{message}"
    );
    assert!(
        reason.ends_with("(below 0.5: far inside their repulsive core)"),
        "{reason}"
    );
    let summary = summary(dir.path());
    assert_eq!(summary["status"], "blew_up");
    assert_eq!(summary["message"], message.as_str());
    assert_eq!(last_row(dir.path()), (step - 1) / 5 * 5);
}
