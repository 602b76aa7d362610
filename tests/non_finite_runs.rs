//! A run whose conserved energy becomes non-finite has blown up: it stops
//! with the step and a rotor, never reports `completed` (issue 37: a
//! Nose-Hoover chain at T = 1e-300 wrote `inf` conserved energies and
//! ended `completed`).

use quatrot::run::execute;
use quatrot::scene::{load_text, Overrides};
use quatrot::simulation::Stop;

mod common;

/// The 2x2x2 Ewald dipole lattice, NO_SQUISH with a Nose-Hoover chain at
/// `T = 1e-300`, energies every 10 steps, no energy-error threshold.
const SCENE: &str = r#"
version = 1
[rotors]
kind = "lattice"
lattice = "simple_cubic"
cells = 2
spacing = 1.0
default = { inertia = 0.1, dipole = [0.0, 0.0, 1.0] }
[interactions]
terms = ["dipole_dipole"]
boundary = { kind = "periodic", sum = "ewald" }
[initial]
kind = "random"
seed = 1
temperature = 1.0
[integrator]
kind = "no_squish"
[thermostat]
kind = "nose_hoover"
temperature = 1e-300
tau = 0.4
[run]
dt = 0.002
steps = 200
[[record.series]]
name = "energies"
every = 10
quantities = ["conserved_energy", "energy_error"]
"#;

#[test]
fn a_non_finite_conserved_energy_is_a_blow_up() {
    let (_, scene) = load_text(SCENE, &Overrides::default()).expect("valid scene");
    let result = execute(
        &scene,
        serde_json::Value::Null,
        &common::in_memory(),
        None,
        None,
    )
    .expect("runs");
    match &result.stop {
        Stop::BlewUp { step, reason, .. } => {
            assert!(*step <= 200, "{step}");
            assert!(
                reason.starts_with("the conserved energy is not finite"),
                "{reason}"
            );
        }
        other => panic!("expected a blow-up, got {other:?}"),
    }
}
