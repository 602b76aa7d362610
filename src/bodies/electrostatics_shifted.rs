//! The shifted-force truncation of charges and point dipoles (Allen &
//! Germano, Mol. Phys. 104, 3225 (2006); LAMMPS `pair_style
//! lj/sf/dipole/sf`): energy and force both vanish at the cutoff `r_c`, so
//! that pairs crossing it leave the total energy continuous.
//!
//! **Derivation.** A pair's energy is a sum of terms of rank `l`, an
//! angular factor in `r^ = r / r` times the radial `f_l(r) = 1 / r^(l+1)`:
//! `q_t q_s f_0` (`l = 0`), `(a.r^) f_1` with `a = q_t mu_s - q_s mu_t`
//! (`l = 1`), `(mu_t.mu_s - 3 (mu_t.r^)(mu_s.r^)) f_2` (`l = 2`), for `r =
//! r_t - r_s`. Each `f_l` is replaced by its shifted-force form
//! `f_l(r) - f_l(r_c) - (r - r_c) f_l'(r_c) = s_l(x) / r^(l+1)`, `x = r /
//! r_c`, with
//!
//! `s_l(x) = 1 - (l + 2) x^(l+1) + (l + 1) x^(l+2)`:
//! `s_0 = (1 - x)^2`, `s_1 = 1 - 3 x^2 + 2 x^3`, `s_2 = 1 - 4 x^3 + 3 x^4`,
//!
//! the factors of LAMMPS's `lj/sf/dipole/sf` (its `ecoul`, `pqfac`,
//! `bfac`), `s_l(1) = s_l'(1) = 0`. The forces and fields below are the
//! exact gradients of these energies (the tests check them by central
//! differences); the radial derivative `-d(s_l / r^(l+1))/dr = (l + 1) (1 -
//! x^(l+2)) / r^(l+2)` is LAMMPS's `afac = 1 - x^4` for `l = 2`.
//!
//! Both truncations reach the pair pass through `Factors`: the radial
//! factors at one distance, `Plain`'s bare `B_l` and
//! `ShiftedForceFactors`.

use crate::potential::multipole::{charge_dipole_force, dipole_field, radial, ChargeDipole};
use nalgebra::Vector3;

/// How a cutoff sum of charges and dipoles is truncated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ElectrostaticTruncation {
    /// The bare pair terms inside the cutoff (default; LAMMPS
    /// `lj/cut/dipole/cut`): the energy jumps as pairs cross it.
    #[default]
    Plain,
    /// Energy and force brought to zero at the cutoff (module doc; LAMMPS
    /// `lj/sf/dipole/sf`); charges and dipoles only.
    ShiftedForce,
}

crate::checks::named_choices!(ElectrostaticTruncation {
    "plain" => ElectrostaticTruncation::Plain,
    "shifted_force" => ElectrostaticTruncation::ShiftedForce,
});

/// A target's share of one pair: the potential `dU/dq_t`, the field `E =
/// -dU/dmu_t` and the force `-dU/dr_t`.
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq)]
struct PairResponse {
    pub potential: f64,
    pub field: Vector3<f64>,
    pub force: Vector3<f64>,
}

/// The radial factors of a truncation at one distance, and what a pair
/// takes from them.
pub(super) trait Factors {
    fn new(r2: f64, cutoff: f64) -> Self;
    /// The potential and field at offset `r` from a source.
    fn fields(&self, r: &Vector3<f64>, source: &ChargeDipole) -> (f64, Vector3<f64>);
    /// The force on a target at offset `r` from a source.
    fn force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64>;
    /// [`Factors::fields`]' field of a source without charge.
    fn dipole_field(&self, r: &Vector3<f64>, source: &ChargeDipole) -> Vector3<f64> {
        self.fields(r, source).1
    }
    /// [`Factors::force`] of sites without charges.
    fn dipole_force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        self.force(r, r2, target, source)
    }
}

/// The bare pair (LAMMPS `lj/cut/dipole/cut`): the radial functions of
/// `1/r`.
pub(super) struct Plain([f64; 5]);

