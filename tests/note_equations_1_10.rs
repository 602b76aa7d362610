//! Eqs 1-10 of Allen's note evaluated literally as printed, each written out
//! locally below (`printed_*`), and checked against the other equations, the
//! library and the ASE/scipy fixture (`fixtures/conventions.json`). Where a
//! printed form is inconsistent, the test asserts that it FAILS by a margin
//! and that the corrected form (the library's) passes. ERRATA.md cites these
//! tests by name.

mod common;

use common::{
    conventions_fixture, mat, mat_diff, max_diff, random_quat, random_unit_quat, random_vector,
    rng, rotation_diff, vec3,
};
use nalgebra::{Matrix3, Vector3};
use quatrot::Quat;

/// Round-off of a few unit-scale products and sums (about 50 ulps).
const TIGHT: f64 = 1e-14;
/// Agreement with the ASE/scipy fixture: both sides are round-off accurate.
const FIXTURE: f64 = 1e-12;
/// A printed form "fails" when it misses the identity by at least this much on
/// every sample (unit-scale quantities; generic random inputs miss by O(1)).
const MARGIN: f64 = 1e-3;
/// Angular velocity read off the matrix by a central difference with h = 1e-3:
/// exact for the quadratic `R(Q + t Q')` up to round-off eps / h.
const MATRIX_FD: f64 = 1e-11;
/// Random samples per equation.
const SAMPLES: usize = 200;

/// Eq 2 as printed: `P*Q = (p0 q0 - p.q, p0 q + q0 p - p x q)`.
fn printed_product(p: &Quat, q: &Quat) -> Quat {
    let (p0, pv, q0, qv) = (p.scalar(), p.vector(), q.scalar(), q.vector());
    let v = qv * p0 + pv * q0 - pv.cross(&qv);
    Quat::new(p0 * q0 - pv.dot(&qv), v.x, v.y, v.z)
}

/// Eq 3 as printed: `Q~ = (q0, -q)`.
fn printed_conjugate(q: &Quat) -> Quat {
    Quat::new(q[0], -q[1], -q[2], -q[3])
}

/// Eq 5 as printed: `|Q|^2 = q0^2 + q1^2 + q2^2 + q3^2`.
fn printed_norm_squared(q: &Quat) -> f64 {
    q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
}

/// Eq 7 as printed, row by row.
fn printed_a(q: &Quat) -> Matrix3<f64> {
    let [q0, q1, q2, q3] = q.0;
    Matrix3::new(
        q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3,
        2.0 * (q1 * q2 + q0 * q3),
        2.0 * (q1 * q3 - q0 * q2),
        2.0 * (q1 * q2 - q0 * q3),
        q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3,
        2.0 * (q2 * q3 + q0 * q1),
        2.0 * (q1 * q3 + q0 * q2),
        2.0 * (q2 * q3 - q0 * q1),
        q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3,
    )
}

/// Eq 8 as printed (y-convention).
fn printed_euler_y(phi: f64, theta: f64, psi: f64) -> Quat {
    let (s, d, t) = (0.5 * (psi + phi), 0.5 * (psi - phi), 0.5 * theta);
    Quat::new(
        s.cos() * t.cos(),
        d.sin() * t.sin(),
        d.cos() * t.sin(),
        s.sin() * t.cos(),
    )
}

/// Goldstein's y-convention matrix (B-3y), `A = Z(psi) Y(theta) Z(phi)` written
/// out; `bottom_row_angle` is the angle in its bottom row: `phi` is correct, the
/// printing on p607 has `psi` (the note's footnote 4).
fn goldstein_b3y(phi: f64, theta: f64, psi: f64, bottom_row_angle: f64) -> Matrix3<f64> {
    let (sf, cf) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    let (ss, cs) = psi.sin_cos();
    let (sb, cb) = bottom_row_angle.sin_cos();
    Matrix3::new(
        -ss * sf + ct * cf * cs,
        ss * cf + ct * sf * cs,
        -cs * st,
        -cs * sf - ct * cf * ss,
        cs * cf - ct * sf * ss,
        ss * st,
        st * cb,
        st * sb,
        ct,
    )
}

/// The pure quaternion `(0, v)`.
fn pure(v: &Vector3<f64>) -> Quat {
    Quat::new(0.0, v.x, v.y, v.z)
}

