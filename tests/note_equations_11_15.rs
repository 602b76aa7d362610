//! Eqs 11, 12, 15a and 15b of the note evaluated literally as printed, against
//! finite-difference derivatives of exact trajectories and against the
//! corrected forms (ERRATA.md rows 11, 12, 15a, 15b). The note's `N` (eq 13)
//! is `N = 2 Q*N_b = 2 N_s*Q` with `N_b = (0, n_b)`, `n_b` the body torque
//! divided by the moment of inertia.

use nalgebra::{Unit, Vector3};
use quatrot::observables::{kinetic_energy, kinetic_energy_spherical};
use quatrot::rotor::Inertia;
use quatrot::Quat;

/// Central-difference step (time units; the trajectories vary on scale ~1).
const FD_STEP: f64 = 1e-4;
/// Agreement of a correct formula with the central differences: truncation
/// `~FD_STEP^2 |Q''''|` plus rounding `~1e-16 / FD_STEP^2`, both ~1e-8.
const FD_TOLERANCE: f64 = 1e-6;
/// A printed form counts as wrong when it misses the derivative by this much
/// (the mistakes are O(1) here: a factor 2 or a wrong power of `w`).
const WRONG: f64 = 1e-2;

fn first_derivative(f: &dyn Fn(f64) -> Quat, t: f64) -> Quat {
    (f(t + FD_STEP) - f(t - FD_STEP)) * (0.5 / FD_STEP)
}

fn second_derivative(f: &dyn Fn(f64) -> Quat, t: f64) -> Quat {
    (f(t + FD_STEP) - f(t) * 2.0 + f(t - FD_STEP)) * (1.0 / (FD_STEP * FD_STEP))
}

fn scalar_first_derivative(f: &dyn Fn(f64) -> f64, t: f64) -> f64 {
    (f(t + FD_STEP) - f(t - FD_STEP)) / (2.0 * FD_STEP)
}

fn scalar_second_derivative(f: &dyn Fn(f64) -> f64, t: f64) -> f64 {
    (f(t + FD_STEP) - 2.0 * f(t) + f(t - FD_STEP)) / (FD_STEP * FD_STEP)
}

/// Moment of inertia of the spherical tops below.
const MOMENT: f64 = 1.5;

/// A spherical top driven by a space-fixed torque `I a e` parallel to its
/// angular velocity `w0 e`: it turns about the fixed axis `e` by
/// `theta(t) = w0 t + a t^2/2`, `Q(t) = exp(theta(t) e) * Q0`, and
/// `n_s = a e` (torque divided by `I`).
struct DrivenSpin {
    q0: Quat,
    axis: Unit<Vector3<f64>>,
    w0: f64,
    a: f64,
}

impl DrivenSpin {
    fn q(&self, t: f64) -> Quat {
        Quat::from_axis_angle(&self.axis, self.w0 * t + 0.5 * self.a * t * t) * self.q0
    }
    /// The note's `N = 2 N_s*Q` (eq 13).
    fn note_n(&self, t: f64) -> Quat {
        Quat::pure(&(self.axis.into_inner() * self.a)) * self.q(t) * 2.0
    }
}

fn driven(w0: f64) -> DrivenSpin {
    DrivenSpin {
        q0: Quat::new(0.6, -0.2, 0.7, 0.3)
            .try_normalize()
            .expect("non-zero"),
        axis: Unit::new_normalize(Vector3::new(0.3, -0.8, 0.5)),
        w0,
        a: 0.9,
    }
}

/// The corrected eq 12 for a spherical top: `Q'' = Q'*Q~*Q' + 1/4 N`.
fn corrected_eq12(q: &Quat, q_dot: &Quat, n: &Quat) -> Quat {
    *q_dot * q.conjugate() * *q_dot + *n * 0.25
}

/// The printed eq 12: `Q'' = Q'*Q'*Q' + 1/2 N`.
fn printed_eq12(q_dot: &Quat, n: &Quat) -> Quat {
    *q_dot * *q_dot * *q_dot + *n * 0.5
}

