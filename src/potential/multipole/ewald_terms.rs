//! The three parts of the Ewald sum for point dipoles and Buckingham
//! quadrupoles, as fields at a target site (the conjugates `E = -dV/dmu`
//! and `W = dV/dTheta` of [`super::kernels`]).
//!
//! A source at `r_s` with dipole `mu` and traceless `Theta` has the
//! potential `phi(r) = (-mu.grad + 1/3 Theta:grad grad) g(r - r_s)` with
//! `g = 1/r`, and a target feels `E = -grad phi`, `W = 1/3 grad grad phi`.
//! Ewald splits `1/r = erfc(alpha r)/r + erf(alpha r)/r` (Smith, "Point
//! multipoles in the Ewald summation (revisited)", CCP5 Newsletter 46 (1998);
//! Aguado & Madden, J. Chem. Phys. 119, 7471 (2003); Laino & Hutter,
//! J. Chem. Phys. 129, 074102 (2008)):
//!
//! * real space: the same operators on `erfc(alpha r)/r`, whose derivatives
//!   are `r`-polynomials times Smith's radial functions `B_l`;
//! * reciprocal space: a source's mode `k` has the coefficient
//!   `c(k) = -i mu.k - 1/3 k.Theta.k`, `phi = (4 pi / V) sum_{k != 0}
//!   exp(-k^2 / 4 alpha^2) / k^2 c(k) exp(i k.(r - r_s))`, and its fields
//!   are `E = -i k phi`, `W = -1/3 k k^T phi`;
//! * self: the reciprocal sum includes each site's own smooth `erf(alpha r)/r`
//!   at `r = 0`, removed by `E_self = 4 alpha^3 / (3 sqrt(pi)) mu`,
//!   `W_self = -16 alpha^5 / (45 sqrt(pi)) Theta` (energy
//!   `-2 alpha^3 / (3 sqrt(pi)) mu^2 - 8 alpha^5 / (45 sqrt(pi)) Theta:Theta`);
//! * surface (vacuum only, de Leeuw, Perram & Smith 1980):
//!   `V = 2 pi |M|^2 / (3 V)`, so every site feels `E = -4 pi M / (3 V)`.

use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Smith's radial functions of `g(r) = erfc(alpha r) / r`:
/// `B_0 = g`, `B_l = [(2l - 1) B_{l-1} + (2 alpha^2)^l exp(-alpha^2 r^2) / (alpha sqrt(pi))] / r^2`,
/// so that `grad g = -r B_1`, `grad grad g = r r^T B_2 - I B_1`, and so on.
/// With `alpha = 0` they are the bare `(2l - 1)!! / r^(2l + 1)`.
pub(crate) fn radial(alpha: f64, r: f64) -> [f64; 5] {
    radial_functions(alpha, r)
}

/// [`radial`] for `l < L` (the mesh Ewald's site forces between quadrupoles
/// need `B_5`).
pub(crate) fn radial_functions<const L: usize>(alpha: f64, r: f64) -> [f64; L] {
    let inv_r2 = 1.0 / (r * r);
    let mut b = [0.0; L];
    if alpha == 0.0 {
        b[0] = 1.0 / r;
        for l in 1..L {
            b[l] = (2 * l - 1) as f64 * b[l - 1] * inv_r2;
        }
        return b;
    }
    let x = alpha * r;
    b[0] = libm::erfc(x) / r;
    let mut gauss = (-x * x).exp() / (alpha * PI.sqrt());
    for l in 1..L {
        gauss *= 2.0 * alpha * alpha;
        b[l] = ((2 * l - 1) as f64 * b[l - 1] + gauss) * inv_r2;
    }
    b
}

