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

/// A stand-in interpreter at `dir/python`: a shell script with `body`.
#[cfg(unix)]
fn fake_python(dir: &Path, body: &str) -> std::path::PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let path = dir.join("python");
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).expect("script");
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    path
}

fn sweep_with(python: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .arg("sweep")
        .args(args)
        .env("QUATROT_PYTHON", python)
        .output()
        .expect("the binary runs")
}

/// `quatrot sweep ARGS` runs `$QUATROT_PYTHON -m quatrot.sweep ARGS`, every
/// argument as given (`--help` included), after checking the import.
#[cfg(unix)]
#[test]
fn sweep_hands_its_arguments_to_the_python_sweep() {
    let dir = tempfile::tempdir().expect("dir");
    let python = fake_python(dir.path(), r#"printf '%s\n' "$@""#);
    let args = [
        "scene.toml",
        "--set",
        "run.dt=0.1,0.2",
        "--out",
        "a b",
        "--help",
    ];
    let out = sweep_with(&python, &args);
    assert!(out.status.success(), "{out:?}");
    let mut expected = vec!["-m", "quatrot.sweep"];
    expected.extend(args);
    assert_eq!(
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .collect::<Vec<_>>(),
        expected
    );
}

/// The Python program's exit code is the launcher's.
#[cfg(unix)]
#[test]
fn sweep_exits_with_the_python_sweeps_code() {
    let dir = tempfile::tempdir().expect("dir");
    let python = fake_python(dir.path(), r#"[ "$1" = "-m" ] && exit 1; exit 0"#);
    assert_eq!(sweep_with(&python, &["x"]).status.code(), Some(1));
}

/// An interpreter that cannot start, or that lacks `quatrot.sweep`, is named
/// in the message with the way out.
#[cfg(unix)]
#[test]
fn sweep_explains_a_missing_interpreter_or_package() {
    let dir = tempfile::tempdir().expect("dir");
    let missing = dir.path().join("no_such_python");
    let out = sweep_with(&missing, &["x"]);
    assert_eq!(out.status.code(), Some(EXIT_ERROR));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.starts_with(&format!(
            "error: cannot start the Python interpreter `{}` (set QUATROT_PYTHON",
            missing.display()
        )),
        "{message}"
    );

    let python = fake_python(
        dir.path(),
        "echo 'Traceback (most recent call last):' >&2\necho \"ModuleNotFoundError: No module named 'distributed'\" >&2\nexit 1",
    );
    let out = sweep_with(&python, &["x"]);
    assert_eq!(out.status.code(), Some(EXIT_ERROR));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.starts_with(&format!(
            "error: `{}` cannot import quatrot.sweep: ModuleNotFoundError: No module named 'distributed'; install it with `pip install 'quatrot[sweep]'`",
            python.display()
        )),
        "{message}"
    );
}

/// `quatrot ARGS` with standard output going to `stdout`.
#[cfg(unix)]
fn quatrot_into(args: &[&str], stdout: std::process::Stdio, dir: &Path) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdout(stdout)
        .env("QUATROT_MEMORY_LIMIT", MEMORY_LIMIT)
        .output()
        .expect("the binary runs")
}

/// A pipe whose reader is already gone: every write to it fails with
/// EPIPE, as `quatrot scenes | head -1` after `head` exits.
#[cfg(unix)]
fn closed_pipe() -> std::process::Stdio {
    use std::os::fd::FromRawFd;
    let mut fds = [0; 2];
    // SAFETY: pipe writes two new descriptors into `fds`, which are then
    // owned here: the reader is closed, the writer handed to the child.
    unsafe {
        assert_eq!(libc::pipe(fds.as_mut_ptr()), 0);
        libc::close(fds[0]);
        std::process::Stdio::from(std::os::fd::OwnedFd::from_raw_fd(fds[1]))
    }
}

/// A reader that goes away ends the output quietly with the command's own
/// exit code; a full standard output is an error with exit code 2. Neither
/// panics (issue 37: `quatrot scenes | head -1` panicked half the time,
/// `> /dev/full` always, `run ... | head -0` after the run).
#[cfg(unix)]
#[test]
fn closed_and_full_standard_outputs_end_without_a_panic() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let run = ["run", "dipole_in_field", "--steps", "2", "--out", "out"];
    for args in [&["scenes"][..], &["check", "dipole_in_field"], &run] {
        let out = quatrot_into(args, closed_pipe(), dir.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full");
        let out = quatrot_into(args, full.into(), dir.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(EXIT_ERROR), "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("error: cannot write to standard output: No space left on device"),
            "{args:?}: {stderr}"
        );
    }
}

