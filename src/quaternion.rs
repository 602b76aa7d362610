//! Quaternions and the orientation conventions of the whole crate.
//!
//! # Conventions (stated once; every statement is tested in `tests/conventions.rs`)
//!
//! * **Component order.** `Quat([q0, q1, q2, q3])`, scalar first, as in eq 1 of
//!   Allen's note: `Q = (q0, q)` with `q = (q1, q2, q3)`.
//! * **Product.** The Hamilton product
//!   `P*Q = (p0 q0 - p.q, p0 q + q0 p + p x q)`.
//!   The note's eq 2 prints `- p x q`; with that sign eqs 7, 9 and 10 contradict
//!   each other (ERRATA.md, row eq 2).
//! * **Orientation.** A unit quaternion `Q` is the orientation of a rotor. Its
//!   matrix `A(Q)` of eq 7 maps **space-fixed to body-fixed** components,
//!   `r_b = A r_s` (eq 6). Its transpose `R(Q) = A(Q)^T`
//!   ([`Quat::body_to_space_matrix`]) maps body to space, `r_s = R r_b`, and is
//!   the active rotation of the Hamilton quaternion: `R(Q) v = vec(Q*(0,v)*Q~)`.
//!   `Q` and `-Q` give the same `A` (the double cover).
//! * **Sandwich (eq 9).** `R_b = Q~ * R_s * Q` and `R_s = Q * R_b * Q~` for
//!   pure quaternions `R = (0, r)`; `Q~` is the conjugate of eq 3.
//! * **Angular velocity (eq 10).** `Q' = 1/2 Q*(0, w_b) = 1/2 (0, w_s)*Q`, so
//!   `w_b = 2 vec(Q~*Q')` and `w_s = 2 vec(Q'*Q~)`.
//! * **Euler angles (eq 8).** Goldstein's y-convention `(phi, theta, psi)`:
//!   `A = Z(psi) Y(theta) Z(phi)` with passive axis rotations, i.e.
//!   `R = Rz(phi) Ry(theta) Rz(psi)` (intrinsic z-y'-z'' active). Ranges
//!   returned: `theta` in `[0, pi]`, `phi`, `psi` in `(-pi, pi]`. At the
//!   singularities only `phi + psi` (`q1 = q2 = 0`, theta = 0) or `psi - phi`
//!   (`q0 = q3 = 0`, theta = pi) is defined, and the inverse splits it evenly
//!   (`phi = psi` or `phi = -psi`); off them, however close, both angles are
//!   recovered from the small components, which keep full relative precision.
//! * **Rotation vectors.** `exp(v)` is the rotation by `|v|` about `v / |v|`
//!   (right-handed, active), `Quat::exp(v) = (cos |v|/2, sin(|v|/2) v/|v|)`.
//! * **nalgebra.** `nalgebra::Quaternion::new(w, i, j, k)` takes the scalar
//!   first but stores `[i, j, k, w]`; its `UnitQuaternion` and `Rotation3` are
//!   active rotations, so they equal `R(Q)`, body to space.

use nalgebra::{Matrix3, Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};
use std::ops::{Add, AddAssign, Index, Mul, Neg, Sub};

/// Below this rotation angle (rad) [`Quat::exp`] sums the series of
/// `cos(h)` and `sin(h)/h`, `h` half the angle, over powers of `h^2` up to
/// `h^8` ([`COS_SERIES`], [`SINC_SERIES`]): the first omitted terms,
/// `h^10/10!` and `h^10/11!`, are below 3e-20 there, far under rounding.
/// (A time step turns a rotor by `|w| dt`, about 0.01 rad in the lattice
/// scenes.) Few terms keep the chain of dependent operations short.
const EXP_SERIES_MAX_ANGLE: f64 = 0.1;
/// `(-1)^k / (2k)!`, k = 0..4: `cos(h)` as a polynomial in `h^2`.
const COS_SERIES: [f64; 5] = [1.0, -1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40_320.0];
/// `(-1)^k / (2k+1)!`, k = 0..4: `sin(h)/h` as a polynomial in `h^2`.
const SINC_SERIES: [f64; 5] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
];

