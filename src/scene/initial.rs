//! Random initial conditions: uniform orientations and Maxwell angular
//! velocities at a reduced temperature, reproducible from a seed.

use crate::integrators::RotorState;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use rand_distr::StandardNormal;

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