impl Factors for Plain {
    #[inline(always)]
    fn new(r2: f64, _: f64) -> Self {
        Plain(radial(0.0, r2.sqrt()))
    }
    #[inline(always)]
    fn fields(&self, r: &Vector3<f64>, s: &ChargeDipole) -> (f64, Vector3<f64>) {
        let b = &self.0;
        (
            s.charge * b[0] + s.dipole.dot(r) * b[1],
            r * (s.charge * b[1]) + dipole_field(r, b, &s.dipole),
        )
    }
    #[inline(always)]
    fn force(
        &self,
        r: &Vector3<f64>,
        _: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        charge_dipole_force(r, &self.0, target, source)
    }
    #[inline(always)]
    fn dipole_field(&self, r: &Vector3<f64>, source: &ChargeDipole) -> Vector3<f64> {
        dipole_field(r, &self.0, &source.dipole)
    }
    /// `charge_dipole_force` with zero charges.
    #[inline(always)]
    fn dipole_force(
        &self,
        r: &Vector3<f64>,
        _: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        let (b, mu_t, mu_s) = (&self.0, &target.dipole, &source.dipole);
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        r * (mu_t.dot(mu_s) * b[2] - t_r * s_r * b[3]) + (mu_t * s_r + mu_s * t_r) * b[2]
    }
}

/// The shifted-force radial factors (module doc) at `r^2 < r_c^2`:
/// `s_l(x)` and the powers of `1/r` they multiply.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShiftedForceFactors {
    inv_r: f64,
    inv_r3: f64,
    inv_r5: f64,
    x2: f64,
    s: [f64; 3],
}

impl Factors for ShiftedForceFactors {
    /// The factors at squared distance `r2` for the cutoff `cutoff`.
    #[inline(always)]
    fn new(r2: f64, cutoff: f64) -> Self {
        let r = r2.sqrt();
        let inv_r = 1.0 / r;
        let (inv_r3, x) = (inv_r / r2, r / cutoff);
        let (x2, x3) = (x * x, x * x * x);
        ShiftedForceFactors {
            inv_r,
            inv_r3,
            inv_r5: inv_r3 / r2,
            x2,
            s: [
                (1.0 - x) * (1.0 - x),
                1.0 - 3.0 * x2 + 2.0 * x3,
                1.0 - 4.0 * x3 + 3.0 * x3 * x,
            ],
        }
    }

    /// The potential and field `(phi, E)` at offset `r` from a source.
    #[inline(always)]
    fn fields(&self, r: &Vector3<f64>, source: &ChargeDipole) -> (f64, Vector3<f64>) {
        let [s0, s1, s2] = self.s;
        let (q_s, mu_s) = (source.charge, &source.dipole);
        let s_r = mu_s.dot(r);
        (
            q_s * s0 * self.inv_r + s1 * s_r * self.inv_r3,
            r * (q_s * s1 * self.inv_r3 + 3.0 * s2 * s_r * self.inv_r5) - mu_s * (s2 * self.inv_r3),
        )
    }

    /// The force on a target at offset `r` (`|r|^2` the factors' `r2`)
    /// from a source.
    #[inline(always)]
    fn force(
        &self,
        r: &Vector3<f64>,
        r2: f64,
        target: &ChargeDipole,
        source: &ChargeDipole,
    ) -> Vector3<f64> {
        let ([_, s1, s2], x2) = (self.s, self.x2);
        let (inv_r3, inv_r5) = (self.inv_r3, self.inv_r5);
        let (q_t, q_s) = (target.charge, source.charge);
        let (mu_t, mu_s) = (&target.dipole, &source.dipole);
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        let a = mu_s * q_t - mu_t * q_s;
        // The force's component along r, over r.
        let radial = q_t * q_s * (1.0 - x2) * inv_r3
            + 3.0 * a.dot(r) * (1.0 - x2) * inv_r5
            + 3.0
                * inv_r5
                * ((1.0 - x2 * x2) * (mu_t.dot(mu_s) - 3.0 * t_r * s_r / r2)
                    - 2.0 * s2 * t_r * s_r / r2);
        r * radial - a * (s1 * inv_r3) + (mu_t * s_r + mu_s * t_r) * (3.0 * s2 * inv_r5)
    }
}

