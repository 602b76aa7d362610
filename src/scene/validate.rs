//! From a [`RawScene`] to a typed [`Scene`]: every check, each error naming
//! the field path and the value (`rotors.sites[3].inertia: must be > 0, got 0`).

use super::error::SceneError;
use super::initial::random_states;
use super::model::*;
use super::raw::*;
use crate::integrators::RotorState;
use crate::lattice::{Lattice, LatticeKind};
use crate::potential::Boundary;
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use nalgebra::{Matrix3, Vector3};

/// The only scene format version this build reads.
pub const SCENE_VERSION: i64 = 1;
/// Largest number of rotors a scene may describe (memory guard).
pub const MAX_ROTORS: usize = 1_000_000;
/// Default interval of the blow-up checks, in steps.
pub const DEFAULT_CHECK_EVERY: u64 = 100;
/// Default distance of the trajectory's body-axis markers from the centre.
pub const DEFAULT_MARKER_LENGTH: f64 = 0.3;
/// Relative tolerance of the symmetry and tracelessness checks of tensors
/// (input written with ~15 significant digits must pass).
const TENSOR_TOLERANCE: f64 = 1e-12;

type Result<T> = std::result::Result<T, SceneError>;

/// Validates a whole scene.
pub fn validate(raw: &RawScene) -> Result<Scene> {
    if raw.version != SCENE_VERSION {
        return Err(SceneError::field(
            "version",
            format!(
                "unsupported version {} (this quatrot reads version {SCENE_VERSION})",
                raw.version
            ),
        ));
    }
    let Sites {
        positions,
        lattice_box,
    } = sites(&raw.rotors)?;
    let rotors = rotors(&raw.rotors, &positions)?;
    let (interactions, box_lengths) = match &raw.interactions {
        Some(i) => interactions(i, &rotors, &raw.rotors, lattice_box)?,
        None => (None, None),
    };
    let fields = match &raw.fields {
        Some(f) => fields(f, &rotors, interactions.is_some())?,
        None => Fields::default(),
    };
    let (initial, seed) = initial(&raw.initial, &rotors)?;
    let integrator = integrator(&raw.integrator)?;
    let (dt, steps) = run(&raw.run)?;
    let record = match &raw.record {
        Some(r) => record(r, &integrator)?,
        None => record(&RawRecord::default(), &integrator)?,
    };
    Ok(Scene {
        name: raw.name.clone().unwrap_or_else(|| "scene".to_string()),
        description: raw.description.clone().unwrap_or_default(),
        rotors,
        box_lengths,
        interactions,
        fields,
        initial,
        seed,
        integrator,
        dt,
        steps,
        record,
    })
}

/// A number as a message shows it: plain in the usual range, in exponent
/// form when very large or very small (Rust's `{}` would print 300 digits).
fn num(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn finite(path: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(SceneError::field(
            path,
            format!("must be finite, got {}", num(v)),
        ))
    }
}

fn positive(path: &str, v: f64) -> Result<f64> {
    finite(path, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(SceneError::field(
            path,
            format!("must be > 0, got {}", num(v)),
        ))
    }
}

fn at_least_one(path: &str, v: i64) -> Result<u64> {
    if v >= 1 {
        Ok(v as u64)
    } else {
        Err(SceneError::field(path, format!("must be >= 1, got {v}")))
    }
}

fn vector(path: &str, v: &[f64; 3]) -> Result<Vector3<f64>> {
    for (k, x) in v.iter().enumerate() {
        finite(&format!("{path}[{k}]"), *x)?;
    }
    Ok(Vector3::from_column_slice(v))
}

fn matrix(path: &str, m: &[[f64; 3]; 3]) -> Result<Matrix3<f64>> {
    for (i, row) in m.iter().enumerate() {
        vector(&format!("{path}[{i}]"), row)?;
    }
    Ok(Matrix3::from_fn(|i, j| m[i][j]))
}

fn symmetric(path: &str, m: &Matrix3<f64>) -> Result<()> {
    let scale = m.amax().max(f64::MIN_POSITIVE);
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if (m[(i, j)] - m[(j, i)]).abs() > TENSOR_TOLERANCE * scale {
            return Err(SceneError::field(
                path,
                format!(
                    "must be symmetric, got [{i}][{j}] = {} but [{j}][{i}] = {}",
                    m[(i, j)],
                    m[(j, i)]
                ),
            ));
        }
    }
    Ok(())
}

