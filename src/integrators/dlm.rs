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

use super::free_rotation::{free_flow, omega_from_momentum, SphericalTops};
use super::kick::KickState;
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
    state: KickState<Vector3<f64>>,
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
}

/// DLM's half kick: `L_b += half A(Q) n_s` (body torque, eq 6).
fn kick(momentum_body: &mut Vector3<f64>, q: &Quat, torque_space: &Vector3<f64>, half: f64) {
    *momentum_body += q.space_to_body(torque_space) * half;
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
        self.state = KickState::new(inertia, potential, initial, dt, |_, l_body| *l_body)?;
        Ok(())
    }

    fn step<P: Potential>(&mut self, potential: &P) {
        self.state.half_kick(kick);
        let (spherical, dt) = (self.spherical, self.state.dt);
        self.state
            .update(|q, l, i| free_flow(q, l, i, spherical, SWEEP_AXES, 1, dt));
        self.state.evaluate_torques(potential);
        self.state.half_kick(kick);
    }

    fn orientations(&self) -> &[Quat] {
        &self.state.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        self.state
            .omega_body(out, |l, _, i| omega_from_momentum(l, i));
    }

    /// Layout of [`KickState::checkpoint`]: `Q`, then `L_b`, then torques.
    fn checkpoint(&self) -> Vec<f64> {
        self.state.checkpoint()
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        self.state.restore(state)
    }
}
