//! The rotational degrees of freedom a global thermostat (Bussi, Nose-Hoover)
//! acts on. A rotor whose inertia is symmetric about a body axis `a` about
//! which the potential never exerts a torque (every multipole symmetric about
//! `a`: a point dipole on a spherical top, for one) keeps its spin
//! `L_b . a = I_a w_b . a` for ever (Euler's equations: `I_a w_a' = n_a = 0`).
//! Scaling every angular momentum by one factor would keep the ratios of
//! those spins too, so they cannot equilibrate; counted as thermostatted
//! degrees of freedom they make the thermostat heat the others (measured on
//! the 1000-dipole lattice at T = 1: the coupled components at 1.24, the
//! spins cooling to 0.5). So a spin about such an axis is left out: it is not
//! counted in `N_f`, its kinetic energy not in `K`, and it is not scaled
//! (its energy stays conserved by itself). Free rotors (no torque at all) and
//! rotors without such an axis count all their positive moments.
//!
//! Bodies that move add their centres: `3N - 3` translational degrees of
//! freedom for a thermostat that keeps the total momentum (Bussi and
//! Nose-Hoover scale the velocities relative to the centre of mass, whose
//! kinetic energy is left out of `K_trans` and stays what it was).

use super::SplitDynamics;
use crate::potential::{symmetric_about, Potential, TorqueAxes};
use nalgebra::{Matrix3, Vector3};

/// A conserved spin: the body unit axis and the moment about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spin {
    /// The body-fixed unit axis.
    pub axis: Vector3<f64>,
    /// The moment of inertia about it (> 0).
    pub moment: f64,
}

/// The thermostatted degrees of freedom of a system (module doc).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CoupledDegrees {
    /// Per rotor, the conserved spin left out, if any.
    pub spins: Vec<Option<Spin>>,
    /// `N_f`: positive moments, less one per conserved spin.
    pub dof: usize,
    /// The masses of the centres that move, in body order (none for rotors
    /// on fixed sites).
    pub masses: Vec<f64>,
}

impl CoupledDegrees {
    /// For rotors of principal moments `moments` in `potential` (on fixed
    /// sites: no centres).
    pub fn new(moments: &[Vector3<f64>], potential: &dyn Potential) -> Self {
        let spins: Vec<Option<Spin>> = moments
            .iter()
            .enumerate()
            .map(|(rotor, m)| match potential.torque_axes(rotor) {
                TorqueAxes::PerpendicularTo(axis) => {
                    let moment = axis.dot(&m.component_mul(&axis));
                    (moment > 0.0 && symmetric_about(&Matrix3::from_diagonal(m), &axis))
                        .then_some(Spin { axis, moment })
                }
                TorqueAxes::Any | TorqueAxes::Never => None,
            })
            .collect();
        Self::with_spins(moments, spins, Vec::new())
    }

    /// For rotors or bodies of principal moments `moments` whose conserved
    /// spins are `spins`, with centres of masses `masses`.
    pub fn with_spins(
        moments: &[Vector3<f64>],
        spins: Vec<Option<Spin>>,
        masses: Vec<f64>,
    ) -> Self {
        let positive: usize = moments
            .iter()
            .map(|m| m.iter().filter(|i| **i > 0.0).count())
            .sum();
        let dof = positive - spins.iter().flatten().count();
        CoupledDegrees { spins, dof, masses }
    }

    /// `3N - 3` for `N` moving centres (0 for fewer than two): the
    /// translational degrees of freedom of a thermostat that keeps the
    /// total momentum.
    pub fn translational_dof(&self) -> usize {
        (3 * self.masses.len()).saturating_sub(3)
    }

    /// The velocity of the centre of mass of the centres `each` visits
    /// (velocity and mass of every moving centre, in body order).
    fn centre_velocity(&self, each: &impl Fn(&mut dyn FnMut(&Vector3<f64>, f64))) -> Vector3<f64> {
        let mut momentum = Vector3::zeros();
        each(&mut |v, mass| momentum += v * mass);
        momentum / self.masses.iter().sum::<f64>()
    }

    /// The kinetic energy relative to the centre of mass of the centres
    /// `each` visits, `sum m |v - V|^2 / 2` in body order (0 without
    /// centres).
    fn relative_kinetic_energy(&self, each: impl Fn(&mut dyn FnMut(&Vector3<f64>, f64))) -> f64 {
        if self.masses.is_empty() {
            return 0.0;
        }
        let centre = self.centre_velocity(&each);
        let mut kinetic = 0.0;
        each(&mut |v, mass| kinetic += 0.5 * mass * (v - centre).norm_squared());
        kinetic
    }

    /// The velocity of the centre of mass of the moving centres.
    fn centre_of_mass_velocity(&self, dynamics: &impl SplitDynamics) -> Vector3<f64> {
        self.centre_velocity(&|f| dynamics.for_each_velocity(|_, v, mass| f(v, mass)))
    }

    /// The velocity of the centre of mass of centres moving at
    /// `velocities` (one per mass, in body order).
    pub fn centre_of_mass_velocity_of(&self, velocities: &[Vector3<f64>]) -> Vector3<f64> {
        self.centre_velocity(&|f| self.each_velocity_of(velocities, f))
    }

