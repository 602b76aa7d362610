//! Exact flows of the free-rotor kinetic energy, shared by NO_SQUISH and DLM.
//!
//! The kinetic energy `T = sum_k L_k^2 / (2 I_k)` (body angular momentum
//! `L_b`) splits into the three terms `T_k = L_k^2 / (2 I_k)`. The flow of one
//! term over a time `h` is an exact rotation about body axis `k` by the angle
//! `h L_k / I_k`: with `E = exp(angle e_k)`, `Q <- Q*E` (eq 10 with
//! `w_b = (L_k / I_k) e_k`) and, since the space-fixed angular momentum does
//! not change, `L_b <- A(E) L_b` (eq 6). A symmetric sweep of these flows
//! (outer, middle, inner, middle, outer, with durations `h/2, h/2, h, h/2,
//! h/2`) is a second-order, symplectic and time-reversible approximation of
//! the free flow.
//!
//! For a spherical top `T = |L_b|^2 / (2 I)` has an exact flow of its own:
//! `Q <- Q*exp(h w_b)` with `L_b` unchanged (the rotation is about `L_b`
//! itself). The three `T_k` do not commute, so the sweep is *not* exact for a
//! spherical top; [`SphericalTops::Exact`] uses the exact flow instead.
//!
//! An axis with zero moment of inertia (a linear rotor) carries no kinetic
//! energy and is skipped. Left out: the exact free flow of a symmetric top
//! (two equal moments), which would also be a composition of two commuting
//! exact flows; symmetric tops use the sweep.

use crate::checks::named_choices;
use crate::quaternion::Quat;
use crate::rotor::is_spherical_top;
use nalgebra::Vector3;

/// How the free rotation of a spherical top (three equal, positive moments)
/// is integrated. Other tops always use the sweep about body axes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SphericalTops {
    /// The exact flow `Q <- Q*exp(h w_b)`: a free spherical top is integrated
    /// to round-off (default).
    #[default]
    Exact,
    /// The same sweep about body axes as for any other top (what LAMMPS
    /// `fix nve/sphere update dipole/dlm` does): second order only.
    Split,
}

named_choices!(SphericalTops {
    "exact" => SphericalTops::Exact,
    "split" => SphericalTops::Split,
});

/// A momentum variable carried by the rotation of the body frame: the body
/// angular momentum itself (DLM) or the conjugate quaternion momentum
/// `P = 2 Q*(0, L_b)` (NO_SQUISH).
pub trait BodyMomentum {
    /// The body angular momentum `L_b` given the orientation `q` (unit).
    fn angular_momentum_body(&self, q: &Quat) -> Vector3<f64>;

    /// The component `axis` of `L_b`.
    fn angular_momentum_about(&self, q: &Quat, axis: usize) -> f64 {
        self.angular_momentum_body(q)[axis]
    }

    /// Updates the momentum for the body rotation `Q <- Q*E` (unit `E`) with
    /// the space-fixed angular momentum unchanged.
    fn carry(&mut self, e: &Quat);

    /// [`BodyMomentum::carry`] for `E = (c, s e_axis)`, a rotation about
    /// body axis `axis`.
    fn carry_about(&mut self, axis: usize, c: f64, s: f64) {
        self.carry(&axis_rotation(axis, c, s));
    }
}

/// The rotation `(c, s e)` about body axis `axis` (0, 1, 2), `e` the unit
/// vector along it.
fn axis_rotation(axis: usize, c: f64, s: f64) -> Quat {
    let mut e = Quat([c, 0.0, 0.0, 0.0]);
    e.0[axis + 1] = s;
    e
}

/// DLM's variable: `L_b <- A(E) L_b`.
impl BodyMomentum for Vector3<f64> {
    fn angular_momentum_body(&self, _: &Quat) -> Vector3<f64> {
        *self
    }
    fn carry(&mut self, e: &Quat) {
        *self = e.space_to_body(self);
    }
}

