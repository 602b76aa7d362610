//! NO_SQUISH (Miller, Eleftheriou, Pattnaik, Ndirango, Newns and Martyna,
//! J. Chem. Phys. 116, 8649 (2002)): symplectic splitting in the quaternion
//! and its conjugate momentum.
//!
//! The conjugate momentum is `P = 2 S(Q) (0, I w_b) = 2 Q*(0, L_b)` (Hamilton
//! product, `Q` body to space; `L_b = 1/2 vec(Q~*P)`). One step of `dt`:
//! 1. half kick `P += dt/2 * 2 Q*(0, A(Q) n_s)` (body torque, eq 6);
//! 2. free rotation ([`super::free_rotation`]): `substeps` symmetric sweeps
//!    about body axes 3, 2, 1, 2, 3, each flow `Q <- Q*E`, `P <- P*E` (Miller's
//!    `exp(zeta P_k)` acting on both); axes with zero moment are skipped; for a
//!    spherical top, by default, the exact flow `Q <- Q*exp(dt w_b)` instead
//!    ([`SphericalTops`]);
//! 3. torques at the new orientations, half kick again.
//!
//! Properties: second order; symplectic; time reversible; `|Q|` stays 1 and
//! `Q.P` stays 0 to round-off. Stores per rotor: `Q` (4), `P` (4) and the
//! space-fixed torque at `Q` (3, reused by the next step's first kick), plus
//! the principal moments (3). One potential evaluation per step; `substeps`
//! only refines the free rotation (1 in LAMMPS `fix rigid/nve` and
//! HOOMD-blue, 10 in DL_POLY).

use super::free_rotation::{free_flow, omega_from_momentum, BodyMomentum, SphericalTops};
use super::kick::KickState;
use super::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;
use std::num::NonZeroUsize;

/// Body axes of the symmetric sweep, outermost first (axes 3, 2, 1).
const SWEEP_AXES: [usize; 3] = [2, 1, 0];

/// The NO_SQUISH integrator (scene name `no_squish`).
#[derive(Clone, Debug)]
pub struct NoSquish {
    substeps: NonZeroUsize,
    spherical: SphericalTops,
    state: KickState<Quat>,
}

impl NoSquish {
    /// One free-rotation sweep per step, as LAMMPS `fix rigid/nve` and HOOMD-blue.
    pub const SUBSTEPS_LAMMPS: NonZeroUsize = NonZeroUsize::MIN;
    /// Ten free-rotation sweeps per step, as DL_POLY.
    pub const SUBSTEPS_DL_POLY: NonZeroUsize = match NonZeroUsize::new(10) {
        Some(n) => n,
        None => NonZeroUsize::MIN,
    };

    /// A NO_SQUISH integrator with `substeps` (>= 1, no default; see the
    /// constants) free-rotation sweeps per step, each over `dt / substeps`;
    /// `spherical` (default [`SphericalTops::Exact`]) chooses the free flow of
    /// spherical tops, for which `substeps` then has no effect.
    pub fn new(substeps: NonZeroUsize, spherical: SphericalTops) -> Self {
        NoSquish {
            substeps,
            spherical,
            state: KickState::default(),
        }
    }
}

/// NO_SQUISH's half kick: `P += half * 2 Q*(0, A(Q) n_s)` (body torque, eq 6),
/// computed as `half * 2 |Q|^2 (0, n_s)*Q`: the same quaternion, since
/// `(0, A(Q) n_s) = Q~*(0, n_s)*Q` (eq 9) and `Q*Q~ = |Q|^2` (eq 4), for one
/// product instead of building `A(Q)`.
fn kick(momentum: &mut Quat, q: &Quat, torque_space: &Vector3<f64>, half: f64) {
    *momentum += Quat::pure(torque_space) * *q * (2.0 * half * q.norm_squared());
}

impl Integrator for NoSquish {
    fn name(&self) -> &'static str {
        "no_squish"
    }

    fn setup<P: Potential>(
        &mut self,
        inertia: &[Inertia],
        potential: &P,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        self.state = KickState::new(inertia, potential, initial, dt, |q, l_body| {
            *q * Quat::pure(l_body) * 2.0
        })?;
        Ok(())
    }

    fn step<P: Potential>(&mut self, potential: &P) {
        let (substeps, spherical, dt) = (self.substeps.get(), self.spherical, self.state.dt);
        self.state.half_kick(kick);
        self.state.update(|q, p, i| {
            free_flow(q, p, i, spherical, SWEEP_AXES, substeps, dt);
        });
        self.state.evaluate_torques(potential);
        self.state.half_kick(kick);
    }

    fn orientations(&self) -> &[Quat] {
        &self.state.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        self.state.omega_body(out, |p, q, i| {
            omega_from_momentum(&p.angular_momentum_body(q), i)
        });
    }

    /// Layout of [`KickState::checkpoint`]: `Q`, then `P`, then torques.
    fn checkpoint(&self) -> Vec<f64> {
        self.state.checkpoint()
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        self.state.restore(state)
    }
}
