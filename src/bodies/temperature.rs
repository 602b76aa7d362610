//! Translational and rotational temperatures of a body system (`k_B = 1`),
//! their degrees of freedom counted as issue 39 asks: `3N - 3`
//! translational (the total momentum is conserved), and per body its
//! positive moments less a spin no torque reaches
//! ([`super::BodyType::conserved_spin`]), whose kinetic energy is left out
//! of `K_rot` too (it stays what it was).

use super::system::BodySystem;

impl BodySystem {
    /// `3N - 3` (0 for fewer than two bodies).
    pub fn translational_degrees(&self) -> usize {
        (3 * self.bodies.len()).saturating_sub(3)
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
    /// freedom), `K_spins` the kinetic energy of the conserved spins.
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
