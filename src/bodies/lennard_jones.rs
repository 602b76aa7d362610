//! Lennard-Jones between sites of different bodies, truncated at a cutoff
//! `r_c`: plain `u(r)`, shifted `u(r) - u(r_c)`, or force-shifted
//! `u(r) - u(r_c) - (r - r_c) u'(r_c)`, for `r < r_c` (zero beyond).
//! Unlike sites mix by Lorentz-Berthelot (`eps = sqrt(eps_a eps_b)`,
//! `sigma = (sigma_a + sigma_b) / 2`) or geometrically (both geometric
//! means, LAMMPS's default).
//!
//! Tail corrections of the plain truncation (Allen and Tildesley, 2nd ed.,
//! eqs 2.144-2.145, summed over site types `a`, `b` with counts `N_a`):
//! `E_tail = (2 pi / V) sum_ab N_a N_b eps sigma^3 4 [x^9 / 9 - x^3 / 3]`,
//! `P_tail = (2 pi / V^2) sum_ab N_a N_b eps sigma^3 4 [4 x^9 / 9 - 2 x^3 / 3]`,
//! `x = sigma / r_c` (all site pairs counted, those within a body too, as
//! LAMMPS does).

use super::overlap::OVERLAP_FRACTION;
use super::site::LennardJones;
use crate::checks::{named_choices, positive, InputError};
use crate::lanes::{Lanes, LANES};
use std::f64::consts::PI;

/// How the potential is cut at the cutoff.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Truncation {
    /// `u(r)` (default); tail corrections to energy and pressure apply.
    #[default]
    Plain,
    /// `u(r) - u(r_c)`: continuous energy.
    Shifted,
    /// `u(r) - u(r_c) - (r - r_c) u'(r_c)`: continuous force.
    ForceShifted,
}

named_choices!(Truncation {
    "plain" => Truncation::Plain,
    "shifted" => Truncation::Shifted,
    "force_shifted" => Truncation::ForceShifted,
});

/// How the parameters of unlike sites combine.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mixing {
    /// `sqrt(eps_a eps_b)`, `(sigma_a + sigma_b) / 2` (default).
    #[default]
    LorentzBerthelot,
    /// `sqrt(eps_a eps_b)`, `sqrt(sigma_a sigma_b)` (LAMMPS's default).
    Geometric,
}

named_choices!(Mixing {
    "lorentz_berthelot" => Mixing::LorentzBerthelot,
    "geometric" => Mixing::Geometric,
});

/// The options of the Lennard-Jones term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LennardJonesOptions {
    /// The cutoff `r_c` (length, > 0).
    pub cutoff: f64,
    /// The truncation (default plain).
    pub truncation: Truncation,
    /// The mixing rule (default Lorentz-Berthelot).
    pub mixing: Mixing,
}

/// One pair of site kinds: its sigma, `4 eps sigma^12`, `4 eps sigma^6`
/// and the truncation's constants.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct PairConstants {
    sigma: f64,
    /// `(OVERLAP_FRACTION sigma)^2`, a part in 1e9 wider: a pair closer
    /// than that may overlap ([`super::overlap`] decides), a pair farther
    /// does not, whatever the roundings of either test.
    core2: f64,
    c12: f64,
    c6: f64,
    /// `u(r_c)` (shifted and force-shifted) or 0.
    shift: f64,
    /// `u'(r_c)` (force-shifted) or 0.
    slope: f64,
}

/// One site kind's pair constants in lanes ([`LennardJonesTerm::kind_lanes`]):
/// `c12, c6, shift, core2, slope` in every lane, or the kind's row of the
/// table.
pub(super) enum KindLanes<'t, T> {
    One([T; 5]),
    Row(&'t [PairConstants]),
}

/// The Lennard-Jones term over `kinds` distinct site parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct LennardJonesTerm {
    options: LennardJonesOptions,
    kinds: Vec<LennardJones>,
    table: Vec<PairConstants>,
}

impl LennardJonesTerm {
    /// The term for these distinct site parameters.
    pub fn new(options: LennardJonesOptions, kinds: Vec<LennardJones>) -> Result<Self, InputError> {
        let rc = positive(options.cutoff).map_err(|e| e.at("cutoff"))?;
        let mut table = Vec::with_capacity(kinds.len() * kinds.len());
        for a in &kinds {
            for b in &kinds {
                let (eps, sigma) = mix(options.mixing, a, b);
                let s6 = sigma.powi(6);
                let (c12, c6) = (4.0 * eps * s6 * s6, 4.0 * eps * s6);
                let plain = PairConstants {
                    sigma,
                    core2: (OVERLAP_FRACTION * sigma).powi(2) * (1.0 + 1e-9),
                    c12,
                    c6,
                    shift: 0.0,
                    slope: 0.0,
                };
                let (u_rc, du_rc) = plain.energy_and_slope(rc * rc);
                table.push(match options.truncation {
                    Truncation::Plain => plain,
                    Truncation::Shifted => PairConstants {
                        shift: u_rc,
                        ..plain
                    },
                    Truncation::ForceShifted => PairConstants {
                        shift: u_rc,
                        slope: du_rc,
                        ..plain
                    },
                });
            }
        }
        Ok(LennardJonesTerm {
            options,
            kinds,
            table,
        })
    }