/// The space- and body-frame angular velocities of the motion `Q(t) = Q + t Q'`
/// read off the rotation matrix `R = A^T` (eq 7), independently of any
/// quaternion product: `[w_s]x = R' R^T`, `[w_b]x = R^T R'`. `R` is quadratic in
/// `Q`, so the central difference is exact up to round-off.
fn omega_from_matrix(q: &Quat, q_dot: &Quat) -> (Vector3<f64>, Vector3<f64>) {
    let h = 1e-3;
    let r = |t: f64| printed_a(&(*q + *q_dot * t)).transpose();
    let r_dot = (r(h) - r(-h)) / (2.0 * h);
    let vee = |m: Matrix3<f64>| {
        Vector3::new(
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        ) * 0.5
    };
    (
        vee(r_dot * r(0.0).transpose()),
        vee(r(0.0).transpose() * r_dot),
    )
}

/// Largest component of `|a - b|`.
fn vdiff(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    (a - b).amax()
}

/// Eq 1, `Q = (q0, q1, q2, q3) = (q0, q)`: `q0` is the scalar, Goldstein's
/// `e0 = cos(angle/2)`; the vector part is `sin(angle/2) axis`. Checked against
/// scipy's rotation vectors and the library's scalar/vector split.
#[test]
fn eq1_scalar_first_components() {
    let fx = conventions_fixture();
    for rec in &fx.quaternions {
        let q = Quat(rec.q);
        assert_eq!(
            (q.scalar(), q.vector()),
            (rec.q[0], Vector3::new(rec.q[1], rec.q[2], rec.q[3]))
        );
        let rotvec = vec3(&rec.scipy_rotvec);
        let angle = rotvec.norm();
        let from_rotvec = Quat::new((0.5 * angle).cos(), 0.0, 0.0, 0.0)
            + pure(&(rotvec * ((0.5 * angle).sin() / angle)));
        assert!(rotation_diff(&from_rotvec, &q) < FIXTURE);
    }
}

/// Eq 2 as printed (`- p x q`) is the Hamilton product with its factors swapped:
/// a consistent algebra (associative, norm-multiplicative) but the opposite one.
#[test]
fn eq2_printed_product_is_reversed_hamilton_product() {
    let mut r = rng(21);
    for _ in 0..SAMPLES {
        let (p, q, s) = (
            random_quat(&mut r),
            random_quat(&mut r),
            random_quat(&mut r),
        );
        assert!(max_diff(&printed_product(&p, &q), &(q * p)) < TIGHT);
        let assoc = max_diff(
            &printed_product(&printed_product(&p, &q), &s),
            &printed_product(&p, &printed_product(&q, &s)),
        );
        assert!(assoc < 10.0 * TIGHT);
        assert!(max_diff(&printed_product(&p, &q), &(p * q)) > MARGIN);
    }
}

/// Eq 2 against ASE and scipy: their composition `q1 * q2` (apply `q2`, then
/// `q1`) is the Hamilton product (`+ p x q`); the printed `- p x q` fails it.
#[test]
fn eq2_printed_sign_fails_ase_and_scipy_composition() {
    let fx = conventions_fixture();
    let n = fx.quaternions.len();
    for (i, rec) in fx.quaternions.iter().enumerate() {
        let (p, q) = (Quat(rec.q), Quat(fx.quaternions[(i + 1) % n].q));
        let (ase, scipy) = (Quat(rec.product_next_ase), Quat(rec.product_next_scipy));
        assert!(max_diff(&(p * q), &ase) < FIXTURE);
        assert!(rotation_diff(&(p * q), &scipy) < FIXTURE);
        assert!(rotation_diff(&printed_product(&p, &q), &ase) > MARGIN);
    }
}

/// Eq 3, `Q~ = (q0, -q)`: the library's conjugate, and the inverse rotation
/// (scipy's `A = R^T` is the matrix of the conjugate).
#[test]
fn eq3_conjugate_is_the_inverse_rotation() {
    let fx = conventions_fixture();
    for rec in &fx.quaternions {
        let q = Quat(rec.q);
        assert_eq!(printed_conjugate(&q), q.conjugate());
        assert!(
            mat_diff(
                &printed_a(&printed_conjugate(&q)).transpose(),
                &mat(&rec.scipy_a)
            ) < FIXTURE
        );
    }
}

