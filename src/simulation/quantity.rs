//! The observables a run can record, each defined once: its name (the
//! scene's), its CSV columns, what it needs from the run loop, and its
//! values at a sample. The quantities of the rotors' multipoles (total
//! dipole, orientational order) also read the rotors' body multipoles,
//! gathered once per series by [`MultipoleInputs`] for the quantities it
//! records only.

use super::observer::{Energies, Needs, Sample};
use crate::checks::InputError;
use crate::observables::multipole_axes::CarriedAxes;
use crate::observables::order::nematic_order;
use crate::observables::polarization::total_dipole;
use crate::observables::{norm_error, norm_velocity};
use crate::quaternion::Quat;
use crate::rotor::Rotor;
use nalgebra::Vector3;

/// An observable of a sample: a scalar, or a few columns (a vector, an order
/// parameter with its director). Per-rotor diagnostics are reduced to their
/// largest magnitude over the rotors; the order parameters average over the
/// rotors carrying the multipole.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `K = 1/2 sum w_b . I w_b`.
    KineticEnergy,
    /// `V`.
    PotentialEnergy,
    /// `K + V`.
    TotalEnergy,
    /// `K + V` plus the thermostat's share (the chain's energy, or minus the
    /// heat a stochastic thermostat put in); `K + V` without a thermostat.
    ConservedEnergy,
    /// `(C - C_0) / s` of the conserved energy `C`, with the scale `s` of
    /// the run's [`super::EnergyReference`].
    EnergyError,
    /// Rotational temperature `2 K / (3 n)`.
    Temperature,
    /// `max_i ||Q_i| - 1|`.
    NormError,
    /// `max_i |Q_i . Q_i'|` (zeroth component of eq 15a).
    NormVelocity,
    /// `max_i |Q_i . N_i|` (zeroth component of eq 15b; scheme B only).
    NormForce,
    /// The total dipole `M = sum_i R(Q_i) mu_i`, space frame
    /// ([`total_dipole`]): three columns.
    TotalDipole,
    /// `|M|^2`.
    TotalDipoleSquared,
    /// The polar order `P1 = <u>.d` of the dipole directions `u_i` along
    /// their director `d` ([`nematic_order`]).
    DipolePolarOrder,
    /// The nematic order `P2` of the dipole directions and their director
    /// `d` (space frame, signed so that `<u>.d >= 0`): four columns.
    DipoleNematicOrder,
    /// The nematic order `P2` of the quadrupole axes
    /// ([`crate::observables::multipole_axes`]) and their director: four
    /// columns.
    QuadrupoleNematicOrder,
}

/// Which multipole a quantity reads from the rotors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Carrier {
    Dipole,
    Quadrupole,
}

/// The largest magnitude of a per-rotor diagnostic (NaN if any is NaN).
fn max_abs(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(
        0.0,
        |m: f64, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
    )
}

impl Quantity {
    /// Every quantity, in the order of [`Quantity::name`]'s documentation.
    pub const ALL: [Quantity; 14] = [
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
        Quantity::ConservedEnergy,
        Quantity::EnergyError,
        Quantity::Temperature,
        Quantity::NormError,
        Quantity::NormVelocity,
        Quantity::NormForce,
        Quantity::TotalDipole,
        Quantity::TotalDipoleSquared,
        Quantity::DipolePolarOrder,
        Quantity::DipoleNematicOrder,
        Quantity::QuadrupoleNematicOrder,
    ];

