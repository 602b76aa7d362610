//! Physical units of a scene: the constants, stated once, and the
//! conversions at the boundary.
//!
//! The engine is unit-free: its integrators and potentials use one
//! consistent set of units in which `4 pi eps0 = 1` and `k_B = 1`. A scene
//! says which set its numbers are in:
//!
//! * `units = "reduced"` (the default): the engine's units themselves
//!   (Lennard-Jones reduced units); nothing is converted.
//! * `units = "real"`, as LAMMPS `units real`: lengths in Angstrom, masses
//!   in g/mol, energies in kcal/mol, time in fs, charges in e, dipoles in
//!   Debye (quadrupoles in Debye Angstrom, Buckingham), temperatures in K,
//!   pressures in atm. Inside, lengths, masses and energies keep these
//!   units; the time unit is then
//!   `tau = sqrt((g/mol) A^2 / (kcal/mol)) = sqrt(1e-3 kg * 1e-20 m^2 / 4184 J) = sqrt(1e7 / 4184) fs`
//!   = 48.888212908 fs ([`TIME_UNIT_FS`]), a charge `q` in e is
//!   `q sqrt(C)` with `C` the Coulomb constant in kcal A/(mol e^2)
//!   ([`COULOMB_KCAL_ANGSTROM`]), so that `q_i q_j / r` is in kcal/mol, and
//!   a temperature `T` in K is the energy `k_B T` in kcal/mol
//!   ([`BOLTZMANN_KCAL`]).
//!
//! A scene is translated into the engine's units once, when it is loaded;
//! outputs (series, `summary.json`, GSD velocities, the Python API's
//! returns) are translated back ([`Units::from_internal`]) and name their
//! units ([`Units::names`]).

use crate::bodies::BodyQuantity;
use serde::{Deserialize, Serialize};

/// The Boltzmann constant, J/K (exact, SI 2019).
pub const BOLTZMANN_SI: f64 = 1.380649e-23;
/// The Avogadro constant, 1/mol (exact, SI 2019).
pub const AVOGADRO: f64 = 6.02214076e23;
/// The elementary charge, C (exact, SI 2019).
pub const ELEMENTARY_CHARGE: f64 = 1.602176634e-19;
/// The vacuum permittivity, F/m (CODATA 2018, the value OpenMM's
/// `ONE_4PI_EPS0` is computed from; LAMMPS's `qqr2e = 332.06371` is 9e-9
/// lower, CODATA 2022's value 6.8e-10 higher: ERRATA.md's traps table).
/// CODATA 2018 is chosen so that quatrot and OpenMM agree to round-off and
/// the constant is traceable, not a rounded literal.
pub const VACUUM_PERMITTIVITY: f64 = 8.8541878128e-12;
/// The speed of light, m/s (exact).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// The thermochemical calorie: 1 kcal = 4184 J (exact).
pub const KCAL: f64 = 4184.0;
/// One standard atmosphere, Pa (exact).
pub const ATMOSPHERE: f64 = 101_325.0;

/// `k_B N_A` in kcal/(mol K): 0.0019872042586408...
pub const BOLTZMANN_KCAL: f64 = BOLTZMANN_SI * AVOGADRO / KCAL;
/// The Coulomb constant `e^2 N_A / (4 pi eps0)` in kcal A/(mol e^2):
/// 332.0637133 (CODATA 2018).
pub const COULOMB_KCAL_ANGSTROM: f64 = ELEMENTARY_CHARGE * ELEMENTARY_CHARGE * AVOGADRO
    / (4.0 * std::f64::consts::PI * VACUUM_PERMITTIVITY)
    / KCAL
    * 1e10;
/// One Debye in e A: `1 D = 1e-18 statC cm = 1e-21 / c C m`, divided by
/// `e * 1e-10 m`: 0.20819434.
pub const DEBYE_E_ANGSTROM: f64 = 1e-21 / SPEED_OF_LIGHT / (ELEMENTARY_CHARGE * 1e-10);
/// The engine's time unit in real units, in fs:
/// `sqrt(1e-3 kg/mol * 1e-20 m^2 / (4184 J/mol)) = sqrt(1e7 / 4184) fs`.
pub const TIME_UNIT_FS: f64 = 48.888_212_908_396_156;
/// One kcal/(mol A^3) in atm: `4184 / N_A * 1e30 / 101325`.
pub const ATM_PER_KCAL_MOL_ANGSTROM3: f64 = KCAL / AVOGADRO * 1e30 / ATMOSPHERE;

