//! Every output of the built-in scenes stays byte for byte what it was when
//! `fixtures/builtin_outputs.json` was recorded: a guard for changes that
//! must not change behaviour (refactors, faster code paths).
//!
//! This is a characterisation test, not a correctness test: the fixture was
//! written by this crate itself (at the commit it names), so it says only
//! "unchanged", never "right". Each built-in scene of `scenes/` runs through
//! the command line with each integrator and each thermostat (and none; the
//! largest scenes with their own pairing only, [`OWN_PAIRING_ONLY`]),
//! 24 steps with a series every 4 steps, a trajectory every 8 (DCD + PDB, and
//! GSD in a second run), checkpoints every 8, then a restart from the last
//! checkpoint for 8 more steps. The SHA-256 of every file (of `summary.json`
//! without its wall-clock time), the exit code and the error message of a
//! refused pairing are compared. Everything a run writes is seeded, and the
//! runs use 2 threads. Scenes of bodies record their own quantities and
//! no checkpoints (they cannot restart yet); the pairings they refuse are
//! recorded with their messages like any other.
//!
//! A change that is meant to change outputs records the fixture again with
//! `QUATROT_BLESS_OUTPUTS=1 cargo test --release --test builtin_outputs_unchanged`
//! and says why in its commit.

use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

const FIXTURE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/builtin_outputs.json");
const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
const INTEGRATORS: [&str; 5] = ["gear_a", "gear_b", "no_squish", "dlm", "richardson"];
const STEPS: i64 = 24;
const RESTART_STEPS: i64 = 32;
/// Results are bitwise reproducible for a given thread count (pair sums over
/// half lists split their rows by thread): the count is fixed.
const THREADS: &str = "2";
/// Cases run at once (`outputs_of_every_case`).
const WORKERS: usize = 2;

/// Built-in scenes run with their own integrator and kind of thermostat
/// only: the 4,096-molecule water box takes the code paths of
/// `spce_water_512` (same model, mesh Ewald, integrators and thermostats)
/// at 2 s per run, where its 40 pairings took half of this test's time.
const OWN_PAIRING_ONLY: [&str; 1] = ["spce_water_4096"];

/// The integrator and the kind of thermostat ("none" without one) of the
/// scene `text`.
fn own_pairing(text: &str) -> (String, String) {
    let scene: toml::Table = text.parse().expect("built-in scene parses");
    let kind = |table: &str| {
        scene
            .get(table)
            .and_then(|t| t.get("kind"))
            .and_then(|k| k.as_str())
            .map(str::to_string)
    };
    let integrator = kind("integrator").expect("[integrator] kind");
    (
        integrator,
        kind("thermostat").unwrap_or_else(|| "none".to_string()),
    )
}

/// The thermostat tables tried with every integrator (none first).
fn thermostats() -> Vec<(&'static str, Option<toml::Table>)> {
    let table = |text: &str| Some(text.parse::<toml::Table>().expect("thermostat table"));
    vec![
        ("none", None),
        (
            "langevin",
            table("kind = \"langevin\"\ntemperature = 0.8\nfriction = 2.0\nseed = 11"),
        ),
        (
            "bussi",
            table("kind = \"bussi\"\ntemperature = 0.8\ntau = 0.05\nseed = 12"),
        ),
        (
            "nose_hoover",
            table("kind = \"nose_hoover\"\ntemperature = 0.8\ntau = 0.1\nchain = 3"),
        ),
    ]
}

