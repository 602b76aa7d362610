//! Property tests (proptest) of the quaternion algebra over random inputs,
//! and of the identities documented as exact for non-unit quaternions.

use nalgebra::{Matrix3, Rotation3, Vector3};
use proptest::prelude::*;
use quatrot::Quat;
use std::f64::consts::PI;

/// Round-off of a few products and sums of O(1) numbers.
const TIGHT: f64 = 1e-13;
/// Euler angles recovered with sin(theta) > 1e-3: round-off amplified by up to
/// 1/sin(theta/2) ~ 2e3.
const ANGLES: f64 = 1e-10;

/// Any quaternion with components in [-2, 2].
fn quat() -> impl Strategy<Value = Quat> {
    prop::array::uniform4(-2.0f64..2.0).prop_map(Quat)
}

/// A unit quaternion (normalised away from the origin, so nearly isotropic).
fn unit_quat() -> impl Strategy<Value = Quat> {
    prop::array::uniform4(-1.0f64..1.0)
        .prop_filter("away from zero", |c| {
            c.iter().map(|x| x * x).sum::<f64>() > 1e-2
        })
        .prop_map(|c| Quat(c) * (1.0 / Quat(c).norm()))
}

/// A quaternion of norm between 0.3 and 2 (far from unit on both sides), as
/// a Gear predictor or a run without renormalisation can make.
fn non_unit_quat() -> impl Strategy<Value = Quat> {
    (unit_quat(), 0.3f64..2.0).prop_map(|(q, s)| q * s)
}

fn vector(max: f64) -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-max..max).prop_map(Vector3::from)
}

fn max_diff(a: &Quat, b: &Quat) -> f64 {
    (*a - *b).0.iter().fold(0.0, |m, x| f64::max(m, x.abs()))
}

fn rotation_diff(a: &Quat, b: &Quat) -> f64 {
    max_diff(a, b).min(max_diff(a, &-*b))
}

fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d)
}

proptest! {
    /// (P*Q)*S = P*(Q*S).
    #[test]
    fn product_is_associative(p in quat(), q in quat(), s in quat()) {
        prop_assert!(max_diff(&((p * q) * s), &(p * (q * s))) < 100.0 * TIGHT);
    }

    /// |P*Q| = |P||Q|.
    #[test]
    fn norm_is_multiplicative(p in quat(), q in quat()) {
        prop_assert!(((p * q).norm() - p.norm() * q.norm()).abs() < 10.0 * TIGHT);
    }

    /// Q*Q~ = Q~*Q = (|Q|^2, 0), so Q~ is the inverse of a unit Q; (P*Q)~ = Q~*P~.
    #[test]
    fn conjugate_is_the_inverse(p in quat(), q in unit_quat()) {
        prop_assert!(max_diff(&(q * q.conjugate()), &Quat::IDENTITY) < TIGHT);
        prop_assert!(max_diff(&(q.conjugate() * q), &Quat::IDENTITY) < TIGHT);
        let n2 = p.norm_squared();
        prop_assert!(max_diff(&(p * p.conjugate()), &Quat::new(n2, 0.0, 0.0, 0.0)) < 10.0 * TIGHT);
        prop_assert!(max_diff(&(p * q).conjugate(), &(q.conjugate() * p.conjugate())) < TIGHT);
    }

    /// Q and -Q give the same A (the double cover), and the same rotated vector.
    #[test]
    fn double_cover(q in unit_quat(), v in vector(3.0)) {
        prop_assert_eq!(q.space_to_body_matrix(), (-q).space_to_body_matrix());
        prop_assert!(((-q).body_to_space(&v) - q.body_to_space(&v)).amax() < TIGHT);
    }

    /// A(Q) is orthogonal with determinant +1, and A(P*Q) = A(Q) A(P).
    #[test]
    fn matrix_is_a_proper_rotation(p in unit_quat(), q in unit_quat()) {
        let a = q.space_to_body_matrix();
        prop_assert!((a * a.transpose() - Matrix3::identity()).amax() < TIGHT);
        prop_assert!((a.determinant() - 1.0).abs() < TIGHT);
        let composed = (p * q).space_to_body_matrix() - q.space_to_body_matrix() * p.space_to_body_matrix();
        prop_assert!(composed.amax() < TIGHT);
    }

    /// Euler -> Q -> A -> Q -> Euler: the rotation comes back, and the angles
    /// too when theta is away from 0 and pi.
    #[test]
    fn euler_to_q_to_matrix_round_trip(phi in -PI..PI, theta in 0.0..PI, psi in -PI..PI) {
        let q = Quat::from_euler_y(phi, theta, psi);
        let a = q.space_to_body_matrix();
        let back = Quat::from(Rotation3::from_matrix_unchecked(a.transpose()));
        prop_assert!(rotation_diff(&back, &q) < TIGHT);
        let (p, t, s) = back.to_euler_y();
        prop_assert!(rotation_diff(&Quat::from_euler_y(p, t, s), &q) < TIGHT);
        if theta.sin() > 1e-3 {
            prop_assert!(angle_diff(p, phi) < ANGLES && (t - theta).abs() < ANGLES && angle_diff(s, psi) < ANGLES);
        }
    }

    /// exp(ln Q) = +-Q, and ln(exp v) = v for |v| < pi.
    #[test]
    fn exp_ln_round_trip(q in unit_quat(), v in vector(1.8)) {
        prop_assert!(rotation_diff(&Quat::exp(&q.ln()), &q) < TIGHT);
        prop_assume!(v.norm() < PI - 1e-6);
        prop_assert!((Quat::exp(&v).ln() - v).amax() < TIGHT);
    }
}

