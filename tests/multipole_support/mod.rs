//! Helpers shared by the multipole tests: seeded random rotors and orientations.
#![allow(dead_code)]

use nalgebra::{Matrix3, Vector3};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A vector uniform in the cube `[-scale, scale]^3`.
pub fn random_vector(rng: &mut ChaCha8Rng, scale: f64) -> Vector3<f64> {
    Vector3::from_fn(|_, _| scale * (2.0 * rng.random::<f64>() - 1.0))
}

/// A unit quaternion uniform on the 3-sphere (rejection from the 4-cube).
pub fn random_orientation(rng: &mut ChaCha8Rng) -> Quat {
    loop {
        let q = Quat(std::array::from_fn(|_| 2.0 * rng.random::<f64>() - 1.0));
        let n2 = q.norm_squared();
        if n2 > 1e-4 && n2 <= 1.0 {
            return q * (1.0 / n2.sqrt());
        }
    }
}

/// A general symmetric traceless matrix with entries of order `scale`.
pub fn random_quadrupole(rng: &mut ChaCha8Rng, scale: f64) -> Matrix3<f64> {
    let m = Matrix3::from_fn(|_, _| scale * (2.0 * rng.random::<f64>() - 1.0));
    let s = (m + m.transpose()) * 0.5;
    s - Matrix3::identity() * (s.trace() / 3.0)
}

/// A rotor at `site` with the requested random body multipoles.
pub fn random_rotor(
    rng: &mut ChaCha8Rng,
    site: Vector3<f64>,
    dipole: bool,
    quadrupole: bool,
) -> Rotor {
    Rotor {
        site,
        inertia: Inertia::Spherical(1.0),
        dipole_body: dipole.then(|| random_vector(rng, 1.0)),
        quadrupole_body: quadrupole.then(|| random_quadrupole(rng, 1.0)),
    }
}

/// `n` sites of an open cluster: a jittered cubic grid of spacing ~1.2, so
/// that no two sites come closer than ~0.6.
pub fn cluster_sites(rng: &mut ChaCha8Rng, n: usize) -> Vec<Vector3<f64>> {
    let edge = (n as f64).cbrt().ceil() as usize;
    (0..n)
        .map(|k| {
            let grid = Vector3::new(
                (k / (edge * edge)) as f64,
                ((k / edge) % edge) as f64,
                (k % edge) as f64,
            );
            grid * 1.2 + random_vector(rng, 0.25)
        })
        .collect()
}