fn quaternion(path: &str, q: &[f64; 4]) -> Result<Quat> {
    for (k, x) in q.iter().enumerate() {
        finite(&format!("{path}[{k}]"), *x)?;
    }
    Quat(*q).try_normalize().ok_or_else(|| {
        SceneError::field(
            path,
            format!(
                "must be a non-zero quaternion with a finite norm, got [{}, {}, {}, {}]",
                num(q[0]),
                num(q[1]),
                num(q[2]),
                num(q[3])
            ),
        )
    })
}

fn lattice_kind(kind: RawLatticeKind) -> LatticeKind {
    match kind {
        RawLatticeKind::SimpleCubic => LatticeKind::SimpleCubic,
        RawLatticeKind::Bcc => LatticeKind::Bcc,
        RawLatticeKind::Fcc => LatticeKind::Fcc,
    }
}

/// Sites in the conventional cubic cell.
fn sites_per_cell(kind: LatticeKind) -> u128 {
    match kind {
        LatticeKind::SimpleCubic => 1,
        LatticeKind::Bcc => 2,
        LatticeKind::Fcc => 4,
    }
}

/// The site positions, and the lattice's periodic box if it is a lattice.
struct Sites {
    positions: Vec<Vector3<f64>>,
    lattice_box: Option<Vector3<f64>>,
}

fn sites(raw: &RawRotors) -> Result<Sites> {
    match raw {
        RawRotors::Lattice(RawLattice {
            lattice,
            cells,
            spacing,
            ..
        }) => {
            let cells = at_least_one("rotors.cells", *cells)?;
            let spacing = positive("rotors.spacing", *spacing)?;
            let kind = lattice_kind(*lattice);
            let count = (cells as u128).pow(3) * sites_per_cell(kind);
            if count > MAX_ROTORS as u128 {
                return Err(SceneError::field(
                    "rotors.cells",
                    format!("{cells} cells give {count} rotors, more than the limit {MAX_ROTORS}"),
                ));
            }
            let lattice = Lattice::cubic(kind, cells as usize, spacing)
                .map_err(|e| SceneError::field("rotors", e.to_string()))?;
            Ok(Sites {
                positions: lattice.sites,
                lattice_box: Some(lattice.box_lengths),
            })
        }
        RawRotors::Sites(RawSites { sites, .. }) => {
            if sites.is_empty() {
                return Err(SceneError::field(
                    "rotors.sites",
                    "must list at least one site (empty system)",
                ));
            }
            let positions = sites
                .iter()
                .enumerate()
                .map(|(i, s)| vector(&format!("rotors.sites[{i}].position"), &s.position))
                .collect::<Result<Vec<_>>>()?;
            Ok(Sites {
                positions,
                lattice_box: None,
            })
        }
    }
}

fn inertia(path: &str, raw: &RawInertia) -> Result<Inertia> {
    match raw {
        RawInertia::Spherical(i) => Ok(Inertia::Spherical(positive(path, *i)?)),
        RawInertia::Principal(m) => {
            for (k, x) in m.iter().enumerate() {
                positive(&format!("{path}[{k}]"), *x)?;
            }
            Ok(Inertia::Principal(Vector3::from_column_slice(m)))
        }
    }
}

fn quadrupole(path: &str, raw: &[[f64; 3]; 3]) -> Result<Matrix3<f64>> {
    let q = matrix(path, raw)?;
    symmetric(path, &q)?;
    let scale = q.amax().max(f64::MIN_POSITIVE);
    if q.trace().abs() > TENSOR_TOLERANCE * scale {
        return Err(SceneError::field(
            path,
            format!("must be traceless, got trace {}", q.trace()),
        ));
    }
    Ok(q)
}

/// One rotor's properties: those at `path` override the defaults.
struct Props<'a> {
    path: String,
    inertia: Option<&'a RawInertia>,
    dipole: Option<&'a [f64; 3]>,
    quadrupole: Option<&'a [[f64; 3]; 3]>,
}

