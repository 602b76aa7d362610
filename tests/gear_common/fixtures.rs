//! The scipy reference trajectories of `fixtures/*.json` and the uniform-field
//! dipole potential they were made with.

use nalgebra::Vector3;
use quatrot::integrators::RotorState;
use quatrot::potential::Potential;
use quatrot::rotor::Inertia;
use quatrot::Quat;

/// One reference case of `gen_free_top.py` / `gen_dipole_field.py`.
pub struct Reference {
    pub name: String,
    pub inertia: Inertia,
    pub field: Option<DipoleInField>,
    pub initial: RotorState,
    pub times: Vec<f64>,
    pub orientations: Vec<Quat>,
    pub omega_body: Vec<Vector3<f64>>,
}

fn vec3(v: &serde_json::Value) -> Vector3<f64> {
    Vector3::from_iterator(
        v.as_array()
            .expect("array")
            .iter()
            .map(|x| x.as_f64().expect("number")),
    )
}

fn quat(v: &serde_json::Value) -> Quat {
    let c: Vec<f64> = v
        .as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    Quat::new(c[0], c[1], c[2], c[3])
}

/// Loads the case `name` of `fixtures/<file>`.
pub fn reference(file: &str, name: &str) -> Reference {
    let path = format!("{}/fixtures/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{path}: {e} (run make fixtures)"));
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let case = json["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("{path}: no case {name}"));
    let inertia = Inertia::from_moments(vec3(&case["inertia"]));
    let field = (!case["field"].is_null()).then(|| DipoleInField {
        dipole_body: vec3(&case["dipole_body"]),
        field: vec3(&case["field"]),
    });
    Reference {
        name: name.to_string(),
        inertia,
        field,
        initial: RotorState {
            orientation: quat(&case["orientation0"])
                .try_normalize()
                .expect("non-zero"),
            omega_body: vec3(&case["omega_body0"]),
        },
        times: case["times"]
            .as_array()
            .expect("times")
            .iter()
            .map(|t| t.as_f64().expect("number"))
            .collect(),
        orientations: case["orientations"]
            .as_array()
            .expect("q")
            .iter()
            .map(quat)
            .collect(),
        omega_body: case["omega_body"]
            .as_array()
            .expect("w")
            .iter()
            .map(vec3)
            .collect(),
    }
}

/// A minimal uniform-field dipole potential for the tests (the multipole
/// module is separate): `V = -mu_s . E` with `mu_s = R(Q) mu_b`, so
/// `V = -mu_b . A(Q) E`, `dV/dq_k = -mu_b . (dA/dq_k) E` (eq 14) and the space
/// torque `mu_s x E`. The same dipole on every rotor.
#[derive(Clone, Copy, Debug)]
pub struct DipoleInField {
    pub dipole_body: Vector3<f64>,
    pub field: Vector3<f64>,
}

impl Potential for DipoleInField {
    fn energy(&self, orientations: &[Quat]) -> f64 {
        orientations
            .iter()
            .map(|q| {
                -self
                    .dipole_body
                    .dot(&(q.space_to_body_matrix() * self.field))
            })
            .sum()
    }
    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) {
        for (q, g) in orientations.iter().zip(gradient) {
            let d = q.space_to_body_matrix_derivatives();
            *g += Quat(std::array::from_fn(|k| {
                -self.dipole_body.dot(&(d[k] * self.field))
            }));
        }
    }
    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]) {
        for (q, t) in orientations.iter().zip(torques_space) {
            *t += q.body_to_space(&self.dipole_body).cross(&self.field);
        }
    }
}
