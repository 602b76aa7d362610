//! The runner on real scenes: built-ins run, sampling happens exactly at the
//! intervals, nothing recorded means no energy evaluation, blow-ups stop with
//! the step and rotor named and valid outputs, checkpoints restart
//! bit-for-bit, and the same seed gives the same output.

use nalgebra::Vector3;
use quatrot::integrators::{Dlm, Integrator, IntegratorError, RotorState};
use quatrot::potential::{Free, Potential};
use quatrot::quaternion::Quat;
use quatrot::rotor::Inertia;
use quatrot::run::{
    execute, run_scene, ScenePotential, CHECKPOINT_FILE, DCD_FILE, GSD_FILE, PDB_FILE, SUMMARY_FILE,
};
use quatrot::scene::{load, parse_toml, validate, Overrides, BUILTINS};
use quatrot::simulation::Stop;
use std::sync::atomic::{AtomicUsize, Ordering};

mod common;

fn definition() -> serde_json::Value {
    serde_json::Value::Null
}

/// Every built-in scene validates and runs a few steps with its own integrator.
#[test]
fn every_builtin_scene_runs_a_few_steps() {
    for b in BUILTINS {
        let (_, scene) =
            load(b.name, &common::steps(5)).unwrap_or_else(|e| panic!("{}: {e}", b.name));
        let result = execute(&scene, definition(), &common::in_memory(), None, None)
            .unwrap_or_else(|e| panic!("{}: {e}", b.name));
        assert_eq!(result.stop, Stop::Completed, "{}", b.name);
        assert_eq!(result.summary.last_step, 5, "{}", b.name);
    }
}

/// The 1000-rotor lattice is the note's test system: simple-cubic unit
/// dipoles, spherical tops with I = 0.1, a periodic box of side 10.
#[test]
fn dipole_lattice_builtin_matches_the_specification() {
    let (_, scene) = load("dipole_lattice_sc", &Overrides::default()).expect("valid");
    assert_eq!(scene.rotors.len(), 1000);
    assert_eq!(scene.box_lengths(), Some(Vector3::repeat(10.0)));
    for r in &scene.rotors {
        assert_eq!(r.inertia, Inertia::Spherical(0.1));
        assert_eq!(r.dipole_body.map(|d| d.norm()), Some(1.0));
    }
}

/// The two-rotor scene of these tests (DLM, 30 steps of 0.001) with `tables`.
fn two_rotors(tables: &str) -> String {
    common::two_rotors("dlm", 0.001, 30, tables)
}

/// Counts energy evaluations of the wrapped potential.
struct Counting<P> {
    inner: P,
    energy_calls: AtomicUsize,
}

impl<P: Potential> Potential for Counting<P> {
    fn energy(&self, q: &[Quat]) -> f64 {
        self.energy_calls.fetch_add(1, Ordering::Relaxed);
        self.inner.energy(q)
    }
    fn accumulate_gradient(&self, q: &[Quat], g: &mut [Quat]) {
        self.inner.accumulate_gradient(q, g)
    }
    fn accumulate_torques(&self, q: &[Quat], t: &mut [Vector3<f64>]) {
        self.inner.accumulate_torques(q, t)
    }
}

/// A run that records nothing evaluates no energy; one recording energies
/// every 7 steps of 30 evaluates it exactly at steps 0, 7, 14, 21, 28.
#[test]
fn energies_are_evaluated_only_at_sampling_steps() {
    let mut raw = parse_toml(&two_rotors("")).expect("valid");
    raw.interactions = None;
    let scene = validate(&raw).expect("valid");
    let counting = Counting {
        inner: Free,
        energy_calls: AtomicUsize::new(0),
    };
    run_scene(
        &scene,
        definition(),
        &mut Dlm::default(),
        ScenePotential::plain(&counting),
        &common::in_memory(),
        None,
        None,
    )
    .expect("runs");
    assert_eq!(counting.energy_calls.load(Ordering::Relaxed), 0);

    let text = two_rotors("[[record.series]]\nevery = 7\nquantities = [\"total_energy\"]\n");
    let mut raw = parse_toml(&text).expect("valid");
    raw.interactions = None;
    let scene = validate(&raw).expect("valid");
    let result = run_scene(
        &scene,
        definition(),
        &mut Dlm::default(),
        ScenePotential::plain(&counting),
        &common::in_memory(),
        None,
        None,
    )
    .expect("runs");
    assert_eq!(counting.energy_calls.load(Ordering::Relaxed), 5);
    let table = &result.series[0];
    let steps: Vec<f64> = table
        .values
        .chunks(table.columns.len())
        .map(|r| r[0])
        .collect();
    assert_eq!(steps, [0.0, 7.0, 14.0, 21.0, 28.0]);
}

/// Wraps an integrator and makes one rotor's orientation NaN from a given step on.
struct Poisoned<I> {
    inner: I,
    step: u64,
    poison_at: u64,
    rotor: usize,
    orientations: Vec<Quat>,
}