/// Eq 11 as printed, `Omega_b' = N_b` and `Omega_s' = N_s`, holds for a
/// driven spherical top (the case the note states it for), and fails for a
/// free symmetric top, whose body angular velocity precesses without torque.
#[test]
fn eq11_printed_holds_for_spherical_top_only() {
    let spin = driven(0.8);
    let omega_b = |t: f64| {
        let q = spin.q(t);
        Quat::pure(&q.omega_body_from_q_dot(&first_derivative(&|s| spin.q(s), t)))
    };
    let omega_s = |t: f64| {
        let q = spin.q(t);
        Quat::pure(&q.omega_space_from_q_dot(&first_derivative(&|s| spin.q(s), t)))
    };
    for t in [0.0, 0.7, 1.9] {
        let n_s = Quat::pure(&(spin.axis.into_inner() * spin.a));
        let n_b = Quat::pure(&spin.q(t).space_to_body(&n_s.vector()));
        let d_body = first_derivative(&omega_b, t) - n_b;
        let d_space = first_derivative(&omega_s, t) - n_s;
        assert!(
            d_body.norm() < FD_TOLERANCE && d_space.norm() < FD_TOLERANCE,
            "t = {t}"
        );
    }
    // Free symmetric top (I1 = I2 = 1, I3 = 2.5): w_b' = (-W w2, W w1, 0) with
    // W = (I3 - I1)/I1 w3, not the zero torque.
    let w = Vector3::new(0.7, -1.1, 0.9);
    let precession = 1.5 * w.z;
    let w_body = |t: f64| {
        let (s, c) = (precession * t).sin_cos();
        Quat::pure(&Vector3::new(c * w.x - s * w.y, s * w.x + c * w.y, w.z))
    };
    assert!(first_derivative(&w_body, 0.0).norm() > WRONG);
}

/// Eq 12 as printed (`Q'*Q'*Q' + 1/2 N`) misses the finite-difference `Q''`
/// of exact trajectories in both terms; the corrected `Q'*Q~*Q' + 1/4 N`
/// matches it.
#[test]
fn eq12_printed_form_is_wrong_and_corrected_form_matches() {
    // Kinetic term alone: a free spinning top (a = 0).
    let free = DrivenSpin {
        a: 0.0,
        ..driven(1.3)
    };
    // Torque term alone: starting from rest (w0 = 0), at t = 0.
    let from_rest = driven(0.0);
    // Both terms: the driven spin at t > 0.
    let both = driven(0.8);
    for (what, spin, t) in [
        ("kinetic", &free, 0.4),
        ("torque", &from_rest, 0.0),
        ("both", &both, 1.1),
    ] {
        let path = |s: f64| spin.q(s);
        let (q, q_dot, q_ddot) = (
            spin.q(t),
            first_derivative(&path, t),
            second_derivative(&path, t),
        );
        let n = spin.note_n(t);
        let corrected = (corrected_eq12(&q, &q_dot, &n) - q_ddot).norm();
        let printed = (printed_eq12(&q_dot, &n) - q_ddot).norm();
        assert!(
            corrected < FD_TOLERANCE,
            "{what}: corrected off by {corrected:.2e}"
        );
        assert!(printed > WRONG, "{what}: printed off by only {printed:.2e}");
    }
}

/// The general-top form of the corrected eq 12, `Q'' = Q'*Q~*Q' + 1/2 Q*(0, w_b')`
/// with Euler's `w_b'`, matches the finite-difference `Q''` of the exact free
/// symmetric top `Q(t) = exp(L_hat |L| t/I1) * Q0 * exp(-W t e3)`.
#[test]
fn eq12_general_top_form_matches_free_symmetric_top() {
    let (i1, i3) = (1.0, 2.5);
    let moments = Vector3::new(i1, i1, i3);
    let q0 = Quat::new(0.3, -0.5, 0.6, 0.2)
        .try_normalize()
        .expect("non-zero");
    let w0 = Vector3::new(0.7, -1.1, 0.9);
    let l_space = q0.body_to_space(&moments.component_mul(&w0));
    let precession = (i3 - i1) / i1 * w0.z;
    let path = |t: f64| {
        Quat::exp(&(l_space * (t / i1))) * q0 * Quat::exp(&Vector3::new(0.0, 0.0, -precession * t))
    };
    for t in [0.0, 0.6, 2.3] {
        let (q, q_dot) = (path(t), first_derivative(&path, t));
        let w = q.omega_body_from_q_dot(&q_dot);
        let w_dot = (-w.cross(&moments.component_mul(&w))).component_div(&moments);
        let rhs = q_dot * q.conjugate() * q_dot + q * Quat::pure(&w_dot) * 0.5;
        let miss = (rhs - second_derivative(&path, t)).norm();
        assert!(miss < FD_TOLERANCE, "t = {t}: off by {miss:.2e}");
    }
}

/// A smooth path of non-unit quaternions, so that the norm identities are
/// tested where `|Q|^2` actually changes.
fn wobbly(t: f64) -> Quat {
    Quat::new(t.cos() + 0.3 * t, (2.0 * t).sin(), 0.5 + t * t, (-t).exp())
}