    /// The cutoff.
    pub fn cutoff(&self) -> f64 {
        self.options.cutoff
    }

    /// The mixed sigma of kinds `a` and `b`.
    #[inline]
    pub fn sigma(&self, a: usize, b: usize) -> f64 {
        self.table[a * self.kinds.len() + b].sigma
    }

    /// The energy and `-(1/r) du/dr` (force = that times the separation) of
    /// kinds `a`, `b` at squared distance `r2 < r_c^2`.
    #[inline]
    pub fn pair(&self, a: usize, b: usize, r2: f64) -> (f64, f64) {
        match self.options.truncation {
            Truncation::ForceShifted => self.pair_of::<true>(a, b, r2),
            Truncation::Plain | Truncation::Shifted => self.pair_of::<false>(a, b, r2),
        }
    }

    /// [`LennardJonesTerm::pair`] for a truncation known to be
    /// force-shifted or not: no square root but for the force shift.
    #[inline]
    pub(super) fn pair_of<const FORCE_SHIFTED: bool>(
        &self,
        a: usize,
        b: usize,
        r2: f64,
    ) -> (f64, f64) {
        let p = &self.table[a * self.kinds.len() + b];
        let inv_r2 = 1.0 / r2;
        let inv_r6 = inv_r2 * inv_r2 * inv_r2;
        let u = inv_r6 * (p.c12 * inv_r6 - p.c6) - p.shift;
        let f_over_r = inv_r6 * (12.0 * p.c12 * inv_r6 - 6.0 * p.c6) * inv_r2;
        if !FORCE_SHIFTED {
            return (u, f_over_r);
        }
        // `1/r = r / r^2`: a multiplication where a division would cost
        // as much as the rest of the pair.
        let r = r2.sqrt();
        (
            u - (r - self.options.cutoff) * p.slope,
            f_over_r + p.slope * (r * inv_r2),
        )
    }

    /// Kind `a`'s constants for [`LennardJonesTerm::pair_lanes`], taken
    /// once per site: in every lane when the term has one kind, else the
    /// kind's row of the table, gathered by partner.
    #[inline(always)]
    pub(super) fn kind_lanes<T: Lanes>(&self, a: usize) -> KindLanes<'_, T> {
        let row = &self.table[a * self.kinds.len()..(a + 1) * self.kinds.len()];
        match row {
            [p] => KindLanes::One([p.c12, p.c6, p.shift, p.core2, p.slope].map(T::splat)),
            _ => KindLanes::Row(row),
        }
    }

    /// [`LennardJonesTerm::pair_of`] of four pairs: the kind of `kind`
    /// with kinds `b` at squared distances `r2` (lanes beyond the cutoff
    /// hold values to be dropped), and 1 in the lanes of pairs that may
    /// overlap ([`PairConstants::core2`]), else 0.
    #[inline(always)]
    pub(super) fn pair_lanes<T: Lanes, const FORCE_SHIFTED: bool>(
        &self,
        kind: &KindLanes<'_, T>,
        b: [usize; LANES],
        r2: T,
    ) -> (T, T, T) {
        let [c12, c6, shift, core2, slope] = match kind {
            KindLanes::One(constants) => *constants,
            KindLanes::Row(row) => {
                let lanes = |f: fn(&PairConstants) -> f64| T::from_array(b.map(|b| f(&row[b])));
                [
                    lanes(|p| p.c12),
                    lanes(|p| p.c6),
                    lanes(|p| p.shift),
                    lanes(|p| p.core2),
                    lanes(|p| p.slope),
                ]
            }
        };
        let core = T::splat(1.0).keep(r2.lt(core2));
        let inv_r2 = T::splat(1.0) / r2;
        let inv_r6 = inv_r2 * inv_r2 * inv_r2;
        let u = inv_r6 * (c12 * inv_r6 - c6) - shift;
        let f_over_r = inv_r6 * (c12 * 12.0 * inv_r6 - c6 * 6.0) * inv_r2;
        if !FORCE_SHIFTED {
            return (u, f_over_r, core);
        }
        let r = r2.sqrt();
        (
            u - (r - T::splat(self.options.cutoff)) * slope,
            f_over_r + slope * (r * inv_r2),
            core,
        )
    }

    /// Whether the truncation is force-shifted.
    pub(super) fn force_shifted(&self) -> bool {
        self.options.truncation == Truncation::ForceShifted
    }

    /// The tail corrections `(E_tail, P_tail)` of the plain truncation for
    /// `counts[a]` sites of each kind in volume `volume`; zero for the other
    /// truncations.
    pub fn tail(&self, counts: &[usize], volume: f64) -> (f64, f64) {
        if self.options.truncation != Truncation::Plain {
            return (0.0, 0.0);
        }
        let (mut energy, mut pressure) = (0.0, 0.0);
        for (a, ka) in self.kinds.iter().enumerate() {
            for (b, kb) in self.kinds.iter().enumerate() {
                let (eps, sigma) = mix(self.options.mixing, ka, kb);
                let x3 = (sigma / self.options.cutoff).powi(3);
                let pairs = counts[a] as f64 * counts[b] as f64;
                let scale = 2.0 * PI * pairs * 4.0 * eps * sigma.powi(3);
                energy += scale * (x3 * x3 * x3 / 9.0 - x3 / 3.0) / volume;
                pressure += scale * (4.0 * x3 * x3 * x3 / 9.0 - 2.0 * x3 / 3.0) / (volume * volume);
            }
        }
        (energy, pressure)
    }
}

