//! Bodies as a scene writes them (`[bodies]`: given, random or on a
//! lattice; `[body_interactions]`), read with the body types
//! ([`mod@super::body_types`]) into a [`BodyScene`], errors naming the field
//! (`bodies.random.density`).

use super::body_types::{checked_types, RawBodyType};
use super::error::SceneError;
use super::initial::{drawn_seed, RawInitial};
use super::interactions::forced_mesh;
use super::parse::parse_value;
use super::tagged::tagged;
use crate::bodies::{
    lattice_start, random_start, Body, BodyQuantity, BodySystem, BodyType, ElectrostaticTruncation,
    ElectrostaticsOptions, EwaldOptions, InteractionOptions, Lattice, LatticeStart,
    LennardJonesOptions, Mixing, RandomStart, Space, Truncation, DEFAULT_ACCURACY,
    OVERLAP_FRACTION,
};
use crate::checks::{each, finite, num, InputError};
use crate::potential::multipole::{SumMethod, Surface};
use crate::quaternion::Quat;
use crate::units::{Dimension, Units};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The `[bodies]` section: the bodies given one by one, or generated.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawBodies {
    /// Each body's state written out.
    Given(RawGivenBodies),
    /// Random non-overlapping centres in a periodic cube.
    Random(RawRandomBodies),
    /// The sites of a cubic lattice filling a periodic cube.
    Lattice(RawLatticeBodies),
}

tagged!(RawBodies {
    "given" => Given(RawGivenBodies),
    "random" => Random(RawRandomBodies),
    "lattice" => Lattice(RawLatticeBodies),
});

/// Bodies given one by one, in open space or a periodic box.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawGivenBodies {
    /// The bodies.
    pub list: Vec<RawBody>,
    /// The periodic box's edges (absent: open space).
    #[serde(rename = "box")]
    pub box_lengths: Option<[f64; 3]>,
}

/// One given body.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBody {
    /// Its index in `body_types` (default 0).
    #[serde(rename = "type")]
    pub body_type: Option<usize>,
    /// The centre.
    pub position: [f64; 3],
    /// The principal frame's orientation (default identity).
    pub orientation: Option<[f64; 4]>,
    /// The centre's velocity (default 0).
    pub velocity: Option<[f64; 3]>,
    /// The angular velocity, principal body frame.
    pub angular_velocity: Option<[f64; 3]>,
    /// The angular momentum, principal body frame.
    pub angular_momentum: Option<[f64; 3]>,
}

/// Random sequential insertion ([`crate::bodies::random_start`]).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRandomBodies {
    /// Bodies of each type, in type order.
    pub counts: Vec<usize>,
    /// Number density of centres.
    pub density: f64,
    /// The smallest distance between centres (default 1).
    pub closest: Option<f64>,
}

/// A cubic lattice ([`crate::bodies::lattice_start`]).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLatticeBodies {
    /// Bodies of each type, in type order.
    pub counts: Vec<usize>,
    /// Number density of centres.
    pub density: f64,
    /// The lattice (default fcc).
    pub lattice: Option<Lattice>,
    /// Every body's orientation (default uniformly random).
    pub orientation: Option<[f64; 4]>,
}

/// The `[body_interactions]` section.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBodyInteractions {
    /// `{ cutoff, truncation, mixing }`.
    pub lennard_jones: Option<RawLennardJonesOptions>,
    /// How charges and dipoles are summed.
    pub electrostatics: Option<RawBodyElectrostatics>,
    /// The neighbour lists' skin (default [`DEFAULT_SKIN`]).
    pub skin: Option<f64>,
}

/// The Lennard-Jones options.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawLennardJonesOptions {
    /// The cutoff.
    pub cutoff: f64,
    /// Default plain.
    pub truncation: Option<Truncation>,
    /// Default Lorentz-Berthelot.
    pub mixing: Option<Mixing>,
}

/// The electrostatics of bodies: the one choice of method.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RawBodyElectrostatics {
    /// Bare pair terms inside a spherical cutoff.
    Cutoff(RawElectrostaticCutoff),
    /// The Ewald sum (periodic boxes).
    Ewald(RawBodyEwald),
}

tagged!(RawBodyElectrostatics {
    "cutoff" => Cutoff(RawElectrostaticCutoff),
    "ewald" => Ewald(RawBodyEwald),
});

