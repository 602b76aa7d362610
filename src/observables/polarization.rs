//! The total dipole moment of a configuration, `M = sum_i R(Q_i) mu_i` with
//! `mu_i` the body-frame dipole of rotor `i` and `R(Q_i)` body to space
//! (eq 6 inverted; `Q_i` normalised first, so a drifting `|Q|` of the Gear
//! schemes does not scale `M`). Its fluctuation gives the dielectric
//! constant ([`crate::analysis::dielectric`]).

use crate::quaternion::Quat;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Rotors per rayon task of the rotations (about 20 ns each, so a task is a
/// few microseconds).
const ROTORS_PER_TASK: usize = 256;

/// `M = sum_i R(Q_i) mu_i`, space frame; `orientations` and `dipoles_body`
/// pair up rotor by rotor (rotors without a dipole have `mu = 0`). The
/// rotations run in parallel and the sum in rotor order, so `M` does not
/// depend on the thread count (and a sampling step leaves no serial stretch
/// long enough for an idle worker to fall asleep, `crate::parallel`).
pub fn total_dipole(orientations: &[Quat], dipoles_body: &[Vector3<f64>]) -> Vector3<f64> {
    debug_assert_eq!(orientations.len(), dipoles_body.len());
    let space: Vec<Vector3<f64>> = orientations
        .par_iter()
        .with_min_len(ROTORS_PER_TASK)
        .zip(dipoles_body)
        .map(|(q, mu)| q.try_normalize().unwrap_or(*q).body_to_space(mu))
        .collect();
    space.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two dipoles turned into opposite directions cancel; the norm of `Q`
    /// does not scale M; a rotation of every rotor rotates M.
    #[test]
    fn total_dipole_rotates_with_the_rotors() {
        let mu = [Vector3::new(0.0, 0.0, 1.5), Vector3::new(0.0, 0.0, 1.5)];
        let flip = Quat::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        assert!(total_dipole(&[Quat::IDENTITY, flip], &mu).norm() < 1e-15);
        let q = [
            Quat::new(0.3, -0.5, 0.6, 0.2),
            Quat::new(0.9, 0.1, 0.0, -0.4),
        ];
        let mu = [Vector3::new(0.2, -1.0, 0.4), Vector3::new(1.0, 0.5, 0.0)];
        let m = total_dipole(&q, &mu);
        let scaled = [q[0] * 2.0, q[1] * 0.5];
        assert!((total_dipole(&scaled, &mu) - m).norm() < 1e-14);
        let turn = Quat::from_axis_angle(&Vector3::y_axis(), 0.7);
        let turned = [turn * q[0], turn * q[1]];
        let expected = turn.body_to_space(&m);
        assert!((total_dipole(&turned, &mu) - expected).norm() < 1e-14);
    }

    /// `M` of 1,000 rotors is the sum in rotor order, bit for bit, on 1, 2
    /// and 3 threads (the rotations split among them, the sum not).
    #[test]
    fn total_dipole_is_the_rotor_order_sum_on_any_thread_count() {
        let n = 1000;
        let q: Vec<Quat> = (0..n)
            .map(|i| {
                let t = i as f64;
                Quat::new(
                    t.cos(),
                    0.3 * t.sin(),
                    (0.7 * t).cos(),
                    0.1 + (1.3 * t).sin(),
                )
            })
            .collect();
        let mu: Vec<Vector3<f64>> = (0..n)
            .map(|i| Vector3::new(1.0, (i as f64).sin(), 0.5 - (0.2 * i as f64).cos()))
            .collect();
        let mut in_order = Vector3::zeros();
        for (q, mu) in q.iter().zip(&mu) {
            in_order += q.try_normalize().unwrap_or(*q).body_to_space(mu);
        }
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a rayon pool");
            let m = pool.install(|| total_dipole(&q, &mu));
            assert_eq!(
                m.map(f64::to_bits),
                in_order.map(f64::to_bits),
                "{threads} threads"
            );
        }
    }
}