/// Eq 4, `Q~*Q = Q*Q~ = (|Q|^2, 0)`, holds for any `Q` with either sign of the
/// cross product (so it cannot detect the eq 2 erratum), with `|Q|^2` of eq 5.
#[test]
fn eq4_conjugate_product_is_the_norm() {
    let mut r = rng(22);
    for _ in 0..SAMPLES {
        let q = random_quat(&mut r) * 1.7;
        let expected = Quat::new(printed_norm_squared(&q), 0.0, 0.0, 0.0);
        let scale = printed_norm_squared(&q);
        for product in [
            printed_product(&printed_conjugate(&q), &q),
            printed_product(&q, &printed_conjugate(&q)),
            q.conjugate() * q,
            q * q.conjugate(),
        ] {
            assert!(max_diff(&product, &expected) < TIGHT * scale);
        }
    }
}

/// Eq 5, `|Q|^2 = sum q_i^2`: the library's norm, nalgebra's, and the norm is
/// multiplicative, `|P*Q| = |P||Q|`, for both signs of eq 2.
#[test]
fn eq5_norm_is_multiplicative() {
    let mut r = rng(23);
    for _ in 0..SAMPLES {
        let (p, q) = (random_quat(&mut r), random_quat(&mut r));
        let n2 = printed_norm_squared(&q);
        assert!((q.norm_squared() - n2).abs() < TIGHT * n2);
        assert!((nalgebra::Quaternion::from(q).norm_squared() - n2).abs() < TIGHT * n2);
        let np = printed_norm_squared(&p);
        assert!((printed_norm_squared(&(p * q)) - np * n2).abs() < TIGHT * np * n2);
        assert!((printed_norm_squared(&printed_product(&p, &q)) - np * n2).abs() < TIGHT * np * n2);
    }
}

/// Eqs 6-7, `r_b = A r_s` with `A` as printed: equals the library's matrix and
/// scipy's `R^T` (`Rotation.apply(v, inverse=True)` is `A v`); `A` is orthogonal
/// with determinant +1 for unit `Q` and `|Q|^2` times that otherwise.
#[test]
fn eq6_eq7_matrix_maps_space_to_body() {
    let fx = conventions_fixture();
    for rec in &fx.quaternions {
        let q = Quat(rec.q);
        let a = printed_a(&q);
        assert!(mat_diff(&a, &q.space_to_body_matrix()) < TIGHT);
        assert!(mat_diff(&a, &mat(&rec.scipy_a)) < FIXTURE);
        assert!(vdiff(&(a * vec3(&rec.v)), &vec3(&rec.scipy_a_v)) < FIXTURE);
        assert!(mat_diff(&(a * a.transpose()), &Matrix3::identity()) < TIGHT);
        assert!((a.determinant() - 1.0).abs() < TIGHT);
        let scaled = q * 2.5;
        assert!(mat_diff(&printed_a(&scaled), &(a * 6.25)) < 10.0 * TIGHT);
    }
}

/// Eq 8 as printed gives, through eq 7, Goldstein's y-convention
/// `A = Z(psi) Y(theta) Z(phi)` and scipy's intrinsic `'ZYZ'` of
/// `(phi, theta, psi)` transposed, for all fixture triples (theta = 0, pi and
/// 1e-9 from them included); it is the library's `from_euler_y`.
#[test]
fn eq8_through_eq7_is_scipy_zyz() {
    let fx = conventions_fixture();
    for rec in &fx.euler {
        let [phi, theta, psi] = rec.angles_y;
        let q = printed_euler_y(phi, theta, psi);
        assert!(max_diff(&q, &Quat::from_euler_y(phi, theta, psi)) < TIGHT);
        assert!(
            rotation_diff(&q, &Quat(rec.scipy_q)) < FIXTURE,
            "{}",
            rec.kind
        );
        assert!(
            mat_diff(&printed_a(&q), &mat(&rec.scipy_a)) < FIXTURE,
            "{}",
            rec.kind
        );
        assert!(mat_diff(&printed_a(&q), &goldstein_b3y(phi, theta, psi, phi)) < TIGHT);
    }
}