/// The Ewald sum of bodies' sites: the rotors' boundary options' names and meanings.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawBodyEwald {
    /// Relative accuracy (default [`DEFAULT_ACCURACY`]).
    pub accuracy: Option<f64>,
    /// `"pme"`, `"direct"` or `"auto"` (default: the cheaper by the cost models).
    pub method: Option<SumMethod>,
    /// `"conducting"` (default) or `"vacuum"`.
    pub surface: Option<Surface>,
    /// The spline order forced (`method = "pme"` only, as the next three).
    pub order: Option<i64>,
    /// The mesh forced: one count of points for every axis, or three.
    pub grid: Option<toml::Value>,
    /// The real-space cutoff forced.
    pub real_cutoff: Option<f64>,
    /// The splitting parameter forced.
    pub alpha: Option<f64>,
}

/// The cutoff of charges and dipoles.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawElectrostaticCutoff {
    /// The cutoff.
    pub cutoff: f64,
    /// `"plain"` (default) or `"shifted_force"`.
    pub truncation: Option<ElectrostaticTruncation>,
}

/// The neighbour lists' skin when a scene gives none (LAMMPS's default in
/// LJ units).
pub const DEFAULT_SKIN: f64 = 0.3;

/// A validated system of bodies: what [`BodySystem::new`] is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyScene {
    /// The body types.
    pub types: Vec<BodyType>,
    /// The bodies at t = 0.
    pub bodies: Vec<Body>,
    /// Open space or the periodic box.
    pub space: Space,
    /// The interactions.
    pub interactions: InteractionOptions,
    /// The series to record.
    pub series: Vec<BodySeries>,
}

/// A table of body observables sampled every `every` steps.
#[derive(Debug, Clone, PartialEq)]
pub struct BodySeries {
    /// File stem and key of the table.
    pub name: String,
    /// Sampling interval in steps (>= 1).
    pub every: u64,
    /// The columns after `step` and `time`.
    pub quantities: Vec<BodyQuantity>,
}

impl BodyScene {
    /// The system of the scene at t = 0.
    pub fn system(&self) -> Result<BodySystem, SceneError> {
        BodySystem::new(
            self.types.clone(),
            self.bodies.clone(),
            self.space,
            &self.interactions,
        )
        .map_err(|e| SceneError::renamed(e, SYSTEM_PATHS))
    }
}

/// The scene paths of [`BodySystem::new`]'s errors.
const SYSTEM_PATHS: &[(&str, &str)] = &[
    ("bodies", "bodies.list"),
    ("lennard_jones", "body_interactions.lennard_jones"),
    ("electrostatics", "body_interactions.electrostatics"),
    ("skin", "body_interactions.skin"),
    ("box_lengths", "bodies.box"),
];

/// The body types, bodies, space and interactions of a scene, with the
/// seed of a generated start; refuses overlapping sites
/// ([`crate::bodies::OVERLAP_FRACTION`]).
pub(super) fn body_scene(
    raw_types: Option<&Vec<RawBodyType>>,
    raw: &RawBodies,
    interactions: Option<&RawBodyInteractions>,
    initial: Option<&RawInitial>,
    units: Units,
) -> Result<(BodyScene, Option<u64>), SceneError> {
    let Some(raw_types) = raw_types.filter(|t| !t.is_empty()) else {
        return Err(SceneError::field(
            "body_types",
            "missing: a scene of bodies lists at least one body type",
        ));
    };
    let types = checked_types(raw_types, units)?;
    let (space, bodies, seed) = start(&types, raw, initial, units)?;
    let interactions = interaction_options(interactions.cloned().unwrap_or_default())
        .map_err(|e| SceneError::renamed(e, SYSTEM_PATHS))?;
    let scene = BodyScene {
        types,
        bodies,
        space,
        interactions,
        series: Vec::new(),
    };
    let mut system = scene.system().map_err(|e| match (e, raw) {
        (SceneError::Field { path, message }, RawBodies::Random(_) | RawBodies::Lattice(_))
            if path.starts_with("bodies.box") =>
        {
            SceneError::field(
                "bodies.density",
                format!("the cube of the bodies at this density is too small: {message}"),
            )
        }
        (e, _) => e,
    })?;
    if let Some(o) = system.first_overlap() {
        let path = match raw {
            RawBodies::Given(_) => format!("bodies.list[{}].position", o.bodies.1),
            RawBodies::Random(_) => "bodies.closest".to_string(),
            RawBodies::Lattice(_) => "bodies.orientation".to_string(),
        };
        return Err(SceneError::field(
            path,
            format!(
                "sites of bodies {} and {} start {} apart, closer than {OVERLAP_FRACTION} of their sigma ({})",
                o.bodies.0,
                o.bodies.1,
                num(o.distance),
                num(o.sigma)
            ),
        ));
    }
    Ok((scene, seed))
}

