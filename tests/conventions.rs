//! One test per statement of the conventions header of `src/quaternion.rs`.
//! References are independent of the code under test: explicit basis
//! products, Rodrigues' formula, elementary axis rotations, finite differences
//! of the rotation matrix, and nalgebra's own quaternion types.

mod common;

use common::{
    angle_diff, mat_diff, max_diff, random_euler, random_unit_quat, random_vector, rng,
    rotation_diff, uniform,
};
use nalgebra::{Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3, Vector4};
use quatrot::Quat;
use std::f64::consts::{FRAC_PI_2, PI};

/// Round-off of a few unit-scale products and sums (about 50 ulps).
const TIGHT: f64 = 1e-14;
/// Round-off after a trigonometric inversion (atan2 of rounded components) and
/// re-evaluation of sines and cosines.
const TRIG: f64 = 1e-13;
/// Central-difference truncation h^2 |Q'''| / 6 with h = 1e-5, plus round-off eps / h.
const FD: f64 = 1e-9;
/// Random samples per statement.
const SAMPLES: usize = 200;

/// Right-handed active rotation by `angle` about the unit `axis` (Rodrigues).
fn rodrigues(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let k = axis.cross_matrix();
    Matrix3::identity() + k * angle.sin() + k * k * (1.0 - angle.cos())
}

/// Active right-handed rotations about the coordinate axes.
fn rz(a: f64) -> Matrix3<f64> {
    rodrigues(&Vector3::z(), a)
}
fn ry(a: f64) -> Matrix3<f64> {
    rodrigues(&Vector3::y(), a)
}

/// The components of `Quat` are `(q0, q1, q2, q3)` with the scalar first: the
/// rotation by `a` about z has `q0 = cos a/2` and `q3 = sin a/2`.
#[test]
fn component_order_is_scalar_first() {
    let q = Quat::new(1.0, 2.0, 3.0, 4.0);
    assert_eq!(q.0, [1.0, 2.0, 3.0, 4.0]);
    assert_eq!(q.scalar(), 1.0);
    assert_eq!(q.vector(), Vector3::new(2.0, 3.0, 4.0));
    assert_eq!(Quat::IDENTITY.0, [1.0, 0.0, 0.0, 0.0]);
    let a: f64 = 0.7;
    let qz = Quat::from_axis_angle(&Vector3::z_axis(), a);
    assert!(max_diff(&qz, &Quat::new((a / 2.0).cos(), 0.0, 0.0, (a / 2.0).sin())) < TIGHT);
}

/// The product is Hamilton's: i*j = k, j*k = i, k*i = j, i*i = -1, and it
/// agrees with nalgebra's quaternion product on random inputs.
#[test]
fn product_is_hamilton() {
    let (one, i, j, k) = (
        Quat::IDENTITY,
        Quat::new(0.0, 1.0, 0.0, 0.0),
        Quat::new(0.0, 0.0, 1.0, 0.0),
        Quat::new(0.0, 0.0, 0.0, 1.0),
    );
    assert_eq!(i * j, k);
    assert_eq!(j * k, i);
    assert_eq!(k * i, j);
    assert_eq!(j * i, -k);
    for u in [i, j, k] {
        assert_eq!(u * u, -one);
    }
    let mut r = rng(1);
    for _ in 0..SAMPLES {
        let (p, q) = (common::random_quat(&mut r), common::random_quat(&mut r));
        let reference = Quaternion::from(p) * Quaternion::from(q);
        assert!(max_diff(&(p * q), &Quat::from(reference)) < TIGHT);
    }
}

/// `A(Q)` maps space to body: for the rotor turned by +90 degrees about space z,
/// the body x axis points along space y, so `A (0,1,0) = (1,0,0)`; in general the
/// body axes in space, `R e_i`, have body components `e_i`.
#[test]
fn space_to_body_matrix_maps_space_to_body() {
    let q = Quat::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
    let body_x = q.space_to_body(&Vector3::y());
    assert!((body_x - Vector3::x()).amax() < TIGHT);
    let mut r = rng(2);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let a = q.space_to_body_matrix();
        assert!(mat_diff(&a, &q.body_to_space_matrix().transpose()) == 0.0);
        for (i, e) in [Vector3::x(), Vector3::y(), Vector3::z()]
            .iter()
            .enumerate()
        {
            let axis_in_space = q.body_to_space(e);
            assert!((a * axis_in_space - e).amax() < TIGHT, "body axis {i}");
        }
    }
}