/// Footnote 4: Goldstein's (B-3y) with `psi` in the bottom row (as printed on
/// p607) disagrees with eq 8 -> eq 7 and with scipy's ZYZ; with `phi` (the
/// note's correction) it agrees. The note is right.
#[test]
fn eq8_footnote4_goldstein_bottom_row_needs_phi() {
    let fx = conventions_fixture();
    for rec in fx.euler.iter().filter(|r| r.kind == "random") {
        let [phi, theta, psi] = rec.angles_y;
        let scipy_a = mat(&rec.scipy_a);
        assert!(mat_diff(&goldstein_b3y(phi, theta, psi, phi), &scipy_a) < FIXTURE);
        let typo = goldstein_b3y(phi, theta, psi, psi);
        let bottom_row_error = (typo.row(2) - scipy_a.row(2)).amax();
        // The typo vanishes only where sin(theta) = 0 or psi = phi (mod 2 pi).
        let expected = theta.sin() * (2.0 * (0.5 * (psi - phi)).sin()).abs();
        assert!(bottom_row_error > 0.5 * expected / std::f64::consts::SQRT_2);
        if expected > 0.01 {
            assert!(bottom_row_error > MARGIN);
        }
    }
}

/// Eq 9, `R_b = Q~*R_s*Q` (the tilde is the conjugate written with a bar in
/// eq 3): with the Hamilton product it is eq 6-7's `A r_s` and scipy's inverse
/// rotation; with the printed eq 2 it gives `R r_s` instead and fails.
#[test]
fn eq9_sandwich_needs_the_hamilton_product() {
    let fx = conventions_fixture();
    for rec in &fx.quaternions {
        let q = Quat(rec.q);
        let r_s = pure(&vec3(&rec.v));
        let hamilton = q.conjugate() * r_s * q;
        assert!(hamilton.scalar().abs() < TIGHT);
        assert!(vdiff(&hamilton.vector(), &(printed_a(&q) * vec3(&rec.v))) < TIGHT);
        assert!(vdiff(&hamilton.vector(), &vec3(&rec.scipy_a_v)) < FIXTURE);
        assert!(vdiff(&hamilton.vector(), &q.space_to_body(&vec3(&rec.v))) < TIGHT);
        let printed = printed_product(&printed_product(&printed_conjugate(&q), &r_s), &q);
        assert!(vdiff(&printed.vector(), &vec3(&rec.scipy_r_v)) < FIXTURE);
        assert!(vdiff(&printed.vector(), &vec3(&rec.scipy_a_v)) > MARGIN);
    }
}

/// Eq 10, `Q' = 1/2 Q*W_b = 1/2 W_s*Q`: with the Hamilton product both forms
/// agree (`w_s = R w_b`) and reproduce the angular velocities read off the
/// rotation matrix, and `2|Q'|^2 = 1/2 |w|^2` (the note's kinetic energy). With
/// the printed eq 2 the body form turns the rotor about `w_b` taken in the SPACE
/// frame and the two forms disagree.
#[test]
fn eq10_needs_the_hamilton_product() {
    let mut r = rng(24);
    for _ in 0..SAMPLES {
        let q = random_unit_quat(&mut r);
        let omega_body = random_vector(&mut r);
        let omega_space = printed_a(&q).transpose() * omega_body;
        let body_form = q * pure(&omega_body) * 0.5;
        let space_form = pure(&omega_space) * q * 0.5;
        assert!(max_diff(&body_form, &space_form) < TIGHT);
        assert!(max_diff(&body_form, &q.q_dot_from_omega_body(&omega_body)) < TIGHT);
        let (w_s, w_b) = omega_from_matrix(&q, &body_form);
        assert!(vdiff(&w_s, &omega_space) < MATRIX_FD && vdiff(&w_b, &omega_body) < MATRIX_FD);
        assert!(
            (2.0 * body_form.norm_squared() - 0.5 * omega_body.norm_squared()).abs()
                < TIGHT * omega_body.norm_squared()
        );

        let printed_body = printed_product(&q, &pure(&omega_body)) * 0.5;
        let printed_space = printed_product(&pure(&omega_space), &q) * 0.5;
        assert!(max_diff(&printed_body, &printed_space) > MARGIN);
        let (w_s, w_b) = omega_from_matrix(&q, &printed_body);
        assert!(
            vdiff(&w_s, &omega_body) < MATRIX_FD,
            "printed body form: w_b acts as a space vector"
        );
        assert!(vdiff(&w_b, &omega_body) > MARGIN);
    }
}