/// The interaction options of the section (checked by the system; the
/// forced mesh parameters by their owner), errors naming the field
/// (`electrostatics.grid`).
fn interaction_options(raw: RawBodyInteractions) -> Result<InteractionOptions, InputError> {
    Ok(InteractionOptions {
        lennard_jones: raw.lennard_jones.map(|lj| LennardJonesOptions {
            cutoff: lj.cutoff,
            truncation: lj.truncation.unwrap_or_default(),
            mixing: lj.mixing.unwrap_or_default(),
        }),
        electrostatics: raw.electrostatics.map(electrostatics_options).transpose()?,
        skin: raw.skin.unwrap_or(DEFAULT_SKIN),
    })
}

/// The options of an `electrostatics` table, defaults filled in, the
/// forced mesh parameters checked ([`forced_mesh`]; path `electrostatics.grid`).
fn electrostatics_options(raw: RawBodyElectrostatics) -> Result<ElectrostaticsOptions, InputError> {
    Ok(match raw {
        RawBodyElectrostatics::Cutoff(c) => {
            ElectrostaticsOptions::Cutoff(c.cutoff, c.truncation.unwrap_or_default())
        }
        RawBodyElectrostatics::Ewald(e) => ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy: e.accuracy.unwrap_or(DEFAULT_ACCURACY),
            method: e.method.unwrap_or_default(),
            surface: e.surface.unwrap_or_default(),
            forced: forced_mesh(e.order, e.grid.as_ref(), e.real_cutoff, e.alpha)
                .map_err(|err| err.at("electrostatics"))?,
        }),
    })
}

/// The options of `value`, a `[body_interactions] electrostatics` table
/// (`quatrot.bodies_evaluate`'s `electrostatics`), errors naming the field
/// (`electrostatics.accuracy`); the values are checked by the system.
pub fn body_electrostatics(value: toml::Value) -> Result<ElectrostaticsOptions, SceneError> {
    let mut table = toml::Table::new();
    let _ = table.insert("electrostatics".to_string(), value);
    let raw: RawElectrostaticsTable = parse_value(toml::Value::Table(table))?;
    Ok(electrostatics_options(raw.electrostatics)?)
}

/// A lone `electrostatics` table.
#[derive(Deserialize)]
struct RawElectrostaticsTable {
    electrostatics: RawBodyElectrostatics,
}

/// The space and the bodies at t = 0, with the seed that drew them.
fn start(
    types: &[BodyType],
    raw: &RawBodies,
    initial: Option<&RawInitial>,
    units: Units,
) -> Result<(Space, Vec<Body>, Option<u64>), SceneError> {
    let paths = [
        ("temperature", "initial.temperature"),
        ("density", "bodies.density"),
        ("closest", "bodies.closest"),
        ("orientation", "bodies.orientation"),
        ("counts", "bodies.counts"),
    ];
    let started = match raw {
        RawBodies::Given(given) => return given_start(given, types, initial, units),
        RawBodies::Random(r) => {
            let (kinds, temperature, seed) = generated(&r.counts, types, initial, units)?;
            let start = RandomStart {
                density: r.density,
                closest: r.closest.unwrap_or(1.0),
                temperature,
                seed,
            };
            random_start(types, &kinds, &start).map(|(space, bodies)| (space, bodies, seed))
        }
        RawBodies::Lattice(l) => {
            let (kinds, temperature, seed) = generated(&l.counts, types, initial, units)?;
            let start = LatticeStart {
                lattice: l.lattice.unwrap_or_default(),
                density: l.density,
                orientation: l.orientation.map(Quat),
                temperature,
                seed,
            };
            lattice_start(types, &kinds, &start).map(|(space, bodies)| (space, bodies, seed))
        }
    };
    let (space, bodies, seed) = started.map_err(|e| SceneError::renamed(e, &paths))?;
    Ok((space, bodies, Some(seed)))
}