    /// The name used in scene files (and as the CSV column header of a
    /// scalar).
    pub fn name(&self) -> &'static str {
        match self {
            Quantity::KineticEnergy => "kinetic_energy",
            Quantity::PotentialEnergy => "potential_energy",
            Quantity::TotalEnergy => "total_energy",
            Quantity::ConservedEnergy => "conserved_energy",
            Quantity::EnergyError => "energy_error",
            Quantity::Temperature => "temperature",
            Quantity::NormError => "norm_error",
            Quantity::NormVelocity => "q_dot_q",
            Quantity::NormForce => "q_dot_n",
            Quantity::TotalDipole => "M",
            Quantity::TotalDipoleSquared => "M2",
            Quantity::DipolePolarOrder => "P1_dipole",
            Quantity::DipoleNematicOrder => "P2_dipole",
            Quantity::QuadrupoleNematicOrder => "P2_quadrupole",
        }
    }

    /// The CSV columns: the name of a scalar; `M_x`, `M_y`, `M_z` for `M`;
    /// `P2_<multipole>` then `director_<multipole>_x`, `_y`, `_z` for a
    /// nematic order.
    pub fn columns(&self) -> Vec<String> {
        let name = self.name();
        match self {
            Quantity::TotalDipole => ["x", "y", "z"].map(|c| format!("{name}_{c}")).to_vec(),
            Quantity::DipoleNematicOrder | Quantity::QuadrupoleNematicOrder => {
                let multipole = name.trim_start_matches("P2_");
                std::iter::once(name.to_string())
                    .chain(["x", "y", "z"].map(|c| format!("director_{multipole}_{c}")))
                    .collect()
            }
            _ => vec![name.to_string()],
        }
    }

    /// The multipole the quantity reads from the rotors, if any.
    fn carrier(&self) -> Option<Carrier> {
        match self {
            Quantity::TotalDipole
            | Quantity::TotalDipoleSquared
            | Quantity::DipolePolarOrder
            | Quantity::DipoleNematicOrder => Some(Carrier::Dipole),
            Quantity::QuadrupoleNematicOrder => Some(Carrier::Quadrupole),
            _ => None,
        }
    }

    /// What the value needs from the run loop.
    pub fn needs(&self) -> Needs {
        match self {
            Quantity::KineticEnergy
            | Quantity::PotentialEnergy
            | Quantity::TotalEnergy
            | Quantity::ConservedEnergy
            | Quantity::EnergyError
            | Quantity::Temperature => Needs {
                energies: true,
                ..Needs::default()
            },
            Quantity::NormError
            | Quantity::TotalDipole
            | Quantity::TotalDipoleSquared
            | Quantity::DipolePolarOrder
            | Quantity::DipoleNematicOrder
            | Quantity::QuadrupoleNematicOrder => Needs::default(),
            Quantity::NormVelocity => Needs {
                q_dot: true,
                ..Needs::default()
            },
            Quantity::NormForce => Needs {
                norm_force: true,
                ..Needs::default()
            },
        }
    }

    /// Appends the values at `sample` (as many as [`Quantity::columns`]) to
    /// `out`: NaN when the sample lacks what the quantity needs, or when no
    /// rotor carries the multipole it reads (`multipoles` built without it).
    pub fn write(&self, sample: &Sample<'_>, multipoles: &mut MultipoleInputs, out: &mut Vec<f64>) {
        let energy = |f: fn(&Energies) -> f64| sample.energies.as_ref().map_or(f64::NAN, f);
        let q = sample.orientations;
        let value = match self {
            Quantity::KineticEnergy => energy(|e| e.kinetic),
            Quantity::PotentialEnergy => energy(|e| e.potential),
            Quantity::TotalEnergy => energy(|e| e.total),
            Quantity::ConservedEnergy => energy(|e| e.conserved),
            Quantity::EnergyError => energy(|e| e.error),
            // Three rotational degrees of freedom per rotor, k_B = 1.
            Quantity::Temperature => {
                let dof = 3.0 * q.len() as f64;
                energy(|e| e.kinetic) * 2.0 / dof
            }
            Quantity::NormError => max_abs(q.iter().map(norm_error)),
            Quantity::NormVelocity => sample.q_dot.map_or(f64::NAN, |q_dot| {
                max_abs(q.iter().zip(q_dot).map(|(q, d)| norm_velocity(q, d)))
            }),
            Quantity::NormForce => sample
                .norm_force
                .map_or(f64::NAN, |qn| max_abs(qn.iter().copied())),
            Quantity::TotalDipole => {
                let m = multipoles.total_dipole(q);
                out.extend(m.iter());
                return;
            }
            Quantity::TotalDipoleSquared => multipoles.total_dipole(q).norm_squared(),
            Quantity::DipolePolarOrder => multipoles.order(Carrier::Dipole, q)[0],
            Quantity::DipoleNematicOrder => {
                out.extend(&multipoles.order(Carrier::Dipole, q)[1..]);
                return;
            }
            Quantity::QuadrupoleNematicOrder => {
                out.extend(&multipoles.order(Carrier::Quadrupole, q)[1..]);
                return;
            }
        };
        out.push(value);
    }
}

/// What the quantities of a series read from the rotors: the body dipoles
/// (for `M`, `M2`) and the multipole axes (for the order parameters), each
/// gathered only when a quantity of the series reads it, and a scratch
/// buffer of space axes.
#[derive(Clone, Debug, Default)]
pub struct MultipoleInputs {
    /// One body dipole per rotor (zero where none); empty unless read.
    dipoles_body: Vec<Vector3<f64>>,
    /// The dipole directions; empty unless read.
    dipole_axes: CarriedAxes,
    /// The quadrupole axes; empty unless read.
    quadrupole_axes: CarriedAxes,
    /// The space axes of the last order computed.
    space_axes: Vec<Vector3<f64>>,
}

