//! Rigid water models a body type names (`model = "spce"`), as the sites a
//! scene would write, in real units (Angstrom, g/mol, kcal/mol, e).
//!
//! Each model puts O at the origin and the hydrogens in the xz plane,
//! `H = (+-r_OH sin(theta/2), 0, r_OH cos(theta/2))`; TIP4P/2005's massless
//! site M, which carries the oxygen's charge, lies on the bisector at
//! `(0, 0, d_OM)`. Lennard-Jones acts between oxygens only. Masses are
//! O 15.9994 and H 1.008 g/mol: the standard atomic weight of O (IUPAC
//! 1995) and the conventional one of H (IUPAC 2009), the masses of the
//! CHARMM and LAMMPS water examples; M has none. The body type's centre and
//! principal axes follow from these masses (water is planar: `I3 = I1 + I2`).

use super::body_types::{RawBodySite, RawLennardJones};
use crate::units::{BOLTZMANN_KCAL, KCAL};
use serde::{Deserialize, Serialize};

/// A rigid water model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WaterModel {
    /// SPC/E: H. J. C. Berendsen, J. R. Grigera and T. P. Straatsma,
    /// J. Phys. Chem. 91, 6269 (1987). r_OH = 1 A, HOH = 109.47 degrees,
    /// q_H = +0.4238 e, sigma_O = 3.166 A, epsilon_O = 0.650 kJ/mol (the
    /// SPC values of Berendsen et al. 1981 it keeps). Dipole 2.351 D.
    Spce,
    /// TIP3P: W. L. Jorgensen, J. Chandrasekhar, J. D. Madura, R. W. Impey
    /// and M. L. Klein, J. Chem. Phys. 79, 926 (1983), Table I. r_OH =
    /// 0.9572 A, HOH = 104.52 degrees, q_H = +0.417 e, the O-O potential
    /// `A / r^12 - C / r^6` with A = 582.0e3 kcal A^12/mol and C = 595.0
    /// kcal A^6/mol. Dipole 2.347 D.
    Tip3p,
    /// TIP4P/2005: J. L. F. Abascal and C. Vega, J. Chem. Phys. 123, 234505
    /// (2005), Table I. r_OH = 0.9572 A, HOH = 104.52 degrees, d_OM =
    /// 0.1546 A, q_H = +0.5564 e, q_M = -2 q_H, sigma_O = 3.1589 A,
    /// epsilon_O / k_B = 93.2 K. Dipole 2.305 D.
    #[serde(rename = "tip4p_2005")]
    Tip4p2005,
}

/// Oxygen's mass, g/mol.
pub const OXYGEN_MASS: f64 = 15.9994;
/// Hydrogen's mass, g/mol.
pub const HYDROGEN_MASS: f64 = 1.008;

/// A model's geometry and parameters.
struct Parameters {
    /// O-H bond length, A.
    r_oh: f64,
    /// H-O-H angle, degrees.
    angle: f64,
    /// Hydrogen charge, e.
    q_h: f64,
    /// The distance of the negative charge from O along the bisector, A
    /// (0: on the oxygen).
    d_om: f64,
    /// Oxygen's Lennard-Jones.
    lennard_jones: RawLennardJones,
}

impl WaterModel {
    fn parameters(self) -> Parameters {
        match self {
            WaterModel::Spce => Parameters {
                r_oh: 1.0,
                angle: 109.47,
                q_h: 0.4238,
                d_om: 0.0,
                lennard_jones: RawLennardJones {
                    epsilon: 0.650 * 1000.0 / KCAL,
                    sigma: 3.166,
                },
            },
            WaterModel::Tip3p => {
                let (a, c): (f64, f64) = (582.0e3, 595.0);
                Parameters {
                    r_oh: 0.9572,
                    angle: 104.52,
                    q_h: 0.417,
                    d_om: 0.0,
                    // A = 4 eps sigma^12, C = 4 eps sigma^6.
                    lennard_jones: RawLennardJones {
                        epsilon: c * c / (4.0 * a),
                        sigma: (a / c).powf(1.0 / 6.0),
                    },
                }
            }
            WaterModel::Tip4p2005 => Parameters {
                r_oh: 0.9572,
                angle: 104.52,
                q_h: 0.5564,
                d_om: 0.1546,
                lennard_jones: RawLennardJones {
                    epsilon: 93.2 * BOLTZMANN_KCAL,
                    sigma: 3.1589,
                },
            },
        }
    }