/// The polynomial `c[0] + c[1] h2 + ... + c[4] h2^4` (Horner's rule).
#[inline(always)]
fn series(c: &[f64; 5], h2: f64) -> f64 {
    c[..4].iter().rev().fold(c[4], |sum, &c| sum * h2 + c)
}

/// `cos(angle / 2)` and `sin(angle / 2)`: the series of [`Quat::exp`]
/// below `EXP_SERIES_MAX_ANGLE` (exact to rounding there, cheaper than
/// libm's `sin_cos`), libm above.
#[inline]
pub(crate) fn half_angle_cos_sin(angle: f64) -> (f64, f64) {
    if angle.abs() < EXP_SERIES_MAX_ANGLE {
        let h2 = 0.25 * angle * angle;
        (
            series(&COS_SERIES, h2),
            0.5 * angle * series(&SINC_SERIES, h2),
        )
    } else {
        let (s, c) = (0.5 * angle).sin_cos();
        (c, s)
    }
}

/// A quaternion `(q0, q1, q2, q3)`, scalar first (eq 1). Not necessarily unit.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Quat(pub [f64; 4]);

impl Quat {
    /// The identity `(1, 0, 0, 0)` (the element `Q~*Q` of eq 4 for unit `Q`).
    pub const IDENTITY: Quat = Quat([1.0, 0.0, 0.0, 0.0]);
    /// The zero quaternion.
    pub const ZERO: Quat = Quat([0.0; 4]);

    /// Builds `(q0, q1, q2, q3)`.
    pub const fn new(q0: f64, q1: f64, q2: f64, q3: f64) -> Self {
        Quat([q0, q1, q2, q3])
    }

    /// The pure quaternion `(0, v)`, as `Omega = (0, w)` and `R = (0, r)` of the note.
    #[inline]
    pub fn pure(v: &Vector3<f64>) -> Self {
        Quat([0.0, v.x, v.y, v.z])
    }

    /// The scalar part `q0`.
    #[inline]
    pub fn scalar(&self) -> f64 {
        self.0[0]
    }

    /// The vector part `(q1, q2, q3)`.
    #[inline]
    pub fn vector(&self) -> Vector3<f64> {
        Vector3::new(self.0[1], self.0[2], self.0[3])
    }

    /// The conjugate `(q0, -q)` (eq 3).
    #[inline]
    pub fn conjugate(&self) -> Self {
        let [a, b, c, d] = self.0;
        Quat([a, -b, -c, -d])
    }

    /// The four-dimensional dot product `p0 q0 + p.q`.
    #[inline]
    pub fn dot(&self, other: &Quat) -> f64 {
        self.0.iter().zip(other.0.iter()).map(|(a, b)| a * b).sum()
    }

    /// `|Q|^2 = q0^2 + q1^2 + q2^2 + q3^2` (eq 5).
    #[inline]
    pub fn norm_squared(&self) -> f64 {
        self.dot(self)
    }

    /// `|Q|`.
    #[inline]
    pub fn norm(&self) -> f64 {
        self.norm_squared().sqrt()
    }

    /// `Q / |Q|` for any finite nonzero `Q`, or `None` for a zero or
    /// non-finite one. When `|Q|^2` overflows or underflows (|Q| beyond
    /// about 1e154 or below 1e-154), `Q` is first divided by its largest
    /// component's magnitude, so the result is a unit quaternion all the same.
    pub fn try_normalize(&self) -> Option<Self> {
        let n2 = self.norm_squared();
        if n2.is_normal() {
            return Some(*self * (1.0 / n2.sqrt()));
        }
        let largest = self.0.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        if !(largest > 0.0 && largest.is_finite() && self.is_finite()) {
            return None;
        }
        let scaled = Quat(self.0.map(|x| x / largest));
        Some(scaled * (1.0 / scaled.norm()))
    }