impl<I: Integrator> Integrator for Poisoned<I> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn setup(
        &mut self,
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        self.inner.setup(inertia, potential, initial, dt)?;
        self.orientations = self.inner.orientations().to_vec();
        Ok(())
    }
    fn step(&mut self, potential: &dyn Potential) {
        self.inner.step(potential);
        self.step += 1;
        self.orientations.copy_from_slice(self.inner.orientations());
        if self.step >= self.poison_at {
            self.orientations[self.rotor] = Quat([f64::NAN; 4]);
        }
    }
    fn dt(&self) -> f64 {
        self.inner.dt()
    }
    fn orientations(&self) -> &[Quat] {
        &self.orientations
    }
    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        self.inner.omega_body(out)
    }
    fn checkpoint(&self) -> Vec<f64> {
        self.inner.checkpoint()
    }
    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        self.inner.restore(state)
    }
}

/// A non-finite orientation stops the run at the first check after it,
/// naming the step and the rotor; the CSV and summary already written stay
/// valid and end at that step.
#[test]
fn blow_up_stops_with_step_and_rotor_and_keeps_outputs() {
    let text = two_rotors("[record]\ncheck_every = 5\n[[record.series]]\nname = \"e\"\nevery = 2\nquantities = [\"kinetic_energy\", \"norm_error\"]\n");
    let mut raw = parse_toml(&text).expect("valid");
    raw.interactions = None;
    let scene = validate(&raw).expect("valid");
    let dir = tempfile::tempdir().expect("temp dir");
    let outputs = common::outputs(Some(dir.path()), false);
    let mut integrator = Poisoned {
        inner: Dlm::default(),
        step: 0,
        poison_at: 11,
        rotor: 1,
        orientations: Vec::new(),
    };
    let result = run_scene(
        &scene,
        definition(),
        &mut integrator,
        ScenePotential::plain(&Free),
        &outputs,
        None,
        None,
    )
    .expect("runs");
    // Poisoned at step 11; samples at even steps and checks every 5: step 12 is the first.
    assert_eq!(
        result.stop,
        Stop::BlewUp {
            step: 12,
            rotor: 1,
            reason: "orientation or angular velocity is not finite".to_string()
        }
    );
    let csv = std::fs::read_to_string(dir.path().join("e.csv")).expect("csv written");
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "step,time,kinetic_energy,norm_error");
    assert_eq!(rows.len(), 1 + 7, "rows at steps 0, 2, ..., 12");
    assert!(rows[7].starts_with("12,"));
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join(SUMMARY_FILE)).expect("summary"),
    )
    .expect("valid JSON");
    assert_eq!(summary["status"], "blew_up");
    assert_eq!(
        summary["message"],
        "blew up at step 12, rotor 1: orientation or angular velocity is not finite"
    );
}

/// An energy error above the scene's threshold stops the run (a time step far
/// too large for the dipole in a field), naming the step.
#[test]
fn energy_threshold_stops_a_run_with_too_large_a_step() {
    let overrides = Overrides {
        dt: Some(0.2),
        steps: Some(2000),
        integrator: Some("gear_a".to_string()),
        ..Overrides::default()
    };
    let (mut raw, _) = load("dipole_in_field", &overrides).expect("valid");
    let mut record = raw.record.take().unwrap_or_default();
    record.energy_error_threshold = Some(1e-3);
    record.check_every = Some(1);
    raw.record = Some(record);
    let scene = validate(&raw).expect("valid");
    let result = execute(&scene, definition(), &common::in_memory(), None, None).expect("runs");
    let Stop::BlewUp {
        step,
        rotor,
        reason,
    } = &result.stop
    else {
        panic!("expected a blow-up, got {:?}", result.stop);
    };
    assert!(*step < 2000 && *rotor == 0, "{:?}", result.stop);
    assert!(reason.contains("exceeds the threshold"), "{reason}");
    let error = result
        .summary
        .final_energies
        .as_ref()
        .expect("energies")
        .error;
    assert!(error.abs() > 1e-3);
}