    /// The model's sites: O, H, H (and M for TIP4P/2005), real units.
    pub fn sites(self) -> Vec<RawBodySite> {
        let p = self.parameters();
        let half = (p.angle / 2.0).to_radians();
        let (x, z) = (p.r_oh * half.sin(), p.r_oh * half.cos());
        let site = |position: [f64; 3], mass: Option<f64>, charge: f64| RawBodySite {
            position,
            mass,
            lennard_jones: None,
            charge: Some(charge),
            dipole: None,
            quadrupole: None,
        };
        let q_negative = -2.0 * p.q_h;
        let on_oxygen = p.d_om == 0.0;
        let q_oxygen = if on_oxygen { q_negative } else { 0.0 };
        let mut oxygen = site([0.0; 3], Some(OXYGEN_MASS), q_oxygen);
        oxygen.lennard_jones = Some(p.lennard_jones);
        let mut sites = vec![
            oxygen,
            site([x, 0.0, z], Some(HYDROGEN_MASS), p.q_h),
            site([-x, 0.0, z], Some(HYDROGEN_MASS), p.q_h),
        ];
        if !on_oxygen {
            sites.push(site([0.0, 0.0, p.d_om], None, q_negative));
        }
        sites
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{Units, DEBYE_E_ANGSTROM};

    /// The dipole moment `sum_s q_s r_s` of each model's sites, in Debye,
    /// against the value its paper publishes (to the paper's 3 decimals).
    #[test]
    fn the_dipoles_are_the_published_ones() {
        for (model, published) in [
            (WaterModel::Spce, 2.351),
            (WaterModel::Tip3p, 2.347),
            (WaterModel::Tip4p2005, 2.305),
        ] {
            let sites = model.sites();
            let charge: f64 = sites.iter().filter_map(|s| s.charge).sum();
            assert!(charge.abs() < 1e-15, "{model:?} is not neutral: {charge}");
            let dipole = sites.iter().fold([0.0; 3], |mut mu, s| {
                let q = s.charge.unwrap_or(0.0);
                (0..3).for_each(|k| mu[k] += q * s.position[k]);
                mu
            });
            let debye = dipole[2].hypot(dipole[0].hypot(dipole[1])) / DEBYE_E_ANGSTROM;
            assert!((debye - published).abs() < 5e-4, "{model:?}: {debye} D");
        }
    }

    /// TIP3P's Lennard-Jones from the paper's A and C against the rounded
    /// values of the LAMMPS TIP3P howto (sigma = 3.1507 A, epsilon = 0.1521
    /// kcal/mol), to their last digit.
    #[test]
    fn tip3p_lennard_jones_is_the_tabulated_one() {
        let lj = WaterModel::Tip3p.parameters().lennard_jones;
        assert!((lj.sigma - 3.1507).abs() < 5e-5, "{}", lj.sigma);
        assert!((lj.epsilon - 0.1521).abs() < 5e-5, "{}", lj.epsilon);
    }

    /// A water molecule is planar: no moment is zero, the largest is the
    /// sum of the other two (perpendicular axes theorem), three rotational
    /// degrees of freedom, and the two in-plane moments are SPC/E's closed
    /// form; TIP4P/2005's massless M changes neither the mass nor the
    /// moments of its TIP3P geometry.
    #[test]
    fn water_is_a_planar_body() {
        let body = |model| {
            let raw = super::super::body_types::RawBodyType {
                model: Some(model),
                sites: None,
                mass: None,
                inertia: None,
            };
            super::super::body_types::checked_types(&[raw], Units::Real)
                .expect("a water model")
                .remove(0)
        };
        let spce = body(WaterModel::Spce);
        let m = spce.moments;
        assert!(m[0] > 0.1 && m[1] > m[0], "{m:?}");
        assert!((m[2] - m[0] - m[1]).abs() < 1e-14 * m[2], "{m:?}");
        assert_eq!(spce.rotational_degrees(), 3);
        assert!((spce.mass - (OXYGEN_MASS + 2.0 * HYDROGEN_MASS)).abs() < 1e-13);
        // SPC/E closed form: H at (+-x, 0, z), O at 0; centre of mass at
        // z_c = 2 m_H z / M. About the bisector: 2 m_H x^2; about the
        // in-plane perpendicular: m_O z_c^2 + 2 m_H (z - z_c)^2.
        let half = (109.47_f64 / 2.0).to_radians();
        let (x, z) = (half.sin(), half.cos());
        let zc = 2.0 * HYDROGEN_MASS * z / spce.mass;
        let about_bisector = 2.0 * HYDROGEN_MASS * x * x;
        let in_plane = OXYGEN_MASS * zc * zc + 2.0 * HYDROGEN_MASS * (z - zc).powi(2);
        let mut expected = [about_bisector, in_plane];
        expected.sort_by(f64::total_cmp);
        assert!((m[0] - expected[0]).abs() < 1e-13 && (m[1] - expected[1]).abs() < 1e-13);
        let (tip3p, tip4p) = (body(WaterModel::Tip3p), body(WaterModel::Tip4p2005));
        assert_eq!(tip4p.mass, tip3p.mass);
        assert!((tip4p.moments - tip3p.moments).amax() < 1e-14);
        assert_eq!(tip4p.sites.len(), 4);
    }
}