    /// True when all four components are finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|x| x.is_finite())
    }

    /// The matrix `A(Q)` of eq 7: space-fixed to body-fixed, `r_b = A r_s`.
    /// For a non-unit `Q` it is `|Q|^2` times a rotation.
    ///
    /// ```
    /// use quatrot::Quat;
    /// use nalgebra::Vector3;
    /// // Turned by +90 degrees about space z, the body x axis points along space y.
    /// let q = Quat::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    /// let r_b = q.space_to_body_matrix() * Vector3::y();
    /// assert!((r_b - Vector3::x()).norm() < 1e-15);
    /// // The double cover: -Q is the same orientation.
    /// assert_eq!(q.space_to_body_matrix(), (-q).space_to_body_matrix());
    /// ```
    pub fn space_to_body_matrix(&self) -> Matrix3<f64> {
        let [q0, q1, q2, q3] = self.0;
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

    /// `R(Q) = A(Q)^T`: body-fixed to space-fixed, `r_s = R r_b`.
    pub fn body_to_space_matrix(&self) -> Matrix3<f64> {
        self.space_to_body_matrix().transpose()
    }

    /// The partial derivatives `dA/dq_k`, k = 0..3, of the matrix of eq 7 (each
    /// entry of `A` is a quadratic form in `Q`, so each derivative is linear).
    /// Used for the quaternion gradient of eq 14.
    pub fn space_to_body_matrix_derivatives(&self) -> [Matrix3<f64>; 4] {
        let [q0, q1, q2, q3] = self.0;
        let d = |a: f64, b: f64, c: f64, e: f64, f: f64, g: f64, h: f64, i: f64, j: f64| {
            Matrix3::new(a, b, c, e, f, g, h, i, j) * 2.0
        };
        [
            d(q0, q3, -q2, -q3, q0, q1, q2, -q1, q0),
            d(q1, q2, q3, q2, -q1, q0, q3, -q0, -q1),
            d(-q2, q1, -q0, q1, q2, q3, q0, q3, -q2),
            d(-q3, q0, q1, -q0, -q3, q2, q1, q2, q3),
        ]
    }

    /// Space-fixed components of a body-fixed vector, `R(Q) v` (inverse of eq 6).
    pub fn body_to_space(&self, v_body: &Vector3<f64>) -> Vector3<f64> {
        self.body_to_space_matrix() * v_body
    }

    /// Body-fixed components of a space-fixed vector, `A(Q) v` (eq 6).
    pub fn space_to_body(&self, v_space: &Vector3<f64>) -> Vector3<f64> {
        self.space_to_body_matrix() * v_space
    }

    /// `Q' = 1/2 Q*(0, w_b)` (eq 10, body form).
    #[inline]
    pub fn q_dot_from_omega_body(&self, omega_body: &Vector3<f64>) -> Quat {
        (*self * Quat::pure(omega_body)) * 0.5
    }

    /// `Q' = 1/2 (0, w_s)*Q` (eq 10, space form).
    #[inline]
    pub fn q_dot_from_omega_space(&self, omega_space: &Vector3<f64>) -> Quat {
        (Quat::pure(omega_space) * *self) * 0.5
    }

    /// `w_b = 2 vec(Q~*Q')/|Q|^2`, the inverse of eq 10 (body form), exact for
    /// a non-unit `Q` too (scaling `Q` and `Q'` together leaves it unchanged).
    #[inline]
    pub fn omega_body_from_q_dot(&self, q_dot: &Quat) -> Vector3<f64> {
        self.omega_body_from_scaled_q_dot(q_dot, 1.0)
    }

    /// [`Quat::omega_body_from_q_dot`] from `h Q'` (the first scaled
    /// derivative of a Gear scheme with step `h`), dividing `h` out.
    #[inline]
    pub fn omega_body_from_scaled_q_dot(&self, h_q_dot: &Quat, h: f64) -> Vector3<f64> {
        (self.conjugate() * *h_q_dot).vector() * (2.0 / (h * self.norm_squared()))
    }

    /// `w_s = 2 vec(Q'*Q~)/|Q|^2`, the inverse of eq 10 (space form), exact
    /// for a non-unit `Q` too.
    #[inline]
    pub fn omega_space_from_q_dot(&self, q_dot: &Quat) -> Vector3<f64> {
        (*q_dot * self.conjugate()).vector() * (2.0 / self.norm_squared())
    }

    /// The unit quaternion of Euler angles `(phi, theta, psi)` in the y-convention (eq 8).
    ///
    /// ```
    /// use quatrot::Quat;
    /// // theta = 0: a turn by phi + psi about z; only the sum is defined, and the
    /// // inverse splits it evenly.
    /// let q = Quat::from_euler_y(0.2, 0.0, 0.4);
    /// let (phi, theta, psi) = q.to_euler_y();
    /// assert_eq!(theta, 0.0);
    /// assert!((phi - 0.3).abs() < 1e-15 && (psi - 0.3).abs() < 1e-15);
    /// // -Q gives the same angles.
    /// let (phi_neg, _, psi_neg) = (-q).to_euler_y();
    /// assert!((phi_neg - phi).abs() < 1e-15 && (psi_neg - psi).abs() < 1e-15);
    /// ```
    pub fn from_euler_y(phi: f64, theta: f64, psi: f64) -> Quat {
        let (s_t, c_t) = (0.5 * theta).sin_cos();
        let (s_sum, c_sum) = (0.5 * (psi + phi)).sin_cos();
        let (s_dif, c_dif) = (0.5 * (psi - phi)).sin_cos();
        Quat([c_sum * c_t, s_dif * s_t, c_dif * s_t, s_sum * c_t])
    }

    /// Euler angles `(phi, theta, psi)` of a unit quaternion in the y-convention,
    /// inverting eq 8; accurate at and near `theta = 0` and `theta = pi` (see the
    /// module conventions for the split of the undefined angle there).
    pub fn to_euler_y(&self) -> (f64, f64, f64) {
        let [q0, q1, q2, q3] = self.0;
        let theta = 2.0 * (q1.hypot(q2)).atan2(q0.hypot(q3));
        let sum = 2.0 * q3.atan2(q0); // psi + phi
        let dif = 2.0 * q1.atan2(q2); // psi - phi
        (
            wrap_angle(0.5 * (sum - dif)),
            theta,
            wrap_angle(0.5 * (sum + dif)),
        )
    }

    /// The rotation by `angle` (radians) about the unit vector `axis` (active,
    /// right-handed): `(cos angle/2, sin(angle/2) axis)`.
    ///
    /// ```
    /// use quatrot::Quat;
    /// use nalgebra::Vector3;
    /// // The zero angle is the identity, whatever the axis; it has no axis back.
    /// let q = Quat::from_axis_angle(&Vector3::x_axis(), 0.0);
    /// assert_eq!(q, Quat::IDENTITY);
    /// assert!(matches!(q.to_axis_angle(), (None, a) if a == 0.0));
    /// // A full turn is -Q of the identity: the same orientation.
    /// let full = Quat::from_axis_angle(&Vector3::x_axis(), 2.0 * std::f64::consts::PI);
    /// assert!(full.angle_to(&Quat::IDENTITY) < 1e-7);
    /// ```
    pub fn from_axis_angle(axis: &Unit<Vector3<f64>>, angle: f64) -> Quat {
        let (s, c) = (0.5 * angle).sin_cos();
        Quat([c, s * axis.x, s * axis.y, s * axis.z])
    }

    /// Axis and angle of a unit quaternion, with the angle in `[0, pi]`; the axis
    /// is `None` for the identity rotation (angle 0).
    pub fn to_axis_angle(&self) -> (Option<Unit<Vector3<f64>>>, f64) {
        let q = if self.0[0] < 0.0 { -*self } else { *self };
        let v = q.vector();
        let s = v.norm();
        let angle = 2.0 * s.atan2(q.0[0]);
        (Unit::try_new(v, 0.0), angle)
    }

    /// The exponential map: the unit quaternion of the rotation vector `v`
    /// (rotation by `|v|` about `v`), accurate for small `|v|`.
    ///
    /// ```
    /// use quatrot::Quat;
    /// use nalgebra::Vector3;
    /// assert_eq!(Quat::exp(&Vector3::zeros()), Quat::IDENTITY);
    /// let v = Vector3::new(1e-9, -2e-9, 0.5e-9);
    /// assert!((Quat::exp(&v).ln() - v).norm() < 1e-24);
    /// ```
    pub fn exp(v: &Vector3<f64>) -> Quat {
        let angle_squared = v.norm_squared();
        // cos(|v|/2) and sin(|v|/2)/|v|: their series below EXP_SERIES_MAX_ANGLE
        // (exact to rounding there, cheaper than sin and cos, and no quotient
        // losing accuracy as |v| -> 0), libm above.
        let (cos_half, sinc) = if angle_squared < EXP_SERIES_MAX_ANGLE * EXP_SERIES_MAX_ANGLE {
            let h2 = 0.25 * angle_squared;
            (series(&COS_SERIES, h2), 0.5 * series(&SINC_SERIES, h2))
        } else {
            let angle = angle_squared.sqrt();
            let (sin_half, cos_half) = (0.5 * angle).sin_cos();
            (cos_half, sin_half / angle)
        };
        Quat([cos_half, sinc * v.x, sinc * v.y, sinc * v.z])
    }

    /// The logarithm: the rotation vector of a unit quaternion, with `|v|` in `[0, pi]`.
    pub fn ln(&self) -> Vector3<f64> {
        match self.to_axis_angle() {
            (Some(axis), angle) => axis.into_inner() * angle,
            (None, _) => Vector3::zeros(),
        }
    }

    /// The unit quaternion (`q0 >= 0`) of a body-to-space rotation matrix `R`,
    /// or `None` unless `R` is a proper rotation to within `tolerance`
    /// (largest entry of `|R^T R - I|` and `|det R - 1|`). For checked input,
    /// e.g. from Python; trusted rotations convert with `From<Rotation3>`.
    pub fn from_body_to_space_matrix(r: &Matrix3<f64>, tolerance: f64) -> Option<Quat> {
        let orthogonality = (r.transpose() * r - Matrix3::identity()).amax();
        let proper = (r.determinant() - 1.0).abs();
        (r.iter().all(|x| x.is_finite()) && orthogonality <= tolerance && proper <= tolerance)
            .then(|| Quat::from(Rotation3::from_matrix_unchecked(*r)))
    }

    /// The rotation angle between two unit orientations, in `[0, pi]`,
    /// insensitive to the double cover: `2 acos |P.Q|`, computed stably as
    /// `4 atan2(min(|P-Q|, |P+Q|), max(|P-Q|, |P+Q|))`.
    pub fn angle_to(&self, other: &Quat) -> f64 {
        let d = (*self - *other).norm();
        let s = (*self + *other).norm();
        4.0 * d.min(s).atan2(d.max(s))
    }
}