impl PairConstants {
    /// `(u(r), du/dr)` at `r2 = r^2`.
    #[inline]
    fn energy_and_slope(&self, r2: f64) -> (f64, f64) {
        let inv_r6 = 1.0 / (r2 * r2 * r2);
        let u = inv_r6 * (self.c12 * inv_r6 - self.c6);
        let du = -inv_r6 * (12.0 * self.c12 * inv_r6 - 6.0 * self.c6) / r2.sqrt();
        (u, du)
    }
}

/// The mixed `(epsilon, sigma)` of two site parameters.
fn mix(rule: Mixing, a: &LennardJones, b: &LennardJones) -> (f64, f64) {
    let eps = (a.epsilon * b.epsilon).sqrt();
    let sigma = match rule {
        Mixing::LorentzBerthelot => 0.5 * (a.sigma + b.sigma),
        Mixing::Geometric => (a.sigma * b.sigma).sqrt(),
    };
    (eps, sigma)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(truncation: Truncation) -> LennardJonesTerm {
        let options = LennardJonesOptions {
            cutoff: 2.5,
            truncation,
            mixing: Mixing::LorentzBerthelot,
        };
        let kinds = vec![
            LennardJones {
                epsilon: 1.0,
                sigma: 1.0,
            },
            LennardJones {
                epsilon: 0.5,
                sigma: 1.4,
            },
        ];
        LennardJonesTerm::new(options, kinds).unwrap()
    }

    /// The closed form at a few distances (eps = sqrt(0.5), sigma = 1.2 for
    /// the unlike pair), each truncation, and the force against a central
    /// difference of the energy.
    #[test]
    fn pair_energies_and_forces_match_the_closed_forms() {
        let (eps, sigma, rc) = (0.5f64.sqrt(), 1.2, 2.5);
        let u = |r: f64| 4.0 * eps * ((sigma / r).powi(12) - (sigma / r).powi(6));
        let du = |r: f64| {
            4.0 * eps * (-12.0 * sigma.powi(12) / r.powi(13) + 6.0 * sigma.powi(6) / r.powi(7))
        };
        let shifted = move |r: f64| u(r) - u(rc);
        let force_shifted = move |r: f64| u(r) - u(rc) - (r - rc) * du(rc);
        let cases: [(Truncation, &dyn Fn(f64) -> f64); 3] = [
            (Truncation::Plain, &u),
            (Truncation::Shifted, &shifted),
            (Truncation::ForceShifted, &force_shifted),
        ];
        for (truncation, exact) in cases {
            let t = term(truncation);
            for r in [1.1, 1.35, 2.0, 2.49] {
                let (e, f_over_r) = t.pair(0, 1, r * r);
                assert!(
                    (e - exact(r)).abs() < 1e-14 * (1.0 + exact(r).abs()),
                    "{truncation:?} {r}"
                );
                let h = 1e-6;
                let fd = -(exact(r + h) - exact(r - h)) / (2.0 * h);
                assert!(
                    (f_over_r * r - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                    "{truncation:?} {r}"
                );
            }
        }
    }

    /// The tail corrections of one kind are the textbook
    /// `8/3 pi N rho eps sigma^3 [x^9/3 - x^3]` and
    /// `16/3 pi rho^2 eps sigma^3 [2 x^9/3 - x^3]` (Allen and Tildesley eqs
    /// 2.144-2.145), and vanish for the shifted truncations.
    #[test]
    fn tail_corrections_match_the_textbook() {
        let (n, volume) = (500usize, 625.0);
        let rho = n as f64 / volume;
        let x: f64 = 1.0 / 2.5;
        let (e, p) = term(Truncation::Plain).tail(&[n, 0], volume);
        let e_ref = 8.0 / 3.0 * PI * n as f64 * rho * (x.powi(9) / 3.0 - x.powi(3));
        let p_ref = 16.0 / 3.0 * PI * rho * rho * (2.0 * x.powi(9) / 3.0 - x.powi(3));
        assert!((e - e_ref).abs() < 1e-13 * e_ref.abs(), "{e} {e_ref}");
        assert!((p - p_ref).abs() < 1e-13 * p_ref.abs(), "{p} {p_ref}");
        assert_eq!(term(Truncation::Shifted).tail(&[n, 0], volume), (0.0, 0.0));
    }
}
