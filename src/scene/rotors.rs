//! The `[rotors]` section: where the rotors sit (a cubic lattice or explicit
//! sites) and their inertia and body multipoles, given once in
//! `[rotors.default]` and overridden per rotor. The facts about a lattice, a
//! site or a multipole are checked by the physics ([`Lattice::cubic`],
//! [`rotor::check_site`], [`rotor::check_dipole`],
//! [`rotor::check_quadrupole`]); this file adds the field paths.

use super::error::SceneError;
use super::tagged::tagged;
use crate::checks::{at_least_one, each, positive, InputError};
use crate::lattice::{Lattice, LatticeKind};
use crate::rotor::{self, Inertia, Rotor};
use nalgebra::{Matrix3, Vector3};
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Where the rotors sit (`kind = "lattice"` or `kind = "sites"`).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawRotors {
    /// A cubic lattice.
    Lattice(RawLattice),
    /// Explicit sites.
    Sites(RawSites),
}

tagged!(RawRotors { "lattice" => Lattice(RawLattice), "sites" => Sites(RawSites) });

/// `cells^3` conventional cubic cells of a lattice.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLattice {
    /// The Bravais lattice.
    pub lattice: LatticeKind,
    /// Conventional cells per edge.
    pub cells: i64,
    /// The lattice constant.
    pub spacing: f64,
    /// Properties of every rotor.
    #[serde(default)]
    pub default: RawRotorProps,
    /// Per-rotor overrides, by rotor index.
    #[serde(default, rename = "override")]
    pub overrides: Vec<RawOverride>,
}

/// An explicit list of sites.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSites {
    /// Properties of every rotor.
    #[serde(default)]
    pub default: RawRotorProps,
    /// The sites and their own properties.
    #[serde(default)]
    pub sites: Vec<RawSite>,
}

/// Properties every rotor has; in `[rotors.default]` they apply to all rotors.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRotorProps {
    /// Principal moments of inertia.
    pub inertia: Option<RawInertia>,
    /// Body dipole.
    pub dipole: Option<[f64; 3]>,
    /// Body (Buckingham) quadrupole.
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// Per-rotor overrides of the defaults on a lattice, by rotor index.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOverride {
    /// The rotor (0-based, in the order of the lattice's sites).
    pub index: i64,
    /// Principal moments of inertia.
    pub inertia: Option<RawInertia>,
    /// Body dipole.
    pub dipole: Option<[f64; 3]>,
    /// Body (Buckingham) quadrupole.
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// One explicit site and its own properties (overriding the defaults).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSite {
    /// Position of the site.
    pub position: [f64; 3],
    /// Principal moments of inertia.
    pub inertia: Option<RawInertia>,
    /// Body dipole.
    pub dipole: Option<[f64; 3]>,
    /// Body (Buckingham) quadrupole.
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// Principal moments: one number (a spherical top) or `[I1, I2, I3]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RawInertia {
    /// `I1 = I2 = I3`.
    Spherical(f64),
    /// `[I1, I2, I3]`.
    Principal([f64; 3]),
}