/// The fields at a target at offset `r = r_t - r_s` from a source with
/// dipole `mu` and traceless quadrupole `theta`, for the radial functions
/// `b` of [`radial`] at `|r|`: `(E, W)` with
/// `E = r (mu.r) B_2 - mu B_1 + 1/3 (r.Theta r) B_3 r - 2/3 (Theta r) B_2`,
/// `W = 1/3 [(mu.r) r r^T B_3 - ((mu.r) I + mu r^T + r mu^T) B_2]
///    + 1/9 [r r^T (r.Theta r) B_4 - (I (r.Theta r) + 2 (Theta r r^T + r (Theta r)^T)) B_3 + 2 Theta B_2]`.
pub(crate) fn pair_fields(
    r: &Vector3<f64>,
    b: &[f64; 5],
    mu: Option<&Vector3<f64>>,
    theta: Option<&Matrix3<f64>>,
) -> (Vector3<f64>, Matrix3<f64>) {
    let mut e = Vector3::zeros();
    let mut w = Matrix3::zeros();
    let rr = r * r.transpose();
    if let Some(mu) = mu {
        let mu_r = mu.dot(r);
        e += dipole_field(r, b, mu);
        let sym = mu * r.transpose() + r * mu.transpose();
        w += (rr * (mu_r * b[3]) - (Matrix3::identity() * mu_r + sym) * b[2]) / 3.0;
    }
    if let Some(theta) = theta {
        let theta_r = theta * r;
        let r_theta_r = r.dot(&theta_r);
        e += r * (r_theta_r * b[3] / 3.0) - theta_r * (2.0 / 3.0 * b[2]);
        let sym = theta_r * r.transpose() + r * theta_r.transpose();
        w += (rr * (r_theta_r * b[4]) - (Matrix3::identity() * r_theta_r + sym * 2.0) * b[3]
            + theta * (2.0 * b[2]))
            / 9.0;
    }
    (e, w)
}

/// The field `E = r (mu.r) B_2 - mu B_1` at offset `r` from a dipole `mu`.
#[inline]
pub(crate) fn dipole_field(r: &Vector3<f64>, b: &[f64; 5], mu: &Vector3<f64>) -> Vector3<f64> {
    r * (mu.dot(r) * b[2]) - mu * b[1]
}

/// A site's charge and dipole (zero when it has none), the sources and
/// targets of the pair pass of moving bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ChargeDipole {
    pub charge: f64,
    pub dipole: Vector3<f64>,
}

/// `E_self / mu` of the self term.
pub(crate) fn self_field_per_dipole(alpha: f64) -> f64 {
    4.0 * alpha.powi(3) / (3.0 * PI.sqrt())
}

/// `W_self / Theta` of the self term.
pub(crate) fn self_conjugate_per_quadrupole(alpha: f64) -> f64 {
    -16.0 * alpha.powi(5) / (45.0 * PI.sqrt())
}

/// The reciprocal-space weight `exp(-k^2 / 4 alpha^2) / k^2` of mode `k`.
pub(crate) fn mode_weight(alpha: f64, k2: f64) -> f64 {
    (-k2 / (4.0 * alpha * alpha)).exp() / k2
}

/// `E_surface / M = -4 pi / (3 V)` of the vacuum surface term, box volume `volume`.
pub(crate) fn surface_field_per_dipole(volume: f64) -> f64 {
    -4.0 * PI / (3.0 * volume)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `erfc(alpha r)/r` reproduce the gradient and
    /// Hessian forms `-r B_1` and `r r^T B_2 - I B_1` (step 1e-5: truncation
    /// ~1e-10, round-off ~1e-11).
    #[test]
    fn radial_functions_are_the_derivatives_of_the_damped_coulomb() {
        let (alpha, r) = (0.9, Vector3::new(0.7, -1.1, 0.4));
        let g = |x: &Vector3<f64>| libm::erfc(alpha * x.norm()) / x.norm();
        let b = radial(alpha, r.norm());
        let h = 1e-5;
        for a in 0..3 {
            let step = Vector3::from_fn(|i, _| if i == a { h } else { 0.0 });
            let fd = (g(&(r + step)) - g(&(r - step))) / (2.0 * h);
            assert!((fd + r[a] * b[1]).abs() < 1e-9, "{fd}");
            let grad = |x: &Vector3<f64>| -x * radial(alpha, x.norm())[1];
            let fd2 = (grad(&(r + step)) - grad(&(r - step))) / (2.0 * h);
            for c in 0..3 {
                let delta = if a == c { 1.0 } else { 0.0 };
                let exact = r[a] * r[c] * b[2] - delta * b[1];
                assert!((fd2[c] - exact).abs() < 1e-8, "{} {exact}", fd2[c]);
            }
        }
    }
}
