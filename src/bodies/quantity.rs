//! The scalar observables a run of bodies records, each computed from the
//! state and the last evaluation (never as the difference of two others).

use super::evaluate::Evaluation;
use super::space::Space;
use super::system::BodySystem;
use crate::checks::InputError;

/// A recorded observable of a body system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyQuantity {
    /// `K_trans + K_rot`.
    KineticEnergy,
    /// `K_trans = sum m v^2 / 2`.
    TranslationalKineticEnergy,
    /// `K_rot = sum_k L_k^2 / (2 I_k)`.
    RotationalKineticEnergy,
    /// Every interaction term, the tail correction included.
    PotentialEnergy,
    /// Kinetic plus potential energy.
    TotalEnergy,
    /// The total energy plus the thermostat's share (the total energy
    /// without a thermostat).
    ConservedEnergy,
    /// `T_trans` ([`BodySystem::translational_temperature`]).
    TranslationalTemperature,
    /// `T_rot` ([`BodySystem::rotational_temperature`]).
    RotationalTemperature,
    /// The pressure (periodic boxes only, [`BodySystem::pressure`]).
    Pressure,
    /// The total linear momentum, three columns `P_x, P_y, P_z`.
    Momentum,
    /// The total angular momentum about the origin, three columns `L_x,
    /// L_y, L_z` (open space only: a periodic box does not conserve it).
    AngularMomentum,
}

impl BodyQuantity {
    /// Every quantity, in the order the docs list them.
    pub const ALL: [BodyQuantity; 11] = [
        BodyQuantity::KineticEnergy,
        BodyQuantity::TranslationalKineticEnergy,
        BodyQuantity::RotationalKineticEnergy,
        BodyQuantity::PotentialEnergy,
        BodyQuantity::TotalEnergy,
        BodyQuantity::ConservedEnergy,
        BodyQuantity::TranslationalTemperature,
        BodyQuantity::RotationalTemperature,
        BodyQuantity::Pressure,
        BodyQuantity::Momentum,
        BodyQuantity::AngularMomentum,
    ];

    /// The name a scene gives it.
    pub fn name(self) -> &'static str {
        match self {
            BodyQuantity::KineticEnergy => "kinetic_energy",
            BodyQuantity::TranslationalKineticEnergy => "translational_kinetic_energy",
            BodyQuantity::RotationalKineticEnergy => "rotational_kinetic_energy",
            BodyQuantity::PotentialEnergy => "potential_energy",
            BodyQuantity::TotalEnergy => "total_energy",
            BodyQuantity::ConservedEnergy => "conserved_energy",
            BodyQuantity::TranslationalTemperature => "T_trans",
            BodyQuantity::RotationalTemperature => "T_rot",
            BodyQuantity::Pressure => "pressure",
            BodyQuantity::Momentum => "momentum",
            BodyQuantity::AngularMomentum => "angular_momentum",
        }
    }

    /// The quantity called `name`; the error lists the names.
    pub fn named(name: &str) -> Result<BodyQuantity, InputError> {
        Self::ALL
            .into_iter()
            .find(|q| q.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|q| q.name()).collect();
                let expected = names.join(", ");
                InputError::new(
                    "",
                    format!("unknown quantity `{name}`, expected one of {expected}"),
                )
            })
    }

    /// Whether it is defined in `space` (the pressure needs a box; the
    /// angular momentum open space).
    pub fn check(self, space: &Space) -> Result<(), InputError> {
        let periodic = matches!(space, Space::Periodic(_));
        let why = match (self, periodic) {
            (BodyQuantity::Pressure, false) => "the pressure needs a periodic box",
            (BodyQuantity::AngularMomentum, true) => {
                "the angular momentum is not conserved in a periodic box: open space only"
            }
            _ => return Ok(()),
        };
        Err(InputError::new("", why))
    }

    /// Its CSV columns.
    pub fn columns(self) -> Vec<String> {
        match self {
            BodyQuantity::Momentum => ["P_x", "P_y", "P_z"].map(String::from).to_vec(),
            BodyQuantity::AngularMomentum => ["L_x", "L_y", "L_z"].map(String::from).to_vec(),
            q => vec![q.name().to_string()],
        }
    }

    /// Appends its values for `system` whose last evaluation is `e` and
    /// whose thermostat's share of the conserved energy is `thermostat`
    /// (NaN for a temperature without degrees of freedom, or a pressure out
    /// of a box).
    pub fn write(self, system: &BodySystem, e: &Evaluation, thermostat: f64, row: &mut Vec<f64>) {
        let kinetic = || system.translational_kinetic_energy() + system.rotational_kinetic_energy();
        match self {
            BodyQuantity::KineticEnergy => row.push(kinetic()),
            BodyQuantity::TranslationalKineticEnergy => {
                row.push(system.translational_kinetic_energy());
            }
            BodyQuantity::RotationalKineticEnergy => row.push(system.rotational_kinetic_energy()),
            BodyQuantity::PotentialEnergy => row.push(e.potential_energy()),
            BodyQuantity::TotalEnergy => row.push(kinetic() + e.potential_energy()),
            BodyQuantity::ConservedEnergy => {
                row.push(kinetic() + e.potential_energy() + thermostat);
            }
            BodyQuantity::TranslationalTemperature => {
                row.push(system.translational_temperature().unwrap_or(f64::NAN));
            }
            BodyQuantity::RotationalTemperature => {
                row.push(system.rotational_temperature().unwrap_or(f64::NAN));
            }
            BodyQuantity::Pressure => row.push(system.pressure(e).unwrap_or(f64::NAN)),
            BodyQuantity::Momentum => row.extend(system.linear_momentum().iter()),
            BodyQuantity::AngularMomentum => row.extend(system.angular_momentum().iter()),
        }
    }
}
