//! Energies and torques of dipole, quadrupole and mixed clusters against
//! OpenMM's AmoebaMultipoleForce (fixtures/multipoles_openmm.json, made by
//! validation/fixtures/gen_multipoles.py; provenance and units in the file).
//! OpenMM was given the Buckingham quadrupoles divided by 3: agreement proves
//! the factor-3 conversion as well as the interaction tensors.

use nalgebra::{Matrix3, Vector3};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;
use serde_json::Value;

/// Both codes evaluate the same closed forms in double precision; OpenMM's
/// frame atoms add round-off of ~1e-15 to the frames.
const ENERGY_TOLERANCE: f64 = 1e-9;
/// Torques pass through OpenMM's torque-to-force mapping on frame atoms, then
/// back through (r_a - r_site) x F_a: relative to the largest torque of the set.
const TORQUE_TOLERANCE: f64 = 1e-7;

fn fixture() -> Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/multipoles_openmm.json"
    );
    let text =
        std::fs::read_to_string(path).expect("run `make fixtures` to create the OpenMM fixtures");
    serde_json::from_str(&text).expect("valid JSON")
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(numbers).collect(),
        other => vec![other.as_f64().expect("a number")],
    }
}

fn vector(v: &Value) -> Vector3<f64> {
    Vector3::from_column_slice(&numbers(v))
}

fn rotors(cluster: &Value) -> Vec<Rotor> {
    let sites = cluster["sites"].as_array().unwrap();
    let dipoles = cluster["dipoles_body"].as_array().unwrap();
    let quadrupoles = cluster["quadrupoles_body"].as_array().unwrap();
    sites
        .iter()
        .zip(dipoles)
        .zip(quadrupoles)
        .map(|((s, d), q)| Rotor {
            site: vector(s),
            inertia: Inertia::Spherical(1.0),
            dipole_body: (!d.is_null()).then(|| vector(d)),
            quadrupole_body: (!q.is_null()).then(|| Matrix3::from_row_slice(&numbers(q))),
        })
        .collect()
}

fn check_cluster(name_prefix: &str) {
    let data = fixture();
    let mut checked = 0;
    for cluster in data["clusters"].as_array().unwrap() {
        let name = cluster["name"].as_str().unwrap();
        if !name.starts_with(name_prefix) {
            continue;
        }
        let p = MultipolePotential::new(&rotors(cluster), Boundary::Open, ExternalFields::NONE)
            .unwrap();
        let configurations = cluster["configurations"].as_array().unwrap();
        assert!(
            configurations.len() >= 20,
            "{name}: at least 20 orientation sets"
        );
        for (c, conf) in configurations.iter().enumerate() {
            let q: Vec<Quat> = conf["orientations"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| {
                    let v = numbers(x);
                    Quat::new(v[0], v[1], v[2], v[3])
                })
                .collect();
            let mut torques = vec![Vector3::zeros(); q.len()];
            p.accumulate_torques(&q, &mut torques);
            let energy = p.energy(&q);
            let want = conf["energy"].as_f64().unwrap();
            let err = (energy - want).abs() / want.abs();
            assert!(
                err < ENERGY_TOLERANCE,
                "{name} #{c}: energy {energy} vs OpenMM {want} (rel {err:e})"
            );
            let want_t: Vec<_> = conf["torques_space"]
                .as_array()
                .unwrap()
                .iter()
                .map(vector)
                .collect();
            let scale = want_t.iter().map(|t| t.amax()).fold(0.0, f64::max);
            for (i, (t, w)) in torques.iter().zip(&want_t).enumerate() {
                let err = (t - w).amax() / scale;
                assert!(
                    err < TORQUE_TOLERANCE,
                    "{name} #{c} rotor {i}: torque {t:?} vs OpenMM {w:?} (rel {err:e})"
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked >= 60,
        "{name_prefix}: expected 3 cluster sizes x 20 sets, got {checked}"
    );
}

/// Dipole-dipole interactions of 8-, 27- and 64-rotor clusters.
#[test]
fn dipole_clusters_match_openmm() {
    check_cluster("dipole-");
}

/// Quadrupole-quadrupole interactions (Buckingham Theta here, Theta/3 in OpenMM).
#[test]
fn quadrupole_clusters_match_openmm() {
    check_cluster("quadrupole-");
}

/// Rotors carrying a dipole, a quadrupole or both: all three pair terms together.
#[test]
fn mixed_clusters_match_openmm() {
    check_cluster("mixed-");
}