/// For every integrator: 40 steps in one go, and 20 steps + a checkpoint +
/// a restart to 40, give the same CSV rows and the same final state, bit for bit.
#[test]
fn restart_from_checkpoint_is_bit_for_bit() {
    for integrator in ["gear_a", "gear_b", "no_squish", "dlm", "richardson"] {
        let text = two_rotors(&common::restart_record(&[
            "kinetic_energy",
            "potential_energy",
            "energy_error",
            "norm_error",
        ]));
        let run_to = |steps: i64, restart: Option<&std::path::Path>, dir: &std::path::Path| {
            let overrides = Overrides {
                integrator: Some(integrator.to_string()),
                ..common::steps(steps)
            };
            let (_, scene) = common::scene_with(&text, &overrides);
            let outputs = common::outputs(Some(dir), true);
            execute(&scene, definition(), &outputs, restart, None).expect("runs")
        };
        let (full_dir, half_dir, rest_dir) = (
            tempfile::tempdir().expect("dir"),
            tempfile::tempdir().expect("dir"),
            tempfile::tempdir().expect("dir"),
        );
        let full = run_to(40, None, full_dir.path());
        run_to(20, None, half_dir.path());
        let checkpoint = half_dir.path().join(CHECKPOINT_FILE);
        let rest = run_to(40, Some(&checkpoint), rest_dir.path());
        let csv = |d: &std::path::Path| std::fs::read_to_string(d.join("e.csv")).expect("csv");
        let full_csv = csv(full_dir.path());
        let rest_csv = csv(rest_dir.path());
        let tail: Vec<&str> = full_csv
            .lines()
            .filter(|l| {
                l.split(',')
                    .next()
                    .and_then(|s| s.parse::<u64>().ok())
                    .is_some_and(|s| s >= 20)
            })
            .collect();
        let rest_rows: Vec<&str> = rest_csv.lines().skip(1).collect();
        assert_eq!(rest_rows, tail, "{integrator}");
        let last = |r: &quatrot::run::RunResult| {
            let t = r.trajectory.as_ref().expect("frames");
            let n = 2 * 4;
            t.orientations[t.orientations.len() - n..]
                .iter()
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(last(&full), last(&rest), "{integrator}");
        assert_eq!(rest.summary.start_step, 20);
    }
}

/// A checkpoint refuses a scene with another integrator.
#[test]
fn checkpoint_of_another_integrator_is_refused() {
    let text = two_rotors("[record]\ncheckpoint_every = 10\n");
    let dir = tempfile::tempdir().expect("dir");
    let outputs = common::outputs(Some(dir.path()), false);
    let scene = validate(&parse_toml(&text).expect("valid")).expect("valid");
    execute(&scene, definition(), &outputs, None, None).expect("runs");
    let overrides = Overrides {
        integrator: Some("gear_a".to_string()),
        ..Overrides::default()
    };
    let (_, other) = common::scene_with(&text, &overrides);
    let err = execute(
        &other,
        definition(),
        &outputs,
        Some(&dir.path().join(CHECKPOINT_FILE)),
        None,
    )
    .expect_err("refused");
    assert!(
        err.to_string().contains(
            "the integrator is {\"kind\":\"gear_a\",\"renormalise\":true,\"startup\":\"consistent\"} \
             in the scene but {\"kind\":\"dlm\",\"spherical_tops\":\"exact\"} in the checkpoint"
        ),
        "{err}"
    );
}

/// The same seed gives the same initial state and the same output; another
/// seed gives another.
#[test]
fn same_seed_same_output() {
    let text = two_rotors(
        "[[record.series]]\nevery = 3\nquantities = [\"kinetic_energy\", \"potential_energy\"]\n",
    );
    let run = |seed: u64| {
        let mut raw =
            parse_toml(&text.replace("seed = 7", &format!("seed = {seed}"))).expect("valid");
        raw.name = Some("seeded".into());
        let scene = validate(&raw).expect("valid");
        let r = execute(&scene, definition(), &common::in_memory(), None, None).expect("runs");
        (scene.initial, r.series[0].values.clone(), r.summary.seed)
    };
    let (a, b, c) = (run(7), run(7), run(8));
    assert_eq!(a, b);
    assert_ne!(a.0, c.0);
    assert_eq!(a.2, Some(7));
}

/// `format = "gsd"` writes `trajectory.gsd` (and no DCD or PDB), one frame
/// per sample: the file grows by one frame's chunks (step, N x 4 float32
/// orientations) per sample after the first, which also holds the box and
/// the positions. Its content is read back with the `gsd` package in the
/// validation suite.
#[test]
fn gsd_format_writes_the_gsd_file_only() {
    let frames_of = |every: u64| {
        let text = two_rotors(&format!(
            "[record.trajectory]\nevery = {every}\nformat = \"gsd\"\n"
        ));
        let scene = validate(&parse_toml(&text).expect("valid")).expect("valid");
        let dir = tempfile::tempdir().expect("dir");
        let outputs = common::outputs(Some(dir.path()), false);
        execute(&scene, definition(), &outputs, None, None).expect("runs");
        assert!(!dir.path().join(DCD_FILE).exists() && !dir.path().join(PDB_FILE).exists());
        std::fs::metadata(dir.path().join(GSD_FILE))
            .expect("trajectory.gsd written")
            .len()
    };
    // 30 steps: frames at 0, 10, 20, 30 and at 0, 15, 30.
    let (four, three) = (frames_of(10), frames_of(15));
    let per_frame = 8 + 2 * 4 * 4;
    assert_eq!(four - three, per_frame);
}
