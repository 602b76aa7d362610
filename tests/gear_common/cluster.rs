//! A tiny pinned cluster of point dipoles (test-only potential; the
//! multipole module is separate): `V = sum_{i<j} [mu_i.mu_j - 3 (mu_i.u)(mu_j.u)] / r^3`
//! with `u` the unit separation, `mu_i = R(Q_i) mu_b`.

use nalgebra::Vector3;
use quatrot::integrators::RotorState;
use quatrot::potential::Potential;
use quatrot::rotor::Inertia;
use quatrot::Quat;

/// Pinned dipoles at fixed sites, all with the same body dipole.
pub struct DipoleCluster {
    pub sites: Vec<Vector3<f64>>,
    pub dipole_body: Vector3<f64>,
}

impl DipoleCluster {
    /// `dV/dmu_i = sum_j [mu_j - 3 u (mu_j.u)] / r^3` (minus the field at `i`).
    fn energy_gradient_wrt_dipoles(&self, orientations: &[Quat]) -> Vec<Vector3<f64>> {
        let mu: Vec<_> = orientations.iter().map(|q| self.dipole_space(q)).collect();
        self.sites
            .iter()
            .enumerate()
            .map(|(i, site_i)| {
                self.sites
                    .iter()
                    .zip(&mu)
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, (site_j, mu_j))| {
                        let d = site_j - site_i;
                        let r = d.norm();
                        let u = d / r;
                        (mu_j - u * (3.0 * mu_j.dot(&u))) / (r * r * r)
                    })
                    .sum()
            })
            .collect()
    }

    /// `mu_s = R(Q) mu_b = A(Q)^T mu_b` (unnormalised `Q` scales it by `|Q|^2`).
    fn dipole_space(&self, q: &Quat) -> Vector3<f64> {
        q.space_to_body_matrix().transpose() * self.dipole_body
    }
}

impl Potential for DipoleCluster {
    fn energy(&self, orientations: &[Quat]) -> f64 {
        let mu: Vec<_> = orientations.iter().map(|q| self.dipole_space(q)).collect();
        let mut e = 0.0;
        for i in 0..mu.len() {
            for j in i + 1..mu.len() {
                let d = self.sites[j] - self.sites[i];
                let r = d.norm();
                let u = d / r;
                e += (mu[i].dot(&mu[j]) - 3.0 * mu[i].dot(&u) * mu[j].dot(&u)) / (r * r * r);
            }
        }
        e
    }
    fn accumulate_gradient(&self, orientations: &[Quat], gradient: &mut [Quat]) {
        let g = self.energy_gradient_wrt_dipoles(orientations);
        for ((q, g_i), out) in orientations.iter().zip(&g).zip(gradient) {
            let d = q.space_to_body_matrix_derivatives();
            *out += Quat(std::array::from_fn(|k| self.dipole_body.dot(&(d[k] * g_i))));
        }
    }
    fn accumulate_torques(&self, orientations: &[Quat], torques_space: &mut [Vector3<f64>]) {
        let g = self.energy_gradient_wrt_dipoles(orientations);
        for ((q, g_i), t) in orientations.iter().zip(&g).zip(torques_space) {
            *t -= self.dipole_space(q).cross(g_i);
        }
    }
}

/// A 2 x 2 x 2 cube (spacing 1.5) of unit dipoles: alternating spherical and
/// asymmetric tops (`mixed`) or all asymmetric, with spread initial states.
pub fn cube(mixed: bool) -> (DipoleCluster, Vec<Inertia>, Vec<RotorState>) {
    let mut sites = Vec::new();
    let mut inertia = Vec::new();
    let mut initial = Vec::new();
    for i in 0..8 {
        let (x, y, z) = ((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
        sites.push(Vector3::new(x, y, z) * 1.5);
        inertia.push(if mixed && i % 2 == 0 {
            Inertia::Spherical(1.2)
        } else {
            Inertia::Principal(Vector3::new(1.0, 1.6, 2.3))
        });
        let s = i as f64;
        initial.push(RotorState {
            orientation: Quat::new(
                1.0 + 0.1 * s,
                (0.7 * s).sin(),
                (1.3 * s).cos(),
                0.2 * s - 0.5,
            )
            .try_normalize()
            .expect("non-zero"),
            omega_body: Vector3::new((0.9 * s).cos(), (0.4 * s).sin(), 0.3 - 0.1 * s) * 0.8,
        });
    }
    let cluster = DipoleCluster {
        sites,
        dipole_body: Vector3::new(0.2, -0.1, 1.0),
    };
    (cluster, inertia, initial)
}
