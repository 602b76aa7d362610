//! The `[interactions]` section: pair interactions between the rotors'
//! multipoles and their boundary, built into the physics [`Boundary`] (the
//! sum's keys read and the accuracy checked by their owner,
//! [`Boundary::periodic`]; the box and the cutoff checked by
//! [`Boundary::validate`]; this file adds the
//! field paths) and the way a periodic sum is taken ([`SumMethod`]). The
//! pair terms follow from the multipoles the rotors carry; the optional
//! `terms` list must name exactly those.

use super::error::SceneError;
use super::model::Interactions;
use super::tagged::tagged;
use crate::checks::{num, InputError};
use crate::potential::multipole::mesh_ewald::ForcedMesh;
pub use crate::potential::SumKind;
use crate::potential::{Boundary, SumMethod, SumOptions, Surface};
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

/// Open (all pairs) or periodic (the Ewald sum, or every image inside a
/// spherical cutoff).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawBoundary {
    /// All pairs, no cutoff.
    Open(RawOpen),
    /// A periodic box and its sum.
    Periodic(RawPeriodic),
}

tagged!(RawBoundary { "open" => Open(RawOpen), "periodic" => Periodic(RawPeriodic) });

/// Open boundaries: no options.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOpen {}

/// Periodic boundaries: [`Boundary::Periodic`], whose box defaults to the
/// lattice's, summed as `sum`, `cutoff`, `accuracy` and `surface` say (read
/// by their owner, [`Boundary::periodic`]: the Ewald sum by default, a
/// spherical cutoff with `sum = "cutoff"` or a `cutoff` alone); `method`
/// chooses the way of summing ([`SumMethod`]); `order`, `grid`,
/// `real_cutoff` and `alpha` force the mesh Ewald sum's parameters
/// ([`ForcedMesh`], `method = "pme"` only).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPeriodic {
    /// [`SumOptions::sum`].
    pub sum: Option<SumKind>,
    /// [`SumOptions::cutoff`].
    pub cutoff: Option<f64>,
    /// [`SumOptions::accuracy`].
    pub accuracy: Option<f64>,
    /// [`SumOptions::surface`].
    pub surface: Option<Surface>,
    /// The way of summing (default "auto").
    pub method: Option<SumMethod>,
    /// [`ForcedMesh::order`].
    pub order: Option<i64>,
    /// [`ForcedMesh::grid`]: one count for every axis, or three.
    pub grid: Option<toml::Value>,
    /// [`ForcedMesh::real_cutoff`].
    pub real_cutoff: Option<f64>,
    /// [`ForcedMesh::alpha`].
    pub alpha: Option<f64>,
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

/// The scene paths of the physics' boundary errors ([`Boundary::periodic`],
/// [`Boundary::validate`] and the sums built from it).
const BOUNDARY_PATHS: [(&str, &str); 9] = [
    ("box_lengths", "interactions.boundary.box"),
    ("cutoff", "interactions.boundary.cutoff"),
    ("accuracy", "interactions.boundary.accuracy"),
    ("surface", "interactions.boundary.surface"),
    ("method", "interactions.boundary.method"),
    ("order", "interactions.boundary.order"),
    ("grid", "interactions.boundary.grid"),
    ("real_cutoff", "interactions.boundary.real_cutoff"),
    ("alpha", "interactions.boundary.alpha"),
];

/// The error of building a scene's potential at the scene's path when it
/// concerns the boundary (`accuracy` becomes `interactions.boundary.accuracy`);
/// `None` for the others (which concern the rotors).
pub fn boundary_error(e: &InputError) -> Option<SceneError> {
    let concerns_boundary = BOUNDARY_PATHS.iter().any(|(physics, _)| {
        e.path
            .strip_prefix(physics)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with(['[', '.']))
    });
    concerns_boundary.then(|| at_scene_path(e.clone()))
}

/// A boundary error of the physics at the scene's path (`accuracy` becomes
/// `interactions.boundary.accuracy`, `box_lengths` `interactions.boundary.box`).
fn at_scene_path(e: InputError) -> SceneError {
    SceneError::renamed(e, &BOUNDARY_PATHS)
}