/// The built-in scene `text` turned into a short run with `integrator` (its
/// own options kept when it is the scene's), `thermostat`, every output, and
/// the trajectory `format`.
fn variant(text: &str, integrator: &str, thermostat: Option<&toml::Table>, format: &str) -> String {
    let mut scene: toml::Table = text.parse().expect("built-in scene parses");
    let bodies = scene.contains_key("bodies");
    let same = scene["integrator"]["kind"].as_str() == Some(integrator);
    if !same {
        let mut table = toml::Table::new();
        let _ = table.insert("kind".into(), integrator.into());
        let _ = scene.insert("integrator".into(), table.into());
    }
    let _ = scene.remove("thermostat");
    if let Some(t) = thermostat {
        let _ = scene.insert("thermostat".into(), t.clone().into());
    }
    let run = scene["run"].as_table_mut().expect("[run]");
    let _ = run.remove("time");
    let _ = run.insert("steps".into(), STEPS.into());
    let record = scene
        .entry("record")
        .or_insert_with(|| toml::Table::new().into())
        .as_table_mut()
        .expect("[record]");
    let _ = record.insert("checkpoint_every".into(), 8.into());
    let mut quantities = vec![
        "kinetic_energy",
        "potential_energy",
        "total_energy",
        "energy_error",
        "temperature",
        "norm_error",
    ];
    if bodies {
        let _ = record.remove("checkpoint_every");
        quantities = vec![
            "kinetic_energy",
            "potential_energy",
            "total_energy",
            "T_trans",
            "T_rot",
        ];
    }
    if thermostat.is_some() {
        quantities.push("conserved_energy");
    }
    let mut series = toml::Table::new();
    let _ = series.insert("name".into(), "golden".into());
    let _ = series.insert("every".into(), 4.into());
    let _ = series.insert("quantities".into(), quantities.into());
    record
        .entry("series")
        .or_insert_with(|| toml::value::Array::new().into())
        .as_array_mut()
        .expect("[[record.series]]")
        .push(series.into());
    let trajectory = record
        .entry("trajectory")
        .or_insert_with(|| toml::Table::new().into())
        .as_table_mut()
        .expect("[record.trajectory]");
    let _ = trajectory.insert("every".into(), 8.into());
    let _ = trajectory.insert("format".into(), format.into());
    if format == "gsd" {
        let _ = trajectory.remove("marker_length");
    }
    toml::to_string(&scene).expect("scene serialises")
}

/// The SHA-256 of `bytes`, in hex.
fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every file below `dir` (paths relative to it) with its digest; the lock
/// (a process id) is left out, `summary.json` is digested without its
/// wall-clock time.
fn digests(dir: &Path, prefix: &str, out: &mut BTreeMap<String, String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.map(|e| e.expect("entry").path()).collect();
    paths.sort();
    for path in paths {
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let key = format!("{prefix}{name}");
        if path.is_dir() {
            digests(&path, &format!("{key}/"), out);
        } else if name == ".quatrot.lock" {
            continue;
        } else if name.starts_with("summary") && name.ends_with(".json") {
            let mut summary: serde_json::Value =
                serde_json::from_slice(&std::fs::read(&path).expect("summary")).expect("json");
            let _ = summary
                .as_object_mut()
                .expect("summary object")
                .remove("wall_seconds");
            let _ = out.insert(key, sha256(summary.to_string().as_bytes()));
        } else {
            let _ = out.insert(key, sha256(&std::fs::read(&path).expect("output")));
        }
    }
}

/// Runs the command line with `args` (the scene file `scene` is written to
/// `work` first) and records the exit code, the error message when it
/// failed, and the digests of the output folder `out`.
fn run(work: &Path, scene: &str, out: &Path, extra: &[&str]) -> serde_json::Value {
    let file = work.join("scene.toml");
    std::fs::write(&file, scene).expect("scene written");
    let output = Command::new(env!("CARGO_BIN_EXE_quatrot"))
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(out)
        .args(extra)
        .env("RAYON_NUM_THREADS", THREADS)
        .output()
        .expect("quatrot runs");
    let code = output.status.code().unwrap_or(-1);
    let mut files = BTreeMap::new();
    digests(out, "", &mut files);
    let mut record = serde_json::json!({ "exit": code, "files": files });
    if code != 0 {
        let message =
            String::from_utf8_lossy(&output.stderr).replace(&work.display().to_string(), "WORK");
        record["stderr"] = message.into();
    }
    record
}