/// The largest time step of a scene in real units, fs (rigid water is
/// stable to about 4 fs; a larger step is a slip of units).
pub const MAX_REAL_DT_FS: f64 = 10.0;

/// The unit system of a scene (`units`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// The engine's own units (`4 pi eps0 = 1`, `k_B = 1`): nothing converted.
    #[default]
    Reduced,
    /// LAMMPS `units real`.
    Real,
}

/// What a number measures, for its conversion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Lengths, masses, energies, forces, torques, moments of inertia, and
    /// pure numbers: the same inside and out.
    Unchanged,
    /// Time.
    Time,
    /// Inverse time (a drift per unit time).
    PerTime,
    /// A velocity, a linear momentum, an angular momentum or velocity (one
    /// power of inverse time).
    Rate,
    /// Temperature.
    Temperature,
    /// Pressure.
    Pressure,
    /// Charge.
    Charge,
    /// Dipole moment.
    Dipole,
    /// Quadrupole moment.
    Quadrupole,
}

impl Units {
    /// How many engine units one unit of `dimension` of the scene is.
    pub fn factor(self, dimension: Dimension) -> f64 {
        match self {
            Units::Reduced => 1.0,
            Units::Real => match dimension {
                Dimension::Unchanged => 1.0,
                Dimension::Time => 1.0 / TIME_UNIT_FS,
                Dimension::PerTime | Dimension::Rate => TIME_UNIT_FS,
                Dimension::Temperature => BOLTZMANN_KCAL,
                Dimension::Pressure => 1.0 / ATM_PER_KCAL_MOL_ANGSTROM3,
                Dimension::Charge => COULOMB_KCAL_ANGSTROM.sqrt(),
                Dimension::Dipole | Dimension::Quadrupole => {
                    DEBYE_E_ANGSTROM * COULOMB_KCAL_ANGSTROM.sqrt()
                }
            },
        }
    }

    /// The scene's `value` of `dimension` in the engine's units (reduced:
    /// `value` itself).
    pub fn to_internal(self, value: f64, dimension: Dimension) -> f64 {
        match self {
            Units::Reduced => value,
            Units::Real => value * self.factor(dimension),
        }
    }

    /// The engine's `value` of `dimension` in the scene's units.
    pub fn from_internal(self, value: f64, dimension: Dimension) -> f64 {
        match self {
            Units::Reduced => value,
            Units::Real => value / self.factor(dimension),
        }
    }

    /// The unit names of the outputs (`summary.json`'s `units`); `None`
    /// for reduced units, whose outputs carry no entry.
    pub fn names(self) -> Option<UnitNames> {
        match self {
            Units::Reduced => None,
            Units::Real => Some(UnitNames {
                system: "real",
                length: "Angstrom",
                time: "fs",
                mass: "g/mol",
                energy: "kcal/mol",
                temperature: "K",
                pressure: "atm",
                charge: "e",
                dipole: "Debye",
                velocity: "Angstrom/fs",
                momentum: "(g/mol) Angstrom/fs",
                angular_momentum: "(g/mol) Angstrom^2/fs",
                coulomb_constant: COULOMB_KCAL_ANGSTROM,
                boltzmann_constant: BOLTZMANN_KCAL,
            }),
        }
    }
}

/// The units of a run's outputs, as `summary.json` records them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnitNames {
    /// The scene's `units`.
    pub system: &'static str,
    /// Lengths, positions, the box.
    pub length: &'static str,
    /// Times (the `time` column, the drift per time).
    pub time: &'static str,
    /// Masses.
    pub mass: &'static str,
    /// Energies (and forces per length, torques).
    pub energy: &'static str,
    /// `T_trans`, `T_rot`.
    pub temperature: &'static str,
    /// The pressure.
    pub pressure: &'static str,
    /// Site charges.
    pub charge: &'static str,
    /// Site dipoles.
    pub dipole: &'static str,
    /// Centre velocities (GSD).
    pub velocity: &'static str,
    /// `P_x, P_y, P_z`.
    pub momentum: &'static str,
    /// `L_x, L_y, L_z`, GSD's `angmom`.
    pub angular_momentum: &'static str,
    /// The Coulomb constant used, kcal A/(mol e^2).
    pub coulomb_constant: f64,
    /// The Boltzmann constant used, kcal/(mol K).
    pub boltzmann_constant: f64,
}