    /// The translational kinetic energy relative to the centre of mass,
    /// `sum m |v - V|^2 / 2`, summed in body order (0 without centres).
    pub fn translational_kinetic_energy(&self, dynamics: &impl SplitDynamics) -> f64 {
        self.relative_kinetic_energy(|f| dynamics.for_each_velocity(|_, v, mass| f(v, mass)))
    }

    /// [`CoupledDegrees::translational_kinetic_energy`] of centres moving
    /// at `velocities` (one per mass, in body order).
    pub fn translational_kinetic_energy_of(&self, velocities: &[Vector3<f64>]) -> f64 {
        self.relative_kinetic_energy(|f| self.each_velocity_of(velocities, f))
    }

    /// Calls `f(v, mass)` for `velocities` and the masses, in body order.
    fn each_velocity_of(&self, velocities: &[Vector3<f64>], f: &mut dyn FnMut(&Vector3<f64>, f64)) {
        for (v, mass) in velocities.iter().zip(&self.masses) {
            f(v, *mass);
        }
    }

    /// Scales the velocities relative to the centre of mass by `factor`:
    /// `v <- V + factor (v - V)` (the total momentum kept).
    pub fn scale_translation(&self, dynamics: &mut impl SplitDynamics, factor: f64) {
        if self.masses.is_empty() {
            return;
        }
        let centre = self.centre_of_mass_velocity(dynamics);
        dynamics.update_velocities(|_, v, _| *v = centre + (*v - centre) * factor);
    }

    /// The part of `w` a thermostat acts on (`w` less its spin component).
    pub fn coupled(&self, rotor: usize, w: &Vector3<f64>) -> Vector3<f64> {
        match &self.spins[rotor] {
            Some(s) => w - s.axis * s.axis.dot(w),
            None => *w,
        }
    }

    /// The thermostatted kinetic energy of rotors with body angular
    /// velocities `omega` and principal moments `moments`, in rotor order.
    pub fn kinetic_energy_of(&self, moments: &[Vector3<f64>], omega: &[Vector3<f64>]) -> f64 {
        moments
            .iter()
            .zip(omega)
            .enumerate()
            .map(|(rotor, (m, w))| {
                let spin = self.spins[rotor].map_or(0.0, |s| s.moment * s.axis.dot(w).powi(2));
                0.5 * (w.dot(&m.component_mul(w)) - spin)
            })
            .sum()
    }

    /// The thermostatted kinetic energy of a kick-based step's rotors.
    pub fn kinetic_energy(&self, dynamics: &impl SplitDynamics) -> f64 {
        let total = dynamics.kinetic_energy();
        if self.spins.iter().all(Option::is_none) {
            return total;
        }
        let mut spins = 0.0;
        dynamics.for_each_omega_body(|rotor, w, _| {
            if let Some(s) = &self.spins[rotor] {
                spins += 0.5 * s.moment * s.axis.dot(w).powi(2);
            }
        });
        total - spins
    }

    /// Scales the thermostatted angular momenta by `factor`, the spins left
    /// as they are.
    pub fn scale(&self, dynamics: &mut impl SplitDynamics, factor: f64) {
        if self.spins.iter().all(Option::is_none) {
            dynamics.scale_momenta(factor);
            return;
        }
        dynamics.update_omega_body(|rotor, w, _| {
            let coupled = self.coupled(rotor, w);
            *w += coupled * (factor - 1.0);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::{Boundary, ExternalFields, Free, MultipolePotential};
    use crate::rotor::{Inertia, Rotor};

    /// Dipoles on spherical tops and on tops symmetric about the dipole keep
    /// their spin; on an asymmetric top, or symmetric about another axis, or
    /// free, nothing is left out.
    #[test]
    fn spins_of_axial_rotors_are_left_out() {
        let rotor = |x: f64, inertia: Vector3<f64>, dipole: Vector3<f64>| Rotor {
            site: Vector3::new(x, 0.0, 0.0),
            inertia: Inertia::from_moments(inertia),
            dipole_body: Some(dipole),
            quadrupole_body: None,
        };
        let rotors = [
            rotor(0.0, Vector3::repeat(0.1), Vector3::new(0.0, 0.6, 0.8)),
            rotor(2.0, Vector3::new(0.1, 0.1, 0.3), Vector3::z()),
            rotor(4.0, Vector3::new(0.1, 0.2, 0.3), Vector3::z()),
            rotor(6.0, Vector3::new(0.1, 0.1, 0.3), Vector3::x()),
        ];
        let moments: Vec<_> = rotors.iter().map(|r| r.inertia.principal()).collect();
        let potential =
            MultipolePotential::new(&rotors, Boundary::Open, ExternalFields::NONE).expect("valid");
        let coupled = CoupledDegrees::new(&moments, &potential);
        assert_eq!(coupled.dof, 12 - 2);
        let spin = |k: usize| coupled.spins[k].map(|s| (s.axis, s.moment));
        assert_eq!(spin(0), Some((Vector3::new(0.0, 0.6, 0.8), 0.1)));
        assert_eq!(spin(1), Some((Vector3::z(), 0.3)));
        assert_eq!((spin(2), spin(3)), (None, None));
        let w = Vector3::new(1.0, 2.0, 3.0);
        assert!(
            coupled
                .coupled(0, &w)
                .dot(&Vector3::new(0.0, 0.6, 0.8))
                .abs()
                < 1e-15
        );
        let free = CoupledDegrees::new(&moments, &Free);
        assert_eq!(free.dof, 12);
    }
}
