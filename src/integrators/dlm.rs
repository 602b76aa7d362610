//! The Dullweber-Leimkuhler-McLachlan splitting (J. Chem. Phys. 107, 5840
//! (1997)), as in LAMMPS `fix nve/sphere update dipole/dlm` and the
//! Allen-Tildesley example programs.
//!
//! One step of `dt`:
//! 1. half kick `L_b += dt/2 A(Q) n_s` (body torque, eq 6);
//! 2. free rotation ([`super::free_rotation`]): exact rotations about body
//!    axes 1, 2, 3, 2, 1 for `dt/2, dt/2, dt, dt/2, dt/2`, each updating `Q`
//!    and `L_b`; for a spherical top, by default, the exact flow
//!    `Q <- Q*exp(dt w_b)` instead ([`SphericalTops`]);
//! 3. torques at the new orientations, half kick again.
//!
//! Properties: second order; symplectic (a composition of exact flows of
//! Hamiltonian pieces); time reversible (the composition is symmetric); `|Q|`
//! stays 1 to round-off (only products with unit quaternions).
//! Stores per rotor: `Q` (4), the body angular momentum `L_b` (3) and the
//! space-fixed torque at `Q` (3, reused by the next step's first kick), plus
//! the principal moments (3). One potential evaluation per step.

use super::checkpoint::{read_kick_state, write_kick_state};
use super::free_rotation::{free_flow, omega_from_momentum, SphericalTops};
use super::setup::{validate_setup, Moments, ValidSetup};
use super::torque::evaluate_torques;
use super::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// Body axes of the symmetric sweep, outermost first (axes 1, 2, 3).
const SWEEP_AXES: [usize; 3] = [0, 1, 2];

/// The DLM integrator (scene name `dlm`).
#[derive(Clone, Debug, Default)]
pub struct Dlm {
    spherical: SphericalTops,
    dt: f64,
    inertia: Vec<Vector3<f64>>,
    orientation: Vec<Quat>,
    momentum_body: Vec<Vector3<f64>>,
    torque_space: Vec<Vector3<f64>>,
}

impl Dlm {
    /// A DLM integrator treating spherical tops as `spherical` says (default,
    /// via `Dlm::default()`: [`SphericalTops::Exact`]; `Split` is LAMMPS's
    /// choice).
    pub fn new(spherical: SphericalTops) -> Self {
        Dlm {
            spherical,
            ..Dlm::default()
        }
    }

    /// Adds `dt/2` times the body torque to the body angular momenta.
    fn half_kick(&mut self) {
        let half = 0.5 * self.dt;
        for ((l, q), n) in self
            .momentum_body
            .iter_mut()
            .zip(&self.orientation)
            .zip(&self.torque_space)
        {
            *l += q.space_to_body(n) * half;
        }
    }
}

impl Integrator for Dlm {
    fn name(&self) -> &'static str {
        "dlm"
    }

    fn setup<P: Potential>(
        &mut self,
        inertia: &[Inertia],
        potential: &P,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        let ValidSetup { moments, initial } =
            validate_setup(inertia, initial, dt, Moments::MayBeZero)?;
        self.dt = dt;
        self.inertia = moments;
        self.orientation = initial.iter().map(|s| s.orientation).collect();
        self.momentum_body = initial
            .iter()
            .zip(&self.inertia)
            .map(|(s, i)| s.omega_body.component_mul(i))
            .collect();
        self.torque_space = vec![Vector3::zeros(); initial.len()];
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
        Ok(())
    }

    fn step<P: Potential>(&mut self, potential: &P) {
        self.half_kick();
        for ((q, l), i) in self
            .orientation
            .iter_mut()
            .zip(&mut self.momentum_body)
            .zip(&self.inertia)
        {
            free_flow(q, l, i, self.spherical, SWEEP_AXES, 1, self.dt);
        }
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
        self.half_kick();
    }

    fn orientations(&self) -> &[Quat] {
        &self.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        for ((w, l), i) in out.iter_mut().zip(&self.momentum_body).zip(&self.inertia) {
            *w = omega_from_momentum(l, i);
        }
    }

    /// Layout: all `Q` (4 each), then all `L_b` (3 each), then all torques (3 each).
    fn checkpoint(&self) -> Vec<f64> {
        write_kick_state(&self.orientation, &self.momentum_body, &self.torque_space)
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        read_kick_state(
            state,
            &mut self.orientation,
            &mut self.momentum_body,
            &mut self.torque_space,
        )
    }
}
