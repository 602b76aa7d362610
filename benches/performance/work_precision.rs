//! Work-precision: every scheme on every benchmark scene over a geometric
//! series of time steps, on one thread. Errors are computed by
//! `validation.bench` from the final orientations written here: against
//! scipy DOP853 for single rotors, against a far smaller step of scheme A
//! for the lattices (two reference steps, to show its own convergence).

use crate::measure::{median, observed, pool, timed, with_step, Observed};
use crate::schemes::{all, Scheme};
use crate::Effort;
use quatrot::integrators::IntegratorSpec;
use quatrot::rotor::Inertia;
use quatrot::scene::{load, Overrides, Scene};
use serde::Serialize;
use serde_json::{json, Value};
use std::error::Error;

/// A scene of the work-precision study.
struct Study {
    scene: &'static str,
    /// Run time (the error is measured at this time).
    time: f64,
    /// Largest time step; the series halves it `dt_count - 1` times.
    dt_max: f64,
    dt_count: usize,
    /// Timing repeats per run (the median is reported).
    repeats: usize,
    /// Reference steps (lattices only; single rotors use scipy).
    reference_dts: &'static [f64],
}

fn studies(effort: Effort) -> Vec<Study> {
    vec![
        Study {
            scene: "free_asymmetric_top",
            time: effort.pick(10.0, 0.5),
            dt_max: 0.1,
            dt_count: effort.pick(10, 2),
            repeats: 5,
            reference_dts: &[],
        },
        Study {
            scene: "dipole_in_field",
            time: effort.pick(4.0, 0.2),
            dt_max: 0.05,
            dt_count: effort.pick(10, 2),
            repeats: 5,
            reference_dts: &[],
        },
        Study {
            scene: "dipole_lattice_sc_cutoff",
            time: effort.pick(0.4, 0.004),
            dt_max: 0.016,
            dt_count: effort.pick(5, 2),
            repeats: effort.pick(3, 1),
            reference_dts: effort.pick(&[2e-4, 1e-4][..], &[1e-3][..]),
        },
        Study {
            scene: "quadrupole_lattice_fcc",
            time: effort.pick(0.4, 0.004),
            dt_max: 0.016,
            dt_count: effort.pick(5, 2),
            repeats: effort.pick(3, 1),
            reference_dts: effort.pick(&[2e-4, 1e-4][..], &[1e-3][..]),
        },
    ]
}

/// The reference scheme of the lattices: scheme A (fifth order, one torque
/// evaluation per step).
fn reference_scheme() -> Scheme {
    all()[0]
}

/// Samples of energy and norm per run.
const SAMPLES: u64 = 200;

#[derive(Serialize)]
struct Run {
    scheme: &'static str,
    dt: f64,
    steps: u64,
    wall_seconds: Vec<f64>,
    wall_median: f64,
    #[serde(flatten)]
    observed: Observed,
}

fn run_one(
    scene: &Scene,
    scheme: &Scheme,
    dt: f64,
    time: f64,
    repeats: usize,
) -> Result<Run, Box<dyn Error + Send + Sync>> {
    let mut s = with_step(scene, dt, time);
    s.integrator = scheme.choice;
    let observed = observed(&s, SAMPLES, None)?;
    let wall_seconds = if observed.failure.is_none() {
        timed(&s, repeats)?
    } else {
        Vec::new()
    };
    Ok(Run {
        scheme: scheme.label,
        dt,
        steps: s.steps,
        wall_median: median(&wall_seconds),
        wall_seconds,
        observed,
    })
}

/// What the Python side needs to rebuild the system: rotors, fields, the
/// initial state.
fn system(scene: &Scene) -> Value {
    let rotor = &scene.rotors[0];
    let inertia = match rotor.inertia {
        Inertia::Spherical(i) => [i; 3],
        Inertia::Principal(v) => [v.x, v.y, v.z],
    };
    json!({
        "rotors": scene.rotors.len(),
        "inertia": inertia,
        "dipole_body": rotor.dipole_body.map(|d| [d.x, d.y, d.z]),
        "field": scene.fields.field.map(|e| [e.x, e.y, e.z]),
        "box_lengths": scene.box_lengths().map(|b| [b.x, b.y, b.z]),
        "sites": scene.rotors.iter().map(|r| [r.site.x, r.site.y, r.site.z]).collect::<Vec<_>>(),
        "orientations": scene.initial.iter().map(|s| s.orientation.0).collect::<Vec<_>>(),
        "omega_body": scene.initial.iter().map(|s| [s.omega_body.x, s.omega_body.y, s.omega_body.z]).collect::<Vec<_>>(),
    })
}

fn study(s: &Study) -> Result<Value, Box<dyn Error + Send + Sync>> {
    let (_, scene) = load(s.scene, &Overrides::default())?;
    let dts: Vec<f64> = (0..s.dt_count)
        .map(|k| s.dt_max / 2f64.powi(k as i32))
        .collect();
    let mut runs = Vec::new();
    for scheme in all() {
        for &dt in &dts {
            runs.push(run_one(&scene, &scheme, dt, s.time, s.repeats)?);
        }
        eprintln!("  {} {}", s.scene, scheme.label);
    }
    let reference = reference_scheme();
    let references = s
        .reference_dts
        .iter()
        .map(|&dt| run_one(&scene, &reference, dt, s.time, 1))
        .collect::<Result<Vec<_>, _>>()?;
    let reference_name = match reference.choice {
        IntegratorSpec::GearA(_) => "scheme A",
        _ => reference.label,
    };
    Ok(json!({
        "scene": s.scene,
        "time": s.time,
        "system": system(&scene),
        "runs": runs,
        "reference_scheme": reference_name,
        "references": references,
    }))
}

/// The whole study, on one thread.
pub fn run(effort: Effort) -> Result<Value, Box<dyn Error + Send + Sync>> {
    let pool = pool(1)?;
    pool.install(|| {
        studies(effort)
            .iter()
            .map(study)
            .collect::<Result<Vec<_>, _>>()
            .map(Value::from)
    })
}
