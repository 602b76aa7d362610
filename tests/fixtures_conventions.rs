//! The library against ASE and scipy, offline: `fixtures/conventions.json`
//! (written by `validation/fixtures/gen_conventions.py`, `make fixtures`; its
//! header records the seed and the package versions). Every value in the
//! fixture was computed by ASE or scipy, none by quatrot.

mod common;

use common::{
    angle_diff, conventions_fixture, mat, mat_diff, max_diff, rotation_diff, vec3, EulerRecord,
};
use nalgebra::{Rotation3, UnitQuaternion};
use quatrot::Quat;

/// Agreement with ASE and scipy: both sides are round-off accurate on unit-scale
/// quantities (the template coordinates are within 3 of the origin).
const FIXTURE: f64 = 1e-12;
/// The same in degrees (angles up to 270 degrees).
const DEGREES: f64 = FIXTURE * 360.0;
/// ASE's and scipy's Euler inverses treat theta within ~1e-8 of 0 or pi as
/// singular; at 1e-9 from it they lose the rotation by O(theta), far above this.
const LOST: f64 = 1e-10;

/// The fixture is large enough and says where it came from.
#[test]
fn fixture_has_provenance_and_size() {
    let fx = conventions_fixture();
    assert!(fx.quaternions.len() >= 200 && fx.euler.len() >= 200);
    assert!(fx.seed > 0);
    for package in ["numpy", "scipy", "ase"] {
        assert!(fx.versions.contains_key(package), "{package}");
    }
    for kind in ["theta=0", "theta=pi", "theta=1e-9", "theta=pi-1e-9"] {
        assert!(fx.euler.iter().any(|r| r.kind == kind), "{kind}");
    }
}

/// `R(Q)` is scipy's `as_matrix()` and ASE's `rotation_matrix()` (both active,
/// body to space); `A(Q)` is their transpose; nalgebra's `Rotation3` agrees too.
#[test]
fn matrices_match_scipy_ase_and_nalgebra() {
    for rec in &conventions_fixture().quaternions {
        let q = Quat(rec.q);
        assert!(mat_diff(&q.body_to_space_matrix(), &mat(&rec.scipy_r)) < FIXTURE);
        assert!(mat_diff(&q.body_to_space_matrix(), &mat(&rec.ase_r)) < FIXTURE);
        assert!(mat_diff(&q.space_to_body_matrix(), &mat(&rec.scipy_a)) < FIXTURE);
        assert!(mat_diff(Rotation3::from(q).matrix(), &mat(&rec.scipy_r)) < FIXTURE);
    }
}

/// Rotated vectors: `body_to_space` is scipy's `apply` and ASE's
/// `Quaternion.rotate`; `space_to_body` is scipy's `apply(inverse=True)`.
#[test]
fn rotated_vectors_match_scipy_and_ase() {
    for rec in &conventions_fixture().quaternions {
        let (q, v) = (Quat(rec.q), vec3(&rec.v));
        assert!((q.body_to_space(&v) - vec3(&rec.scipy_r_v)).amax() < FIXTURE);
        assert!((q.body_to_space(&v) - vec3(&rec.ase_rotate_v)).amax() < FIXTURE);
        assert!((q.space_to_body(&v) - vec3(&rec.scipy_a_v)).amax() < FIXTURE);
        assert!((UnitQuaternion::from(q) * v - vec3(&rec.scipy_r_v)).amax() < FIXTURE);
    }
}

/// `Atoms.rotate(angle_deg, axis, center)` on the NH3 template placed at
/// `center` gives `center + R(Q) r_body`: ASE's rotate is active, in degrees,
/// about `center`.
#[test]
fn ase_atoms_rotate_is_body_to_space_about_center() {
    let fx = conventions_fixture();
    let center = vec3(&fx.template.center);
    for rec in &fx.quaternions {
        let q = Quat(rec.q);
        for (r_body, moved) in fx.template.positions.iter().zip(&rec.atoms_rotate) {
            let expected = center + q.body_to_space(&vec3(r_body));
            assert!((expected - vec3(moved)).amax() < FIXTURE);
        }
    }
}

/// The logarithm is scipy's rotation vector; the matrix-to-quaternion
/// conversion recovers `Q` from scipy's matrix up to the sign.
#[test]
fn ln_and_from_matrix_match_scipy() {
    for rec in &conventions_fixture().quaternions {
        let q = Quat(rec.q);
        assert!((q.ln() - vec3(&rec.scipy_rotvec)).amax() < FIXTURE);
        assert!(rotation_diff(&Quat::exp(&vec3(&rec.scipy_rotvec)), &q) < FIXTURE);
        let from_matrix = Quat::from(Rotation3::from_matrix_unchecked(mat(&rec.scipy_r)));
        assert!(rotation_diff(&from_matrix, &q) < FIXTURE);
    }
}

/// The product is ASE's `Quaternion.__mul__` and scipy's composition.
#[test]
fn product_matches_ase_and_scipy() {
    let fx = conventions_fixture();
    let n = fx.quaternions.len();
    for (i, rec) in fx.quaternions.iter().enumerate() {
        let product = Quat(rec.q) * Quat(fx.quaternions[(i + 1) % n].q);
        assert!(max_diff(&product, &Quat(rec.product_next_ase)) < FIXTURE);
        assert!(rotation_diff(&product, &Quat(rec.product_next_scipy)) < FIXTURE);
    }
}

