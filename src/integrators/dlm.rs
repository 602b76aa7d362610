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
//! the principal moments (3). One potential evaluation per step. The step
//! itself is [`Kicked`]'s.

use super::free_rotation::{free_flow, omega_from_momentum, SphericalTops};
use super::kick::{Kicked, Splitting};
use super::spec::IntegratorOptions;
use super::Integrator;
use crate::quaternion::Quat;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Body axes of the symmetric sweep, outermost first (axes 1, 2, 3).
const SWEEP_AXES: [usize; 3] = [0, 1, 2];

/// The DLM integrator (scene name `dlm`).
pub type Dlm = Kicked<DlmOptions>;

/// Options of [`Dlm`] (the scene's `[integrator]` table with `kind = "dlm"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct DlmOptions {
    /// The free flow of spherical tops (default [`SphericalTops::Exact`];
    /// `Split` is LAMMPS's choice).
    pub spherical_tops: SphericalTops,
}

impl IntegratorOptions for DlmOptions {
    const NAME: &'static str = "dlm";

    fn build(&self) -> Box<dyn Integrator> {
        Box::new(Dlm::new(*self))
    }
}

impl Splitting for DlmOptions {
    /// The body angular momentum `L_b`.
    type Momentum = Vector3<f64>;

    fn momentum(_: &Quat, angular_momentum_body: &Vector3<f64>) -> Vector3<f64> {
        *angular_momentum_body
    }

    /// `L_b += half A(Q) n_s` (body torque, eq 6).
    fn kick(momentum_body: &mut Vector3<f64>, q: &Quat, torque_space: &Vector3<f64>, half: f64) {
        *momentum_body += q.space_to_body(torque_space) * half;
    }

    fn rotate<const K: usize>(
        &self,
        q: &mut [Quat; K],
        momentum_body: &mut [Vector3<f64>; K],
        moments: &[Vector3<f64>; K],
        dt: f64,
    ) {
        free_flow(
            q,
            momentum_body,
            moments,
            self.spherical_tops,
            SWEEP_AXES,
            1,
            dt,
        );
    }

    fn omega_body(momentum_body: &Vector3<f64>, _: &Quat, moments: &Vector3<f64>) -> Vector3<f64> {
        omega_from_momentum(momentum_body, moments)
    }

    fn angular_momentum_body(momentum_body: &Vector3<f64>, _: &Quat) -> Vector3<f64> {
        *momentum_body
    }
}
