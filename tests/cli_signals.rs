//! The `quatrot run` command under SIGINT and `kill -9` (issue 19): an
//! interrupt ends the run at the end of a step with every output flushed
//! and closed and exit code 130; a killed run leaves files readable up to
//! their last complete sample, a summary saying "running" at its last
//! checkpoint's step, and a checkpoint that restarts it bit for bit.

#![cfg(unix)]

use quatrot::run::{read_header, Checkpoint, CHECKPOINT_FILE, DCD_FILE, SUMMARY_FILE};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_quatrot");
/// Exit code of an interrupted run (documented in the README).
const EXIT_INTERRUPTED: i32 = 130;
/// How long a run may take to start writing, or to stop after a signal.
const PATIENCE: Duration = Duration::from_secs(60);

/// The built-in 1000-rotor lattice with checkpoints every 50 steps.
fn long_scene(dir: &Path) -> std::path::PathBuf {
    let text = quatrot::scene::builtin("dipole_lattice_sc")
        .expect("built-in")
        .toml
        .replace(
            "energy_error_threshold = 0.5",
            "energy_error_threshold = 0.5\ncheckpoint_every = 50",
        );
    assert!(text.contains("checkpoint_every"));
    let path = dir.join("long.toml");
    std::fs::write(&path, text).expect("scene written");
    path
}

/// Starts a run of a billion steps and waits until it has written a checkpoint.
fn start(scene: &Path, out: &Path) -> Child {
    let child = Command::new(BIN)
        .args([
            "run",
            scene.to_str().unwrap(),
            "--steps",
            "1000000000",
            "--out",
        ])
        .arg(out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let started = Instant::now();
    while !out.join(CHECKPOINT_FILE).exists() {
        assert!(started.elapsed() < PATIENCE, "no checkpoint written");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    child
}

fn signal(child: &Child, signal: i32) {
    // SAFETY: kill sends a signal to the child this test started.
    assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
}

/// Every line of the CSV is complete.
fn whole_lines(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("csv");
    assert!(
        text.ends_with('\n'),
        "{} ends in a partial line",
        path.display()
    );
    text
}

/// SIGINT: exit code 130, a summary saying "interrupted", whole CSV rows, a
/// DCD whose header counts exactly the frames in the file, and a checkpoint
/// at the step the run stopped at.
#[test]
fn sigint_stops_the_run_with_every_output_flushed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let mut child = start(&long_scene(dir.path()), &out);
    signal(&child, libc::SIGINT);
    let status = child.wait().expect("ends");
    let mut stderr = String::new();
    let _ = std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr);
    assert_eq!(status.code(), Some(EXIT_INTERRUPTED), "{stderr}");
    assert!(stderr.contains("stopping at the end of step"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    whole_lines(&out.join("energies.csv"));
    assert!(read_header(&out.join(DCD_FILE)).unwrap().complete);
    let checkpoint = Checkpoint::read(&out.join(CHECKPOINT_FILE)).expect("valid");
    assert_eq!(Some(checkpoint.step), summary["last_step"].as_u64());
}

/// `kill -9`: the CSV ends with a complete row, the DCD's header counts
/// only complete frames, `summary.json` reads as a run still "running" at
/// a checkpoint's step, and the last checkpoint restarts the run bit for
/// bit: the killed run's rows and the restart's rows are those of one
/// uninterrupted run of the same length.
#[test]
fn after_kill_9_the_outputs_read_and_the_checkpoint_restarts_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = long_scene(dir.path());
    let mut child = start(&scene, &out);
    signal(&child, libc::SIGKILL);
    let _ = child.wait().expect("ends");
    let killed = whole_lines(&out.join("energies.csv"));
    let dcd = read_header(&out.join(DCD_FILE)).unwrap();
    let frame_bytes = 3 * (8 + 4 * dcd.atoms as u64) + 56;
    let size = std::fs::metadata(out.join(DCD_FILE)).unwrap().len();
    assert!(dcd.frames >= 1);
    assert!(size >= 92 + 84 + 8 + 12 + dcd.frames as u64 * frame_bytes);
    let checkpoint = Checkpoint::read(&out.join(CHECKPOINT_FILE)).expect("valid");
    // The summary describes the killed run: still "running", at a
    // checkpoint's step (the last one, or the one before when the kill
    // came between the checkpoint and the summary).
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap()).unwrap();
    assert_eq!(summary["status"], "running");
    assert_eq!(summary["start_step"], 0);
    let last = summary["last_step"].as_u64().expect("a step");
    assert!(last % 50 == 0 && last > 0, "{last}");
    assert!(
        last == checkpoint.step || last + 50 == checkpoint.step,
        "{last} {}",
        checkpoint.step
    );
    let end = (checkpoint.step + 60).to_string();
    let run = |extra: &[&std::ffi::OsStr], out: &Path| {
        let result = Command::new(BIN)
            .args(["run", scene.to_str().unwrap(), "--steps", &end])
            .args(extra)
            .arg("--out")
            .arg(out)
            .output()
            .expect("runs");
        let stdout = String::from_utf8_lossy(&result.stdout).into_owned();
        assert!(result.status.success(), "{stdout}");
        stdout
    };
    let stdout = run(
        &["--restart".as_ref(), out.join(CHECKPOINT_FILE).as_os_str()],
        &out,
    );
    let resumed_dir = if stdout.contains("appended") {
        out.clone()
    } else {
        out.join(format!("restart-{}", checkpoint.step))
    };
    let resumed = whole_lines(&resumed_dir.join("energies.csv"));
    let reference_dir = dir.path().join("reference");
    let _ = run(&[], &reference_dir);
    let reference = whole_lines(&reference_dir.join("energies.csv"));
    let rows = |text: &str, after: u64| -> Vec<String> {
        text.lines()
            .skip(1)
            .filter(|l| l.split(',').next().unwrap().parse::<u64>().unwrap() > after)
            .map(str::to_string)
            .collect()
    };
    let killed_rows = rows(&killed, 0);
    assert!(killed_rows.len() >= 2);
    assert_eq!(killed_rows[..], rows(&reference, 0)[..killed_rows.len()]);
    let resumed_rows = rows(&resumed, checkpoint.step);
    assert!(!resumed_rows.is_empty());
    assert_eq!(resumed_rows, rows(&reference, checkpoint.step));
}