/// Validates the section for `rotors` (listed explicitly when `explicit_sites`;
/// on a lattice whose box is `lattice_box` otherwise): the boundary of the
/// pair interactions and the way of summing.
pub(super) fn interactions(
    raw: &RawInteractions,
    rotors: &[Rotor],
    explicit_sites: bool,
    lattice_box: Option<Vector3<f64>>,
) -> Result<Interactions, SceneError> {
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
    let RawBoundary::Periodic(p) = &raw.boundary else {
        return Ok(Interactions {
            boundary: Boundary::Open,
            method: SumMethod::Auto,
            forced: ForcedMesh::default(),
        });
    };
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
    let options = SumOptions {
        sum: p.sum,
        cutoff: p.cutoff,
        accuracy: p.accuracy,
        surface: p.surface,
    };
    let boundary = Boundary::periodic(box_lengths, &options).map_err(at_scene_path)?;
    boundary.validate(rotors.len()).map_err(at_scene_path)?;
    if explicit_sites {
        check_inside_box(rotors, &box_lengths)?;
    }
    let method = p.method.unwrap_or_default();
    let forced = forced_mesh(p.order, p.grid.as_ref(), p.real_cutoff, p.alpha)
        .and_then(|forced| method.check_forced(&forced).map(|()| forced))
        .map_err(at_scene_path)?;
    Ok(Interactions {
        boundary,
        method,
        forced,
    })
}

/// The mesh Ewald sum's parameters a table forces (`grid`: one count of
/// mesh points or a list of three), checked by their owner
/// ([`ForcedMesh::new`]); errors name the key (`grid[1]`).
pub(super) fn forced_mesh(
    order: Option<i64>,
    grid: Option<&toml::Value>,
    real_cutoff: Option<f64>,
    alpha: Option<f64>,
) -> Result<ForcedMesh, InputError> {
    let counts = grid
        .map(|value| {
            let bad = || {
                InputError::new(
                    "grid",
                    format!("must be a count of mesh points or a list of three, got {value}"),
                )
            };
            match value {
                toml::Value::Integer(k) => Ok(vec![*k]),
                toml::Value::Array(items) => items
                    .iter()
                    .map(|v| v.as_integer().ok_or_else(bad))
                    .collect(),
                _ => Err(bad()),
            }
        })
        .transpose()?;
    ForcedMesh::new(order, counts.as_deref(), real_cutoff, alpha)
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
    use crate::potential::{Accuracy, PeriodicSum};
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
        interactions(&raw, rotors, lattice_box.is_none(), lattice_box)
            .map(|i| i.boundary)
            .map_err(|e| e.to_string())
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

    /// A periodic boundary without `sum` is the Ewald sum (default accuracy,
    /// conducting surroundings, the automatic path); a `cutoff` without
    /// `sum` is the truncated sum of older scene files; `surface` and
    /// `method` are read by name.
    #[test]
    fn periodic_sum_defaults_to_ewald() {
        let rotors = [dipole_at(0.0), dipole_at(1.0)];
        let l = Vector3::repeat(2.0);
        let read = |table: &str| {
            let raw: RawInteractions = toml::from_str(table).expect("valid table");
            interactions(&raw, &rotors, false, Some(l)).expect("valid")
        };
        assert_eq!(
            read("boundary = { kind = 'periodic' }"),
            Interactions {
                boundary: Boundary::periodic_ewald(l),
                method: SumMethod::Auto,
                forced: ForcedMesh::default(),
            }
        );
        assert_eq!(
            read("boundary = { kind = 'periodic', cutoff = 0.9 }").boundary,
            read("boundary = { kind = 'periodic', sum = 'cutoff', cutoff = 0.9 }").boundary,
        );
        let vacuum = read(
            "boundary = { kind = 'periodic', sum = 'ewald', accuracy = 1e-6, surface = 'vacuum', method = 'direct' }",
        );
        assert_eq!(
            vacuum,
            Interactions {
                boundary: Boundary::Periodic {
                    box_lengths: l,
                    sum: PeriodicSum::Ewald {
                        accuracy: Accuracy::new(1e-6).unwrap(),
                        surface: Surface::Vacuum
                    }
                },
                method: SumMethod::Direct,
                forced: ForcedMesh::default(),
            }
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
