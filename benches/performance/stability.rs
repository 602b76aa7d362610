//! How far each scheme can be pushed: the largest stable time step (energy
//! error below 10 % of the initial kinetic energy over a fixed time; found by
//! doubling, then bisection in log dt), and long runs with their energy and
//! norm drift.

use crate::measure::{observed, pool, with_step, Observed};
use crate::schemes::all;
use crate::Effort;
use quatrot::scene::{load, Overrides, Scene};
use serde_json::{json, Value};
use std::error::Error;

type Res<T> = Result<T, Box<dyn Error + Send + Sync>>;

/// "Stable" means `|E - E_0| < STABLE_ENERGY_ERROR * KE_0` over the run
/// (`|E_0|` instead of `KE_0` for rotors starting at rest).
const STABLE_ENERGY_ERROR: f64 = 0.1;
/// Bisection steps in log dt after the doubling (2^(1/32): about 2 %).
const BISECTIONS: usize = 5;
/// Doublings before giving up.
const MAX_DOUBLINGS: usize = 14;
/// Halvings before reporting "unstable at every step tried" (each halving
/// doubles the cost of a run).
const MAX_HALVINGS: usize = 5;
/// The fixed time spans at least this many steps: larger steps are not tried
/// (a scheme stable there is reported as stable up to `time / MIN_STEPS`).
const MIN_STEPS: f64 = 10.0;

struct Case {
    scene: &'static str,
    time: f64,
    dt_start: f64,
    /// Energy checks every this many steps (the lattices: every step would
    /// double the cost).
    check_every: u64,
}

fn cases(effort: Effort) -> Vec<Case> {
    vec![
        Case {
            scene: "free_asymmetric_top",
            time: effort.pick(20.0, 1.0),
            dt_start: 0.05,
            check_every: 1,
        },
        Case {
            scene: "dipole_in_field",
            time: effort.pick(10.0, 1.0),
            dt_start: 0.02,
            check_every: 1,
        },
        Case {
            scene: "dipole_lattice_sc_cutoff",
            time: effort.pick(2.0, 0.02),
            dt_start: 0.004,
            check_every: 2,
        },
        Case {
            scene: "quadrupole_lattice_fcc",
            time: effort.pick(2.0, 0.02),
            dt_start: 0.004,
            check_every: 2,
        },
    ]
}

/// One attempt at `dt`: `None` when stable, else how it failed.
fn attempt(scene: &Scene, case: &Case, dt: f64) -> Res<Option<String>> {
    let s = with_step(scene, dt, case.time);
    let samples = (s.steps / case.check_every).max(1);
    let o = observed(&s, samples, Some(STABLE_ENERGY_ERROR))?;
    Ok(o.failure)
}

fn largest_stable(scene: &Scene, case: &Case) -> Res<Value> {
    let mut stable = None;
    let mut unstable: Option<(f64, String)> = None;
    let cap = case.time / MIN_STEPS;
    let mut dt = case.dt_start.min(cap);
    let mut halvings = 0;
    for _ in 0..MAX_DOUBLINGS {
        match attempt(scene, case, dt)? {
            None => {
                stable = Some(dt);
                if unstable.is_some() || dt >= cap {
                    break;
                }
                dt = (dt * 2.0).min(cap);
            }
            Some(why) => {
                unstable = Some((dt, why));
                if stable.is_some() || halvings == MAX_HALVINGS {
                    break;
                }
                halvings += 1;
                dt /= 2.0;
            }
        }
    }
    if let (Some(mut lo), Some((mut hi, mut why))) = (stable, unstable.clone()) {
        for _ in 0..BISECTIONS {
            let mid = (lo * hi).sqrt();
            match attempt(scene, case, mid)? {
                None => lo = mid,
                Some(w) => (hi, why) = (mid, w),
            }
        }
        return Ok(
            json!({"largest_stable_dt": lo, "capped": false, "first_unstable_dt": hi, "failure": why}),
        );
    }
    Ok(json!({
        "largest_stable_dt": stable,
        "capped": stable == Some(cap),
        "first_unstable_dt": unstable.as_ref().map(|u| u.0),
        "failure": unstable.map(|u| u.1),
    }))
}

/// The largest stable step of every scheme on every scene, on one thread.
pub fn run(effort: Effort) -> Res<Value> {
    pool(1)?.install(|| {
        let mut out = Vec::new();
        for case in cases(effort) {
            let (_, scene) = load(case.scene, &Overrides::default())?;
            for scheme in all() {
                let mut s = scene.clone();
                s.integrator = scheme.choice;
                let mut r = largest_stable(&s, &case)?;
                r["scene"] = json!(case.scene);
                r["scheme"] = json!(scheme.label);
                r["time"] = json!(case.time);
                r["check_every"] = json!(case.check_every);
                out.push(r);
            }
            eprintln!("  {}", case.scene);
        }
        Ok(Value::from(out))
    })
}

/// Long runs at the scenes' own time steps: energy and norm drift.
pub fn long_runs(effort: Effort) -> Res<Value> {
    let runs: [(&str, u64, u64); 2] = [
        ("free_asymmetric_top", effort.pick(1_000_000, 2_000), 1000),
        (
            "dipole_lattice_sc_cutoff",
            effort.pick(LATTICE_LONG_STEPS, 20),
            100,
        ),
    ];
    pool(1)?.install(|| {
        let mut out = Vec::new();
        for (name, steps, samples) in runs {
            let (_, scene) = load(name, &Overrides::default())?;
            for scheme in all() {
                let mut s = with_step(&scene, scene.dt, scene.dt * steps as f64);
                s.integrator = scheme.choice;
                let mut o: Observed = observed(&s, samples, None)?;
                o.final_orientations.clear();
                let mut r = serde_json::to_value(&o)?;
                r["scene"] = json!(name);
                r["scheme"] = json!(scheme.label);
                r["dt"] = json!(s.dt);
                r["steps"] = json!(s.steps);
                out.push(r);
            }
            eprintln!("  {name}");
        }
        Ok(Value::from(out))
    })
}

/// Steps of the lattice long runs.
const LATTICE_LONG_STEPS: u64 = 100_000;
