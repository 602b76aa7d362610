//! Translational and rotational temperatures of a body system (`k_B = 1`),
//! their degrees of freedom counted as issue 39 asks: `3N - 3`
//! translational when the total momentum is conserved (`3N` under a
//! Langevin thermostat, [`BodySystem::keeps_momentum`]), and per body its
//! positive moments less a spin no torque reaches
//! ([`super::BodyType::conserved_spin`]), whose kinetic energy is left out
//! of `K_rot` too (it stays what it was). The same counts are the
//! thermostats' ([`BodySystem::coupled_degrees`]).

use super::system::BodySystem;
use crate::thermostat_hook::CoupledDegrees;
use nalgebra::Vector3;

impl BodySystem {
    /// `3N - 3` (0 for fewer than two bodies), or `3N` when the dynamics
    /// does not keep the total momentum.
    pub fn translational_degrees(&self) -> usize {
        let n = 3 * self.bodies.len();
        if self.keeps_momentum {
            n.saturating_sub(3)
        } else {
            n
        }
    }

    /// The degrees of freedom a thermostat acts on: per body its principal
    /// moments and conserved spin, and its centre's mass.
    pub fn coupled_degrees(&self) -> CoupledDegrees {
        let types = || self.bodies.iter().map(|b| &self.types[b.kind]);
        let spins: Vec<_> = self.types.iter().map(|t| t.conserved_spin()).collect();
        let moments: Vec<Vector3<f64>> = types().map(|t| t.moments).collect();
        let masses = types().map(|t| t.mass).collect();
        let spins = self.bodies.iter().map(|b| spins[b.kind]).collect();
        CoupledDegrees::with_spins(&moments, spins, masses)
    }

    /// The rotational degrees of freedom torques reach: positive moments
    /// less one per conserved spin.
    pub fn rotational_degrees(&self) -> usize {
        let per_type: Vec<usize> = self
            .types
            .iter()
            .map(|t| t.rotational_degrees() - usize::from(t.conserved_spin().is_some()))
            .collect();
        self.bodies.iter().map(|b| per_type[b.kind]).sum()
    }

    /// `T_trans = 2 K_trans / (3N - 3)` (`None` without degrees of freedom).
    pub fn translational_temperature(&self) -> Option<f64> {
        let degrees = self.translational_degrees();
        (degrees > 0).then(|| 2.0 * self.translational_kinetic_energy() / degrees as f64)
    }

    /// `T_rot = 2 (K_rot - K_spins) / N_rot` (`None` without degrees of
    /// freedom), `K_spins` the kinetic energy of the conserved spins. Read
    /// at the end of a kick-based step, under Langevin it is low by
    /// `(dt^2/4) <n_k^2> / I_k` per axis (`crate::thermostats::Langevin`:
    /// 1.2 % for SPC/E water at 2 fs; benchmarks/RESULTS.md, issue 41, for
    /// the other thermostats).
    pub fn rotational_temperature(&self) -> Option<f64> {
        let degrees = self.rotational_degrees();
        let spins: Vec<_> = self.types.iter().map(|t| t.conserved_spin()).collect();
        let spin_energy: f64 = self
            .bodies
            .iter()
            .filter_map(|b| {
                let spin = spins[b.kind]?;
                Some(0.5 * b.angular_momentum_body.dot(&spin.axis).powi(2) / spin.moment)
            })
            .sum();
        (degrees > 0)
            .then(|| 2.0 * (self.rotational_kinetic_energy() - spin_energy) / degrees as f64)
    }
}

#[cfg(test)]
mod tests {
    use crate::bodies::{
        Body, BodySystem, BodyType, BodyTypeSpec, ElectrostaticTruncation, ElectrostaticsOptions,
        InteractionOptions, LennardJones, LennardJonesOptions, Mixing, Site, Space, Truncation,
    };
    use crate::quaternion::Quat;
    use nalgebra::{Matrix3, Vector3};

    /// A Lennard-Jones site at `position` of mass `mass`, with `dipole`.
    fn site(position: [f64; 3], mass: f64, dipole: Option<[f64; 3]>) -> Site {
        Site {
            position: Vector3::from(position),
            mass,
            lennard_jones: Some(LennardJones {
                epsilon: 1.0,
                sigma: 1.0,
            }),
            dipole: dipole.map(Vector3::from),
            ..Site::default()
        }
    }