/// SIGTERM on a run of bodies (the built-in Stockmayer fluid, checkpoints
/// every 50 steps): exit code 130, a summary saying "interrupted", whole
/// CSV rows and a checkpoint at the step the run stopped at, which
/// `--restart` continues to the end.
#[test]
fn sigterm_stops_a_run_of_bodies_with_a_checkpoint_its_restart_continues() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let text = quatrot::scene::builtin("stockmayer_fluid")
        .expect("built-in")
        .toml
        .replace(
            "[[record.series]]",
            "[record]\ncheckpoint_every = 50\n\n[[record.series]]",
        );
    let scene = dir.path().join("fluid.toml");
    std::fs::write(&scene, text).expect("scene written");
    let mut child = start(&scene, &out);
    signal(&child, libc::SIGTERM);
    let status = child.wait().expect("ends");
    let mut stderr = String::new();
    let _ = std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr);
    assert_eq!(status.code(), Some(EXIT_INTERRUPTED), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    let last = summary["last_step"].as_u64().expect("a step");
    let rows = whole_lines(&out.join("series.csv"));
    let last_row = rows.lines().last().unwrap().split(',').next().unwrap();
    assert_eq!(last_row, (last / 10 * 10).to_string());
    let checkpoint = Checkpoint::read(&out.join(CHECKPOINT_FILE)).expect("valid");
    assert_eq!(checkpoint.step, last);
    let end = (last + 20).to_string();
    let restart = Command::new(BIN)
        .args(["run", scene.to_str().unwrap(), "--steps", &end, "--out"])
        .arg(&out)
        .arg("--restart")
        .arg(out.join(CHECKPOINT_FILE))
        .output()
        .expect("runs");
    assert!(restart.status.success(), "{restart:?}");
    let folder = out.join(format!("restart-{last}"));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join(SUMMARY_FILE)).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["start_step"], last);
    assert_eq!(summary["last_step"], last + 20);
}