impl MultipoleInputs {
    /// What `quantities` read from `rotors`. A quantity of a multipole no
    /// rotor carries (nonzero) is refused (path empty, the message naming
    /// the quantity), as is `P2_quadrupole` when a quadrupole has no single
    /// axis ([`crate::observables::multipole_axes::quadrupole_axis`]).
    pub fn new(rotors: &[Rotor], quantities: &[Quantity]) -> Result<Self, InputError> {
        let mut out = MultipoleInputs::default();
        for q in quantities {
            let name = q.name();
            match q.carrier() {
                Some(Carrier::Dipole) => {
                    if out.dipole_axes.is_empty() {
                        out.dipole_axes = CarriedAxes::of_dipoles(rotors);
                    }
                    if out.dipole_axes.is_empty() {
                        return Err(InputError::new(
                            "",
                            format!("`{name}` needs rotors that carry a dipole, and none does"),
                        ));
                    }
                    if matches!(q, Quantity::TotalDipole | Quantity::TotalDipoleSquared)
                        && out.dipoles_body.is_empty()
                    {
                        out.dipoles_body = rotors
                            .iter()
                            .map(|r| r.dipole_body.unwrap_or_default())
                            .collect();
                    }
                }
                Some(Carrier::Quadrupole) => {
                    out.quadrupole_axes = CarriedAxes::of_quadrupoles(rotors).map_err(|e| {
                        InputError::new(
                            "",
                            format!(
                                "`{name}` needs the axis of every quadrupole, but {} {}",
                                e.path, e.message
                            ),
                        )
                    })?;
                    if out.quadrupole_axes.is_empty() {
                        return Err(InputError::new(
                            "",
                            format!("`{name}` needs rotors that carry a quadrupole, and none does"),
                        ));
                    }
                }
                None => {}
            }
        }
        Ok(out)
    }

    /// `M` at `orientations` (NaN without the body dipoles).
    fn total_dipole(&self, orientations: &[Quat]) -> Vector3<f64> {
        if self.dipoles_body.is_empty() {
            return Vector3::repeat(f64::NAN);
        }
        total_dipole(orientations, &self.dipoles_body)
    }