/// `from_euler_y(phi, theta, psi)` is scipy's `from_euler('ZYZ', [phi, theta, psi])`
/// (intrinsic, upper case) and ASE's `from_euler_angles(psi, theta, phi, 'zyz')`
/// (first angle = the note's psi), at every triple including the singular ones.
#[test]
fn euler_y_matches_scipy_zyz_and_ase_zyz() {
    for rec in &conventions_fixture().euler {
        let [phi, theta, psi] = rec.angles_y;
        let q = Quat::from_euler_y(phi, theta, psi);
        assert!(
            rotation_diff(&q, &Quat(rec.scipy_q)) < FIXTURE,
            "{}",
            rec.kind
        );
        assert!(
            rotation_diff(&q, &Quat(rec.ase_q)) < FIXTURE,
            "{}",
            rec.kind
        );
        assert!(mat_diff(&q.space_to_body_matrix(), &mat(&rec.scipy_a)) < FIXTURE);
        assert!(mat_diff(&q.body_to_space_matrix(), &mat(&rec.scipy_r)) < FIXTURE);
    }
}

/// `Atoms.euler_rotate(phi + 90, theta, psi - 90, center)` (degrees, Goldstein's
/// x-convention, passive) moves the template placed at `center` to
/// `center + A(phi, theta, psi) r`: it maps space to body.
#[test]
fn ase_euler_rotate_is_space_to_body_in_x_convention_degrees() {
    let fx = conventions_fixture();
    let center = vec3(&fx.template.center);
    for rec in &fx.euler {
        let [phi, theta, psi] = rec.angles_y;
        let [phi_x, theta_x, psi_x] = rec.ase_euler_rotate_deg;
        assert!((phi_x - (phi.to_degrees() + 90.0)).abs() < DEGREES);
        assert!(
            (theta_x - theta.to_degrees()).abs() < DEGREES
                && (psi_x - (psi.to_degrees() - 90.0)).abs() < DEGREES
        );
        let q = Quat::from_euler_y(phi, theta, psi);
        for (r, moved) in fx.template.positions.iter().zip(&rec.atoms_euler_rotate) {
            let expected = center + q.space_to_body(&vec3(r));
            assert!((expected - vec3(moved)).amax() < FIXTURE, "{}", rec.kind);
        }
    }
}

/// The inverse `to_euler_y` returns scipy's `as_euler('ZYZ')` angles and ASE's
/// `euler_angles('zyz')` (reordered) away from the singularities; at and near
/// them it recovers the fixture's rotation to round-off.
#[test]
fn to_euler_y_matches_scipy_and_ase_and_recovers_the_rotation() {
    for rec in &conventions_fixture().euler {
        let q = Quat(rec.scipy_q);
        let (phi, theta, psi) = q.to_euler_y();
        let back = Quat::from_euler_y(phi, theta, psi);
        assert!(
            mat_diff(&back.space_to_body_matrix(), &mat(&rec.scipy_a)) < FIXTURE,
            "{}",
            rec.kind
        );
        if rec.kind == "random" {
            let [s_phi, s_theta, s_psi] = rec.scipy_euler_zyz;
            assert!(
                angle_diff(phi, s_phi) < FIXTURE
                    && (theta - s_theta).abs() < FIXTURE
                    && angle_diff(psi, s_psi) < FIXTURE
            );
            let [a_psi, a_theta, a_phi] = rec.ase_euler_zyz;
            assert!(
                angle_diff(phi, a_phi) < FIXTURE
                    && (theta - a_theta).abs() < FIXTURE
                    && angle_diff(psi, a_psi) < FIXTURE
            );
        }
    }
}

/// Trap: within ~1e-8 of theta = 0 or pi, ASE's `euler_angles` (an arccos) and
/// scipy's `as_euler` (a gimbal-lock threshold) return angles whose rotation is
/// off by O(theta) = 1e-9; quatrot's inverse is exact there (test above).
#[test]
fn trap_ase_and_scipy_euler_inverses_lose_near_singular_rotations() {
    let fx = conventions_fixture();
    let near: Vec<&EulerRecord> = fx
        .euler
        .iter()
        .filter(|r| r.kind == "theta=1e-9" || r.kind == "theta=pi-1e-9")
        .collect();
    let worst = |angles: &dyn Fn(&EulerRecord) -> Quat| {
        near.iter()
            .map(|r| rotation_diff(&angles(r), &Quat(r.scipy_q)))
            .fold(0.0, f64::max)
    };
    let ase =
        worst(&|r| Quat::from_euler_y(r.ase_euler_zyz[2], r.ase_euler_zyz[1], r.ase_euler_zyz[0]));
    let scipy = worst(&|r| {
        Quat::from_euler_y(
            r.scipy_euler_zyz[0],
            r.scipy_euler_zyz[1],
            r.scipy_euler_zyz[2],
        )
    });
    let ours = worst(&|r| {
        let (phi, theta, psi) = Quat(r.scipy_q).to_euler_y();
        Quat::from_euler_y(phi, theta, psi)
    });
    assert!(ase > LOST && scipy > LOST, "ase {ase:e}, scipy {scipy:e}");
    assert!(ours < FIXTURE, "quatrot {ours:e}");
    // ASE's theta itself collapses to 0 at theta = 1e-9.
    assert!(fx
        .euler
        .iter()
        .filter(|r| r.kind == "theta=1e-9")
        .all(|r| r.ase_euler_zyz[1] == 0.0));
}
