//! Failure paths lose nothing (issue 37, item 7): a restart refused after
//! its checks leaves the earlier run's `summary.json` in place (it was
//! renamed away first); a run whose writes fail mid-run (a file size limit
//! stands for a full disk) exits 2 with no `*.partial` file left and a
//! summary that says `"failed"` with the error, not `"running"`.

use std::path::Path;
use std::process::{Command, Output};

mod common;

/// 512 rotors: a checkpoint of about 80 kB.
const LATTICE: &str = r#"kind = "lattice"
lattice = "simple_cubic"
cells = 8
spacing = 1.0"#;

/// The two rotors of [`common::two_rotors`] (NO_SQUISH, dt 0.01), or the
/// rotors `lattice` in their place, for `steps` steps with a series,
/// checkpoints every 50 steps and a DCD trajectory when `trajectory`.
fn scene(lattice: Option<&str>, steps: i64, trajectory: bool) -> String {
    let trajectory = if trajectory {
        "[record.trajectory]\nevery = 1\nformat = \"dcd\"\n"
    } else {
        ""
    };
    let record = format!(
        "[record]\ncheckpoint_every = 50\n[[record.series]]\nname = \"energies\"\nevery = 1\n\
         quantities = [\"kinetic_energy\", \"potential_energy\", \"total_energy\"]\n{trajectory}"
    );
    let text = common::two_rotors("no_squish", 0.01, steps, &record);
    match lattice {
        Some(rotors) => {
            let start = text.find("kind = \"sites\"").expect("the rotors' kind");
            let end = text.find("default =").expect("the rotors' default");
            format!("{}{rotors}\n{}", &text[..start], &text[end..])
        }
        None => text,
    }
}

fn quatrot(work: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quatrot"))
        .current_dir(work)
        .args(args)
        .output()
        .expect("quatrot runs")
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json is there");
    serde_json::from_str(&text).expect("summary.json parses")
}

/// A restart refused because an output was replaced by a link keeps the
/// folder's summary: same bytes, and no `summary.until-*.json` made.
#[cfg(unix)]
#[test]
fn a_refused_restart_keeps_the_earlier_summary() {
    let work = tempfile::tempdir().expect("temporary folder");
    std::fs::write(work.path().join("scene.toml"), scene(None, 100, true)).expect("scene written");
    let first = quatrot(work.path(), &["run", "scene.toml", "--out", "o"]);
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let out = work.path().join("o");
    std::fs::copy(out.join("checkpoint.json"), work.path().join("c.json")).expect("copy");
    let before = std::fs::read(out.join("summary.json")).expect("summary");
    let victim = work.path().join("victim.csv");
    std::fs::rename(out.join("energies.csv"), &victim).expect("moved out");
    let series = std::fs::read(&victim).expect("series");
    std::os::unix::fs::symlink(&victim, out.join("energies.csv")).expect("link");
    let again = quatrot(
        work.path(),
        &["run", "scene.toml", "--out", "o", "--restart", "c.json"],
    );
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert_eq!(again.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("energies.csv"), "{stderr}");
    assert_eq!(
        std::fs::read(out.join("summary.json")).expect("summary still there"),
        before
    );
    assert_eq!(std::fs::read(&victim).expect("victim"), series);
    let kept: Vec<_> = std::fs::read_dir(&out)
        .expect("folder")
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with("summary.until"))
        .collect();
    assert!(kept.is_empty(), "{kept:?}");
}

/// Writes refused mid-run (`ulimit -f`: no file may grow past 64 KiB, and
/// SIGXFSZ ignored so that the write fails with EFBIG as on a full disk):
/// exit 2 naming the file, no `*.partial` left, the summary says "failed"
/// with the error and the step of the last checkpoint written. With two
/// rotors the series and trajectory outgrow the limit after some
/// checkpoints; with 512 (no trajectory) the first checkpoint does, through
/// its temporary file.
#[cfg(unix)]
#[test]
fn a_run_whose_writes_fail_says_failed_and_leaves_no_partial_file() {
    let cases = [
        (None, 20_000, true, "trajectory.dcd"),
        (Some(LATTICE), 60, false, "checkpoint"),
    ];
    for (lattice, steps, trajectory, failing) in cases {
        let work = tempfile::tempdir().expect("temporary folder");
        std::fs::write(
            work.path().join("scene.toml"),
            scene(lattice, steps, trajectory),
        )
        .expect("scene");
        let run = format!(
            "trap '' XFSZ; ulimit -f 64; exec '{}' run scene.toml --out o",
            env!("CARGO_BIN_EXE_quatrot")
        );
        let out = Command::new("sh")
            .current_dir(work.path())
            .args(["-c", &run])
            .output()
            .expect("sh runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("File too large"), "{stderr}");
        assert!(stderr.contains(failing), "{stderr}");
        let dir = work.path().join("o");
        let partial: Vec<_> = std::fs::read_dir(&dir)
            .expect("folder")
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|name| name.ends_with(".partial"))
            .collect();
        assert!(partial.is_empty(), "{failing}: {partial:?}");
        let summary = summary(&dir);
        assert_eq!(summary["status"], "failed", "{summary}");
        let message = summary["message"].as_str().expect("a message");
        assert!(message.contains("File too large"), "{message}");
        let last = summary["last_step"].as_u64().expect("last_step");
        assert!(last % 50 == 0 && last < steps as u64, "{last}");
    }
}
