//! Single rotors under stress, every scheme at one fixed step: fast spin,
//! near-degenerate and strongly asymmetric inertia, orientations at the
//! Euler-angle singularity and the poles of every axis, a strong field with
//! tight libration. Errors against scipy are added by `validation.bench`.

use crate::measure::{observed, with_step};
use crate::schemes::all;
use crate::Effort;
use nalgebra::Vector3;
use quatrot::integrators::RotorState;
use quatrot::rotor::Inertia;
use quatrot::scene::{load, Overrides, Scene};
use quatrot::Quat;
use serde_json::{json, Value};
use std::error::Error;

type Res<T> = Result<T, Box<dyn Error + Send + Sync>>;

struct Case {
    name: &'static str,
    inertia: [f64; 3],
    dipole: Option<[f64; 3]>,
    field: Option<[f64; 3]>,
    orientation: [f64; 4],
    omega_body: [f64; 3],
    dt: f64,
    time: f64,
}

const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn cases() -> Vec<Case> {
    let top = |name, orientation| Case {
        name,
        inertia: [1.0, 2.0, 3.0],
        dipole: Some([0.0, 0.0, 1.0]),
        field: Some([0.0, 0.0, 1.0]),
        orientation,
        omega_body: [0.3, -0.2, 0.5],
        dt: 0.01,
        time: 10.0,
    };
    vec![
        Case {
            name: "fast spin |w| = 50 (I = 1,2,3)",
            inertia: [1.0, 2.0, 3.0],
            dipole: None,
            field: None,
            orientation: [1.0, 0.0, 0.0, 0.0],
            omega_body: [0.5, 0.5, 50.0],
            dt: 0.002,
            time: 5.0,
        },
        Case {
            name: "near-spherical I = (1, 1+1e-9, 1+2e-9)",
            inertia: [1.0, 1.0 + 1e-9, 1.0 + 2e-9],
            dipole: None,
            field: None,
            orientation: [1.0, 0.0, 0.0, 0.0],
            omega_body: [0.3, 0.7, 1.1],
            dt: 0.01,
            time: 10.0,
        },
        Case {
            name: "near-symmetric I = (1, 1+1e-9, 2)",
            inertia: [1.0, 1.0 + 1e-9, 2.0],
            dipole: None,
            field: None,
            orientation: [1.0, 0.0, 0.0, 0.0],
            omega_body: [0.3, 0.7, 1.1],
            dt: 0.01,
            time: 10.0,
        },
        Case {
            name: "strongly asymmetric I = (0.01, 1, 100)",
            inertia: [0.01, 1.0, 100.0],
            dipole: None,
            field: None,
            orientation: [1.0, 0.0, 0.0, 0.0],
            omega_body: [1.0, 1.0, 1.0],
            dt: 0.002,
            time: 5.0,
        },
        top("theta = 0 (identity), field along z", [1.0, 0.0, 0.0, 0.0]),
        top("pole: pi about x", [0.0, 1.0, 0.0, 0.0]),
        top("pole: pi about y", [0.0, 0.0, 1.0, 0.0]),
        top("pole: pi about z", [0.0, 0.0, 0.0, 1.0]),
        top("pi/2 about x", [H, H, 0.0, 0.0]),
        top("pi/2 about y", [H, 0.0, H, 0.0]),
        top("pi/2 about z", [H, 0.0, 0.0, H]),
        Case {
            name: "tight libration E = 1000 (I = 0.1, 30 deg)",
            inertia: [0.1, 0.1, 0.1],
            dipole: Some([0.0, 0.0, 1.0]),
            field: Some([0.0, 0.0, 1000.0]),
            orientation: [0.9659258262890683, 0.25881904510252074, 0.0, 0.0],
            omega_body: [0.0, 0.0, 0.0],
            dt: 0.002,
            time: 1.0,
        },
    ]
}

fn scene_of(base: &Scene, case: &Case) -> Scene {
    let mut s = base.clone();
    let rotor = &mut s.rotors[0];
    rotor.inertia = Inertia::from_moments(Vector3::from(case.inertia));
    rotor.dipole_body = case.dipole.map(Vector3::from);
    s.fields.field = case.field.map(Vector3::from);
    s.initial = vec![RotorState {
        orientation: Quat(case.orientation),
        omega_body: Vector3::from(case.omega_body),
    }];
    s
}

/// Every case with every scheme.
pub fn run(effort: Effort) -> Res<Value> {
    // A single-rotor scene with a dipole and a field, reshaped per case.
    let (_, base) = load("dipole_in_field", &Overrides::default())?;
    let mut out = Vec::new();
    for case in cases() {
        let time = effort.pick(case.time, case.dt * 10.0);
        let scene = scene_of(&base, &case);
        for scheme in all() {
            let mut s = with_step(&scene, case.dt, time);
            s.integrator = scheme.choice;
            let o = observed(&s, 200, None)?;
            let mut r = serde_json::to_value(&o)?;
            r["case"] = json!(case.name);
            r["scheme"] = json!(scheme.label);
            r["dt"] = json!(case.dt);
            r["time"] = json!(time);
            r["inertia"] = json!(case.inertia);
            r["dipole_body"] = json!(case.dipole);
            r["field"] = json!(case.field);
            r["orientation"] = json!(case.orientation);
            r["omega_body"] = json!(case.omega_body);
            out.push(r);
        }
    }
    Ok(Value::from(out))
}
