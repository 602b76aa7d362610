//! The `[interactions]` section: pair interactions between the rotors'
//! multipoles and their boundary, built into the physics [`Boundary`] (which
//! checks the box and the cutoff, [`Boundary::validate`]; this file adds the
//! field paths). The pair terms follow from the multipoles the rotors carry;
//! the optional `terms` list must name exactly those.

use super::error::SceneError;
use super::tagged::tagged;
use crate::checks::num;
use crate::potential::Boundary;
use crate::rotor::Rotor;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Pair interactions between the rotors' multipoles.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawInteractions {
    /// The pair terms, as a check (optional).
    pub terms: Option<Vec<String>>,
    /// The boundary.
    pub boundary: RawBoundary,
}

/// Open (all pairs) or periodic (every image inside a spherical cutoff).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawBoundary {
    /// All pairs, no cutoff.
    Open(RawOpen),
    /// A periodic box and a cutoff.
    Periodic(RawPeriodic),
}

tagged!(RawBoundary { "open" => Open(RawOpen), "periodic" => Periodic(RawPeriodic) });

/// Open boundaries: no options.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOpen {}

/// Periodic boundaries: [`Boundary::Periodic`], whose box defaults to the
/// lattice's.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPeriodic {
    /// The spherical cutoff.
    pub cutoff: f64,
    /// The box (default: the lattice's).
    #[serde(rename = "box")]
    pub box_lengths: Option<[f64; 3]>,
}

/// The names of the pair terms, in the order they are checked.
const TERM_NAMES: [&str; 3] = [
    "dipole_dipole",
    "dipole_quadrupole",
    "quadrupole_quadrupole",
];

/// Validates the section for `rotors` (listed explicitly when `explicit_sites`;
/// on a lattice whose box is `lattice_box` otherwise): the boundary of the
/// pair interactions.
pub(super) fn interactions(
    raw: &RawInteractions,
    rotors: &[Rotor],
    explicit_sites: bool,
    lattice_box: Option<Vector3<f64>>,
) -> Result<Boundary, SceneError> {
    let any_dipole = rotors.iter().any(|r| r.dipole_body.is_some());
    let any_quadrupole = rotors.iter().any(|r| r.quadrupole_body.is_some());
    // The pair terms follow from the multipoles the rotors carry.
    let implied = [any_dipole, any_dipole && any_quadrupole, any_quadrupole];
    if implied == [false; 3] {
        return Err(SceneError::field(
            "interactions",
            "no rotor carries a dipole or a quadrupole, so there is nothing to interact",
        ));
    }
    if let Some(listed) = &raw.terms {
        check_terms(listed, implied)?;
    }
    match &raw.boundary {
        RawBoundary::Open(_) => Ok(Boundary::Open),
        RawBoundary::Periodic(p) => {
            let box_lengths = match (p.box_lengths, lattice_box) {
                (Some(b), _) => Vector3::from(b),
                (None, Some(b)) => b,
                (None, None) => {
                    return Err(SceneError::field(
                        "interactions.boundary.box",
                        "required for a periodic boundary with explicit sites",
                    ))
                }
            };
            // Any cutoff is a lattice sum over the images inside it; only its
            // size is limited.
            let boundary = Boundary::periodic_cutoff(box_lengths, p.cutoff);
            boundary.validate(rotors.len()).map_err(|e| {
                SceneError::renamed(
                    e,
                    &[
                        ("box_lengths", "interactions.boundary.box"),
                        ("cutoff", "interactions.boundary.cutoff"),
                    ],
                )
            })?;
            if explicit_sites {
                check_inside_box(rotors, &box_lengths)?;
            }
            Ok(boundary)
        }
    }
}

