//! Body types as a scene writes them (`body_types = [{ sites = [...] }]`;
//! a Python list of dicts reads the same way), read into the physics'
//! [`BodyType`]s with errors naming the field
//! (`body_types[0].sites[2].charge`).

use super::error::SceneError;
use super::parse::parse_value;
use crate::bodies::{BodyType, BodyTypeSpec, LennardJones, Site};
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
    /// The sites, at least one.
    pub sites: Vec<RawBodySite>,
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

/// The body types of the list `value`, read and checked.
pub fn body_types(value: toml::Value) -> Result<Vec<BodyType>, SceneError> {
    let mut table = toml::Table::new();
    let _ = table.insert("body_types".to_string(), value);
    let raw: RawBodyTypes = parse_value(toml::Value::Table(table))?;
    checked_types(&raw.body_types)
}

/// The physics' body types of raw ones, errors at `body_types[i]`.
pub(super) fn checked_types(raw: &[RawBodyType]) -> Result<Vec<BodyType>, SceneError> {
    raw.iter()
        .enumerate()
        .map(|(i, t)| {
            BodyType::new(&spec(t)).map_err(|e| SceneError::from(e.at(&format!("body_types[{i}]"))))
        })
        .collect()
}

fn matrix(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

fn spec(raw: &RawBodyType) -> BodyTypeSpec {
    let site = |s: &RawBodySite| Site {
        position: Vector3::from(s.position),
        mass: s.mass.unwrap_or(0.0),
        lennard_jones: s.lennard_jones.map(|lj| LennardJones {
            epsilon: lj.epsilon,
            sigma: lj.sigma,
        }),
        charge: s.charge.unwrap_or(0.0),
        dipole: s.dipole.map(Vector3::from),
        quadrupole: s.quadrupole.as_ref().map(matrix),
    };
    BodyTypeSpec {
        sites: raw.sites.iter().map(site).collect(),
        mass: raw.mass,
        inertia: raw.inertia.as_ref().map(matrix),
    }
}
