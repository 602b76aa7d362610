//! The `[fields]` section: a uniform field and field gradient, built into the
//! physics [`ExternalFields`] (which checks them,
//! [`ExternalFields::validate`]; this file adds the field paths and what
//! only a scene can say: a field needs rotors that feel it).

use super::error::SceneError;
use crate::potential::ExternalFields;
use crate::rotor::Rotor;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// External fields acting on every rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawFields {
    /// The uniform field `E`.
    pub uniform: Option<[f64; 3]>,
    /// The field gradient `G[a][b] = dE_b/dr_a`.
    pub gradient: Option<[[f64; 3]; 3]>,
}

/// Validates the section for `rotors`, with or without pair interactions.
pub(super) fn fields(
    raw: &RawFields,
    rotors: &[Rotor],
    with_pairs: bool,
) -> Result<ExternalFields, SceneError> {
    let fields = ExternalFields {
        field: raw.uniform.map(Vector3::from),
        field_gradient: raw.gradient.map(|g| Matrix3::from_fn(|i, j| g[i][j])),
    };
    fields.validate().map_err(|e| {
        SceneError::renamed(
            e,
            &[
                ("field", "fields.uniform"),
                ("field_gradient", "fields.gradient"),
            ],
        )
    })?;
    if fields.field.is_some() && rotors.iter().all(|r| r.dipole_body.is_none()) {
        return Err(SceneError::field(
            "fields.uniform",
            "acts on dipoles, but no rotor has one",
        ));
    }
    if fields.field_gradient.is_some() && rotors.iter().all(|r| r.quadrupole_body.is_none()) {
        return Err(SceneError::field(
            "fields.gradient",
            "acts on quadrupoles, but no rotor has one",
        ));
    }
    let carriers = rotors
        .iter()
        .filter(|r| r.dipole_body.is_some() || r.quadrupole_body.is_some())
        .count();
    if !with_pairs && carriers > 1 {
        return Err(SceneError::field(
            "fields",
            format!(
                "{carriers} rotors carry multipoles: add [interactions] (the multipole potential always includes their pair terms)"
            ),
        ));
    }
    Ok(fields)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Inertia;

    fn dipole() -> Rotor {
        Rotor {
            site: Vector3::zeros(),
            inertia: Inertia::Spherical(1.0),
            dipole_body: Some(Vector3::z()),
            quadrupole_body: None,
        }
    }

    fn check(table: &str, rotors: &[Rotor], with_pairs: bool) -> Result<ExternalFields, String> {
        let raw: RawFields = toml::from_str(table).expect("valid table");
        fields(&raw, rotors, with_pairs).map_err(|e| e.to_string())
    }

    /// The physics' checks come back with the scene's paths, the gradient's
    /// rows as written.
    #[test]
    fn physics_checks_name_the_scene_fields() {
        assert_eq!(
            check("uniform = [0.0, 0.0, 2.0]", &[dipole()], false),
            Ok(ExternalFields {
                field: Some(Vector3::new(0.0, 0.0, 2.0)),
                field_gradient: None
            })
        );
        assert_eq!(
            check("uniform = [0.0, inf, 2.0]", &[dipole()], false),
            Err("fields.uniform[1]: must be finite, got inf".to_string())
        );
        assert_eq!(
            check(
                "gradient = [[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]",
                &[dipole()],
                false
            ),
            Err("fields.gradient: must be symmetric, got [0][1] = 1 but [1][0] = 0".to_string())
        );
        assert_eq!(
            check(
                "gradient = [[0.0, 0.0, 0.0], [0.0, 0.0, nan], [0.0, 0.0, 0.0]]",
                &[dipole()],
                false
            ),
            Err("fields.gradient[1][2]: must be finite, got NaN".to_string())
        );
    }

    /// A field needs rotors that feel it, and several carriers need the pair
    /// terms.
    #[test]
    fn fields_need_rotors_that_feel_them() {
        assert_eq!(
            check(
                "gradient = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -2.0]]",
                &[dipole()],
                false
            ),
            Err("fields.gradient: acts on quadrupoles, but no rotor has one".to_string())
        );
        assert!(check("uniform = [0.0, 0.0, 1.0]", &[dipole(), dipole()], true).is_ok());
        assert!(
            check("uniform = [0.0, 0.0, 1.0]", &[dipole(), dipole()], false)
                .is_err_and(|e| e.starts_with("fields: 2 rotors carry multipoles"))
        );
    }
}