/// NO_SQUISH's variable `P = 2 Q*(0, L_b)`: `P <- P*E`, since
/// `2 (Q*E)*(E~*(0, L_b)*E) = P*E`; `L_b = 1/2 vec(Q~*P)`.
impl BodyMomentum for Quat {
    fn angular_momentum_body(&self, q: &Quat) -> Vector3<f64> {
        (q.conjugate() * *self).vector() * 0.5
    }
    fn angular_momentum_about(&self, q: &Quat, axis: usize) -> f64 {
        vector_component_of_product(&q.conjugate(), self, axis) * 0.5
    }
    fn carry(&mut self, e: &Quat) {
        *self = *self * *e;
    }
    fn carry_about(&mut self, axis: usize, c: f64, s: f64) {
        *self = times_axis_rotation(self, axis, c, s);
    }
}

/// The exact flow of `T_k = L_k^2 / (2 I_k)` for a time `duration`: rotation
/// about body axis `axis` (0, 1, 2 for axes 1, 2, 3) by `duration L_k / I_k`.
/// Does nothing when `I_k = 0`.
pub fn rotate_about_body_axis<M: BodyMomentum>(
    q: &mut Quat,
    momentum: &mut M,
    axis: usize,
    inertia_k: f64,
    duration: f64,
) {
    if inertia_k == 0.0 {
        return;
    }
    let angle = duration * momentum.angular_momentum_about(q, axis) / inertia_k;
    let (c, s) = crate::quaternion::half_angle_cos_sin(angle);
    *q = times_axis_rotation(q, axis, c, s);
    momentum.carry_about(axis, c, s);
}

/// Component `axis` (0, 1, 2) of `vec(p*q)`: the operations of that
/// component of `*`, so the same bits.
#[inline]
fn vector_component_of_product(p: &Quat, q: &Quat, axis: usize) -> f64 {
    let ([p0, p1, p2, p3], [q0, q1, q2, q3]) = (p.0, q.0);
    match axis {
        0 => p0 * q1 + q0 * p1 + p2 * q3 - p3 * q2,
        1 => p0 * q2 + q0 * p2 + p3 * q1 - p1 * q3,
        _ => p0 * q3 + q0 * p3 + p1 * q2 - p2 * q1,
    }
}

/// `p*axis_rotation(axis, c, s)`, the rotation of an axis flow: `*`
/// without its terms in the zero components (the same bits but for the
/// sign of an exact zero).
#[inline]
fn times_axis_rotation(p: &Quat, axis: usize, c: f64, s: f64) -> Quat {
    let [p0, p1, p2, p3] = p.0;
    Quat(match axis {
        0 => [
            c * p0 - s * p1,
            c * p1 + s * p0,
            c * p2 + s * p3,
            c * p3 - s * p2,
        ],
        1 => [
            c * p0 - s * p2,
            c * p1 - s * p3,
            c * p2 + s * p0,
            c * p3 + s * p1,
        ],
        _ => [
            c * p0 - s * p3,
            c * p1 + s * p2,
            c * p2 - s * p1,
            c * p3 + s * p0,
        ],
    })
}

/// The symmetric sweep over `duration` of the rotors `swept`: flows about
/// `axes[0]`, `axes[1]` for `duration/2`, `axes[2]` for `duration`, then
/// `axes[1]`, `axes[0]` for `duration/2`, each flow taken by all of them
/// before the next.
fn symmetric_sweep<M: BodyMomentum, const K: usize>(
    q: &mut [Quat; K],
    momentum: &mut [M; K],
    inertia: &[Vector3<f64>; K],
    swept: &[bool; K],
    axes: [usize; 3],
    duration: f64,
) {
    let half = 0.5 * duration;
    let [outer, middle, inner] = axes;
    let flows = [
        (outer, half),
        (middle, half),
        (inner, duration),
        (middle, half),
        (outer, half),
    ];
    for (axis, flow) in flows {
        for k in (0..K).filter(|&k| swept[k]) {
            rotate_about_body_axis(&mut q[k], &mut momentum[k], axis, inertia[k][axis], flow);
        }
    }
}

