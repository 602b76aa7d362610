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
//! HOOMD-blue, 10 in DL_POLY). The step itself is [`Kicked`]'s.

use super::free_rotation::{free_flow, omega_from_momentum, BodyMomentum, SphericalTops};
use super::kick::{Kicked, Splitting};
use super::spec::IntegratorOptions;
use super::Integrator;
use crate::quaternion::Quat;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::num::NonZeroU32;

/// Body axes of the symmetric sweep, outermost first (axes 3, 2, 1).
const SWEEP_AXES: [usize; 3] = [2, 1, 0];

/// The NO_SQUISH integrator (scene name `no_squish`).
pub type NoSquish = Kicked<NoSquishOptions>;

/// Options of [`NoSquish`] (the scene's `[integrator]` table with
/// `kind = "no_squish"`).
///
/// [`MAX_SUBSTEPS`] bounds the sweeps per step: far beyond any use (the
/// splitting error falls as `1 / substeps^2`, and DL_POLY takes 10), it
/// keeps a step from taking hours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct NoSquishOptions {
    /// Free-rotation sweeps per step, each over `dt / substeps` (1 to
    /// [`MAX_SUBSTEPS`], default 1 as LAMMPS `fix rigid/nve` and
    /// HOOMD-blue; 10 as DL_POLY). No effect on spherical tops with
    /// [`SphericalTops::Exact`].
    #[serde(deserialize_with = "deserialize_substeps")]
    pub substeps: NonZeroU32,
    /// The free flow of spherical tops (default [`SphericalTops::Exact`]).
    pub spherical_tops: SphericalTops,
}

impl NoSquishOptions {
    /// One free-rotation sweep per step, as LAMMPS `fix rigid/nve` and HOOMD-blue.
    pub const SUBSTEPS_LAMMPS: NonZeroU32 = NonZeroU32::MIN;
    /// Ten free-rotation sweeps per step, as DL_POLY.
    pub const SUBSTEPS_DL_POLY: NonZeroU32 = match NonZeroU32::new(10) {
        Some(n) => n,
        None => NonZeroU32::MIN,
    };
}

/// The most free-rotation sweeps per step.
pub const MAX_SUBSTEPS: u32 = 10_000;

/// `substeps`: an integer from 1 to [`MAX_SUBSTEPS`].
fn deserialize_substeps<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<NonZeroU32, D::Error> {
    let n = crate::checks::deserialize_at_least_one(deserializer)?;
    if n.get() > MAX_SUBSTEPS {
        return Err(serde::de::Error::custom(format!(
            "must be <= {MAX_SUBSTEPS}, got {n}"
        )));
    }
    Ok(n)
}

impl Default for NoSquishOptions {
    fn default() -> Self {
        NoSquishOptions {
            substeps: NoSquishOptions::SUBSTEPS_LAMMPS,
            spherical_tops: SphericalTops::default(),
        }
    }
}

impl IntegratorOptions for NoSquishOptions {
    const NAME: &'static str = "no_squish";

    fn build(&self) -> Box<dyn Integrator> {
        Box::new(NoSquish::new(*self))
    }
}

impl Splitting for NoSquishOptions {
    /// The conjugate momentum `P = 2 Q*(0, L_b)`.
    type Momentum = Quat;

    fn momentum(q: &Quat, angular_momentum_body: &Vector3<f64>) -> Quat {
        *q * Quat::pure(angular_momentum_body) * 2.0
    }

    /// `P += half * 2 Q*(0, A(Q) n_s)` (body torque, eq 6), computed as
    /// `half * 2 |Q|^2 (0, n_s)*Q`: the same quaternion, since
    /// `(0, A(Q) n_s) = Q~*(0, n_s)*Q` (eq 9) and `Q*Q~ = |Q|^2` (eq 4), for one
    /// product instead of building `A(Q)`.
    fn kick(momentum: &mut Quat, q: &Quat, torque_space: &Vector3<f64>, half: f64) {
        *momentum += Quat::pure(torque_space) * *q * (2.0 * half * q.norm_squared());
    }

    fn rotate<const K: usize>(
        &self,
        q: &mut [Quat; K],
        momentum: &mut [Quat; K],
        moments: &[Vector3<f64>; K],
        dt: f64,
    ) {
        let substeps = self.substeps.get() as usize;
        free_flow(
            q,
            momentum,
            moments,
            self.spherical_tops,
            SWEEP_AXES,
            substeps,
            dt,
        );
    }

    fn omega_body(momentum: &Quat, q: &Quat, moments: &Vector3<f64>) -> Vector3<f64> {
        omega_from_momentum(&Self::angular_momentum_body(momentum, q), moments)
    }

    /// `L_b = 1/2 vec(Q~*P)`.
    fn angular_momentum_body(momentum: &Quat, q: &Quat) -> Vector3<f64> {
        momentum.angular_momentum_body(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The half kick is `P += half * 2 Q*(0, A(Q) n_s)` as its doc states,
    /// for a non-unit `Q` too (where `A(Q)` of eq 7 is `|Q|^2` times a
    /// rotation): the product form's factor `|Q|^2` is exact, not a rounding
    /// of 1.
    #[test]
    fn the_half_kick_is_the_body_torque_form_for_any_norm() {
        let q = Quat::new(0.9, -0.3, 0.5, 0.7); // |Q|^2 = 1.64
        let torque_space = Vector3::new(0.4, -1.1, 0.6);
        let (start, half) = (Quat::new(0.1, 0.2, -0.3, 0.4), 0.025);
        let mut momentum = start;
        <NoSquishOptions as Splitting>::kick(&mut momentum, &q, &torque_space, half);
        let torque_body = q.space_to_body_matrix() * torque_space;
        let expected = start + q * Quat::pure(&torque_body) * (2.0 * half);
        for k in 0..4 {
            assert!(
                (momentum[k] - expected[k]).abs() < 1e-15,
                "component {k}: {momentum:?} against {expected:?}"
            );
        }
    }

    /// `substeps` takes every count from 1 to [`MAX_SUBSTEPS`] and refuses
    /// the next one with a message naming the bound.
    #[test]
    fn substeps_are_accepted_up_to_the_bound_and_refused_beyond_it() {
        let read = |n: u32| toml::from_str::<NoSquishOptions>(&format!("substeps = {n}"));
        for n in [1, MAX_SUBSTEPS] {
            let options = read(n).expect("a count within the bounds");
            assert_eq!(options.substeps.get(), n);
        }
        let refused = read(MAX_SUBSTEPS + 1)
            .expect_err("one past the bound")
            .to_string();
        assert!(refused.contains("must be <= 10000, got 10001"), "{refused}");
    }
}