impl Serialize for RawInertia {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            RawInertia::Spherical(i) => serializer.serialize_f64(*i),
            RawInertia::Principal(m) => m.serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for RawInertia {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct InertiaVisitor;
        impl<'de> Visitor<'de> for InertiaVisitor {
            type Value = RawInertia;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawInertia, E> {
                Ok(RawInertia::Spherical(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawInertia, E> {
                Ok(RawInertia::Spherical(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawInertia, E> {
                Ok(RawInertia::Spherical(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<RawInertia, A::Error> {
                let moments = <[f64; 3]>::deserialize(de::value::SeqAccessDeserializer::new(seq))?;
                Ok(RawInertia::Principal(moments))
            }
        }
        deserializer.deserialize_any(InertiaVisitor)
    }
}

/// The rotors of a scene, and the periodic box of its lattice if it is one.
pub(super) struct Rotors {
    pub rotors: Vec<Rotor>,
    pub lattice_box: Option<Vector3<f64>>,
}

/// Validates the section: sites first, then each rotor's properties.
pub(super) fn rotors(raw: &RawRotors) -> Result<Rotors, SceneError> {
    match raw {
        RawRotors::Lattice(l) => {
            let cells = at_least_one(l.cells).map_err(|e| e.at("rotors.cells"))?;
            let lattice =
                Lattice::cubic(l.lattice, cells as usize, l.spacing).map_err(|e| e.at("rotors"))?;
            Ok(Rotors {
                rotors: lattice_rotors(l, &lattice.sites)?,
                lattice_box: Some(lattice.box_lengths),
            })
        }
        RawRotors::Sites(s) => {
            if s.sites.is_empty() {
                return Err(SceneError::field(
                    "rotors.sites",
                    "must list at least one site (empty system)",
                ));
            }
            let positions = s
                .sites
                .iter()
                .enumerate()
                .map(|(i, site)| {
                    let position = Vector3::from(site.position);
                    rotor::check_site(&position)
                        .map_err(|e| e.at(&format!("rotors.sites[{i}].position")))?;
                    Ok(position)
                })
                .collect::<Result<Vec<_>, SceneError>>()?;
            let rotors = s
                .sites
                .iter()
                .zip(positions)
                .enumerate()
                .map(|(i, (site, position))| {
                    let own = Props {
                        path: format!("rotors.sites[{i}]"),
                        inertia: site.inertia.as_ref(),
                        dipole: site.dipole.as_ref(),
                        quadrupole: site.quadrupole.as_ref(),
                    };
                    rotor(position, own, &s.default)
                })
                .collect::<Result<_, _>>()?;
            Ok(Rotors {
                rotors,
                lattice_box: None,
            })
        }
    }
}

/// The rotors on the sites of a lattice: the defaults, with each override
/// applied to its rotor.
fn lattice_rotors(raw: &RawLattice, sites: &[Vector3<f64>]) -> Result<Vec<Rotor>, SceneError> {
    let mut own: Vec<Option<(usize, &RawOverride)>> = vec![None; sites.len()];
    for (k, o) in raw.overrides.iter().enumerate() {
        let path = format!("rotors.override[{k}].index");
        let index = usize::try_from(o.index)
            .ok()
            .filter(|&i| i < sites.len())
            .ok_or_else(|| {
                SceneError::field(
                    &path,
                    format!(
                        "must be in 0..{} (the number of rotors), got {}",
                        sites.len(),
                        o.index
                    ),
                )
            })?;
        if let Some((first, _)) = own[index] {
            return Err(SceneError::field(
                path,
                format!("rotor {index} is already overridden by rotors.override[{first}]"),
            ));
        }
        own[index] = Some((k, o));
    }
    sites
        .iter()
        .zip(own)
        .map(|(site, o)| {
            let props = match o {
                Some((k, o)) => Props {
                    path: format!("rotors.override[{k}]"),
                    inertia: o.inertia.as_ref(),
                    dipole: o.dipole.as_ref(),
                    quadrupole: o.quadrupole.as_ref(),
                },
                None => Props {
                    path: "rotors.default".to_string(),
                    inertia: None,
                    dipole: None,
                    quadrupole: None,
                },
            };
            rotor(*site, props, &raw.default)
        })
        .collect()
}

/// One rotor's own properties (at `path`), which override the defaults.
struct Props<'a> {
    path: String,
    inertia: Option<&'a RawInertia>,
    dipole: Option<&'a [f64; 3]>,
    quadrupole: Option<&'a [[f64; 3]; 3]>,
}

/// The rotor at `site`: each property from `own` if set there, otherwise
/// from `default`, checked with the path of where it was written.
fn rotor(site: Vector3<f64>, own: Props<'_>, default: &RawRotorProps) -> Result<Rotor, SceneError> {
    let path = |field: &str, own_set: bool| {
        if own_set {
            format!("{}.{field}", own.path)
        } else {
            format!("rotors.default.{field}")
        }
    };
    let raw_inertia = own.inertia.or(default.inertia.as_ref()).ok_or_else(|| {
        SceneError::field(
            format!("{}.inertia", own.path),
            "missing (set it here or in rotors.default)",
        )
    })?;
    let inertia =
        inertia(raw_inertia).map_err(|e| e.at(&path("inertia", own.inertia.is_some())))?;
    let dipole_body = own
        .dipole
        .or(default.dipole.as_ref())
        .map(|d| {
            let d = Vector3::from(*d);
            rotor::check_dipole(&d)
                .map(|()| d)
                .map_err(|e| e.at(&path("dipole", own.dipole.is_some())))
        })
        .transpose()?;
    let quadrupole_body = own
        .quadrupole
        .or(default.quadrupole.as_ref())
        .map(|q| {
            let q = Matrix3::from_fn(|i, j| q[i][j]);
            rotor::check_quadrupole(&q)
                .map(|()| q)
                .map_err(|e| e.at(&path("quadrupole", own.quadrupole.is_some())))
        })
        .transpose()?;
    Ok(Rotor {
        site,
        inertia,
        dipole_body,
        quadrupole_body,
    })
}

/// Moments of inertia: each finite and > 0 (the scene's rotors are
/// three-dimensional bodies; the baselines also accept zero moments), and a
/// normal number, so that `1 / I` is finite.
fn inertia(raw: &RawInertia) -> Result<Inertia, InputError> {
    let moment = |i: f64| {
        let i = positive(i)?;
        if i < f64::MIN_POSITIVE {
            return Err(InputError::new(
                "",
                format!(
                    "must be at least {:e} (1 / I must be finite), got {i:e}",
                    f64::MIN_POSITIVE
                ),
            ));
        }
        Ok(i)
    };
    match raw {
        RawInertia::Spherical(i) => Ok(Inertia::Spherical(moment(*i)?)),
        RawInertia::Principal(m) => {
            each(m, moment)?;
            Ok(Inertia::Principal(Vector3::from(*m)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sites(text: &str) -> Result<Rotors, SceneError> {
        let raw: RawRotors = toml::from_str(text).expect("valid table");
        rotors(&raw)
    }

    /// A property set on a site overrides the default, and the path of an
    /// error names where the bad value was written.
    #[test]
    fn own_properties_override_the_defaults_and_errors_name_their_origin() {
        let ok = sites(
            "kind = 'sites'\ndefault = { inertia = 1.0, dipole = [0.0, 0.0, 1.0] }\n\
             sites = [{ position = [0.0, 0.0, 0.0] }, { position = [1.0, 0.0, 0.0], inertia = [1.0, 2.0, 3.0] }]",
        )
        .expect("valid");
        assert_eq!(ok.rotors[0].inertia, Inertia::Spherical(1.0));
        assert_eq!(
            ok.rotors[1].inertia,
            Inertia::Principal(Vector3::new(1.0, 2.0, 3.0))
        );
        assert!(ok.lattice_box.is_none());
        let bad_own = sites(
            "kind = 'sites'\ndefault = { inertia = 1.0 }\n\
             sites = [{ position = [0.0, 0.0, 0.0], dipole = [0.0, nan, 0.0] }]",
        );
        assert_eq!(
            bad_own.err().map(|e| e.to_string()).as_deref(),
            Some("rotors.sites[0].dipole[1]: must be finite, got NaN")
        );
        let bad_default = sites(
            "kind = 'sites'\ndefault = { inertia = 1.0, quadrupole = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] }\n\
             sites = [{ position = [0.0, 0.0, 0.0] }]",
        );
        assert_eq!(
            bad_default.err().map(|e| e.to_string()).as_deref(),
            Some("rotors.default.quadrupole: must be traceless, got trace 3")
        );
    }

    /// A lattice gives its sites in order and its box; an override changes
    /// one rotor, and an index out of range is refused.
    #[test]
    fn lattice_overrides_change_one_rotor() {
        let lattice = "kind = 'lattice'\nlattice = 'bcc'\ncells = 2\nspacing = 1.5\n\
                       default = { inertia = 1.0 }\n";
        let ok = sites(&format!(
            "{lattice}override = [{{ index = 3, inertia = 2.0 }}]"
        ))
        .expect("valid");
        assert_eq!(ok.rotors.len(), 16);
        assert_eq!(ok.lattice_box, Some(Vector3::repeat(3.0)));
        assert_eq!(ok.rotors[3].inertia, Inertia::Spherical(2.0));
        assert_eq!(ok.rotors[4].inertia, Inertia::Spherical(1.0));
        let err = sites(&format!(
            "{lattice}override = [{{ index = -1, inertia = 2.0 }}]"
        ));
        assert_eq!(
            err.err().map(|e| e.to_string()).as_deref(),
            Some("rotors.override[0].index: must be in 0..16 (the number of rotors), got -1")
        );
        let err = sites("kind = 'lattice'\nlattice = 'fcc'\ncells = -2\nspacing = 1.0");
        assert_eq!(
            err.err().map(|e| e.to_string()).as_deref(),
            Some("rotors.cells: must be >= 1, got -2")
        );
    }
}