/// An unknown `--integrator` is refused with the choices, and the message
/// ends without an escaped newline (issue 37: it ended with a literal `\n`).
#[test]
fn an_unknown_integrator_option_is_refused_in_one_clean_line() {
    let out = quatrot(&["check", "dipole_in_field"]);
    assert!(out.status.success());
    let out = quatrot(&[
        "run",
        "dipole_in_field",
        "--integrator",
        "foo",
        "--out",
        "/nonexistent/never",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(EXIT_ERROR), "{stderr}");
    assert_eq!(
        stderr,
        "error: integrator.kind: unknown variant `foo`, expected one of `gear_a`, `gear_b`, \
         `no_squish`, `dlm`, `richardson`\n"
    );
}

/// A built-in with a thermostat runs a scheme that takes none once
/// `--no-thermostat` drops it; without it the scheme is refused, naming it.
#[test]
fn no_thermostat_lets_a_thermostatted_builtin_run_any_scheme() {
    let dir = tempfile::tempdir().expect("dir");
    let out_dir = dir.path().join("out");
    let out = |extra: &[&str]| {
        let mut args = vec!["run", "lewis_wahnstrom_otp", "--integrator", "richardson"];
        args.extend_from_slice(&["--steps", "2", "--out", out_dir.to_str().expect("utf-8")]);
        args.extend_from_slice(extra);
        quatrot(&args)
    };
    let refused = out(&[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(EXIT_ERROR), "{stderr}");
    assert!(stderr.contains("richardson"), "{stderr}");
    let ran = out(&["--no-thermostat"]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let summary = std::fs::read_to_string(out_dir.join("summary.json")).expect("summary");
    let summary: serde_json::Value = serde_json::from_str(&summary).expect("json");
    assert_eq!(summary["integrator"], "richardson");
    assert_eq!(summary["last_step"], 2);
    assert!(summary["definition"]["integrator"].is_object());
    assert!(summary["definition"].get("thermostat").is_none());
}

/// The `summary.json` of `quatrot run dipole_in_field` with `args`,
/// `RAYON_NUM_THREADS` set to `env` (or unset), its `[run]` table given
/// `run_threads` as its `threads` (or none).
fn run_summary(
    dir: &Path,
    args: &[&str],
    env: Option<&str>,
    run_threads: Option<&str>,
) -> serde_json::Value {
    let out_dir = dir.join("threads");
    let scene = match run_threads {
        Some(value) => {
            let builtin = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/dipole_in_field.toml");
            let text = std::fs::read_to_string(builtin).expect("built-in scene");
            let path = dir.join("dipole_in_field.toml");
            let with_threads = text.replace("[run]\n", &format!("[run]\nthreads = {value}\n"));
            assert_ne!(with_threads, text, "the scene has a [run] table");
            std::fs::write(&path, with_threads).expect("scene written");
            path.to_string_lossy().into_owned()
        }
        None => "dipole_in_field".to_string(),
    };
    summary_of_run(&scene, 4, &out_dir, args, env)
}

/// `summary.json` of `quatrot run scene --steps steps --out out_dir` with
/// `args`, `RAYON_NUM_THREADS` set to `env` (or unset); the run must succeed.
fn summary_of_run(
    scene: &str,
    steps: u32,
    out_dir: &Path,
    args: &[&str],
    env: Option<&str>,
) -> serde_json::Value {
    let mut command = Command::new(BIN);
    command
        .args(["run", scene, "--steps", &steps.to_string(), "--out"])
        .arg(out_dir)
        .args(args)
        .env_remove("RAYON_NUM_THREADS")
        .env("QUATROT_MEMORY_LIMIT", MEMORY_LIMIT);
    if let Some(value) = env {
        command.env("RAYON_NUM_THREADS", value);
    }
    let out = command.output().expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(out_dir.join("summary.json")).expect("summary");
    serde_json::from_str(&text).expect("json")
}

/// The `threads` entry of `summary.json` after `quatrot run dipole_in_field`
/// with `args`, `RAYON_NUM_THREADS` set to `env` (or unset).
fn run_threads(dir: &Path, args: &[&str], env: Option<&str>) -> serde_json::Value {
    run_summary(dir, args, env, None)["threads"].clone()
}

/// The thread count: `--threads N` is honoured exactly (3, more than this
/// machine's cores) and recorded as given, also over `RAYON_NUM_THREADS`;
/// without it `RAYON_NUM_THREADS` sizes the run; without either the
/// one-rotor scene takes one thread (automatic: one per 500 rotors, at
/// least one). Counts outside 1..=1024 are refused naming the option.
#[test]
fn the_thread_count_is_given_from_the_environment_or_automatic() {
    let dir = tempfile::tempdir().expect("dir");
    let given = run_threads(dir.path(), &["--threads", "3"], Some("1"));
    assert_eq!(given["count"], 3);
    assert_eq!(given["chosen"], "given");
    let environment = run_threads(dir.path(), &[], Some("2"));
    assert_eq!(environment["count"], 2);
    assert_eq!(environment["chosen"], "RAYON_NUM_THREADS");
    assert_eq!(environment["reason"], "RAYON_NUM_THREADS=2");
    let automatic = run_threads(dir.path(), &[], None);
    assert_eq!(automatic["count"], 1);
    assert_eq!(automatic["chosen"], "automatic");
    assert!(
        automatic["reason"]
            .as_str()
            .is_some_and(|r| r.starts_with("rotors 1, cores ")),
        "{automatic}"
    );
    for bad in ["0", "1025", "-2"] {
        let out = quatrot(&["run", "dipole_in_field", "--threads", bad]);
        assert_eq!(out.status.code(), Some(EXIT_ERROR));
        assert_eq!(
            String::from_utf8_lossy(&out.stderr).trim_end(),
            format!("error: --threads: must be between 1 and 1024, got {bad}")
        );
    }
}

/// A scene of moving bodies left to choose takes one thread per 250 of
/// its bodies' sites (at least 1, at most the cores), not the count of a
/// scene without rotors: the 256 single-site bodies of the Stockmayer
/// fluid one thread, the 512 three-site waters (1,536 sites) every core
/// up to 6; the reason names the sites.
#[test]
fn moving_bodies_choose_their_threads_by_their_sites() {
    let dir = tempfile::tempdir().expect("dir");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    for (scene, sites, count) in [
        ("stockmayer_fluid", 256, 1),
        ("spce_water_512", 1536, cores.min(6)),
    ] {
        let summary = summary_of_run(scene, 1, &dir.path().join(scene), &[], None);
        let threads = &summary["threads"];
        assert_eq!(threads["chosen"], "automatic", "{scene}");
        assert_eq!(threads["count"], count, "{scene}");
        let reason = format!("body sites {sites}, cores {cores}: one thread per 250 body sites");
        assert!(
            threads["reason"]
                .as_str()
                .is_some_and(|r| r.starts_with(&reason)),
            "{scene}: {threads}"
        );
    }
}

/// A scene's `run.threads` is honoured (3, more than this machine's
/// cores), recorded as the scene's choice, also over `RAYON_NUM_THREADS`,
/// and kept in the summary's scene definition; `--threads` overrides it;
/// `"auto"` leaves the count automatic.
#[test]
fn the_scene_fixes_the_thread_count_unless_the_command_line_does() {
    let dir = tempfile::tempdir().expect("dir");
    let scene = run_summary(dir.path(), &[], Some("1"), Some("3"));
    assert_eq!(
        scene["threads"],
        serde_json::json!({"count": 3, "chosen": "scene", "reason": "run.threads = 3 in the scene"})
    );
    assert_eq!(scene["definition"]["run"]["threads"], 3);
    let given = run_summary(dir.path(), &["--threads", "2"], None, Some("3"))["threads"].clone();
    assert_eq!(
        (&given["count"], &given["chosen"]),
        (&2.into(), &"given".into())
    );
    let auto = run_summary(dir.path(), &[], None, Some("\"auto\""));
    assert_eq!(
        (&auto["threads"]["count"], &auto["threads"]["chosen"]),
        (&1.into(), &"automatic".into())
    );
    assert_eq!(auto["definition"]["run"]["threads"], "auto");
}

/// The PDB topology's coordinate columns bound only a DCD trajectory: the
/// scene whose sites reach beyond them (`tests/bad_scenes/`) passes `check`
/// with a GSD trajectory, which writes no PDB (issue 37: it was refused
/// for "the PDB topology's columns").
#[test]
fn sites_beyond_the_pdb_columns_are_fine_for_a_gsd_trajectory() {
    let bad = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/bad_scenes/trajectory_beyond_pdb_columns.toml");
    let text = std::fs::read_to_string(bad).expect("bad scene");
    assert!(text.contains("marker_length = 0.3"));
    let gsd = text.replace("marker_length = 0.3", "format = \"gsd\"");
    let dir = tempfile::tempdir().expect("temporary folder");
    let file = dir.path().join("far.toml");
    std::fs::write(&file, gsd).expect("scene written");
    let out = quatrot(&["check", file.to_str().expect("utf-8")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
