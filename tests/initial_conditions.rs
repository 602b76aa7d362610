//! Random initial conditions follow the distributions the scene format
//! promises: orientations uniform over rotations, body angular velocities
//! Maxwell distributed with `<I_a w_a^2> = T` (k_B = 1).

use nalgebra::Vector3;
use quatrot::rotor::Inertia;
use quatrot::scene::random_states;

/// Enough rotors for the sample means below to be within a few percent.
const SAMPLES: usize = 20_000;
/// Sample means are accepted within this many standard errors (a failure
/// by chance has probability ~6e-5 per check).
const SIGMAS: f64 = 4.0;

#[test]
fn random_states_are_uniform_and_maxwellian() {
    let moments = Vector3::new(0.1, 0.5, 2.0);
    let temperature = 1.7;
    let inertia = vec![Inertia::Principal(moments); SAMPLES];
    let states = random_states(&inertia, temperature, 2024);
    let n = SAMPLES as f64;
    // Equipartition: I_a w_a^2 is T times a chi-squared variable with one
    // degree of freedom, variance 2 T^2.
    for a in 0..3 {
        let mean = states
            .iter()
            .map(|s| moments[a] * s.omega_body[a].powi(2))
            .sum::<f64>()
            / n;
        let error = SIGMAS * temperature * (2.0 / n).sqrt();
        assert!((mean - temperature).abs() < error, "axis {a}: {mean}");
    }
    // Uniform rotations: each body axis is uniform on the sphere, so each
    // space component has mean 0 and variance 1/3; each quaternion component
    // squared is Beta(1/2, 3/2) on the uniform 3-sphere: mean 1/4, variance 1/16.
    for axis in 0..3 {
        let mut e = Vector3::zeros();
        e[axis] = 1.0;
        let directions: Vec<Vector3<f64>> = states
            .iter()
            .map(|s| s.orientation.body_to_space(&e))
            .collect();
        let mean = directions.iter().sum::<Vector3<f64>>() / n;
        assert!(
            mean.norm() < SIGMAS * (1.0 / (3.0 * n)).sqrt() * 3f64.sqrt(),
            "axis {axis}: {mean}"
        );
        let zz = directions.iter().map(|d| d.z * d.z).sum::<f64>() / n;
        assert!(
            (zz - 1.0 / 3.0).abs() < SIGMAS * (4.0 / 45.0 / n).sqrt(),
            "axis {axis}: {zz}"
        );
    }
    for k in 0..4 {
        let mean = states.iter().map(|s| s.orientation[k].powi(2)).sum::<f64>() / n;
        assert!(
            (mean - 0.25).abs() < SIGMAS * (1.0 / 16.0 / n).sqrt(),
            "q{k}: {mean}"
        );
    }
    for s in &states {
        assert!((s.orientation.norm() - 1.0).abs() < 1e-15);
    }
}

/// A zero temperature gives rotors at rest.
#[test]
fn zero_temperature_means_rest() {
    let states = random_states(&[Inertia::Spherical(0.3); 10], 0.0, 1);
    assert!(states.iter().all(|s| s.omega_body == Vector3::zeros()));
}

/// Explicit orientations are normalised whatever their size: a huge and a
/// tiny quaternion (their squared norms overflow and underflow) are the unit
/// quaternions along them, not refused as "not finite" (issue 37).
#[test]
fn huge_and_tiny_explicit_orientations_are_normalised() {
    let text = r#"
version = 1

[rotors]
kind = "sites"
sites = [{ position = [0.0, 0.0, 0.0] }, { position = [1.0, 0.0, 0.0] }, { position = [2.0, 0.0, 0.0] }]
default = { inertia = 1.0, dipole = [0.0, 0.0, 1.0] }

[initial]
kind = "explicit"
orientations = [[1.0, 0.0, 0.0, 0.0], [1e308, 1e308, 0.0, 0.0], [0.0, 0.0, 1e-300, 0.0]]
omega_body = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]

[integrator]
kind = "dlm"

[run]
dt = 0.01
steps = 10
"#;
    let (_, scene) = quatrot::scene::load_text(text, &Default::default()).expect("valid scene");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let expected = [[1.0, 0.0, 0.0, 0.0], [h, h, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
    for (state, unit) in scene.initial.iter().zip(expected) {
        for (a, b) in state.orientation.0.iter().zip(unit) {
            assert!(
                (a - b).abs() <= 2.0 * f64::EPSILON,
                "{:?}",
                state.orientation
            );
        }
    }
}
