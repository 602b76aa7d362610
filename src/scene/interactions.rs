//! The `[interactions]` section: pair interactions between the rotors'
//! multipoles and their boundary, built into the physics [`Boundary`] (which
//! checks the box, the cutoff and the accuracy, [`Boundary::validate`]; this
//! file adds the field paths and the rules of the keys) and the way a
//! periodic sum is taken ([`SumMethod`]). The pair terms follow from the
//! multipoles the rotors carry; the optional `terms` list must name exactly
//! those.

use super::error::SceneError;
use super::model::Interactions;
use super::tagged::tagged;
use crate::checks::{named_choices, num, InputError};
use crate::potential::multipole::DEFAULT_ACCURACY;
use crate::potential::{Boundary, PeriodicSum, SumMethod, Surface};
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

/// How the images of a periodic box are summed (the scene's `sum`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SumKind {
    /// [`PeriodicSum::Ewald`].
    Ewald,
    /// [`PeriodicSum::Cutoff`].
    Cutoff,
}

named_choices!(SumKind {
    "ewald" => SumKind::Ewald,
    "cutoff" => SumKind::Cutoff,
});

/// Periodic boundaries: [`Boundary::Periodic`], whose box defaults to the
/// lattice's, summed by Ewald (`sum = "ewald"`, the default, with `accuracy`
/// and `surface`) or with a spherical cutoff (`sum = "cutoff"` and
/// `cutoff`; a `cutoff` without `sum` means `sum = "cutoff"`, the form of
/// scene files written before the Ewald sum, which run unchanged); `method`
/// chooses the way of summing ([`SumMethod`]).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPeriodic {
    /// The sum: "ewald" (default) or "cutoff" (default when `cutoff` is given).
    pub sum: Option<SumKind>,
    /// The spherical cutoff of `sum = "cutoff"`.
    pub cutoff: Option<f64>,
    /// The relative accuracy of `sum = "ewald"` (default 1e-12).
    pub accuracy: Option<f64>,
    /// The surroundings of `sum = "ewald"` (default conducting).
    pub surface: Option<Surface>,
    /// The way of summing (default "auto").
    pub method: Option<SumMethod>,
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

/// The scene paths of the physics' boundary errors ([`Boundary::validate`]
/// and the sums built from it).
const BOUNDARY_PATHS: [(&str, &str); 4] = [
    ("box_lengths", "interactions.boundary.box"),
    ("cutoff", "interactions.boundary.cutoff"),
    ("accuracy", "interactions.boundary.accuracy"),
    ("method", "interactions.boundary.method"),
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
    concerns_boundary.then(|| SceneError::renamed(e.clone(), &BOUNDARY_PATHS))
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
    let boundary = Boundary::Periodic {
        box_lengths,
        sum: periodic_sum(p)?,
    };
    boundary
        .validate(rotors.len())
        .map_err(|e| SceneError::renamed(e, &BOUNDARY_PATHS))?;
    if explicit_sites {
        check_inside_box(rotors, &box_lengths)?;
    }
    Ok(Interactions {
        boundary,
        method: p.method.unwrap_or_default(),
    })
}

/// The periodic sum of the table: its `sum` (or the one implied: `cutoff`
/// given means a truncated sum), with only the keys of that sum.
fn periodic_sum(p: &RawPeriodic) -> Result<PeriodicSum, SceneError> {
    let path = |key: &str| format!("interactions.boundary.{key}");
    let kind = p.sum.unwrap_or(match p.cutoff {
        Some(_) => SumKind::Cutoff,
        None => SumKind::Ewald,
    });
    match kind {
        SumKind::Cutoff => {
            let why = if p.sum.is_some() {
                "only for sum = \"ewald\", not with sum = \"cutoff\""
            } else {
                "only for sum = \"ewald\" (a cutoff without sum means sum = \"cutoff\")"
            };
            if p.accuracy.is_some() {
                return Err(SceneError::field(path("accuracy"), why));
            }
            if p.surface.is_some() {
                return Err(SceneError::field(path("surface"), why));
            }
            let cutoff = p.cutoff.ok_or_else(|| {
                SceneError::field(path("cutoff"), "required with sum = \"cutoff\"")
            })?;
            Ok(PeriodicSum::Cutoff { cutoff })
        }
        SumKind::Ewald => {
            if p.cutoff.is_some() {
                return Err(SceneError::field(
                    path("cutoff"),
                    "not with sum = \"ewald\" (its real- and reciprocal-space cutoffs \
                     follow from accuracy)",
                ));
            }
            Ok(PeriodicSum::Ewald {
                accuracy: p.accuracy.unwrap_or(DEFAULT_ACCURACY),
                surface: p.surface.unwrap_or_default(),
            })
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
                method: SumMethod::Auto
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
                        accuracy: 1e-6,
                        surface: Surface::Vacuum
                    }
                },
                method: SumMethod::Direct
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
