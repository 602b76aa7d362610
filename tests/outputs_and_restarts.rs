//! Regressions of issue 19 on the outputs of runs: the output folder is
//! locked, a restart never destroys what an earlier run wrote (it appends
//! when the files end at the checkpoint's step, else writes to a new
//! folder), checkpoints carry the identity of their run and a checksum, and
//! an interrupted run leaves whole, consistent outputs that a restart
//! continues bit for bit.

use quatrot::run::{
    execute, Checkpoint, OutputFolder, Outputs, Placement, Progress, RunError, RunResult,
    CHECKPOINT_FILE, DCD_FILE, SUMMARY_FILE,
};
use quatrot::scene::Scene;
use quatrot::simulation::{Control, Needs, Observer, Sample, Stop};
use std::path::Path;
use std::sync::Arc;

mod common;

/// The two-rotor scene of these tests (scheme B, 40 steps of 0.001) with a
/// series every 4 steps, a trajectory every 10 and checkpoints every 20.
fn two_rotors() -> String {
    let record = common::restart_record(&["kinetic_energy", "potential_energy", "energy_error"]);
    common::two_rotors("gear_b", 0.001, 40, &record)
}

fn scene(steps: i64, text: &str) -> Scene {
    common::scene_with(text, &common::steps(steps)).1
}

