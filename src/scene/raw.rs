//! The scene file as written: serde structs that mirror the TOML (or JSON)
//! exactly, with `deny_unknown_fields` everywhere and internally tagged enums
//! (`kind = "..."`) of struct variants. Nothing here is checked beyond types;
//! [`super::validate`] turns a [`RawScene`] into a typed [`super::Scene`].

use super::tagged::tagged;
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// A whole scene file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    pub version: i64,
    pub name: Option<String>,
    pub description: Option<String>,
    pub rotors: RawRotors,
    pub interactions: Option<RawInteractions>,
    pub fields: Option<RawFields>,
    pub initial: RawInitial,
    pub integrator: RawIntegrator,
    pub run: RawRun,
    pub record: Option<RawRecord>,
}

impl RawScene {
    /// The scene as JSON without the keys left out (for run summaries).
    pub fn definition(&self) -> serde_json::Value {
        fn strip_nulls(value: &mut serde_json::Value) {
            match value {
                serde_json::Value::Object(map) => {
                    map.retain(|_, v| !v.is_null());
                    map.values_mut().for_each(strip_nulls);
                }
                serde_json::Value::Array(items) => items.iter_mut().for_each(strip_nulls),
                _ => {}
            }
        }
        let mut value = serde_json::to_value(self).unwrap_or_default();
        strip_nulls(&mut value);
        value
    }
}

/// Principal moments: one number (a spherical top) or `[I1, I2, I3]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RawInertia {
    Spherical(f64),
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
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
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

/// Properties every rotor has; in `[rotors.default]` they apply to all rotors.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRotorProps {
    pub inertia: Option<RawInertia>,
    pub dipole: Option<[f64; 3]>,
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// Per-rotor overrides of the defaults on a lattice, by rotor index.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOverride {
    pub index: i64,
    pub inertia: Option<RawInertia>,
    pub dipole: Option<[f64; 3]>,
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// One explicit site and its own properties (overriding the defaults).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSite {
    pub position: [f64; 3],
    pub inertia: Option<RawInertia>,
    pub dipole: Option<[f64; 3]>,
    pub quadrupole: Option<[[f64; 3]; 3]>,
}

/// Where the rotors sit (`kind = "lattice"` or `kind = "sites"`).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawRotors {
    Lattice(RawLattice),
    Sites(RawSites),
}

/// `cells^3` conventional cubic cells of a lattice.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLattice {
    pub lattice: RawLatticeKind,
    pub cells: i64,
    pub spacing: f64,
    #[serde(default)]
    pub default: RawRotorProps,
    #[serde(default, rename = "override")]
    pub overrides: Vec<RawOverride>,
}

/// An explicit list of sites.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSites {
    #[serde(default)]
    pub default: RawRotorProps,
    #[serde(default)]
    pub sites: Vec<RawSite>,
}

tagged!(RawRotors { "lattice" => Lattice(RawLattice), "sites" => Sites(RawSites) });

/// The cubic lattices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RawLatticeKind {
    SimpleCubic,
    Bcc,
    Fcc,
}

/// Pair interactions between the rotors' multipoles.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawInteractions {
    pub terms: Option<Vec<String>>,
    pub boundary: RawBoundary,
}

/// Open (all pairs) or periodic (every image inside a spherical cutoff).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawBoundary {
    Open(RawOpen),
    Periodic(RawPeriodic),
}

/// Open boundaries: no options.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawOpen {}

/// Periodic boundaries.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawPeriodic {
    pub cutoff: f64,
    #[serde(rename = "box")]
    pub box_lengths: Option<[f64; 3]>,
}

tagged!(RawBoundary { "open" => Open(RawOpen), "periodic" => Periodic(RawPeriodic) });

/// External fields acting on every rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawFields {
    pub uniform: Option<[f64; 3]>,
    pub gradient: Option<[[f64; 3]; 3]>,
}

/// Initial orientations and body angular velocities.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawInitial {
    Uniform(RawUniformInitial),
    Explicit(RawExplicitInitial),
    Random(RawRandomInitial),
}

/// The same orientation and angular velocity for every rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawUniformInitial {
    pub orientation: [f64; 4],
    pub omega_body: [f64; 3],
}

/// One orientation and one angular velocity per rotor.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawExplicitInitial {
    pub orientations: Vec<[f64; 4]>,
    pub omega_body: Vec<[f64; 3]>,
}

/// Uniform random orientations and Maxwell angular velocities.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRandomInitial {
    pub seed: Option<u64>,
    pub temperature: f64,
}

tagged!(RawInitial {
    "uniform" => Uniform(RawUniformInitial),
    "explicit" => Explicit(RawExplicitInitial),
    "random" => Random(RawRandomInitial),
});

/// The integrator and its options.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawIntegrator {
    GearA(RawGearA),
    GearB(RawGearB),
    NoSquish(RawNoSquish),
    Dlm(RawDlm),
    Richardson(RawNoOptions),
}

/// Scheme A options.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawGearA {
    pub renormalise: Option<bool>,
    pub startup: Option<String>,
}

/// Scheme B options.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawGearB {
    pub c0: Option<String>,
    pub project_torque: Option<bool>,
    pub project_velocity: Option<bool>,
    pub renormalise: Option<bool>,
    pub correct_higher_derivatives: Option<bool>,
    pub startup: Option<String>,
}

/// NO_SQUISH options.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawNoSquish {
    pub substeps: Option<i64>,
    pub spherical_tops: Option<String>,
}

/// DLM options.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawDlm {
    pub spherical_tops: Option<String>,
}

/// Integrators without options.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawNoOptions {}

tagged!(RawIntegrator {
    "gear_a" => GearA(RawGearA),
    "gear_b" => GearB(RawGearB),
    "no_squish" => NoSquish(RawNoSquish),
    "dlm" => Dlm(RawDlm),
    "richardson" => Richardson(RawNoOptions),
});

/// Time step and length of the run.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRun {
    pub dt: f64,
    pub steps: Option<i64>,
    pub time: Option<f64>,
}

/// What to record; nothing by default.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRecord {
    #[serde(default)]
    pub series: Vec<RawSeries>,
    pub trajectory: Option<RawTrajectory>,
    pub checkpoint_every: Option<i64>,
    pub energy_error_threshold: Option<f64>,
    pub check_every: Option<i64>,
}

/// A table of scalar observables sampled every `every` steps.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSeries {
    pub name: Option<String>,
    pub every: i64,
    pub quantities: Vec<String>,
}

/// Frames of rotor centres and body-axis markers.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawTrajectory {
    pub every: i64,
    pub marker_length: Option<f64>,
}
