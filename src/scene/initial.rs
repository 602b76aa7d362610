//! The `[initial]` section: orientations and body angular velocities at
//! t = 0, the same for every rotor, one per rotor, or random (uniform
//! orientations and Maxwell angular velocities at a reduced temperature,
//! reproducible from a seed).

use super::error::SceneError;
use super::tagged::tagged;
use crate::checks::{each, finite, num, orientation};
use crate::integrators::RotorState;
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

/// Initial orientations and body angular velocities.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawInitial {
    /// The same state for every rotor.
    Uniform(RawUniformInitial),
    /// One state per rotor.
    Explicit(RawExplicitInitial),
    /// Random states at a temperature.
    Random(RawRandomInitial),
}

tagged!(RawInitial {
    "uniform" => Uniform(RawUniformInitial),
    "explicit" => Explicit(RawExplicitInitial),
    "random" => Random(RawRandomInitial),
});

/// The same orientation and angular velocity for every rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawUniformInitial {
    /// The orientation (normalised).
    pub orientation: [f64; 4],
    /// The body angular velocity.
    pub omega_body: [f64; 3],
}

/// One orientation and one angular velocity per rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawExplicitInitial {
    /// The orientations (normalised).
    pub orientations: Vec<[f64; 4]>,
    /// The body angular velocities.
    pub omega_body: Vec<[f64; 3]>,
}

/// Uniform random orientations and Maxwell angular velocities.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRandomInitial {
    /// The seed (drawn from the OS if absent, below 2^63).
    #[serde(default, deserialize_with = "crate::checks::deserialize_seed")]
    pub seed: Option<u64>,
    /// The reduced temperature (>= 0).
    pub temperature: f64,
}

/// Smallest norm of a 4-d Gaussian sample accepted as a direction (the chance
/// of a rejection is ~1e-24 per draw; the bound only avoids dividing by ~0).
const MIN_SAMPLE_NORM: f64 = 1e-6;

/// One state per rotor, drawn from ChaCha20 seeded with `seed`: the
/// orientation is a normalised 4-d Gaussian vector (uniform on the unit
/// 3-sphere, so uniform over rotations), and each body component of the
/// angular velocity is `w_a ~ N(0, sqrt(T / I_a))` (Maxwell, reduced units
/// with k_B = 1). Rotors are drawn in order, orientation first.
pub fn random_states(inertia: &[Inertia], temperature: f64, seed: u64) -> Vec<RotorState> {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    inertia
        .iter()
        .map(|i| {
            let orientation = loop {
                let q = Quat(std::array::from_fn(|_| rng.sample(StandardNormal)));
                if q.norm() > MIN_SAMPLE_NORM {
                    break q * (1.0 / q.norm());
                }
            };
            let moments = i.principal();
            let omega_body = Vector3::from_fn(|a, _| {
                let g: f64 = rng.sample(StandardNormal);
                g * (temperature / moments[a]).sqrt()
            });
            RotorState {
                orientation,
                omega_body,
            }
        })
        .collect()
}

/// A seed drawn from the operating system when the scene gives none: below
/// 2^63, so that it can be written back into a scene (TOML integers are
/// signed 64-bit) to replay the run.
pub(super) fn drawn_seed() -> u64 {
    rand::random::<u64>() >> 1
}

/// One rotor's state from the file, with the paths of its two entries.
fn state(
    (q_path, q): (&str, &[f64; 4]),
    (w_path, w): (&str, &[f64; 3]),
) -> Result<RotorState, SceneError> {
    let orientation = orientation(&Quat(*q)).map_err(|e| e.at(q_path))?;
    each(w, finite).map_err(|e| e.at(w_path))?;
    Ok(RotorState {
        orientation,
        omega_body: Vector3::from(*w),
    })
}