/// The exact free flow of a spherical top with moment `inertia` (> 0):
/// `Q <- Q*exp(duration L_b / I)`, `L_b` unchanged.
pub fn rotate_spherical_top<M: BodyMomentum>(
    q: &mut Quat,
    momentum: &mut M,
    inertia: f64,
    duration: f64,
) {
    let e = Quat::exp(&(momentum.angular_momentum_body(q) * (duration / inertia)));
    *q = *q * e;
    momentum.carry(&e);
}

/// The free flow over `duration` of `K` rotors, used by NO_SQUISH and DLM:
/// for each, the exact spherical-top flow when `spherical` allows it,
/// otherwise `substeps` symmetric sweeps of `duration / substeps` about
/// `axes`. Each flow of a sweep is taken by all the rotors before the next:
/// the same operations on each rotor as one by one (the same bits), but the
/// rotors' chains of dependent operations (a division, the half angle's
/// series, a product, five times) are independent of one another and
/// overlap in the CPU instead of following one after the other.
pub fn free_flow<M: BodyMomentum, const K: usize>(
    q: &mut [Quat; K],
    momentum: &mut [M; K],
    inertia: &[Vector3<f64>; K],
    spherical: SphericalTops,
    axes: [usize; 3],
    substeps: usize,
    duration: f64,
) {
    let swept: [bool; K] = std::array::from_fn(|k| {
        spherical == SphericalTops::Split || !is_spherical_top(&inertia[k])
    });
    for k in (0..K).filter(|&k| !swept[k]) {
        rotate_spherical_top(&mut q[k], &mut momentum[k], inertia[k].x, duration);
    }
    let sub = duration / substeps as f64;
    for _ in 0..substeps {
        symmetric_sweep(q, momentum, inertia, &swept, axes, sub);
    }
}

