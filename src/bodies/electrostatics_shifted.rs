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
//! Both truncations reach the pair pass through `Factors`, four pairs at
//! a time (the lanes of `super::lanes`): the radial factors at one
//! distance, `Plain`'s bare `B_l` and `ShiftedForceFactors`.

use crate::lanes::{Lanes, V4};
use crate::potential::multipole::ChargeDipole;
#[cfg(test)]
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

/// The charges and dipoles of four sites (zero where a site has none).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ChargeDipoles<T> {
    pub charge: T,
    pub dipole: V4<T>,
}

impl<T: Lanes> ChargeDipoles<T> {
    /// One site's in every lane.
    #[inline(always)]
    pub fn splat(site: &ChargeDipole) -> Self {
        ChargeDipoles {
            charge: T::splat(site.charge),
            dipole: V4::splat(&site.dipole),
        }
    }
}

/// The radial factors of a truncation at four distances, and what the
/// pairs take from them: separations `r = r_t - r_s` of targets from
/// sources, `r2 = |r|^2` within the cutoff (the lanes beyond it hold
/// values to be dropped).
pub(super) trait Factors<T: Lanes> {
    fn new(r2: T, cutoff: f64) -> Self;
    /// The potentials and fields at offsets `r` from the sources.
    fn fields(&self, r: &V4<T>, source: &ChargeDipoles<T>) -> (T, V4<T>);
    /// The forces on the targets.
    fn force(
        &self,
        r: &V4<T>,
        r2: T,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> V4<T>;
    /// [`Factors::fields`]' fields of sources without charge.
    #[inline(always)]
    fn dipole_field(&self, r: &V4<T>, source: &ChargeDipoles<T>) -> V4<T> {
        self.fields(r, source).1
    }
    /// [`Factors::force`] of sites without charges.
    #[inline(always)]
    fn dipole_force(
        &self,
        r: &V4<T>,
        r2: T,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> V4<T> {
        self.force(r, r2, target, source)
    }
}

/// The bare pair (LAMMPS `lj/cut/dipole/cut`): Smith's radial functions
/// of `1/r`, `B_0 = 1/r`, `B_l = (2l - 1) B_(l-1) / r^2` (`grad B_l = -r
/// B_(l+1)`), as `crate::potential::multipole`'s `radial` computes them
/// (but for rounding: `1/r^2` is `(1/r)^2` here, one division fewer), and
/// its `dipole_field`, in lanes, with the force of the pair energy in
/// [`Plain::force`]'s doc.
pub(super) struct Plain<T>([T; 4]);

impl<T: Lanes> Factors<T> for Plain<T> {
    #[inline(always)]
    fn new(r2: T, _: f64) -> Self {
        // One division: `1/r^2 = (1/r)^2`.
        let b0 = T::splat(1.0) / r2.sqrt();
        let inv_r2 = b0 * b0;
        let b1 = b0 * inv_r2;
        let b2 = b1 * 3.0 * inv_r2;
        Plain([b0, b1, b2, b2 * 5.0 * inv_r2])
    }
    /// `(q_s B_0 + (mu_s.r) B_1, q_s r B_1 + E_mu)`, `E_mu = r (mu_s.r) B_2
    /// - mu_s B_1`.
    #[inline(always)]
    fn fields(&self, r: &V4<T>, s: &ChargeDipoles<T>) -> (T, V4<T>) {
        let b = &self.0;
        (
            s.charge * b[0] + s.dipole.dot(r) * b[1],
            *r * (s.charge * b[1]) + self.dipole_field(r, s),
        )
    }
    /// `F = -grad U`, `U = q_t q_s B_0 + (q_t mu_s - q_s mu_t).r B_1 +
    /// (mu_t.mu_s) B_1 - (mu_t.r)(mu_s.r) B_2`.
    #[inline(always)]
    fn force(
        &self,
        r: &V4<T>,
        _: T,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> V4<T> {
        let b = &self.0;
        let (mu_t, mu_s) = (&target.dipole, &source.dipole);
        let a = *mu_s * target.charge - *mu_t * source.charge;
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        *r * (target.charge * source.charge * b[1] + (a.dot(r) + mu_t.dot(mu_s)) * b[2]
            - t_r * s_r * b[3])
            - a * b[1]
            + (*mu_t * s_r + *mu_s * t_r) * b[2]
    }
    #[inline(always)]
    fn dipole_field(&self, r: &V4<T>, source: &ChargeDipoles<T>) -> V4<T> {
        let (b, mu) = (&self.0, &source.dipole);
        *r * (mu.dot(r) * b[2]) - *mu * b[1]
    }
    /// [`Plain::force`] with zero charges.
    #[inline(always)]
    fn dipole_force(
        &self,
        r: &V4<T>,
        _: T,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> V4<T> {
        let (b, mu_t, mu_s) = (&self.0, &target.dipole, &source.dipole);
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        *r * (mu_t.dot(mu_s) * b[2] - t_r * s_r * b[3]) + (*mu_t * s_r + *mu_s * t_r) * b[2]
    }
}

/// The shifted-force radial factors (module doc) at `r^2 < r_c^2`:
/// `s_l(x)` and the powers of `1/r` they multiply.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShiftedForceFactors<T> {
    inv_r: T,
    inv_r3: T,
    inv_r5: T,
    x2: T,
    s: [T; 3],
}

impl<T: Lanes> Factors<T> for ShiftedForceFactors<T> {
    /// The factors at squared distances `r2` for the cutoff `cutoff`.
    #[inline(always)]
    fn new(r2: T, cutoff: f64) -> Self {
        // One division: the odd powers of `1/r` from `1/r` and `(1/r)^2`.
        let r = r2.sqrt();
        let one = T::splat(1.0);
        let inv_r = one / r;
        let inv_r2 = inv_r * inv_r;
        let (inv_r3, x) = (inv_r * inv_r2, r * T::splat(1.0 / cutoff));
        let (x2, x3) = (x * x, x * x * x);
        ShiftedForceFactors {
            inv_r,
            inv_r3,
            inv_r5: inv_r3 * inv_r2,
            x2,
            s: [
                (one - x) * (one - x),
                one - x2 * 3.0 + x3 * 2.0,
                one - x3 * 4.0 + x3 * 3.0 * x,
            ],
        }
    }

    /// The potentials and fields `(phi, E)` at offsets `r` from the sources.
    #[inline(always)]
    fn fields(&self, r: &V4<T>, source: &ChargeDipoles<T>) -> (T, V4<T>) {
        let [s0, s1, s2] = self.s;
        let (q_s, mu_s) = (source.charge, &source.dipole);
        let s_r = mu_s.dot(r);
        (
            q_s * s0 * self.inv_r + s1 * s_r * self.inv_r3,
            *r * (q_s * s1 * self.inv_r3 + s2 * 3.0 * s_r * self.inv_r5)
                - *mu_s * (s2 * self.inv_r3),
        )
    }

    /// The forces on the targets at offsets `r` (`|r|^2` the factors'
    /// `r2`) from the sources.
    #[inline(always)]
    fn force(
        &self,
        r: &V4<T>,
        r2: T,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> V4<T> {
        let ([_, s1, s2], x2) = (self.s, self.x2);
        let (inv_r3, inv_r5) = (self.inv_r3, self.inv_r5);
        let (q_t, q_s) = (target.charge, source.charge);
        let (mu_t, mu_s) = (&target.dipole, &source.dipole);
        let (t_r, s_r) = (mu_t.dot(r), mu_s.dot(r));
        let a = *mu_s * q_t - *mu_t * q_s;
        let one = T::splat(1.0);
        // The force's component along r, over r.
        let radial = q_t * q_s * (one - x2) * inv_r3
            + a.dot(r) * 3.0 * (one - x2) * inv_r5
            + inv_r5
                * 3.0
                * ((one - x2 * x2) * (mu_t.dot(mu_s) - t_r * 3.0 * s_r / r2)
                    - s2 * 2.0 * t_r * s_r / r2);
        *r * radial - a * (s1 * inv_r3) + (*mu_t * s_r + *mu_s * t_r) * (s2 * 3.0 * inv_r5)
    }
}

/// A target's share of one pair: the potential `dU/dq_t`, the field `E =
/// -dU/dmu_t` and the force `-dU/dr_t`.
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq)]
struct PairResponse {
    pub potential: f64,
    pub field: Vector3<f64>,
    pub force: Vector3<f64>,
}

/// The pair of truncation factors `F` (`ShiftedForceFactors` for the
/// shifted-force pair of the module doc) of a target at offset `r = r_t -
/// r_s` (`|r| < cutoff`) from a source, in every lane (the first read).
#[cfg(test)]
fn pair_response<F: Factors<crate::lanes::F4>>(
    r: &Vector3<f64>,
    cutoff: f64,
    target: &ChargeDipole,
    source: &ChargeDipole,
) -> PairResponse {
    let (r, target, source) = (
        V4::splat(r),
        ChargeDipoles::splat(target),
        ChargeDipoles::splat(source),
    );
    let r2 = r.dot(&r);
    let factors = F::new(r2, cutoff);
    let (potential, field) = factors.fields(&r, &source);
    PairResponse {
        potential: potential.0[0],
        field: field.to_vectors()[0],
        force: factors.force(&r, r2, &target, &source).to_vectors()[0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::F4;

    type ShiftedForce = ShiftedForceFactors<F4>;

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
    fn energy<F: Factors<F4>>(
        r: &Vector3<f64>,
        cutoff: f64,
        t: &ChargeDipole,
        s: &ChargeDipole,
    ) -> f64 {
        let p = pair_response::<F>(r, cutoff, t, s);
        t.charge * p.potential - t.dipole.dot(&p.field)
    }

    /// The force is minus the gradient of the energy, the field minus its
    /// derivative in the target's dipole, the potential its derivative in
    /// the target's charge, and swapping target and source gives the same
    /// energy, for both truncations; the dipoles-only forms are the general
    /// ones with zero charges.
    #[test]
    fn force_field_and_potential_are_derivatives_of_the_energy() {
        derivatives_of_the_energy::<ShiftedForce>();
        derivatives_of_the_energy::<Plain<F4>>();
        dipoles_only_forms::<ShiftedForce>();
        dipoles_only_forms::<Plain<F4>>();
    }

    fn dipoles_only_forms<F: Factors<F4>>() {
        let (mut t, mut s) = pair();
        (t.charge, s.charge) = (0.0, 0.0);
        let (t, s) = (ChargeDipoles::splat(&t), ChargeDipoles::splat(&s));
        let r = V4::splat(&Vector3::new(0.9, -0.4, 0.3));
        let r2 = r.dot(&r);
        let factors = F::new(r2, 2.5);
        let (field, general) = (factors.dipole_field(&r, &s), factors.fields(&r, &s).1);
        assert!((field.to_vectors()[0] - general.to_vectors()[0]).norm() < 1e-14);
        let (force, general) = (
            factors.dipole_force(&r, r2, &t, &s),
            factors.force(&r, r2, &t, &s),
        );
        assert!((force.to_vectors()[0] - general.to_vectors()[0]).norm() < 1e-14);
    }

    fn derivatives_of_the_energy<F: Factors<F4>>() {
        let energy = energy::<F>;
        let (t, s) = pair();
        let cutoff = 2.5;
        let h = 1e-6;
        for r in [Vector3::new(0.9, -0.4, 0.3), Vector3::new(1.2, 1.4, -1.1)] {
            let p = pair_response::<F>(&r, cutoff, &t, &s);
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
        let p = pair_response::<ShiftedForce>(&r, 2.5, &t, &s);
        assert!(energy::<ShiftedForce>(&r, 2.5, &t, &s).abs() < 10.0 * gap * gap);
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
        let e = energy::<ShiftedForce>(&r, cutoff, &t, &s);
        assert!((e - bare).abs() < 5.0 * (d / cutoff).powi(3) * bare.abs());
        let e = energy::<Plain<F4>>(&r, cutoff, &t, &s);
        assert!((e - bare).abs() < 1e-14 * bare.abs(), "{e} {bare}");
    }
}