fn run_in(
    dir: &Path,
    steps: i64,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let outputs = common::outputs(Some(dir), false);
    let scene = scene(steps, &two_rotors());
    execute(&scene, serde_json::Value::Null, &outputs, restart, progress)
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A second run on a folder in use is refused, naming the holder, and
/// writes nothing there.
#[test]
fn a_second_run_on_a_locked_folder_is_refused() {
    let dir = tempfile::tempdir().expect("dir");
    let held = OutputFolder::lock(dir.path()).expect("first lock");
    let e = run_in(dir.path(), 40, None, None).expect_err("refused");
    assert!(
        e.to_string()
            .contains(&format!("in use by process {}", std::process::id())),
        "{e}"
    );
    assert!(!dir.path().join("e.csv").exists());
    drop(held);
    run_in(dir.path(), 40, None, None).expect("free again");
}

/// Restarting from an earlier checkpoint into a folder whose files go on
/// past it (the case that truncated the CSV) keeps those files untouched
/// and writes to a new folder, whose rows are the full run's from there on.
#[test]
fn restart_into_files_past_the_checkpoint_keeps_them_and_writes_a_new_folder() {
    let (full, half) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    run_in(full.path(), 40, None, None).expect("full run");
    run_in(half.path(), 20, None, None).expect("half run");
    let before = read(&full.path().join("e.csv"));
    let result = run_in(
        full.path(),
        40,
        Some(&half.path().join(CHECKPOINT_FILE)),
        None,
    )
    .expect("restart");
    assert_eq!(read(&full.path().join("e.csv")), before);
    let Some((dir, Placement::NewFolder { reason, .. })) = &result.written else {
        panic!("a new folder, got {:?}", result.written);
    };
    assert_eq!(dir, &full.path().join("restart-20"));
    assert!(
        reason.contains("e.csv: its last row is at step 40"),
        "{reason}"
    );
    let new_rows = String::from_utf8(read(&dir.join("e.csv"))).unwrap();
    let full_rows = String::from_utf8(before).unwrap();
    let tail: Vec<&str> = full_rows.lines().skip(1 + 20 / 4).collect();
    assert_eq!(new_rows.lines().skip(1).collect::<Vec<_>>(), tail);
    assert_eq!(result.summary.outputs, Some("new_folder"));
}

/// Restarting from the checkpoint at the step where the files end appends
/// to them: the CSV and the DCD are then byte for byte those of one run
/// over the whole length, and the first part's summary is kept.
#[test]
fn restart_at_the_end_of_the_files_appends_to_them() {
    let (full, split) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    run_in(full.path(), 40, None, None).expect("full run");
    run_in(split.path(), 20, None, None).expect("first part");
    let checkpoint = split.path().join(CHECKPOINT_FILE);
    let result = run_in(split.path(), 40, Some(&checkpoint), None).expect("second part");
    assert!(matches!(result.written, Some((_, Placement::Append(_)))));
    for name in ["e.csv", DCD_FILE, "topology.pdb"] {
        assert_eq!(
            read(&split.path().join(name)),
            read(&full.path().join(name)),
            "{name}"
        );
    }
    assert!(split.path().join("summary.until-20.json").is_file());
    assert_eq!(result.summary.outputs, Some("appended"));
}

/// A checkpoint is refused by a scene with other physics, and when its
/// file was edited or holds a non-finite energy reference.
#[test]
fn checkpoints_are_refused_by_other_scenes_and_when_damaged() {
    let dir = tempfile::tempdir().unwrap();
    run_in(dir.path(), 20, None, None).expect("run");
    let path = dir.path().join(CHECKPOINT_FILE);
    let outputs = Outputs::default();
    let restart = |scene: &Scene, path: &Path| {
        execute(scene, serde_json::Value::Null, &outputs, Some(path), None)
            .expect_err("refused")
            .to_string()
    };
    let other = scene(
        40,
        &two_rotors().replace("dipole = [0.0, 0.0, 1.0]", "dipole = [0.0, 0.0, 1.1]"),
    );
    assert!(
        restart(&other, &path).contains("the rotors (sites, inertia, multipoles) differ"),
        "{}",
        restart(&other, &path)
    );
    let same = scene(40, &two_rotors());
    let text = std::fs::read_to_string(&path).unwrap();
    let edited = dir.path().join("edited.json");
    let step = "\"step\":20";
    assert!(text.contains(step));
    std::fs::write(&edited, text.replace(step, "\"step\":21")).unwrap();
    assert!(restart(&same, &edited).contains("damaged or edited"));
    let mut nan = Checkpoint::read(&path).expect("valid");
    nan.reference_bits = Some([f64::NAN.to_bits(), 1f64.to_bits()]);
    nan.seal();
    std::fs::write(&edited, serde_json::to_string(&nan).unwrap()).unwrap();
    assert!(restart(&same, &edited).contains("energy reference is not finite"));
}

/// Requests a stop when it sees a step at or past `at`.
struct StopAt {
    control: Arc<Control>,
    at: u64,
}

impl Observer for StopAt {
    type Error = RunError;
    fn needs(&self) -> Needs {
        Needs::default()
    }
    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError> {
        if sample.step >= self.at {
            self.control.request_stop();
        }
        Ok(())
    }
}

/// A run whose stop is requested at step 25 (by an observer, as a signal
/// handler would between two steps) ends there with whole CSV rows, a DCD
/// counting its frames, a summary saying "interrupted" and a checkpoint at
/// step 25; the restart from it appends,
/// and the files are then byte for byte those of an uninterrupted run.
#[test]
fn an_interrupted_run_ends_cleanly_and_its_restart_continues_bit_for_bit() {
    let (full, cut) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    run_in(full.path(), 40, None, None).expect("full run");
    let control = Arc::new(Control::new());
    let mut stopper = StopAt {
        control: Arc::clone(&control),
        at: 25,
    };
    let outputs = Outputs {
        dir: Some(cut.path().to_path_buf()),
        keep: false,
        control: Some(Arc::clone(&control)),
        threads: None,
    };
    let progress = Progress {
        every: 5,
        observer: &mut stopper,
    };
    let result = execute(
        &scene(40, &two_rotors()),
        serde_json::Value::Null,
        &outputs,
        None,
        Some(progress),
    )
    .expect("runs");
    assert_eq!(result.stop, Stop::Interrupted { step: 25 });
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&cut.path().join(SUMMARY_FILE))).unwrap();
    assert_eq!(summary["status"], "interrupted");
    assert_eq!(summary["last_step"], 25);
    let csv = String::from_utf8(read(&cut.path().join("e.csv"))).unwrap();
    assert!(csv.ends_with('\n'));
    assert_eq!(csv.lines().last().unwrap().split(',').next(), Some("24"));
    let checkpoint = cut.path().join(CHECKPOINT_FILE);
    assert_eq!(Checkpoint::read(&checkpoint).expect("valid").step, 25);
    let rest = run_in(cut.path(), 40, Some(&checkpoint), None).expect("restart");
    assert!(matches!(rest.written, Some((_, Placement::Append(_)))));
    for name in ["e.csv", DCD_FILE] {
        assert_eq!(
            read(&cut.path().join(name)),
            read(&full.path().join(name)),
            "{name}"
        );
    }
}