/// The shifted-force pair (module doc) of a target at offset `r = r_t -
/// r_s` (`|r| < cutoff`) from a source.
#[cfg(test)]
fn shifted_force_pair(
    r: &Vector3<f64>,
    cutoff: f64,
    target: &ChargeDipole,
    source: &ChargeDipole,
) -> PairResponse {
    let r2 = r.norm_squared();
    let factors = ShiftedForceFactors::new(r2, cutoff);
    let (potential, field) = factors.fields(r, source);
    PairResponse {
        potential,
        field,
        force: factors.force(r, r2, target, source),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of the pair energy at steps of 1e-6: errors
    /// ~1e-12 from the third derivative, ~1e-10 from round-off.
    const DIFFERENCE: f64 = 1e-8;

    fn pair() -> (ChargeDipole, ChargeDipole) {
        (
            ChargeDipole {
                charge: 0.7,
                dipole: Vector3::new(0.3, -0.8, 0.5),
            },
            ChargeDipole {
                charge: -1.2,
                dipole: Vector3::new(-0.6, 0.2, 0.9),
            },
        )
    }

    /// The pair energy `q_t phi + ... - mu_t.E`, bilinear in the target's
    /// charge and dipole.
    fn energy(r: &Vector3<f64>, cutoff: f64, t: &ChargeDipole, s: &ChargeDipole) -> f64 {
        let p = shifted_force_pair(r, cutoff, t, s);
        t.charge * p.potential - t.dipole.dot(&p.field)
    }

    /// The force is minus the gradient of the energy, the field minus its
    /// derivative in the target's dipole, the potential its derivative in
    /// the target's charge, and swapping target and source gives the same
    /// energy.
    #[test]
    fn force_field_and_potential_are_derivatives_of_the_energy() {
        let (t, s) = pair();
        let cutoff = 2.5;
        let h = 1e-6;
        for r in [Vector3::new(0.9, -0.4, 0.3), Vector3::new(1.2, 1.4, -1.1)] {
            let p = shifted_force_pair(&r, cutoff, &t, &s);
            // The central difference of the energy as `change(target, +-h)` alters the target.
            let derivative = |change: &dyn Fn(&mut ChargeDipole, f64)| {
                let at = |d: f64| {
                    let mut m = t;
                    change(&mut m, d);
                    energy(&r, cutoff, &m, &s)
                };
                (at(h) - at(-h)) / (2.0 * h)
            };
            for k in 0..3 {
                let mut step = Vector3::zeros();
                step[k] = h;
                let fd = -(energy(&(r + step), cutoff, &t, &s)
                    - energy(&(r - step), cutoff, &t, &s))
                    / (2.0 * h);
                assert!(
                    (p.force[k] - fd).abs() < DIFFERENCE,
                    "force {k}: {} vs {fd}",
                    p.force[k]
                );
                let fd = -derivative(&|m, d| m.dipole[k] += d);
                assert!(
                    (p.field[k] - fd).abs() < DIFFERENCE,
                    "field {k}: {} vs {fd}",
                    p.field[k]
                );
            }
            let fd = derivative(&|m, d| m.charge += d);
            assert!((p.potential - fd).abs() < DIFFERENCE);
            let swapped = energy(&-r, cutoff, &s, &t);
            assert!((energy(&r, cutoff, &t, &s) - swapped).abs() < 1e-14);
        }
    }

    /// Energy, force and field fall to zero at the cutoff (to the order of
    /// the distance left, `(1 - x)^2` for the energy, `1 - x` for the rest).
    #[test]
    fn energy_and_force_vanish_at_the_cutoff() {
        let (t, s) = pair();
        let direction = Vector3::new(0.48, -0.6, 0.64);
        let gap = 1e-6;
        let r = direction * (2.5 - gap);
        let p = shifted_force_pair(&r, 2.5, &t, &s);
        assert!(energy(&r, 2.5, &t, &s).abs() < 10.0 * gap * gap);
        assert!(p.force.norm() < 10.0 * gap && p.field.norm() < 10.0 * gap);
        assert!(p.potential.abs() < 10.0 * gap * gap);
    }

    /// Far inside the cutoff the terms tend to the bare ones: the energy of
    /// two dipoles at `r << r_c` against `(mu_t.mu_s - 3 (mu_t.r^)(mu_s.r^))
    /// / r^3` within the `4 (r / r_c)^3` of `s_2`.
    #[test]
    fn the_bare_dipole_pair_is_the_limit_of_a_large_cutoff() {
        let (mut t, mut s) = pair();
        (t.charge, s.charge) = (0.0, 0.0);
        let r = Vector3::new(0.9, -0.4, 0.3);
        let cutoff = 1e3;
        let d = r.norm();
        let bare = (t.dipole.dot(&s.dipole) - 3.0 * t.dipole.dot(&r) * s.dipole.dot(&r) / (d * d))
            / d.powi(3);
        let e = energy(&r, cutoff, &t, &s);
        assert!((e - bare).abs() < 5.0 * (d / cutoff).powi(3) * bare.abs());
    }
}