/// The dimension of a recorded quantity's columns.
pub fn quantity_dimension(quantity: BodyQuantity) -> Dimension {
    match quantity {
        BodyQuantity::KineticEnergy
        | BodyQuantity::TranslationalKineticEnergy
        | BodyQuantity::RotationalKineticEnergy
        | BodyQuantity::PotentialEnergy
        | BodyQuantity::TotalEnergy
        | BodyQuantity::ConservedEnergy => Dimension::Unchanged,
        BodyQuantity::TranslationalTemperature | BodyQuantity::RotationalTemperature => {
            Dimension::Temperature
        }
        BodyQuantity::Pressure => Dimension::Pressure,
        BodyQuantity::Momentum | BodyQuantity::AngularMomentum => Dimension::Rate,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derived constants against their published values: LAMMPS's
    /// `units real` time unit (`ftm2v = 1 / 48.88821291^2`, update.cpp),
    /// CODATA 2018's `e^2 N_A / (4 pi eps0)` = 138.935 457 64 kJ nm/mol
    /// (OpenMM 8's `ONE_4PI_EPS0`, validation/tests/test_unit_constants.py), the Debye of the IUPAC Green Book
    /// (3.335 640 95e-30 C m) and `R = 8.314 462 618 J/(mol K)` (CODATA 2018,
    /// exact).
    #[test]
    fn the_constants_match_their_published_values() {
        assert!((TIME_UNIT_FS - (1e-23_f64 / KCAL).sqrt() * 1e15).abs() < 1e-12);
        assert!((TIME_UNIT_FS - 48.888_212_91).abs() < 1e-8);
        assert!((COULOMB_KCAL_ANGSTROM * KCAL / 1e4 - 138.935_457_64).abs() < 1e-8);
        assert!((DEBYE_E_ANGSTROM * ELEMENTARY_CHARGE * 1e-10 - 3.335_640_95e-30).abs() < 1e-38);
        assert!((DEBYE_E_ANGSTROM - 0.208_194_34).abs() < 1e-8);
        assert!((BOLTZMANN_KCAL * KCAL - 8.314_462_618).abs() < 1e-9);
        // LAMMPS's real-units `nktv2p = 68568.415` (force.cpp), rounded there.
        assert!((ATM_PER_KCAL_MOL_ANGSTROM3 / 68_568.415 - 1.0).abs() < 2e-7);
    }

    /// Every dimension goes in and comes back out to round-off; reduced
    /// units leave every value as it is, bit for bit.
    #[test]
    fn conversions_round_trip() {
        let all = [
            Dimension::Unchanged,
            Dimension::Time,
            Dimension::PerTime,
            Dimension::Rate,
            Dimension::Temperature,
            Dimension::Pressure,
            Dimension::Charge,
            Dimension::Dipole,
            Dimension::Quadrupole,
        ];
        for d in all {
            for value in [0.0, -1.5, 298.15, 1e-7, 3.3e12] {
                let back = Units::Real.from_internal(Units::Real.to_internal(value, d), d);
                assert!(
                    (back - value).abs() <= 4.0 * f64::EPSILON * value.abs(),
                    "{d:?}"
                );
                let same = Units::Reduced.to_internal(value, d);
                assert_eq!(same.to_bits(), value.to_bits());
            }
        }
        // 1 fs is 1 / 48.888 time units; 298 K is R * 298 K = 0.5922 kcal/mol.
        let dt = Units::Real.to_internal(1.0, Dimension::Time);
        assert!((dt * 48.888_212_908 - 1.0).abs() < 1e-10);
        let kt = Units::Real.to_internal(298.0, Dimension::Temperature);
        assert!((kt - 0.592_186_869).abs() < 1e-9);
        // Two unit charges 1 A apart: C kcal/mol.
        let q = Units::Real.to_internal(1.0, Dimension::Charge);
        assert!((q * q - COULOMB_KCAL_ANGSTROM).abs() < 1e-10);
    }
}
