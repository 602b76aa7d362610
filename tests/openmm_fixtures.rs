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

/// Both codes evaluate the same closed forms in double precision: each pair
/// term carries a few ulps of round-off in each (tens of operations), OpenMM
/// adds its Coulomb-constant conversion and the frame atoms' rounded
/// positions (a few ulps of each multipole's orientation), and the sum
/// rounds at a few ulps of the sum of the terms' magnitudes. So the energies
/// agree to a small multiple of `eps` times `sum_{i<j} |v_ij|`, not of
/// `|V|`, which cancels (the sum of magnitudes is up to 430 times `|V|` in
/// these clusters). Measured: at most 11 eps.
const ENERGY_ROUND_OFF: f64 = 64.0 * f64::EPSILON;
/// OpenMM's torques also pass through its mapping onto forces on two frame
/// atoms 0.1 nm from each site and back through `(r_a - r_site) x F_a`, with
/// positions rounded at the scale of the sites (up to ~1 nm, ten times the
/// arm): a few tens of ulps of rotor `i`'s torque scale
/// `sum_j |n_ij|` (largest component of each pair's torque on `i`).
/// Measured: at most 124 eps.
const TORQUE_ROUND_OFF: f64 = 512.0 * f64::EPSILON;

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

/// The round-off scales of a configuration: `sum_{i<j} |v_ij|` and, per
/// rotor, `sum_j |n_ij|` (each pair evaluated on its own).
fn round_off_scales(pairs: &[(usize, usize, MultipolePotential)], q: &[Quat]) -> (f64, Vec<f64>) {
    let mut energy = 0.0;
    let mut torques = vec![0.0; q.len()];
    for (i, j, pair) in pairs {
        let both = [q[*i], q[*j]];
        energy += pair.energy(&both).abs();
        let mut t = [Vector3::zeros(); 2];
        pair.accumulate_torques(&both, &mut t);
        torques[*i] += t[0].amax();
        torques[*j] += t[1].amax();
    }
    (energy, torques)
}

fn check_cluster(name_prefix: &str) {
    // The many two-rotor evaluations of the scales are too small to share
    // between threads.
    let serial = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a rayon pool");
    serial.install(|| check_cluster_serial(name_prefix));
}

fn check_cluster_serial(name_prefix: &str) {
    let data = fixture();
    let mut checked = 0;
    for cluster in data["clusters"].as_array().unwrap() {
        let name = cluster["name"].as_str().unwrap();
        if !name.starts_with(name_prefix) {
            continue;
        }
        let all = rotors(cluster);
        let p = MultipolePotential::new(&all, Boundary::Open, ExternalFields::NONE).unwrap();
        let pairs: Vec<(usize, usize, MultipolePotential)> = (0..all.len())
            .flat_map(|i| (i + 1..all.len()).map(move |j| (i, j)))
            .map(|(i, j)| {
                let pair = [all[i].clone(), all[j].clone()];
                let pair = MultipolePotential::new(&pair, Boundary::Open, ExternalFields::NONE);
                (i, j, pair.unwrap())
            })
            .collect();
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
            let (energy_scale, torque_scales) = round_off_scales(&pairs, &q);
            let mut torques = vec![Vector3::zeros(); q.len()];
            p.accumulate_torques(&q, &mut torques);
            let energy = p.energy(&q);
            let want = conf["energy"].as_f64().unwrap();
            let err = (energy - want).abs() / energy_scale;
            assert!(
                err < ENERGY_ROUND_OFF,
                "{name} #{c}: energy {energy} vs OpenMM {want} ({:.1} eps of sum |v_ij|)",
                err / f64::EPSILON
            );
            let want_t: Vec<_> = conf["torques_space"]
                .as_array()
                .unwrap()
                .iter()
                .map(vector)
                .collect();
            for (i, (t, w)) in torques.iter().zip(&want_t).enumerate() {
                let err = (t - w).amax() / torque_scales[i];
                assert!(
                    err < TORQUE_ROUND_OFF,
                    "{name} #{c} rotor {i}: torque {t:?} vs OpenMM {w:?} ({:.1} eps of sum |n_ij|)",
                    err / f64::EPSILON
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