/// Body angular velocity `w_k = L_k / I_k`, zero about axes with `I_k = 0`.
pub fn omega_from_momentum(momentum_body: &Vector3<f64>, inertia: &Vector3<f64>) -> Vector3<f64> {
    Vector3::from_fn(|k, _| {
        if inertia[k] == 0.0 {
            0.0
        } else {
            momentum_body[k] / inertia[k]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The products of one component and with an axis rotation are `*`'s
    /// bits: for random quaternions (zeros among their components too) and
    /// each axis, `vector_component_of_product` equals the component of the
    /// full product, and `times_axis_rotation` equals the full product with
    /// `(c, s e_axis)` but for the sign of a zero.
    #[test]
    fn sparse_products_are_the_full_products_bits() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut draw = |zeros: bool| {
            Quat(std::array::from_fn(|_| {
                match zeros && rng.random::<f64>() < 0.3 {
                    true => 0.0,
                    false => rng.random::<f64>() * 2.0 - 1.0,
                }
            }))
        };
        for n in 0..2_000 {
            let (p, q) = (draw(n % 2 == 1), draw(n % 2 == 1));
            let (c, s) = (q.0[0], q.0[1]);
            for axis in 0..3 {
                let full = p * q;
                assert_eq!(
                    vector_component_of_product(&p, &q, axis).to_bits(),
                    full.0[axis + 1].to_bits()
                );
                let full = p * axis_rotation(axis, c, s);
                let sparse = times_axis_rotation(&p, axis, c, s);
                for (a, b) in sparse.0.iter().zip(full.0) {
                    assert!(
                        a.to_bits() == b.to_bits() || (*a == 0.0 && b == 0.0),
                        "{p:?} {axis}"
                    );
                }
            }
        }
    }

    /// A group's free flow gives each rotor the bits of its flow alone, with
    /// its own moments: a spherical top (the exact flow or the sweep), an
    /// asymmetric, a symmetric and a linear top together, for both momentum
    /// variables and one or two substeps.
    #[test]
    fn a_group_flows_each_rotor_as_alone() {
        let moments = [
            Vector3::new(1.5, 1.5, 1.5),
            Vector3::new(1.0, 2.0, 3.5),
            Vector3::new(2.0, 2.0, 0.7),
            Vector3::new(0.0, 1.5, 1.5),
        ];
        let q: [Quat; 4] = std::array::from_fn(|k| {
            let k = k as f64;
            Quat::new(0.4 + k, -0.3, 0.8 - k, 0.1 * k)
                .try_normalize()
                .unwrap()
        });
        let l: [Vector3<f64>; 4] =
            std::array::from_fn(|k| Vector3::new(0.7, -1.3 + k as f64, 0.4 * k as f64));
        let p: [Quat; 4] = std::array::from_fn(|k| q[k] * Quat::pure(&l[k]) * 2.0);
        fn check<M: BodyMomentum + Copy + std::fmt::Debug>(
            q: [Quat; 4],
            m: [M; 4],
            moments: &[Vector3<f64>; 4],
            bits: impl Fn(&M) -> Vec<u64>,
        ) {
            for spherical in [SphericalTops::Exact, SphericalTops::Split] {
                for substeps in [1, 2] {
                    let (mut q4, mut m4) = (q, m);
                    free_flow(
                        &mut q4,
                        &mut m4,
                        moments,
                        spherical,
                        [2, 1, 0],
                        substeps,
                        0.37,
                    );
                    for k in 0..4 {
                        let (mut q1, mut m1) = ([q[k]], [m[k]]);
                        let one = [moments[k]];
                        free_flow(&mut q1, &mut m1, &one, spherical, [2, 1, 0], substeps, 0.37);
                        assert_ne!(q1[0], q[k], "rotor {k} turned");
                        let quat_bits = |q: &Quat| q.0.map(f64::to_bits);
                        assert_eq!(quat_bits(&q4[k]), quat_bits(&q1[0]), "rotor {k}");
                        assert_eq!(bits(&m4[k]), bits(&m1[0]), "rotor {k}");
                    }
                }
            }
        }
        check(q, p, &moments, |p: &Quat| p.0.map(f64::to_bits).to_vec());
        check(q, l, &moments, |l: &Vector3<f64>| {
            l.iter().map(|x| x.to_bits()).collect()
        });
    }

    /// One axis flow conserves the space-fixed angular momentum and matches
    /// eq 10 for a constant `w_b` along the axis; both momentum forms agree.
    #[test]
    fn axis_flow_keeps_space_momentum_and_agrees_between_forms() {
        let q0 = Quat::new(0.4, -0.3, 0.8, 0.1).try_normalize().unwrap();
        let l_body = Vector3::new(0.7, -1.3, 0.4);
        let inertia = Vector3::new(1.0, 2.0, 3.5);
        let (mut q_l, mut l) = (q0, l_body);
        let mut q_p = q0;
        let mut p = q0 * Quat::pure(&l_body) * 2.0;
        for axis in 0..3 {
            rotate_about_body_axis(&mut q_l, &mut l, axis, inertia[axis], 0.37);
            rotate_about_body_axis(&mut q_p, &mut p, axis, inertia[axis], 0.37);
        }
        let l_space_before = q0.body_to_space(&l_body);
        assert!((q_l.body_to_space(&l) - l_space_before).norm() < 1e-14);
        assert!((q_l - q_p).norm() < 1e-14);
        assert!((p.angular_momentum_body(&q_p) - l).norm() < 1e-14);
    }

    /// A zero moment of inertia leaves the rotor untouched about that axis.
    #[test]
    fn zero_moment_axis_is_skipped() {
        let mut q = Quat::IDENTITY;
        let mut l = Vector3::new(1.0, 2.0, 3.0);
        rotate_about_body_axis(&mut q, &mut l, 2, 0.0, 1.0);
        assert_eq!(q, Quat::IDENTITY);
        assert_eq!(l, Vector3::new(1.0, 2.0, 3.0));
    }
}