/// Given bodies (no `[initial]`: they carry their velocities).
fn given_start(
    given: &RawGivenBodies,
    types: &[BodyType],
    initial: Option<&RawInitial>,
    units: Units,
) -> Result<(Space, Vec<Body>, Option<u64>), SceneError> {
    if initial.is_some() {
        return Err(SceneError::field(
            "initial",
            "given bodies carry their own velocities: leave [initial] out",
        ));
    }
    let bodies = given
        .list
        .iter()
        .enumerate()
        .map(|(i, b)| {
            given_body(b, types, units)
                .map_err(|e| SceneError::from(e.at(&format!("bodies.list[{i}]"))))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if bodies.is_empty() {
        return Err(SceneError::field(
            "bodies.list",
            "must hold at least one body",
        ));
    }
    let space = given
        .box_lengths
        .map_or(Space::Open, |l| Space::Periodic(Vector3::from(l)));
    Ok((space, bodies, None))
}

/// The type of each generated body (in type order) of `counts`, and the
/// temperature (in the engine's units) and seed of `[initial]`.
fn generated(
    counts: &[usize],
    types: &[BodyType],
    initial: Option<&RawInitial>,
    units: Units,
) -> Result<(Vec<usize>, f64, u64), SceneError> {
    let (temperature, seed) = match initial {
        Some(RawInitial::Random(r)) if units == Units::Real && r.temperature < 0.0 => {
            return Err(SceneError::field(
                "initial.temperature",
                format!("must be >= 0 K, got {} K", num(r.temperature)),
            ))
        }
        Some(RawInitial::Random(r)) => (
            units.to_internal(r.temperature, Dimension::Temperature),
            r.seed.unwrap_or_else(drawn_seed),
        ),
        Some(_) => {
            return Err(SceneError::field(
                "initial.kind",
                "generated bodies start from kind = \"random\" (a temperature and a seed)",
            ))
        }
        None => {
            return Err(SceneError::field(
                "initial",
                "missing: generated bodies need [initial] kind = \"random\" with a temperature",
            ))
        }
    };
    if counts.len() != types.len() {
        return Err(SceneError::field(
            "bodies.counts",
            format!(
                "must give one count per body type ({}), got {}",
                types.len(),
                counts.len()
            ),
        ));
    }
    let kinds: Vec<usize> = counts
        .iter()
        .enumerate()
        .flat_map(|(t, &c)| std::iter::repeat_n(t, c))
        .collect();
    if kinds.is_empty() {
        return Err(SceneError::field(
            "bodies.counts",
            "must add up to at least one body",
        ));
    }
    Ok((kinds, temperature, seed))
}

/// One given body, its velocities converted from `units`; errors name its
/// field.
fn given_body(raw: &RawBody, types: &[BodyType], units: Units) -> Result<Body, InputError> {
    let rate = |v: [f64; 3]| Vector3::from(v).map(|c| units.to_internal(c, Dimension::Rate));
    let kind = raw.body_type.unwrap_or(0);
    let moments = types.get(kind).map(|t| t.moments).ok_or_else(|| {
        InputError::new(
            "type",
            format!(
                "must be below the number of body types ({}), got {kind}",
                types.len()
            ),
        )
    })?;
    let angular_momentum_body = match (raw.angular_velocity, raw.angular_momentum) {
        (Some(_), Some(_)) => {
            return Err(InputError::new(
                "angular_momentum",
                "give the angular velocity or the angular momentum, not both",
            ))
        }
        (Some(w), None) => {
            each(&w, finite).map_err(|e| e.at("angular_velocity"))?;
            Vector3::from_fn(|k, _| moments[k] * units.to_internal(w[k], Dimension::Rate))
        }
        (None, Some(l)) => rate(l),
        (None, None) => Vector3::zeros(),
    };
    Ok(Body {
        kind,
        position: Vector3::from(raw.position),
        image: [0; 3],
        velocity: rate(raw.velocity.unwrap_or_default()),
        orientation: Quat(raw.orientation.unwrap_or(Quat::IDENTITY.0)),
        angular_momentum_body,
    })
}