/// Wraps an angle into `(-pi, pi]`.
fn wrap_angle(a: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let w = (a + pi).rem_euclid(2.0 * pi) - pi;
    if w <= -pi {
        w + 2.0 * pi
    } else {
        w
    }
}

// The arithmetic below and the small methods above are `#[inline]`: called
// from generic integrator code compiled in other codegen units, they were
// otherwise not inlined (a call per quaternion addition in the predictor).

/// The Hamilton product (corrected eq 2).
impl Mul for Quat {
    type Output = Quat;
    #[inline]
    fn mul(self, q: Quat) -> Quat {
        let [p0, p1, p2, p3] = self.0;
        let [q0, q1, q2, q3] = q.0;
        Quat([
            p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
            p0 * q1 + q0 * p1 + p2 * q3 - p3 * q2,
            p0 * q2 + q0 * p2 + p3 * q1 - p1 * q3,
            p0 * q3 + q0 * p3 + p1 * q2 - p2 * q1,
        ])
    }
}

impl Mul<f64> for Quat {
    type Output = Quat;
    #[inline]
    fn mul(self, s: f64) -> Quat {
        Quat(self.0.map(|x| x * s))
    }
}

impl Add for Quat {
    type Output = Quat;
    #[inline]
    fn add(self, o: Quat) -> Quat {
        Quat(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}

impl AddAssign for Quat {
    #[inline]
    fn add_assign(&mut self, o: Quat) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

impl Sub for Quat {
    type Output = Quat;
    #[inline]
    fn sub(self, o: Quat) -> Quat {
        Quat(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}

impl Neg for Quat {
    type Output = Quat;
    #[inline]
    fn neg(self) -> Quat {
        Quat(self.0.map(|x| -x))
    }
}

impl Index<usize> for Quat {
    type Output = f64;
    fn index(&self, i: usize) -> &f64 {
        &self.0[i]
    }
}

/// To nalgebra: the constructor takes `(w, i, j, k)`; storage is `[i, j, k, w]`.
impl From<Quat> for Quaternion<f64> {
    fn from(q: Quat) -> Self {
        Quaternion::new(q.0[0], q.0[1], q.0[2], q.0[3])
    }
}

impl From<Quaternion<f64>> for Quat {
    fn from(q: Quaternion<f64>) -> Self {
        Quat([q.w, q.i, q.j, q.k])
    }
}

/// To nalgebra's unit quaternion (normalised): the body-to-space rotation `R(Q)`.
impl From<Quat> for UnitQuaternion<f64> {
    fn from(q: Quat) -> Self {
        UnitQuaternion::from_quaternion(q.into())
    }
}

impl From<UnitQuaternion<f64>> for Quat {
    fn from(q: UnitQuaternion<f64>) -> Self {
        q.into_inner().into()
    }
}

/// To nalgebra's rotation matrix: `R(Q) = A(Q)^T`, body to space.
impl From<Quat> for Rotation3<f64> {
    fn from(q: Quat) -> Self {
        UnitQuaternion::from(q).to_rotation_matrix()
    }
}

/// From a rotation matrix (body to space) to the unit quaternion with `q0 >= 0`.
impl From<Rotation3<f64>> for Quat {
    fn from(r: Rotation3<f64>) -> Self {
        let q = Quat::from(UnitQuaternion::from_rotation_matrix(&r));
        if q.0[0] < 0.0 {
            -q
        } else {
            q
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Doc-level sanity: the double cover gives one matrix, and the identity is neutral.
    #[test]
    fn double_cover_and_identity() {
        let q = Quat::new(0.5, -0.5, 0.5, 0.5);
        assert_eq!(q.space_to_body_matrix(), (-q).space_to_body_matrix());
        assert_eq!(Quat::IDENTITY * q, q);
        assert_eq!(q * Quat::IDENTITY, q);
    }

    /// Every finite nonzero quaternion normalises to a unit one, the tiny
    /// and the huge too (their squared norm underflows or overflows); an
    /// ordinary one gives exactly `Q * (1 / |Q|)`; zero and non-finite ones
    /// give `None`.
    #[test]
    fn every_finite_nonzero_quaternion_normalises() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let cases = [
            (Quat::new(1e308, 1e308, 0.0, 0.0), [h, h, 0.0, 0.0]),
            (Quat::new(-1e300, 0.0, 0.0, 1e300), [-h, 0.0, 0.0, h]),
            (Quat::new(1e-300, 0.0, 0.0, 0.0), [1.0, 0.0, 0.0, 0.0]),
            (Quat::new(0.0, 5e-324, 0.0, -5e-324), [0.0, h, 0.0, -h]),
            (Quat::new(3e-160, 4e-160, 0.0, 0.0), [0.6, 0.8, 0.0, 0.0]),
        ];
        for (q, unit) in cases {
            let n = q.try_normalize().expect("finite and nonzero");
            for (a, b) in n.0.iter().zip(unit) {
                assert!((a - b).abs() <= 2.0 * f64::EPSILON, "{q:?}: {n:?}");
            }
        }
        let q = Quat::new(0.3, -0.5, 0.6, 0.2);
        assert_eq!(q.try_normalize(), Some(q * (1.0 / q.norm())));
        for bad in [
            Quat::new(0.0, 0.0, 0.0, 0.0),
            Quat::new(f64::NAN, 1.0, 0.0, 0.0),
            Quat::new(f64::INFINITY, 1.0, 0.0, 0.0),
        ] {
            assert_eq!(bad.try_normalize(), None, "{bad:?}");
        }
    }

    /// `wrap_angle` maps every angle to the one in `(-pi, pi]` that differs
    /// from it by a multiple of `2 pi`, the ends included: `-pi` becomes `pi`.
    #[test]
    fn angles_wrap_into_the_half_open_interval() {
        use std::f64::consts::PI;
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(-PI), PI);
        assert_eq!(wrap_angle(0.0), 0.0);
        for k in -3..=3 {
            for a in [-3.0, -1.0, 0.25, 2.5, 3.1] {
                let w = wrap_angle(a + 2.0 * PI * f64::from(k));
                assert!(w > -PI && w <= PI, "{w}");
                assert!((w - a).abs() < 1e-14, "{a} + {k} turns wrapped to {w}");
            }
        }
    }

    /// The series branch of `exp` agrees with libm's `sin` and `cos` to a few
    /// ulps at every angle below its threshold and across it, and stays unit.
    #[test]
    fn exp_series_matches_libm() {
        // Both sides are within about one ulp of the true values.
        const ULPS: f64 = 4.0 * f64::EPSILON;
        let axis = Vector3::new(0.48, -0.6, 0.64);
        let mut angle = 1e-9;
        while angle < 2.0 * EXP_SERIES_MAX_ANGLE {
            let v = axis * angle;
            let half = 0.5 * angle;
            let libm = Quat::new(
                half.cos(),
                half.sin() * axis.x,
                half.sin() * axis.y,
                half.sin() * axis.z,
            );
            let q = Quat::exp(&v);
            for k in 0..4 {
                let tolerance = ULPS * libm.0[k].abs().max(f64::MIN_POSITIVE);
                assert!(
                    (q.0[k] - libm.0[k]).abs() <= tolerance,
                    "angle {angle}, k = {k}"
                );
            }
            assert!((q.norm_squared() - 1.0).abs() <= ULPS, "angle {angle}");
            angle *= 1.07;
        }
    }

    /// `half_angle_cos_sin` is libm's `cos` and `sin` of half the angle to
    /// about an ulp, below, at and above `EXP_SERIES_MAX_ANGLE`, for angles
    /// of either sign.
    #[test]
    fn half_angle_series_matches_libm() {
        const ULPS: f64 = 4.0 * f64::EPSILON;
        let mut angle = 1e-9;
        while angle < 4.0 * EXP_SERIES_MAX_ANGLE {
            for a in [angle, -angle] {
                let (c, s) = half_angle_cos_sin(a);
                let (libm_s, libm_c) = (0.5 * a).sin_cos();
                assert!((c - libm_c).abs() <= ULPS * libm_c.abs(), "cos, angle {a}");
                assert!((s - libm_s).abs() <= ULPS * libm_s.abs(), "sin, angle {a}");
            }
            angle *= 1.07;
        }
        assert_eq!(half_angle_cos_sin(0.0), (1.0, 0.0));
        let above = 1.5 * EXP_SERIES_MAX_ANGLE;
        let (s, c) = (0.5 * above).sin_cos();
        assert_eq!(half_angle_cos_sin(above), (c, s));
    }

    /// The derivative matrices agree with central differences of eq 7.
    #[test]
    fn matrix_derivatives_match_central_differences() {
        let q = Quat::new(0.3, -0.7, 0.2, 0.6);
        let d = q.space_to_body_matrix_derivatives();
        for (k, dk) in d.iter().enumerate() {
            let h = 1e-6;
            let mut qp = q;
            let mut qm = q;
            qp.0[k] += h;
            qm.0[k] -= h;
            let fd = (qp.space_to_body_matrix() - qm.space_to_body_matrix()) / (2.0 * h);
            assert!((fd - dk).norm() < 1e-9, "k = {k}");
        }
    }
}