/// `R(Q) = A(Q)^T` is the active rotation of the Hamilton sandwich,
/// `R v = vec(Q*(0,v)*Q~)`, and equals Rodrigues' rotation by the quaternion's
/// angle about its axis.
#[test]
fn body_to_space_matrix_is_active_rotation_of_the_sandwich() {
    let mut r = rng(3);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let v = random_vector(&mut r);
        let sandwich = (q * Quat::pure(&v) * q.conjugate()).vector();
        assert!((q.body_to_space(&v) - sandwich).amax() < TIGHT);
        let s = q.vector().norm();
        let angle = 2.0 * s.atan2(q.scalar());
        let rod = rodrigues(&(q.vector() / s), angle);
        assert!(mat_diff(&q.body_to_space_matrix(), &rod) < TIGHT);
    }
}

/// The double cover: `Q` and `-Q` give the same matrix, the same rotated
/// vectors, the same Euler angles and a zero rotation angle between them.
#[test]
fn double_cover_minus_q_is_the_same_rotation() {
    let mut r = rng(4);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let v = random_vector(&mut r);
        assert!(mat_diff(&q.space_to_body_matrix(), &(-q).space_to_body_matrix()) == 0.0);
        let sandwich = |q: Quat| (q.conjugate() * Quat::pure(&v) * q).vector();
        assert!((sandwich(q) - sandwich(-q)).amax() < TIGHT);
        let (e, f) = (q.to_euler_y(), (-q).to_euler_y());
        assert!(
            angle_diff(e.0, f.0) < TRIG && (e.1 - f.1).abs() < TRIG && angle_diff(e.2, f.2) < TRIG
        );
        assert!(q.angle_to(&-q) < TIGHT);
    }
}

/// Eq 9 both ways: `(0, r_b) = Q~*(0, r_s)*Q` is `A r_s`, `(0, r_s) = Q*(0, r_b)*Q~`
/// is `R r_b`, and the two invert each other.
#[test]
fn sandwich_forms_of_eq9_invert_each_other() {
    let mut r = rng(5);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let r_s = random_vector(&mut r);
        let r_b = q.conjugate() * Quat::pure(&r_s) * q;
        assert!(r_b.scalar().abs() < TIGHT);
        assert!((r_b.vector() - q.space_to_body(&r_s)).amax() < TIGHT);
        let back = q * r_b * q.conjugate();
        assert!((back.vector() - r_s).amax() < TIGHT);
    }
}

/// Eq 10: the body and space forms agree when `w_s = R w_b`, the inverses recover
/// both angular velocities, and `Q'` is the time derivative of the rotor turning
/// at `w_b`: `Q(t) = Q exp(w_b t) = exp(w_s t) Q` (central differences).
#[test]
fn eq10_body_and_space_forms_agree_and_invert() {
    let mut r = rng(6);
    let h = 1e-5;
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let omega_body = random_vector(&mut r);
        let omega_space = q.body_to_space(&omega_body);
        let q_dot = q.q_dot_from_omega_body(&omega_body);
        assert!(max_diff(&q_dot, &q.q_dot_from_omega_space(&omega_space)) < TIGHT);
        assert!((q.omega_body_from_q_dot(&q_dot) - omega_body).amax() < TIGHT);
        assert!((q.omega_space_from_q_dot(&q_dot) - omega_space).amax() < TIGHT);
        let body_path = |t: f64| q * Quat::exp(&(omega_body * t));
        let space_path = |t: f64| Quat::exp(&(omega_space * t)) * q;
        for path in [&body_path as &dyn Fn(f64) -> Quat, &space_path] {
            let fd = (path(h) - path(-h)) * (0.5 / h);
            assert!(max_diff(&fd, &q_dot) < FD);
        }
    }
}

/// Eq 8: `A(phi, theta, psi) = Z(psi) Y(theta) Z(phi)` with passive axis
/// rotations, i.e. `R = Rz(phi) Ry(theta) Rz(psi)` (intrinsic z-y'-z'').
#[test]
fn euler_y_is_intrinsic_zyz() {
    let mut r = rng(7);
    for _ in 0..SAMPLES {
        let (phi, theta, psi) = random_euler(&mut r);
        let q = Quat::from_euler_y(phi, theta, psi);
        let reference = rz(phi) * ry(theta) * rz(psi);
        assert!(mat_diff(&q.body_to_space_matrix(), &reference) < TIGHT);
        assert!((q.norm() - 1.0).abs() < TIGHT);
    }
}

/// The inverse returns `theta` in `[0, pi]` and `phi`, `psi` in `(-pi, pi]`,
/// and recovers the angles it was given away from the singularities.
#[test]
fn euler_y_ranges_and_round_trip() {
    let mut r = rng(8);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let (phi, theta, psi) = q.to_euler_y();
        assert!((0.0..=PI).contains(&theta));
        assert!(phi > -PI && phi <= PI && psi > -PI && psi <= PI);
        assert!(rotation_diff(&Quat::from_euler_y(phi, theta, psi), &q) < TRIG);
        let (a, b, c) = random_euler(&mut r);
        let (phi, theta, psi) = Quat::from_euler_y(a, b, c).to_euler_y();
        assert!(angle_diff(phi, a) < TRIG && (theta - b).abs() < TRIG && angle_diff(psi, c) < TRIG);
    }
    // The closed end of the range: an angle of pi is returned as pi, not -pi.
    let (phi, _, psi) = Quat::from_euler_y(PI, 1.0, PI).to_euler_y();
    assert!(phi > 0.0 && psi > 0.0);
}