fn rotor(site: Vector3<f64>, own: Props, default: &RawRotorProps) -> Result<Rotor> {
    let pick = |field: &str, own_set: bool| {
        if own_set {
            format!("{}.{field}", own.path)
        } else {
            format!("rotors.default.{field}")
        }
    };
    let inertia_raw = own.inertia.or(default.inertia.as_ref()).ok_or_else(|| {
        SceneError::field(
            format!("{}.inertia", own.path),
            "missing (set it here or in rotors.default)",
        )
    })?;
    let inertia = inertia(&pick("inertia", own.inertia.is_some()), inertia_raw)?;
    let dipole_body = own
        .dipole
        .or(default.dipole.as_ref())
        .map(|d| vector(&pick("dipole", own.dipole.is_some()), d))
        .transpose()?;
    let quadrupole_body = own
        .quadrupole
        .or(default.quadrupole.as_ref())
        .map(|q| quadrupole(&pick("quadrupole", own.quadrupole.is_some()), q))
        .transpose()?;
    Ok(Rotor {
        site,
        inertia,
        dipole_body,
        quadrupole_body,
    })
}

fn rotors(raw: &RawRotors, sites: &[Vector3<f64>]) -> Result<Vec<Rotor>> {
    match raw {
        RawRotors::Lattice(RawLattice {
            default, overrides, ..
        }) => {
            let mut own: Vec<Option<(usize, &RawOverride)>> = vec![None; sites.len()];
            for (k, o) in overrides.iter().enumerate() {
                let path = format!("rotors.override[{k}].index");
                if o.index < 0 || o.index as usize >= sites.len() {
                    return Err(SceneError::field(
                        path,
                        format!(
                            "must be in 0..{} (the number of rotors), got {}",
                            sites.len(),
                            o.index
                        ),
                    ));
                }
                if let Some((first, _)) = own[o.index as usize] {
                    return Err(SceneError::field(
                        path,
                        format!(
                            "rotor {} is already overridden by rotors.override[{first}]",
                            o.index
                        ),
                    ));
                }
                own[o.index as usize] = Some((k, o));
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
                    rotor(*site, props, default)
                })
                .collect()
        }
        RawRotors::Sites(RawSites { default, sites: s }) => s
            .iter()
            .zip(sites)
            .enumerate()
            .map(|(i, (s, site))| {
                let props = Props {
                    path: format!("rotors.sites[{i}]"),
                    inertia: s.inertia.as_ref(),
                    dipole: s.dipole.as_ref(),
                    quadrupole: s.quadrupole.as_ref(),
                };
                rotor(*site, props, default)
            })
            .collect(),
    }
}

const TERM_NAMES: [&str; 3] = [
    "dipole_dipole",
    "dipole_quadrupole",
    "quadrupole_quadrupole",
];

fn interactions(
    raw: &RawInteractions,
    rotors: &[Rotor],
    raw_rotors: &RawRotors,
    lattice_box: Option<Vector3<f64>>,
) -> Result<(Option<Interactions>, Option<Vector3<f64>>)> {
    let any_dipole = rotors.iter().any(|r| r.dipole_body.is_some());
    let any_quadrupole = rotors.iter().any(|r| r.quadrupole_body.is_some());
    // The pair terms follow from the multipoles the rotors carry.
    let implied = Terms {
        dipole_dipole: any_dipole,
        dipole_quadrupole: any_dipole && any_quadrupole,
        quadrupole_quadrupole: any_quadrupole,
    };
    if implied == Terms::default() {
        return Err(SceneError::field(
            "interactions",
            "no rotor carries a dipole or a quadrupole, so there is nothing to interact",
        ));
    }
    if let Some(listed) = &raw.terms {
        check_terms(listed, &implied)?;
    }
    let (boundary, box_lengths) = match &raw.boundary {
        RawBoundary::Open(_) => (BoundaryChoice::Open, None),
        RawBoundary::Periodic(RawPeriodic {
            cutoff,
            box_lengths,
        }) => {
            let box_lengths = match (box_lengths, lattice_box) {
                (Some(b), _) => {
                    for (k, x) in b.iter().enumerate() {
                        positive(&format!("interactions.boundary.box[{k}]"), *x)?;
                    }
                    Vector3::from_column_slice(b)
                }
                (None, Some(b)) => b,
                (None, None) => {
                    return Err(SceneError::field(
                        "interactions.boundary.box",
                        "required for a periodic boundary with explicit sites",
                    ))
                }
            };
            let cutoff = positive("interactions.boundary.cutoff", *cutoff)?;
            // Any cutoff is a lattice sum over the images inside it; only its
            // size is limited.
            Boundary::periodic_cutoff(box_lengths, cutoff)
                .validate(rotors.len())
                .map_err(|e| {
                    SceneError::field(format!("interactions.boundary.{}", e.what), e.problem)
                })?;
            if matches!(raw_rotors, RawRotors::Sites(_)) {
                check_inside_box(rotors, &box_lengths)?;
            }
            (BoundaryChoice::Periodic { cutoff }, Some(box_lengths))
        }
    };
    Ok((
        Some(Interactions {
            terms: implied,
            boundary,
        }),
        box_lengths,
    ))
}