    /// A dipolar sphere (inertia 0.1, dipole along body z), a linear
    /// two-site rod along x (masses 1 at +-0.5: moments 0, 0.5, 0.5) and a
    /// bent three-site body (three positive moments).
    fn types() -> Vec<BodyType> {
        let specs = [
            BodyTypeSpec {
                sites: vec![site([0.0; 3], 0.0, Some([0.0, 0.0, 1.0]))],
                mass: Some(1.0),
                inertia: Some(Matrix3::identity() * 0.1),
            },
            BodyTypeSpec {
                sites: vec![
                    site([-0.5, 0.0, 0.0], 1.0, None),
                    site([0.5, 0.0, 0.0], 1.0, None),
                ],
                mass: None,
                inertia: None,
            },
            BodyTypeSpec {
                sites: vec![
                    site([0.0, 0.0, 0.0], 2.0, None),
                    site([0.5, 0.3, 0.0], 1.0, None),
                    site([-0.4, 0.35, 0.1], 1.0, None),
                ],
                mass: None,
                inertia: None,
            },
        ];
        specs.iter().map(|s| BodyType::new(s).unwrap()).collect()
    }

    /// Bodies of the kinds `kinds`, 3 apart on the x axis, at velocity
    /// `(1, 2, 3)` and body angular momentum `(0, 2, 3)` (none about a
    /// linear body's axis, body x).
    fn system(kinds: &[usize]) -> BodySystem {
        let bodies = kinds
            .iter()
            .enumerate()
            .map(|(i, &kind)| Body {
                kind,
                position: Vector3::new(3.0 * i as f64, 0.0, 0.0),
                image: [0; 3],
                velocity: Vector3::new(1.0, 2.0, 3.0),
                orientation: Quat::new(1.0, 0.0, 0.0, 0.0),
                angular_momentum_body: Vector3::new(0.0, 2.0, 3.0),
            })
            .collect();
        let options = InteractionOptions {
            lennard_jones: Some(LennardJonesOptions {
                cutoff: 2.5,
                truncation: Truncation::Plain,
                mixing: Mixing::LorentzBerthelot,
            }),
            electrostatics: Some(ElectrostaticsOptions::Cutoff(
                2.5,
                ElectrostaticTruncation::Plain,
            )),
            skin: 0.3,
        };
        BodySystem::new(types(), bodies, Space::Open, &options).unwrap()
    }

    /// Rotational degrees: 2 for a dipolar sphere (no torque reaches its
    /// spin about the dipole, as ERRATA found for rotors), 2 for a linear
    /// body, 3 for a general one; translational `3N - 3` (the total
    /// momentum conserved), `3N` when it is not, none for one body; the
    /// thermostats count the same.
    #[test]
    fn degrees_of_freedom_by_kind_of_body() {
        for (kinds, rotational) in [
            (vec![0, 0], 4),
            (vec![1, 1, 1], 6),
            (vec![2, 2], 6),
            (vec![0, 1, 2], 7),
        ] {
            let mut s = system(&kinds);
            assert_eq!(s.rotational_degrees(), rotational, "{kinds:?}");
            assert_eq!(s.translational_degrees(), 3 * kinds.len() - 3, "{kinds:?}");
            let coupled = s.coupled_degrees();
            assert_eq!(coupled.dof, rotational, "{kinds:?}");
            assert_eq!(coupled.translational_dof(), 3 * kinds.len() - 3);
            // A thermostat that does not keep the momentum (Langevin): 3N.
            s.keeps_momentum = false;
            assert_eq!(s.translational_degrees(), 3 * kinds.len(), "{kinds:?}");
        }
        let one = system(&[2]);
        assert_eq!(one.translational_degrees(), 0);
        assert_eq!(one.translational_temperature(), None);
    }

    /// The temperatures from hand-computed kinetic energies: two bodies at
    /// velocity (1, 2, 3), masses 1 (spheres): `K_trans = 14`, 3 degrees,
    /// `T_trans = 28/3`; rotation of the spheres about x and y only counts,
    /// `L_b = (0, 2, 3)` at `I = 0.1`: `(0 + 4) / 0.2 = 20` each, 4 degrees,
    /// `T_rot = 2 * 40 / 4 = 20` (the spin's `9 / 0.2` left out).
    #[test]
    fn temperatures_leave_out_the_conserved_spins() {
        let s = system(&[0, 0]);
        let t_trans = s.translational_temperature().unwrap();
        assert!((t_trans - 28.0 / 3.0).abs() < 1e-14, "{t_trans}");
        let t_rot = s.rotational_temperature().unwrap();
        assert!((t_rot - 20.0).abs() < 1e-13, "{t_rot}");
        // A rod (moments 0, 0.5, 0.5): (4 + 9) / 1 = 13 over 2 degrees.
        let rod = system(&[1, 1]);
        let t_rot = rod.rotational_temperature().unwrap();
        assert!((t_rot - 13.0).abs() < 1e-13, "{t_rot}");
    }
}