/// At an exactly singular quaternion only `phi + psi` (`q1 = q2 = 0`) or
/// `psi - phi` (`q0 = q3 = 0`) is defined and the inverse splits it evenly,
/// `phi = psi` or `phi = -psi`. At `theta = 0`, at the float `pi` (whose `q0`,
/// `q3` are ~1e-17 but exact to relative precision) and at `1e-9` from both,
/// the rotation, `theta` and the individual angles are all recovered.
#[test]
fn euler_y_robust_at_and_near_singularities() {
    let mut r = rng(9);
    for _ in 0..SAMPLES {
        let a = uniform(&mut r, -PI, PI);
        for q in [
            Quat::new(a.cos(), 0.0, 0.0, a.sin()),
            -Quat::new(a.cos(), 0.0, 0.0, a.sin()),
        ] {
            let (p, t, s) = q.to_euler_y();
            assert!(t == 0.0 && angle_diff(p, s) < TRIG && angle_diff(p + s, 2.0 * a) < TRIG);
        }
        for q in [
            Quat::new(0.0, a.sin(), a.cos(), 0.0),
            -Quat::new(0.0, a.sin(), a.cos(), 0.0),
        ] {
            let (p, t, s) = q.to_euler_y();
            assert!(t == PI && angle_diff(p, -s) < TRIG && angle_diff(s - p, 2.0 * a) < TRIG);
        }
        let (phi, _, psi) = random_euler(&mut r);
        for theta in [0.0, PI, 1e-9, PI - 1e-9] {
            let q = Quat::from_euler_y(phi, theta, psi);
            let (p, t, s) = q.to_euler_y();
            assert!(
                rotation_diff(&Quat::from_euler_y(p, t, s), &q) < TRIG,
                "theta {theta}"
            );
            assert!((t - theta).abs() < TRIG);
            if theta == 0.0 {
                assert!(angle_diff(p, s) < TRIG && angle_diff(p + s, phi + psi) < TRIG);
            } else {
                assert!(
                    angle_diff(p, phi) < TRIG && angle_diff(s, psi) < TRIG,
                    "theta {theta}"
                );
            }
        }
    }
}

/// `exp(v)` rotates by `|v|` about `v` (Rodrigues), `exp(0)` is the identity and
/// `ln` inverts `exp` for `|v| < pi`; at `|v| = pi` the rotation is recovered
/// (the axis up to sign); small angles keep full relative accuracy.
#[test]
fn exp_and_ln_are_rotation_vectors() {
    assert_eq!(Quat::exp(&Vector3::zeros()), Quat::IDENTITY);
    assert_eq!(Quat::IDENTITY.ln(), Vector3::zeros());
    let mut r = rng(10);
    for _ in 0..SAMPLES {
        let axis = random_vector(&mut r).normalize();
        let angle = uniform(&mut r, 0.0, PI);
        let v = axis * angle;
        let q = Quat::exp(&v);
        assert!(mat_diff(&q.body_to_space_matrix(), &rodrigues(&axis, angle)) < TIGHT);
        assert!((q.ln() - v).amax() < TRIG);
        let q = random_unit_quat(&mut r);
        assert!(rotation_diff(&Quat::exp(&q.ln()), &q) < TRIG);
        assert!(q.ln().norm() <= PI);
        let half_turn = Quat::exp(&(axis * PI));
        let back = half_turn.ln();
        assert!((back.norm() - PI).abs() < TRIG);
        assert!(rotation_diff(&Quat::exp(&back), &half_turn) < TRIG);
        let tiny = axis * 1e-9;
        let q = Quat::exp(&tiny);
        assert!(((q.vector() - tiny * 0.5).norm() / 5e-10) < TIGHT);
        assert!(((q.ln() - tiny).norm() / 1e-9) < TRIG);
    }
}

