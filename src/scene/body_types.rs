//! Body types as a scene writes them (`body_types = [{ sites = [...] }]`,
//! or a water model, `{ model = "spce" }`; a Python list of dicts reads the
//! same way), read into the physics' [`BodyType`]s with errors naming the
//! field (`body_types[0].sites[2].charge`). Charges, dipoles and
//! quadrupoles are converted from the scene's units here.

use super::error::SceneError;
use super::parse::parse_value;
use super::water::WaterModel;
use crate::bodies::{BodyType, BodyTypeSpec, LennardJones, Site};
use crate::checks::InputError;
use crate::units::{Dimension, Units};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// The `body_types` list.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawBodyTypes {
    body_types: Vec<RawBodyType>,
}

/// One body type.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBodyType {
    /// A water model whose sites the type has (real units only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<WaterModel>,
    /// The sites, at least one (absent with a model).
    pub sites: Option<Vec<RawBodySite>>,
    /// The mass (default: the sum of the site masses).
    pub mass: Option<f64>,
    /// The inertia tensor about the centre (default: from the site masses).
    pub inertia: Option<[[f64; 3]; 3]>,
}

/// One site of a body type.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBodySite {
    /// Position in the type's input frame.
    pub position: [f64; 3],
    /// Mass (default 0).
    pub mass: Option<f64>,
    /// `{ epsilon, sigma }`.
    pub lennard_jones: Option<RawLennardJones>,
    /// Charge (default 0).
    pub charge: Option<f64>,
    /// Point dipole.
    pub dipole: Option<[f64; 3]>,
    /// Traceless symmetric point quadrupole (Buckingham).
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// A site's Lennard-Jones parameters.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLennardJones {
    /// Well depth.
    pub epsilon: f64,
    /// Diameter.
    pub sigma: f64,
}

/// The body types of the list `value` in `units`, read and checked.
pub fn body_types(value: toml::Value, units: Units) -> Result<Vec<BodyType>, SceneError> {
    let mut table = toml::Table::new();
    let _ = table.insert("body_types".to_string(), value);
    let raw: RawBodyTypes = parse_value(toml::Value::Table(table))?;
    checked_types(&raw.body_types, units)
}

/// The physics' body types of raw ones in `units`, errors at `body_types[i]`.
pub(super) fn checked_types(
    raw: &[RawBodyType],
    units: Units,
) -> Result<Vec<BodyType>, SceneError> {
    raw.iter()
        .enumerate()
        .map(|(i, t)| {
            spec(t, units)
                .and_then(|spec| BodyType::new(&spec))
                .map_err(|e| SceneError::from(e.at(&format!("body_types[{i}]"))))
        })
        .collect()
}

fn matrix(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// The sites of `raw`: its model's or its own.
fn raw_sites(raw: &RawBodyType, units: Units) -> Result<Vec<RawBodySite>, InputError> {
    match (raw.model, &raw.sites) {
        (Some(_), Some(_)) => Err(InputError::new(
            "sites",
            "give a water model or the sites, not both",
        )),
        (Some(_), None) if units != Units::Real => Err(InputError::new(
            "model",
            "water models are in real units (Angstrom, kcal/mol, e): set units = \"real\"",
        )),
        (Some(model), None) => Ok(model.sites()),
        (None, Some(sites)) => Ok(sites.clone()),
        (None, None) => Err(InputError::new("sites", "missing")),
    }
}

/// The input-frame spec of `raw`, its electrostatics converted from `units`.
fn spec(raw: &RawBodyType, units: Units) -> Result<BodyTypeSpec, InputError> {
    let site = |s: &RawBodySite| Site {
        position: Vector3::from(s.position),
        mass: s.mass.unwrap_or(0.0),
        lennard_jones: s.lennard_jones.map(|lj| LennardJones {
            epsilon: lj.epsilon,
            sigma: lj.sigma,
        }),
        charge: units.to_internal(s.charge.unwrap_or(0.0), Dimension::Charge),
        dipole: s
            .dipole
            .map(|mu| Vector3::from(mu).map(|c| units.to_internal(c, Dimension::Dipole))),
        quadrupole: s
            .quadrupole
            .as_ref()
            .map(|t| matrix(t).map(|c| units.to_internal(c, Dimension::Quadrupole))),
    };
    Ok(BodyTypeSpec {
        sites: raw_sites(raw, units)?.iter().map(site).collect(),
        mass: raw.mass,
        inertia: raw.inertia.as_ref().map(matrix),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{COULOMB_KCAL_ANGSTROM, DEBYE_E_ANGSTROM};

    /// In real units a site's charge (e) becomes `q sqrt(C)`, its dipole
    /// (D) and quadrupole (D A) `0.20819434 sqrt(C)` times themselves;
    /// positions, masses and Lennard-Jones are kept; reduced units keep
    /// every value.
    #[test]
    fn real_units_scale_the_electrostatics_only() {
        let text = r#"body_types = [{ mass = 18.0, inertia = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]],
            sites = [{ position = [0.0, 0.0, 0.0], charge = -0.5, dipole = [0.0, 0.0, 2.0],
                       quadrupole = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -2.0]],
                       lennard_jones = { epsilon = 0.15, sigma = 3.1 } }] }]"#;
        let table: toml::Table = toml::from_str(text).expect("TOML");
        let value = table["body_types"].clone();
        let real = body_types(value.clone(), Units::Real).expect("real")[0].sites[0].clone();
        let reduced = body_types(value, Units::Reduced).expect("reduced")[0].sites[0].clone();
        let root_c = COULOMB_KCAL_ANGSTROM.sqrt();
        assert_eq!(reduced.charge, -0.5);
        assert!((real.charge - -0.5 * root_c).abs() < 1e-14);
        let dipole = |s: &Site| s.dipole.expect("a dipole").norm();
        assert!((dipole(&real) - 2.0 * DEBYE_E_ANGSTROM * root_c).abs() < 1e-13);
        assert_eq!(dipole(&reduced), 2.0);
        let zz = |s: &Site| s.quadrupole.expect("a quadrupole").amax();
        assert!((zz(&real) - 2.0 * DEBYE_E_ANGSTROM * root_c).abs() < 1e-13);
        assert_eq!(zz(&reduced), 2.0);
        assert_eq!(real.lennard_jones, reduced.lennard_jones);
        assert_eq!(real.position, reduced.position);
    }
}
