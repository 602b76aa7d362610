//! The `quatrot` binary: listing, checking and running scenes, exit codes,
//! and no panic on any bad scene.

use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_quatrot");
/// Exit codes documented in `src/cli/mod.rs`.
const EXIT_ERROR: i32 = 2;
const EXIT_BLOW_UP: i32 = 3;

/// The memory limit of the bad-scene corpus (`tests/bad_scenes.rs`).
const MEMORY_LIMIT: &str = "4G";

fn quatrot(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env("QUATROT_MEMORY_LIMIT", MEMORY_LIMIT)
        .output()
        .expect("the binary runs")
}

/// `quatrot scenes` prints one line per built-in, starting with its name.
#[test]
fn scenes_lists_every_builtin_on_one_line() {
    let out = quatrot(&["scenes"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let names: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let builtins: Vec<&str> = quatrot::scene::BUILTINS.iter().map(|b| b.name).collect();
    assert_eq!(names, builtins);
}

/// `quatrot check` on every bad scene exits with the error code and the
/// stated message, without a panic.
#[test]
fn check_rejects_every_bad_scene_without_panicking() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    for entry in std::fs::read_dir(dir).expect("bad scenes") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("readable");
        let expected = text
            .lines()
            .find_map(|l| l.strip_prefix("# error: "))
            .expect("stated message");
        let out = quatrot(&["check", path.to_str().expect("utf-8")]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(EXIT_ERROR), "{}", path.display());
        assert_eq!(
            stderr.trim_end(),
            format!("error: {expected}"),
            "{}",
            path.display()
        );
        assert!(!stderr.contains("panicked"));
    }
}

/// `check` also builds the potential, so coincident sites are caught.
#[test]
fn check_catches_coincident_sites() {
    let dir = tempfile::tempdir().expect("dir");
    let scene = dir.path().join("coincident.toml");
    let text = r#"
version = 1
[rotors]
kind = "sites"
default = { inertia = 1.0, dipole = [0.0, 0.0, 1.0] }
sites = [{ position = [0.0, 0.0, 0.0] }, { position = [0.0, 0.0, 0.0] }]
[interactions]
boundary = { kind = "open" }
[initial]
kind = "random"
temperature = 1.0
[integrator]
kind = "dlm"
[run]
dt = 0.01
steps = 1
"#;
    std::fs::write(&scene, text).expect("written");
    let out = quatrot(&["check", scene.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(EXIT_ERROR));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("error: potential: rotors[0].site and rotors[1].site: coincide"),
        "{stderr}"
    );
}

/// A run writes its outputs and a one-line summary; a bad override names the field.
#[test]
fn run_writes_outputs_and_a_one_line_summary() {
    let dir = tempfile::tempdir().expect("dir");
    let out_dir = dir.path().join("out");
    let out = quatrot(&[
        "run",
        "dipole_in_field",
        "--steps",
        "20",
        "--out",
        out_dir.to_str().expect("utf-8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().count(), 1);
    assert!(stdout.starts_with("dipole_in_field: 20 steps of gear_b"));
    for file in ["energies.csv", "summary.json"] {
        assert!(out_dir.join(file).is_file(), "{file}");
    }
    let out = quatrot(&[
        "run",
        "dipole_in_field",
        "--dt",
        "-1",
        "--out",
        out_dir.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(EXIT_ERROR));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim_end(),
        "error: run.dt: must be > 0, got -1"
    );
    let out = quatrot(&["run", "no_such_scene"]);
    assert_eq!(out.status.code(), Some(EXIT_ERROR));
}

/// Every built-in scene runs from the command line.
#[test]
fn every_builtin_runs_from_the_command_line() {
    let dir = tempfile::tempdir().expect("dir");
    for b in quatrot::scene::BUILTINS {
        let out_dir = dir.path().join(b.name);
        let out = quatrot(&[
            "run",
            b.name,
            "--steps",
            "3",
            "--out",
            out_dir.to_str().expect("utf-8"),
        ]);
        assert!(
            out.status.success(),
            "{}: {}",
            b.name,
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(out_dir.join("summary.json").is_file(), "{}", b.name);
    }
}

/// A run that blows up exits with its own code and says where.
#[test]
fn run_that_blows_up_exits_with_the_blow_up_code() {
    let dir = tempfile::tempdir().expect("dir");
    let scene = dir.path().join("unstable.toml");
    let text = quatrot::scene::builtin("dipole_in_field")
        .expect("built-in")
        .toml;
    let text = text.replace(
        "[[record.series]]",
        "[record]\nenergy_error_threshold = 1e-3\ncheck_every = 1\n\n[[record.series]]",
    );
    std::fs::write(&scene, text).expect("written");
    let out = quatrot(&[
        "run",
        scene.to_str().expect("utf-8"),
        "--dt",
        "0.2",
        "--integrator",
        "gear_a",
        "--out",
        dir.path().join("out").to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(EXIT_BLOW_UP));
    assert!(String::from_utf8_lossy(&out.stdout).contains("STOPPED: blew up at step"));
}