/// The listed terms (a check, optional in the file) must be exactly the ones
/// the rotors' multipoles produce (`implied`, in the order of [`TERM_NAMES`]).
fn check_terms(listed: &[String], implied: [bool; 3]) -> Result<(), SceneError> {
    let mut seen = [false; 3];
    for (k, name) in listed.iter().enumerate() {
        let path = format!("interactions.terms[{k}]");
        let Some(t) = TERM_NAMES.iter().position(|n| n == name) else {
            return Err(SceneError::field(
                path,
                format!(
                    "unknown term `{name}`, expected one of {}",
                    TERM_NAMES.join(", ")
                ),
            ));
        };
        if seen[t] {
            return Err(SceneError::field(path, format!("`{name}` is listed twice")));
        }
        if !implied[t] {
            return Err(SceneError::field(
                path,
                format!("`{name}` needs multipoles that no rotor carries"),
            ));
        }
        seen[t] = true;
    }
    for ((name, on), listed) in TERM_NAMES.iter().zip(implied).zip(seen) {
        if on && !listed {
            return Err(SceneError::field(
                "interactions.terms",
                format!("the rotors' multipoles give the term `{name}`, which is not listed"),
            ));
        }
    }
    Ok(())
}

/// Explicit sites of a periodic system must lie in `[0, L)` on each axis.
fn check_inside_box(rotors: &[Rotor], box_lengths: &Vector3<f64>) -> Result<(), SceneError> {
    for (i, r) in rotors.iter().enumerate() {
        for k in 0..3 {
            if r.site[k] < 0.0 || r.site[k] >= box_lengths[k] {
                return Err(SceneError::field(
                    format!("rotors.sites[{i}].position[{k}]"),
                    format!(
                        "must be in [0, {}) (inside the periodic box), got {}",
                        num(box_lengths[k]),
                        num(r.site[k])
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Inertia;

    fn dipole_at(x: f64) -> Rotor {
        Rotor {
            site: Vector3::new(x, 0.0, 0.0),
            inertia: Inertia::Spherical(1.0),
            dipole_body: Some(Vector3::z()),
            quadrupole_body: None,
        }
    }

    fn check(
        table: &str,
        rotors: &[Rotor],
        lattice_box: Option<Vector3<f64>>,
    ) -> Result<Boundary, String> {
        let raw: RawInteractions = toml::from_str(table).expect("valid table");
        interactions(&raw, rotors, lattice_box.is_none(), lattice_box).map_err(|e| e.to_string())
    }

    /// The box defaults to the lattice's; the physics' box and cutoff checks
    /// come back with the scene's paths (`box`, not `box_lengths`).
    #[test]
    fn periodic_box_defaults_to_the_lattice_and_errors_name_scene_fields() {
        let rotors = [dipole_at(0.0), dipole_at(1.0)];
        let lattice = Some(Vector3::repeat(2.0));
        assert_eq!(
            check(
                "boundary = { kind = 'periodic', cutoff = 0.9 }",
                &rotors,
                lattice
            ),
            Ok(Boundary::periodic_cutoff(Vector3::repeat(2.0), 0.9))
        );
        assert_eq!(
            check(
                "boundary = { kind = 'periodic', cutoff = 0.9, box = [2.0, 0.0, 2.0] }",
                &rotors,
                None
            ),
            Err("interactions.boundary.box[1]: must be > 0, got 0".to_string())
        );
        assert_eq!(
            check(
                "boundary = { kind = 'periodic', cutoff = -1.0 }",
                &rotors,
                lattice
            ),
            Err("interactions.boundary.cutoff: must be > 0, got -1".to_string())
        );
        assert_eq!(
            check("boundary = { kind = 'open' }", &rotors, None),
            Ok(Boundary::Open)
        );
    }

    /// The listed terms must be exactly those the multipoles give.
    #[test]
    fn listed_terms_must_match_the_multipoles() {
        let rotors = [dipole_at(0.0), dipole_at(1.0)];
        let open = "boundary = { kind = 'open' }";
        assert!(check(&format!("terms = ['dipole_dipole']\n{open}"), &rotors, None).is_ok());
        assert_eq!(
            check(
                &format!("terms = ['dipole_quadrupole']\n{open}"),
                &rotors,
                None
            ),
            Err(
                "interactions.terms[0]: `dipole_quadrupole` needs multipoles that no rotor carries"
                    .to_string()
            )
        );
        assert_eq!(
            check(&format!("terms = []\n{open}"), &rotors, None),
            Err("interactions.terms: the rotors' multipoles give the term `dipole_dipole`, which is not listed".to_string())
        );
    }
}