    /// `[P1, P2, d_x, d_y, d_z]` of the axes of `carrier` at `orientations`
    /// (NaN without axes).
    fn order(&mut self, carrier: Carrier, orientations: &[Quat]) -> [f64; 5] {
        let axes = match carrier {
            Carrier::Dipole => &self.dipole_axes,
            Carrier::Quadrupole => &self.quadrupole_axes,
        };
        axes.space_axes(orientations, &mut self.space_axes);
        nematic_order(&self.space_axes).map_or([f64::NAN; 5], |o| {
            [o.p1, o.p2, o.director.x, o.director.y, o.director.z]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Inertia;
    use nalgebra::Matrix3;

    fn sample<'a>(q: &'a [Quat], norm_force: Option<&'a [f64]>) -> Sample<'a> {
        Sample {
            step: 0,
            time: 0.0,
            inertia: &[],
            orientations: q,
            omega_body: None,
            q_dot: None,
            norm_force,
            energies: None,
        }
    }

    fn values(q: Quantity, sample: &Sample<'_>, inputs: &mut MultipoleInputs) -> Vec<f64> {
        let mut out = Vec::new();
        q.write(sample, inputs, &mut out);
        assert_eq!(out.len(), q.columns().len(), "{}", q.name());
        out
    }

    /// Per-rotor diagnostics reduce to the largest magnitude; a missing part
    /// of the sample gives NaN.
    #[test]
    fn diagnostics_reduce_to_the_largest_magnitude() {
        let q = [Quat::IDENTITY, Quat::IDENTITY * 1.5];
        let sample = sample(&q, Some(&[0.5, -2.0]));
        let mut none = MultipoleInputs::default();
        assert_eq!(values(Quantity::NormError, &sample, &mut none), [0.5]);
        assert_eq!(values(Quantity::NormForce, &sample, &mut none), [2.0]);
        assert!(values(Quantity::NormVelocity, &sample, &mut none)[0].is_nan());
        assert!(values(Quantity::Temperature, &sample, &mut none)[0].is_nan());
        assert!(values(Quantity::TotalDipole, &sample, &mut none)
            .iter()
            .all(|x| x.is_nan()));
    }

    /// Three rotors: dipoles 2 z and 1 z, the second turned by 60 degrees
    /// about y (to `u = (sin 60, 0, cos 60)`), a linear quadrupole on the
    /// third, turned the same way. `M = (sin 60, 0, 2.5)` (|Q| does not
    /// matter), `|M|^2 = 7`; two unit axes at angle 60 degrees have
    /// `P2 = (1 + 3 cos 60) / 4` along their bisector and `P1 = cos 30`;
    /// one quadrupole axis has `P2 = 1` along itself.
    #[test]
    fn multipole_quantities_follow_their_definitions() {
        let axial = Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0));
        let rotor = |dipole: Option<Vector3<f64>>, quadrupole| Rotor {
            site: Vector3::zeros(),
            inertia: Inertia::Spherical(1.0),
            dipole_body: dipole,
            quadrupole_body: quadrupole,
        };
        let rotors = [
            rotor(Some(Vector3::z() * 2.0), None),
            rotor(Some(Vector3::z()), None),
            rotor(None, Some(axial)),
        ];
        let angle = std::f64::consts::FRAC_PI_3;
        let turn = Quat::from_axis_angle(&Vector3::y_axis(), angle);
        let q = [Quat::IDENTITY * 2.0, turn, turn];
        let s = sample(&q, None);
        let mut inputs = MultipoleInputs::new(&rotors, &Quantity::ALL[8..]).expect("carried");
        let m = values(Quantity::TotalDipole, &s, &mut inputs);
        let expected = Vector3::new(angle.sin(), 0.0, 2.0 + angle.cos());
        assert!((Vector3::from_column_slice(&m) - expected).norm() < 1e-15);
        let m2 = values(Quantity::TotalDipoleSquared, &s, &mut inputs)[0];
        assert!((m2 - 7.0).abs() < 1e-14);
        let p1 = values(Quantity::DipolePolarOrder, &s, &mut inputs)[0];
        assert!((p1 - (angle / 2.0).cos()).abs() < 1e-14);
        let p2 = values(Quantity::DipoleNematicOrder, &s, &mut inputs);
        assert!((p2[0] - (1.0 + 3.0 * angle.cos()) / 4.0).abs() < 1e-14);
        let bisector = Vector3::new((angle / 2.0).sin(), 0.0, (angle / 2.0).cos());
        assert!((Vector3::from_column_slice(&p2[1..]) - bisector).norm() < 1e-14);
        let quadrupole = values(Quantity::QuadrupoleNematicOrder, &s, &mut inputs);
        assert!((quadrupole[0] - 1.0).abs() < 1e-14);
        let axis = Vector3::new(angle.sin(), 0.0, angle.cos());
        assert!((Vector3::from_column_slice(&quadrupole[1..]) - axis).norm() < 1e-14);
        assert_eq!(
            Quantity::DipoleNematicOrder.columns(),
            [
                "P2_dipole",
                "director_dipole_x",
                "director_dipole_y",
                "director_dipole_z"
            ]
        );
        assert_eq!(Quantity::TotalDipole.columns(), ["M_x", "M_y", "M_z"]);
    }

    /// Only the inputs a series reads are gathered; a quantity of a
    /// multipole no rotor carries is refused, naming the quantity.
    #[test]
    fn multipole_inputs_are_gathered_for_the_quantities_asked() {
        let dipole_only = [Rotor {
            site: Vector3::zeros(),
            inertia: Inertia::Spherical(1.0),
            dipole_body: Some(Vector3::z()),
            quadrupole_body: None,
        }];
        let inputs =
            MultipoleInputs::new(&dipole_only, &[Quantity::DipoleNematicOrder]).expect("carried");
        assert!(inputs.dipoles_body.is_empty() && inputs.quadrupole_axes.is_empty());
        assert_eq!(inputs.dipole_axes.len(), 1);
        let none = MultipoleInputs::new(&dipole_only, &Quantity::ALL[..8]).expect("nothing read");
        assert!(none.dipoles_body.is_empty() && none.dipole_axes.is_empty());
        assert_eq!(
            MultipoleInputs::new(&dipole_only, &[Quantity::QuadrupoleNematicOrder])
                .unwrap_err()
                .message,
            "`P2_quadrupole` needs rotors that carry a quadrupole, and none does"
        );
    }
}