/// Validates the section for `rotors`: the states, and the seed that drew
/// them if they are random.
pub(super) fn initial(
    raw: &RawInitial,
    rotors: &[Rotor],
) -> Result<(Vec<RotorState>, Option<u64>), SceneError> {
    let n = rotors.len();
    match raw {
        RawInitial::Uniform(u) => {
            let s = state(
                ("initial.orientation", &u.orientation),
                ("initial.omega_body", &u.omega_body),
            )?;
            Ok((vec![s; n], None))
        }
        RawInitial::Explicit(e) => {
            for (path, len) in [
                ("initial.orientations", e.orientations.len()),
                ("initial.omega_body", e.omega_body.len()),
            ] {
                if len != n {
                    return Err(SceneError::field(
                        path,
                        format!("must have one entry per rotor ({n}), got {len}"),
                    ));
                }
            }
            let states = e
                .orientations
                .iter()
                .zip(&e.omega_body)
                .enumerate()
                .map(|(i, (q, w))| {
                    state(
                        (&format!("initial.orientations[{i}]"), q),
                        (&format!("initial.omega_body[{i}]"), w),
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok((states, None))
        }
        RawInitial::Random(r) => {
            let temperature = finite(r.temperature).map_err(|e| e.at("initial.temperature"))?;
            if temperature < 0.0 {
                return Err(SceneError::field(
                    "initial.temperature",
                    format!("must be >= 0, got {}", num(temperature)),
                ));
            }
            let seed = r.seed.unwrap_or_else(drawn_seed);
            let inertia: Vec<Inertia> = rotors.iter().map(|r| r.inertia).collect();
            let states = random_states(&inertia, temperature, seed);
            let kinetic: f64 = states
                .iter()
                .zip(&inertia)
                .map(|(s, i)| crate::observables::kinetic_energy(i, &s.omega_body))
                .sum();
            if !kinetic.is_finite() {
                return Err(SceneError::field(
                    "initial.temperature",
                    format!(
                        "too high for these moments of inertia: the kinetic energy is not finite, got {}",
                        num(temperature)
                    ),
                ));
            }
            Ok((states, Some(seed)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotors(n: usize) -> Vec<Rotor> {
        let r = Rotor {
            site: Vector3::zeros(),
            inertia: Inertia::Spherical(2.0),
            dipole_body: None,
            quadrupole_body: None,
        };
        vec![r; n]
    }

    fn check(table: &str, n: usize) -> Result<(Vec<RotorState>, Option<u64>), String> {
        let raw: RawInitial = toml::from_str(table).expect("valid table");
        initial(&raw, &rotors(n)).map_err(|e| e.to_string())
    }

    /// Orientations are normalised; a zero quaternion and a wrong count are
    /// refused with the entry's path.
    #[test]
    fn orientations_are_normalised_and_checked_per_entry() {
        let (states, seed) = check(
            "kind = 'uniform'\norientation = [2.0, 0.0, 0.0, 0.0]\nomega_body = [0.0, 0.0, 1.0]",
            3,
        )
        .expect("valid");
        assert_eq!((states.len(), seed), (3, None));
        assert_eq!(states[2].orientation, Quat::IDENTITY);
        assert_eq!(
            check(
                "kind = 'explicit'\norientations = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]]\nomega_body = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]",
                2
            )
            .err()
            .as_deref(),
            Some("initial.orientations[1]: must be a non-zero quaternion, got [0, 0, 0, 0]")
        );
        assert_eq!(
            check(
                "kind = 'explicit'\norientations = [[1.0, 0.0, 0.0, 0.0]]\nomega_body = [[0.0, 0.0, 0.0]]",
                2
            )
            .err()
            .as_deref(),
            Some("initial.orientations: must have one entry per rotor (2), got 1")
        );
    }

    /// The same seed draws the same states, and the seed is reported.
    #[test]
    fn random_states_are_reproducible_from_the_seed() {
        let table = "kind = 'random'\nseed = 11\ntemperature = 0.5";
        let (a, seed) = check(table, 4).expect("valid");
        assert_eq!(seed, Some(11));
        assert_eq!(check(table, 4).expect("valid").0, a);
        assert_eq!(a, random_states(&[Inertia::Spherical(2.0); 4], 0.5, 11));
    }

    /// Regression: seeds drawn from the OS at or above 2^63 could not be
    /// written back into a scene. A drawn seed is below 2^63, and the scene
    /// with it written in (as the summary records it) draws the same states.
    #[test]
    fn drawn_seeds_can_be_written_back_into_a_scene() {
        for _ in 0..64 {
            assert!(drawn_seed() < 1 << 63);
        }
        let (states, seed) = check("kind = 'random'\ntemperature = 0.5", 3).expect("valid");
        let seed = seed.expect("drawn");
        let replay = format!("kind = 'random'\nseed = {seed}\ntemperature = 0.5");
        assert_eq!(check(&replay, 3).expect("replays").0, states);
    }
}