proptest! {
    /// Eq 10 inverted is exact for any non-zero `Q`: with
    /// `Q' = 1/2 Q*(0, w_b) + lambda Q` (a turn about `w_b` while `|Q|`
    /// changes at the rate `lambda`), `Q.omega_body_from_q_dot(Q') = w_b`, and likewise
    /// `Q.omega_space_from_q_dot(1/2 (0, w_s)*Q + lambda Q) = w_s` (the `1/|Q|^2` of
    /// both undoes the scale of `Q` and of `Q'`).
    #[test]
    fn angular_velocities_are_exact_for_non_unit_q(q in non_unit_quat(), w in vector(3.0), lambda in -2.0f64..2.0) {
        let body = q.omega_body_from_q_dot(&(q.q_dot_from_omega_body(&w) + q * lambda));
        prop_assert!((body - w).amax() < TIGHT * (1.0 + w.amax()));
        let space = q.omega_space_from_q_dot(&(q.q_dot_from_omega_space(&w) + q * lambda));
        prop_assert!((space - w).amax() < TIGHT * (1.0 + w.amax()));
    }

    /// Body and space angular velocities of the same motion are related by
    /// the rotation of `Q/|Q|` (eq 6), for any non-zero `Q`.
    #[test]
    fn body_and_space_angular_velocities_agree_for_non_unit_q(q in non_unit_quat(), w in vector(3.0)) {
        let q_dot = q.q_dot_from_omega_body(&w);
        let unit = q * (1.0 / q.norm());
        let rotated = unit.body_to_space(&q.omega_body_from_q_dot(&q_dot));
        prop_assert!((q.omega_space_from_q_dot(&q_dot) - rotated).amax() < TIGHT * (1.0 + w.amax()));
    }

    /// The matrix of eq 7 of a non-unit `Q` is `|Q|^2` times the rotation of
    /// `Q/|Q|`: `A A^T = |Q|^4 I`, `det A = |Q|^6`.
    #[test]
    fn matrix_of_non_unit_q_is_scaled_rotation(q in non_unit_quat()) {
        let n2 = q.norm_squared();
        let a = q.space_to_body_matrix();
        let unit = q * (1.0 / q.norm());
        prop_assert!((a - unit.space_to_body_matrix() * n2).amax() < TIGHT * n2);
        prop_assert!((a * a.transpose() - Matrix3::identity() * (n2 * n2)).amax() < TIGHT * n2 * n2);
        prop_assert!((a.determinant() - n2 * n2 * n2).abs() < TIGHT * n2 * n2 * n2);
    }
}

proptest! {
    /// The component-wise operations agree with each other: `p += q` is
    /// `p + q`, `p - q` is `p + (-q)`, and indexing reads the components.
    #[test]
    fn sums_and_differences_are_component_wise(p in quat(), q in quat()) {
        let mut sum = p;
        sum += q;
        for k in 0..4 {
            prop_assert_eq!(sum[k], p.0[k] + q.0[k]);
            prop_assert_eq!((p - q)[k], p.0[k] - q.0[k]);
            prop_assert_eq!((-q)[k], -q.0[k]);
        }
    }

    /// `angle_to` is the angle of the rotation from one orientation to the
    /// other, `|v|` for `P` and `exp(v) P` with `|v| <= pi`, whichever sign
    /// either quaternion has.
    #[test]
    fn angle_between_orientations_is_the_rotation_angle(p in unit_quat(), v in vector(1.8)) {
        prop_assume!(v.norm() <= PI);
        let q = Quat::exp(&v) * p;
        for (a, b) in [(p, q), (q, p), (-p, q), (p, -q)] {
            prop_assert!((a.angle_to(&b) - v.norm()).abs() < ANGLES, "{} vs {}", a.angle_to(&b), v.norm());
        }
        prop_assert!(p.angle_to(&p) < TIGHT);
    }

    /// `try_normalize` of a non-zero finite `Q` is the unit quaternion along
    /// it, whatever the scale (down to subnormal-free tiny and up to huge
    /// norms whose square still fits in a double).
    #[test]
    fn normalising_gives_the_unit_quaternion_along_q(q in unit_quat(), log_scale in -150.0f64..150.0) {
        let scale = 10f64.powf(log_scale);
        let unit = (q * scale).try_normalize().expect("non-zero and finite");
        prop_assert!((unit.norm() - 1.0).abs() < TIGHT);
        prop_assert!(max_diff(&unit, &q) < TIGHT);
    }
}

/// A zero or non-finite `Q` has no direction: `try_normalize` refuses it
/// (instead of returning NaN components), and `is_finite` tells the
/// non-finite ones apart.
#[test]
fn zero_and_non_finite_quaternions_are_refused() {
    assert!(Quat::new(0.0, 0.0, 0.0, 0.0).try_normalize().is_none());
    assert!(Quat::new(0.0, 0.0, 0.0, 0.0).is_finite());
    for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
        for k in 0..4 {
            let mut c = [0.5; 4];
            c[k] = bad;
            let q = Quat(c);
            assert!(q.try_normalize().is_none(), "{q:?} normalised");
            assert!(!q.is_finite(), "{q:?} taken for finite");
        }
    }
    assert!(Quat::new(0.5, -0.5, 0.5, 0.5).is_finite());
}