/// Eq 15a: `d|Q|^2/dt = 2 (Q'~*Q)_0 = 2 Q.Q' = (Omega_b)_0 = (Omega_s)_0`
/// with `Omega_b = 2 Q~*Q'`, `Omega_s = 2 Q'*Q~`. The printed `(Q'^*Q)_0`
/// must be read with a conjugate: the plain product `(Q'*Q)_0 = q0' q0 - q'.q`
/// is wrong. On the rotor's motion (eq 10) all of them vanish.
#[test]
fn eq15a_needs_the_conjugate_and_vanishes_on_the_motion() {
    for t in [0.2, 1.0] {
        let (q, q_dot) = (wobbly(t), first_derivative(&wobbly, t));
        let fd = scalar_first_derivative(&|s| wobbly(s).norm_squared(), t);
        let forms = [
            2.0 * (q_dot.conjugate() * q).scalar(),
            2.0 * q.dot(&q_dot),
            (q.conjugate() * q_dot * 2.0).scalar(),
            (q_dot * q.conjugate() * 2.0).scalar(),
        ];
        for (k, f) in forms.iter().enumerate() {
            assert!(
                (f - fd).abs() < FD_TOLERANCE,
                "t = {t}, form {k}: {f} vs {fd}"
            );
        }
        let literal = 2.0 * (q_dot * q).scalar();
        assert!(
            (literal - fd).abs() > WRONG,
            "t = {t}: literal product agrees"
        );
    }
    let q = Quat::new(0.6, -0.2, 0.7, 0.3)
        .try_normalize()
        .expect("non-zero");
    let q_dot = q.q_dot_from_omega_body(&Vector3::new(0.4, -1.2, 0.8));
    assert!(q.dot(&q_dot).abs() < 1e-15);
}

/// Eq 15b: along the corrected eq 12 with an unprojected `N` and unit `Q`,
/// `d^2|Q|^2/dt^2 = 1/2 (Q~*N)_0 = 1/2 Q.N = (N_b)_0 = (N_s)_0` with
/// `N_b = 1/2 Q~*N` and `N_s = 1/2 N*Q~` (eq 13 inverted). The printed
/// `1/2 (Q''^*N)_0` is not it (a garbled `Q~`).
#[test]
fn eq15b_holds_with_q_conjugate_not_q_double_dot() {
    let q = Quat::new(0.6, -0.2, 0.7, 0.3)
        .try_normalize()
        .expect("non-zero");
    let q_dot = q.q_dot_from_omega_body(&Vector3::new(0.4, -1.2, 0.8));
    let n = Quat::new(0.9, -0.3, 0.5, 1.1); // a sizeable component along Q
    let q_ddot = corrected_eq12(&q, &q_dot, &n);
    let path = |t: f64| q + q_dot * t + q_ddot * (0.5 * t * t);
    let fd = scalar_second_derivative(&|t| path(t).norm_squared(), 0.0);
    let forms = [
        0.5 * (q.conjugate() * n).scalar(),
        0.5 * q.dot(&n),
        (q.conjugate() * n * 0.5).scalar(),
        (n * q.conjugate() * 0.5).scalar(),
    ];
    assert!(q.dot(&n).abs() > WRONG, "the test needs Q.N != 0");
    for (k, f) in forms.iter().enumerate() {
        assert!((f - fd).abs() < FD_TOLERANCE, "form {k}: {f} vs {fd}");
    }
    for literal in [
        0.5 * (q_ddot * n).scalar(),
        0.5 * (q_ddot.conjugate() * n).scalar(),
    ] {
        assert!(
            (literal - fd).abs() > WRONG,
            "printed Q'' form agrees: {literal} vs {fd}"
        );
    }
}

/// The kinetic-energy identity under eq 10: `2 I |Q'|^2 = 1/2 I w_b^2 = 1/2 I w_s^2`.
#[test]
fn kinetic_energy_identity() {
    let q = Quat::new(-0.4, 0.1, 0.8, -0.3)
        .try_normalize()
        .expect("non-zero");
    for w_b in [Vector3::new(0.4, -1.2, 0.8), Vector3::new(3.0, 0.0, -0.1)] {
        let q_dot = q.q_dot_from_omega_body(&w_b);
        let half_i_w2 = 0.5 * MOMENT * w_b.norm_squared();
        let w_s = q.body_to_space(&w_b);
        for value in [
            kinetic_energy_spherical(MOMENT, &q_dot),
            kinetic_energy(&Inertia::Spherical(MOMENT), &w_b),
            0.5 * MOMENT * w_s.norm_squared(),
        ] {
            assert!(
                (value - half_i_w2).abs() < 1e-14 * half_i_w2,
                "{value} vs {half_i_w2}"
            );
        }
    }
}