/// The runs of one case: the first, and for a DCD run that succeeded, its
/// restart from the last checkpoint (keys `key` and `key/restart`).
fn outputs_of_case(key: &str, text: &str, format: &str) -> Vec<(String, serde_json::Value)> {
    let work = tempfile::tempdir().expect("temporary folder");
    let out = work.path().join("out");
    let first = run(work.path(), text, &out, &[]);
    let ran = first["exit"] == 0;
    let mut runs = vec![(key.to_string(), first)];
    if ran && format == "dcd" {
        let checkpoint = out.join("checkpoint.json");
        let restart = run(
            work.path(),
            text,
            &out,
            &[
                "--restart",
                checkpoint.to_str().expect("utf-8 path"),
                "--steps",
                &RESTART_STEPS.to_string(),
            ],
        );
        runs.push((format!("{key}/restart"), restart));
    }
    runs
}

/// Every case: scene x integrator x thermostat, DCD then GSD, and a restart.
/// The cases are independent processes, run `WORKERS` at a time (each
/// case's runs in order): most are short runs whose start-up is serial, so
/// one at a time would leave a core idle. The outputs do not depend on it
/// (each run's thread count is fixed).
fn outputs_of_every_case() -> BTreeMap<String, serde_json::Value> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(SCENES)
        .expect("scenes/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    let mut jobs = Vec::new();
    for path in &names {
        let text = std::fs::read_to_string(path).expect("scene");
        let scene = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let own = own_pairing(&text);
        for integrator in INTEGRATORS {
            for (thermostat, table) in thermostats() {
                if OWN_PAIRING_ONLY.contains(&scene.as_str())
                    && (own.0.as_str(), own.1.as_str()) != (integrator, thermostat)
                {
                    continue;
                }
                for format in ["dcd", "gsd"] {
                    let key = format!("{scene}/{integrator}/{thermostat}/{format}");
                    jobs.push((
                        key,
                        variant(&text, integrator, table.as_ref(), format),
                        format,
                    ));
                }
            }
        }
    }
    let next = AtomicUsize::new(0);
    let cases = Mutex::new(BTreeMap::new());
    std::thread::scope(|scope| {
        for _ in 0..WORKERS {
            let _ = scope.spawn(|| {
                while let Some((key, text, format)) = jobs.get(next.fetch_add(1, Ordering::Relaxed))
                {
                    let runs = outputs_of_case(key, text, format);
                    cases.lock().expect("no worker panicked").extend(runs);
                }
            });
        }
    });
    cases.into_inner().expect("no worker panicked")
}

#[test]
fn every_builtin_scene_writes_the_recorded_bytes() {
    let cases = outputs_of_every_case();
    if std::env::var_os("QUATROT_BLESS_OUTPUTS").is_some() {
        let commit = Command::new("git")
            .args(["rev-parse", "HEAD"])
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .unwrap_or_default();
        let fixture = serde_json::json!({
            "provenance": "written by this crate (QUATROT_BLESS_OUTPUTS=1 cargo test --release --test builtin_outputs_unchanged); a record of behaviour to keep, not a reference of correctness",
            "recorded_at_commit": commit,
            "cases": cases,
        });
        let text = serde_json::to_string_pretty(&fixture).expect("json");
        std::fs::write(FIXTURE, text + "\n").expect("fixture written");
        return;
    }
    let text = std::fs::read_to_string(FIXTURE).expect("fixtures/builtin_outputs.json");
    let fixture: serde_json::Value = serde_json::from_str(&text).expect("fixture parses");
    let recorded = fixture["cases"].as_object().expect("cases");
    let mut differences = Vec::new();
    for (key, value) in &cases {
        match recorded.get(key) {
            None => differences.push(format!("{key}: not in the fixture")),
            Some(expected) if expected != value => {
                differences.push(format!("{key}: expected {expected}, got {value}"));
            }
            Some(_) => {}
        }
    }
    for key in recorded.keys().filter(|k| !cases.contains_key(*k)) {
        differences.push(format!("{key}: in the fixture, not run"));
    }
    assert!(
        differences.is_empty(),
        "{} of {} cases differ from {} (recorded at {}):\n{}",
        differences.len(),
        cases.len(),
        FIXTURE,
        fixture["recorded_at_commit"],
        differences.join("\n")
    );
}