/// Axis-angle: the zero angle is the identity with no axis; angle `pi` round
/// trips (axis up to sign); random axis-angle pairs with angle in `(0, pi)` round trip.
#[test]
fn axis_angle_including_zero_and_pi() {
    let mut r = rng(11);
    for _ in 0..SAMPLES {
        let axis = Unit::new_normalize(random_vector(&mut r));
        assert_eq!(Quat::from_axis_angle(&axis, 0.0), Quat::IDENTITY);
        assert!(matches!(Quat::IDENTITY.to_axis_angle(), (None, a) if a == 0.0));
        let angle = uniform(&mut r, 0.0, PI);
        let (back_axis, back_angle) = Quat::from_axis_angle(&axis, angle).to_axis_angle();
        assert!((back_angle - angle).abs() < TRIG);
        assert!(back_axis.is_some_and(|b| (b.into_inner() - axis.into_inner()).amax() < TRIG));
        let (pi_axis, pi_angle) = Quat::from_axis_angle(&axis, PI).to_axis_angle();
        assert!((pi_angle - PI).abs() < TRIG);
        let pi_axis = pi_axis.map(Unit::into_inner).unwrap_or_default();
        assert!((pi_axis.dot(&axis).abs() - 1.0).abs() < TRIG);
        let rotation = rodrigues(&axis, angle);
        assert!(
            mat_diff(
                &Quat::from_axis_angle(&axis, angle).body_to_space_matrix(),
                &rotation
            ) < TIGHT
        );
        // The negative angle is the inverse rotation.
        let inverse = Quat::from_axis_angle(&axis, -angle);
        assert!(rotation_diff(&inverse, &Quat::from_axis_angle(&axis, angle).conjugate()) < TIGHT);
    }
}

/// nalgebra's `Quaternion::new(w, i, j, k)` takes the scalar first but stores
/// `coords = [i, j, k, w]`; the conversions keep the meaning, not the storage.
#[test]
fn nalgebra_quaternion_new_stores_ijkw() {
    let n = Quaternion::new(1.0, 2.0, 3.0, 4.0);
    assert_eq!(n.coords, Vector4::new(2.0, 3.0, 4.0, 1.0));
    assert_eq!((n.w, n.i, n.j, n.k), (1.0, 2.0, 3.0, 4.0));
    let q = Quat::new(1.0, 2.0, 3.0, 4.0);
    let converted = Quaternion::from(q);
    assert_eq!(converted.coords, Vector4::new(2.0, 3.0, 4.0, 1.0));
    assert_eq!(Quat::from(converted), q);
    // The trap: reading the storage as scalar-first gives a different quaternion.
    let storage_misread = Quat(converted.coords.into());
    assert!(max_diff(&storage_misread, &q) >= 1.0);
}

/// nalgebra's `UnitQuaternion` and `Rotation3` of `Q` are `R(Q)` (body to space),
/// and its axis-angle constructor agrees with ours.
#[test]
fn nalgebra_unit_quaternion_and_rotation3_equal_r() {
    let mut r = rng(12);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let v = random_vector(&mut r);
        let unit = UnitQuaternion::from(q);
        assert!(
            mat_diff(
                unit.to_rotation_matrix().matrix(),
                &q.body_to_space_matrix()
            ) < TIGHT
        );
        assert!(mat_diff(Rotation3::from(q).matrix(), &q.body_to_space_matrix()) < TIGHT);
        assert!((unit * v - q.body_to_space(&v)).amax() < TIGHT);
        assert!((unit.inverse() * v - q.space_to_body(&v)).amax() < TIGHT);
        let axis = Unit::new_normalize(random_vector(&mut r));
        let angle = uniform(&mut r, -PI, PI);
        let theirs = Quat::from(UnitQuaternion::from_axis_angle(&axis, angle));
        assert!(max_diff(&theirs, &Quat::from_axis_angle(&axis, angle)) < TIGHT);
    }
}

/// Round trips through nalgebra: `Quaternion` exactly, `UnitQuaternion` to
/// round-off, `Rotation3` up to the sign (returned with `q0 >= 0`).
#[test]
fn nalgebra_round_trips() {
    let mut r = rng(13);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        assert_eq!(Quat::from(Quaternion::from(q)), q);
        assert!(max_diff(&Quat::from(UnitQuaternion::from(q)), &q) < TIGHT);
        let back = Quat::from(Rotation3::from(q));
        assert!(back.scalar() >= 0.0);
        assert!(rotation_diff(&back, &q) < TIGHT);
    }
}

/// The checked matrix conversion accepts proper rotations (returning `q0 >= 0`)
/// and rejects reflections, non-orthogonal and non-finite matrices.
#[test]
fn checked_matrix_conversion_rejects_non_rotations() {
    let tolerance = 1e-9;
    let mut r = rng(14);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let back = Quat::from_body_to_space_matrix(&q.body_to_space_matrix(), tolerance);
        assert!(back.is_some_and(|b| b.scalar() >= 0.0 && rotation_diff(&b, &q) < TIGHT));
    }
    let reflection = -Matrix3::identity();
    let sheared = Matrix3::new(1.0, 1e-6, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    let nan = Matrix3::from_element(f64::NAN);
    for bad in [reflection, sheared, nan, Matrix3::zeros()] {
        assert!(
            Quat::from_body_to_space_matrix(&bad, tolerance).is_none(),
            "{bad}"
        );
    }
}
