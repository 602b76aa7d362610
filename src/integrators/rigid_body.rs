//! Rigid-body kinematics shared by the Gear schemes: Euler's equations in the
//! principal body frame, the second-order quaternion equation (eq 12), and
//! the choice (once per system, at compile time in the step) between the
//! spherical-top shortcut and the general top.

use crate::quaternion::Quat;
use nalgebra::Vector3;

/// Principal moments of one rotor and their inverses, precomputed at setup.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalMoments {
    /// `(I1, I2, I3)`.
    pub moments: Vector3<f64>,
    /// `(1/I1, 1/I2, 1/I3)`.
    pub inverse: Vector3<f64>,
    /// `1/I0` with `I0 = (I1 + I2 + I3)/3`: the moment applied to the norm
    /// component `n0` of an unprojected quaternion force (scheme B), so that
    /// the general-top form reduces exactly to eq 12 for a spherical top.
    pub inverse_mean: f64,
}

impl PrincipalMoments {
    /// From the principal moments `(I1, I2, I3)`, all finite and > 0 (as
    /// every integrator's setup checks them).
    pub fn new(moments: Vector3<f64>) -> Self {
        PrincipalMoments {
            moments,
            inverse: moments.map(|m| 1.0 / m),
            inverse_mean: 3.0 / moments.sum(),
        }
    }
}

/// How the body angular acceleration follows from the body torque. The
/// schemes pick the implementation once per system, so the step is
/// monomorphised and a spherical top does no inertia-tensor work.
pub trait TopKind {
    /// True for [`Spherical`] (lets scheme B use eq 12 directly).
    const SPHERICAL: bool;
    /// `w_b'` from the body torque `n_b` (not divided by the moments).
    fn omega_dot_body(
        moments: &PrincipalMoments,
        omega_body: &Vector3<f64>,
        torque_body: &Vector3<f64>,
    ) -> Vector3<f64>;
}

/// Every rotor is a spherical top: eq 11, `w_b' = n_b / I`.
pub struct Spherical;

/// General tops: Euler's equations `I w_b' = n_b - w_b x (I w_b)`.
pub struct General;

impl TopKind for Spherical {
    const SPHERICAL: bool = true;
    fn omega_dot_body(
        moments: &PrincipalMoments,
        _omega_body: &Vector3<f64>,
        torque_body: &Vector3<f64>,
    ) -> Vector3<f64> {
        torque_body * moments.inverse.x
    }
}

impl TopKind for General {
    const SPHERICAL: bool = false;
    fn omega_dot_body(
        moments: &PrincipalMoments,
        omega_body: &Vector3<f64>,
        torque_body: &Vector3<f64>,
    ) -> Vector3<f64> {
        let angular_momentum_body = moments.moments.component_mul(omega_body);
        (torque_body - omega_body.cross(&angular_momentum_body)).component_mul(&moments.inverse)
    }
}

/// `Q'*Q~*Q'`, the velocity term of eq 12 (the printed `Q'*Q'*Q'` is a
/// misprint: ERRATA.md).
fn velocity_term(q: &Quat, q_dot: &Quat) -> Quat {
    *q_dot * q.conjugate() * *q_dot
}

/// Eq 12 (corrected), derived from eq 10: `Q'' = Q'*Q~*Q' + 1/2 Q*A` with
/// the body-frame acceleration quaternion `A = (a0, w_b')` (`a0 = 0` on the
/// exact motion of a unit `Q`; scheme B puts `n0/I0` there).
pub fn q_ddot(q: &Quat, q_dot: &Quat, acceleration_body: &Quat) -> Quat {
    velocity_term(q, q_dot) + *q * *acceleration_body * 0.5
}

/// Eq 12 (corrected) for a spherical top of inverse moment `inverse_moment`
/// driven by the quaternion force `N = -dV/dQ` (eq 14):
/// `Q'' = Q'*Q~*Q' + 1/4 N/I`, without body-frame work (the printed eq 12
/// has `1/2 N`: ERRATA.md).
pub fn q_ddot_spherical(q: &Quat, q_dot: &Quat, force: &Quat, inverse_moment: f64) -> Quat {
    velocity_term(q, q_dot) + *force * (0.25 * inverse_moment)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For equal moments the general form reduces to the spherical one.
    #[test]
    fn general_reduces_to_spherical_for_equal_moments() {
        let m = PrincipalMoments::new(Vector3::repeat(2.0));
        let w = Vector3::new(0.3, -1.1, 0.7);
        let n = Vector3::new(-0.2, 0.5, 0.9);
        let d = General::omega_dot_body(&m, &w, &n) - Spherical::omega_dot_body(&m, &w, &n);
        assert!(d.norm() < 1e-15);
    }
}