/// The listed terms (a check, optional in the file) must be exactly the ones
/// the rotors' multipoles produce.
fn check_terms(listed: &[String], implied: &Terms) -> Result<()> {
    let mut seen = Terms::default();
    for (k, name) in listed.iter().enumerate() {
        let path = format!("interactions.terms[{k}]");
        let (flag, present) = match name.as_str() {
            "dipole_dipole" => (&mut seen.dipole_dipole, implied.dipole_dipole),
            "dipole_quadrupole" => (&mut seen.dipole_quadrupole, implied.dipole_quadrupole),
            "quadrupole_quadrupole" => (
                &mut seen.quadrupole_quadrupole,
                implied.quadrupole_quadrupole,
            ),
            other => {
                return Err(SceneError::field(
                    path,
                    format!(
                        "unknown term `{other}`, expected one of {}",
                        TERM_NAMES.join(", ")
                    ),
                ))
            }
        };
        if *flag {
            return Err(SceneError::field(path, format!("`{name}` is listed twice")));
        }
        if !present {
            return Err(SceneError::field(
                path,
                format!("`{name}` needs multipoles that no rotor carries"),
            ));
        }
        *flag = true;
    }
    for (name, on, listed) in [
        (TERM_NAMES[0], implied.dipole_dipole, seen.dipole_dipole),
        (
            TERM_NAMES[1],
            implied.dipole_quadrupole,
            seen.dipole_quadrupole,
        ),
        (
            TERM_NAMES[2],
            implied.quadrupole_quadrupole,
            seen.quadrupole_quadrupole,
        ),
    ] {
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
fn check_inside_box(rotors: &[Rotor], box_lengths: &Vector3<f64>) -> Result<()> {
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

fn fields(raw: &RawFields, rotors: &[Rotor], with_pairs: bool) -> Result<Fields> {
    let uniform = raw
        .uniform
        .as_ref()
        .map(|e| vector("fields.uniform", e))
        .transpose()?;
    let gradient = raw
        .gradient
        .as_ref()
        .map(|g| {
            let m = matrix("fields.gradient", g)?;
            symmetric("fields.gradient", &m)?;
            Ok(m)
        })
        .transpose()?;
    if uniform.is_some() && rotors.iter().all(|r| r.dipole_body.is_none()) {
        return Err(SceneError::field(
            "fields.uniform",
            "acts on dipoles, but no rotor has one",
        ));
    }
    if gradient.is_some() && rotors.iter().all(|r| r.quadrupole_body.is_none()) {
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
    Ok(Fields { uniform, gradient })
}

fn initial(raw: &RawInitial, rotors: &[Rotor]) -> Result<(Vec<RotorState>, Option<u64>)> {
    let n = rotors.len();
    match raw {
        RawInitial::Uniform(RawUniformInitial {
            orientation,
            omega_body,
        }) => {
            let state = RotorState {
                orientation: quaternion("initial.orientation", orientation)?,
                omega_body: vector("initial.omega_body", omega_body)?,
            };
            Ok((vec![state; n], None))
        }
        RawInitial::Explicit(RawExplicitInitial {
            orientations,
            omega_body,
        }) => {
            for (path, len) in [
                ("initial.orientations", orientations.len()),
                ("initial.omega_body", omega_body.len()),
            ] {
                if len != n {
                    return Err(SceneError::field(
                        path,
                        format!("must have one entry per rotor ({n}), got {len}"),
                    ));
                }
            }
            let states = orientations
                .iter()
                .zip(omega_body)
                .enumerate()
                .map(|(i, (q, w))| {
                    Ok(RotorState {
                        orientation: quaternion(&format!("initial.orientations[{i}]"), q)?,
                        omega_body: vector(&format!("initial.omega_body[{i}]"), w)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            Ok((states, None))
        }
        RawInitial::Random(RawRandomInitial { seed, temperature }) => {
            let temperature = finite("initial.temperature", *temperature)?;
            if temperature < 0.0 {
                return Err(SceneError::field(
                    "initial.temperature",
                    format!("must be >= 0, got {}", num(temperature)),
                ));
            }
            let seed = seed.unwrap_or_else(rand::random);
            let inertia: Vec<Inertia> = rotors.iter().map(|r| r.inertia).collect();
            Ok((random_states(&inertia, temperature, seed), Some(seed)))
        }
    }
}

fn flag(v: Option<bool>, default: bool) -> bool {
    v.unwrap_or(default)
}

fn startup(path: &str, v: &Option<String>) -> Result<GearStartup> {
    match v.as_deref() {
        None | Some("consistent") => Ok(GearStartup::Consistent),
        Some("zeros") => Ok(GearStartup::Zeros),
        Some(other) => Err(SceneError::field(
            path,
            format!("must be \"consistent\" or \"zeros\", got \"{other}\""),
        )),
    }
}

fn spherical_tops(path: &str, v: &Option<String>) -> Result<SphericalTopRotation> {
    match v.as_deref() {
        None | Some("exact") => Ok(SphericalTopRotation::Exact),
        Some("split") => Ok(SphericalTopRotation::Split),
        Some(other) => Err(SceneError::field(
            path,
            format!("must be \"exact\" or \"split\", got \"{other}\""),
        )),
    }
}

fn integrator(raw: &RawIntegrator) -> Result<IntegratorChoice> {
    Ok(match raw {
        RawIntegrator::GearA(o) => IntegratorChoice::GearA {
            renormalise: flag(o.renormalise, true),
            startup: startup("integrator.startup", &o.startup)?,
        },
        RawIntegrator::GearB(o) => IntegratorChoice::GearB {
            c0: match o.c0.as_deref() {
                None | Some("3/16") => GearBC0::ThreeSixteenths,
                Some("3/20") => GearBC0::ThreeTwentieths,
                Some(other) => {
                    return Err(SceneError::field(
                        "integrator.c0",
                        format!("must be \"3/16\" or \"3/20\", got \"{other}\""),
                    ))
                }
            },
            project_torque: flag(o.project_torque, true),
            project_velocity: flag(o.project_velocity, true),
            renormalise: flag(o.renormalise, true),
            correct_higher_derivatives: flag(o.correct_higher_derivatives, false),
            startup: startup("integrator.startup", &o.startup)?,
        },
        RawIntegrator::NoSquish(o) => {
            let substeps = at_least_one("integrator.substeps", o.substeps.unwrap_or(1))?;
            IntegratorChoice::NoSquish {
                substeps: u32::try_from(substeps).map_err(|_| {
                    SceneError::field(
                        "integrator.substeps",
                        format!("must be <= {}, got {substeps}", u32::MAX),
                    )
                })?,
                spherical_tops: spherical_tops("integrator.spherical_tops", &o.spherical_tops)?,
            }
        }
        RawIntegrator::Dlm(o) => IntegratorChoice::Dlm {
            spherical_tops: spherical_tops("integrator.spherical_tops", &o.spherical_tops)?,
        },
        RawIntegrator::Richardson(_) => IntegratorChoice::Richardson,
    })
}

/// Time step and number of steps; a run time is rounded to whole steps.
fn run(raw: &RawRun) -> Result<(f64, u64)> {
    let dt = positive("run.dt", raw.dt)?;
    let steps = match (raw.steps, raw.time) {
        (Some(_), Some(_)) => {
            return Err(SceneError::field(
                "run",
                "give either steps or time, not both",
            ))
        }
        (None, None) => return Err(SceneError::field("run", "give steps or time")),
        (Some(steps), None) => at_least_one("run.steps", steps)?,
        (None, Some(time)) => {
            let time = positive("run.time", time)?;
            let steps = (time / dt).round();
            if steps < 1.0 {
                return Err(SceneError::field(
                    "run.time",
                    format!(
                        "must be at least one step (dt = {}), got {}",
                        num(dt),
                        num(time)
                    ),
                ));
            }
            if steps > u64::MAX as f64 {
                return Err(SceneError::field(
                    "run.time",
                    format!(
                        "gives too many steps of dt = {}, got {}",
                        num(dt),
                        num(time)
                    ),
                ));
            }
            steps as u64
        }
    };
    Ok((dt, steps))
}

fn quantity(path: &str, name: &str) -> Result<Quantity> {
    Quantity::ALL
        .into_iter()
        .find(|q| q.name() == name)
        .ok_or_else(|| {
            let names: Vec<&str> = Quantity::ALL.iter().map(|q| q.name()).collect();
            SceneError::field(
                path,
                format!(
                    "unknown quantity `{name}`, expected one of {}",
                    names.join(", ")
                ),
            )
        })
}

fn record(raw: &RawRecord, integrator: &IntegratorChoice) -> Result<Record> {
    let mut series: Vec<Series> = Vec::with_capacity(raw.series.len());
    for (s, rs) in raw.series.iter().enumerate() {
        let path = format!("record.series[{s}]");
        let name = rs.name.clone().unwrap_or_else(|| match s {
            0 => "observables".to_string(),
            _ => format!("observables{s}"),
        });
        let name_ok = !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !name_ok {
            return Err(SceneError::field(
                format!("{path}.name"),
                format!("must be letters, digits, _ or -, got \"{name}\""),
            ));
        }
        if series.iter().any(|o| o.name == name) {
            return Err(SceneError::field(
                format!("{path}.name"),
                format!("\"{name}\" is used by another series"),
            ));
        }
        let every = at_least_one(&format!("{path}.every"), rs.every)?;
        if rs.quantities.is_empty() {
            return Err(SceneError::field(
                format!("{path}.quantities"),
                "must name at least one quantity",
            ));
        }
        let mut quantities = Vec::with_capacity(rs.quantities.len());
        for (k, qn) in rs.quantities.iter().enumerate() {
            let qpath = format!("{path}.quantities[{k}]");
            let q = quantity(&qpath, qn)?;
            if quantities.contains(&q) {
                return Err(SceneError::field(qpath, format!("`{qn}` is listed twice")));
            }
            if q == Quantity::QDotN && !matches!(integrator, IntegratorChoice::GearB { .. }) {
                return Err(SceneError::field(
                    qpath,
                    format!(
                        "q_dot_n needs an integrator that stores the quaternion force (gear_b), got {}",
                        integrator.name()
                    ),
                ));
            }
            quantities.push(q);
        }
        series.push(Series {
            name,
            every,
            quantities,
        });
    }
    let trajectory = raw
        .trajectory
        .as_ref()
        .map(|t| {
            Ok(TrajectorySpec {
                every: at_least_one("record.trajectory.every", t.every)?,
                marker_length: positive(
                    "record.trajectory.marker_length",
                    t.marker_length.unwrap_or(DEFAULT_MARKER_LENGTH),
                )?,
            })
        })
        .transpose()?;
    let checkpoint_every = raw
        .checkpoint_every
        .map(|c| at_least_one("record.checkpoint_every", c))
        .transpose()?;
    let energy_error_threshold = raw
        .energy_error_threshold
        .map(|t| positive("record.energy_error_threshold", t))
        .transpose()?;
    let check_every = raw
        .check_every
        .map(|c| at_least_one("record.check_every", c))
        .transpose()?
        .unwrap_or(DEFAULT_CHECK_EVERY);
    Ok(Record {
        series,
        trajectory,
        checkpoint_every,
        energy_error_threshold,
        check_every,
    })
}
