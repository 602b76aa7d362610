//! The `[record]` section: what a run records (tables of scalar observables,
//! a trajectory, checkpoints) and its blow-up guard. Nothing by default.

use super::bodies::BodySeries;
use super::error::SceneError;
use crate::bodies::{BodyQuantity, Space};
use crate::checks::{at_least_one, named_choices, positive};
use crate::integrators::IntegratorSpec;
use crate::rotor::Rotor;
use crate::simulation::{MultipoleInputs, Quantity};
use serde::{Deserialize, Serialize};

/// Default interval of the blow-up checks, in steps.
pub const DEFAULT_CHECK_EVERY: u64 = 100;
/// Default distance of the trajectory's body-axis markers from the centre.
pub const DEFAULT_MARKER_LENGTH: f64 = 0.3;

/// What to record; nothing by default.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawRecord {
    /// Tables of scalar observables.
    #[serde(default)]
    pub series: Vec<RawSeries>,
    /// Trajectory frames.
    pub trajectory: Option<RawTrajectory>,
    /// Checkpoint interval in steps.
    pub checkpoint_every: Option<i64>,
    /// Stop when `|energy_error|` exceeds this.
    pub energy_error_threshold: Option<f64>,
    /// Interval of the blow-up checks in steps.
    pub check_every: Option<i64>,
}

/// A table of scalar observables sampled every `every` steps.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawSeries {
    /// File stem and key of the table.
    pub name: Option<String>,
    /// Sampling interval in steps.
    pub every: i64,
    /// The quantities' names.
    pub quantities: Vec<String>,
}

/// Trajectory frames: DCD (rotor centres and body-axis markers) or GSD
/// (sites, quaternions, box).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RawTrajectory {
    /// Frame interval in steps.
    pub every: i64,
    /// The file format (default DCD).
    pub format: Option<TrajectoryFormat>,
    /// Distance of the markers from the centre (DCD only).
    pub marker_length: Option<f64>,
}

/// The format of the trajectory file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrajectoryFormat {
    /// `trajectory.dcd` + `topology.pdb`: each rotor as a centre and three
    /// markers along its body axes (the default; mdtraj, VMD).
    #[default]
    Dcd,
    /// `trajectory.gsd`: HOOMD-blue's format, the sites, the orientation
    /// quaternions, the box and the step of each frame
    /// ([`crate::run::GsdWriter`]; the `gsd` package, HOOMD-blue, OVITO,
    /// freud).
    Gsd,
}

named_choices!(TrajectoryFormat {
    "dcd" => TrajectoryFormat::Dcd,
    "gsd" => TrajectoryFormat::Gsd,
});

/// Everything the scene asks to record.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Record {
    /// Tables of scalar observables (CSV).
    pub series: Vec<Series>,
    /// Trajectory frames (DCD + PDB, or GSD).
    pub trajectory: Option<TrajectorySpec>,
    /// Checkpoint interval in steps, if any.
    pub checkpoint_every: Option<u64>,
    /// Stop when `|energy_error|` exceeds this (needs energies at check steps).
    pub energy_error_threshold: Option<f64>,
    /// Interval of the blow-up checks in steps (default 100).
    pub check_every: u64,
}

/// A table of scalar observables sampled every `every` steps (CSV).
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// File stem and key of the table (`[A-Za-z0-9_-]+`, unique).
    pub name: String,
    /// Sampling interval in steps (>= 1); step 0 is always sampled.
    pub every: u64,
    /// The columns after `step` and `time`.
    pub quantities: Vec<Quantity>,
}

/// Trajectory frames: rotor centres and markers along the body axes (DCD),
/// or sites and orientation quaternions (GSD).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrajectorySpec {
    /// Frame interval in steps (>= 1).
    pub every: u64,
    /// The file format.
    pub format: TrajectoryFormat,
    /// Distance of the body-axis markers from the centre (length units, > 0;
    /// DCD only).
    pub marker_length: f64,
}

fn quantity(path: &str, name: &str) -> Result<Quantity, SceneError> {
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

/// One series: its name (default `observables`, `observables1`, ...),
/// interval and quantities (each one the integrator and the rotors can give).
fn series(
    s: usize,
    raw: &RawSeries,
    others: &[Series],
    integrator: &IntegratorSpec,
    rotors: &[Rotor],
) -> Result<Series, SceneError> {
    let names: Vec<&str> = others.iter().map(|o| o.name.as_str()).collect();
    let (path, name, every) = series_head(s, raw, &names)?;
    let quantities = listed(&path, &raw.quantities, |qpath, qn| {
        let q = quantity(qpath, qn)?;
        if q == Quantity::NormForce && !integrator.stores_quaternion_force() {
            return Err(SceneError::field(
                qpath,
                format!(
                    "q_dot_n needs an integrator that stores the quaternion force (gear_b), got {}",
                    integrator.name()
                ),
            ));
        }
        let _ = MultipoleInputs::new(rotors, &[q]).map_err(|e| e.at(qpath))?;
        Ok(q)
    })?;
    Ok(Series {
        name,
        every,
        quantities,
    })
}

/// One series of bodies in `space`: its name, interval and quantities
/// ([`BodyQuantity`]).
fn body_series(
    s: usize,
    raw: &RawSeries,
    others: &[BodySeries],
    space: &Space,
) -> Result<BodySeries, SceneError> {
    let names: Vec<&str> = others.iter().map(|o| o.name.as_str()).collect();
    let (path, name, every) = series_head(s, raw, &names)?;
    let quantities = listed(&path, &raw.quantities, |qpath, qn| {
        BodyQuantity::named(qn)
            .and_then(|q| q.check(space).map(|()| q))
            .map_err(|e| e.at(qpath).into())
    })?;
    Ok(BodySeries {
        name,
        every,
        quantities,
    })
}

/// The quantities `names` of the series at `path`, each read by `read`
/// (given its path), none listed twice.
fn listed<Q: PartialEq>(
    path: &str,
    names: &[String],
    read: impl Fn(&str, &str) -> Result<Q, SceneError>,
) -> Result<Vec<Q>, SceneError> {
    let mut quantities = Vec::with_capacity(names.len());
    for (k, name) in names.iter().enumerate() {
        let qpath = format!("{path}.quantities[{k}]");
        let q = read(&qpath, name)?;
        if quantities.contains(&q) {
            return Err(SceneError::field(
                qpath,
                format!("`{name}` is listed twice"),
            ));
        }
        quantities.push(q);
    }
    Ok(quantities)
}

/// A series' path, name (default `observables`, `observables1`, ...,
/// unique among `others`) and interval; its quantities are not empty.
fn series_head(
    s: usize,
    raw: &RawSeries,
    others: &[&str],
) -> Result<(String, String, u64), SceneError> {
    let path = format!("record.series[{s}]");
    let name = raw.name.clone().unwrap_or_else(|| match s {
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
    if others.contains(&name.as_str()) {
        return Err(SceneError::field(
            format!("{path}.name"),
            format!("\"{name}\" is used by another series"),
        ));
    }
    let every = at_least_one(raw.every).map_err(|e| e.at(&format!("{path}.every")))?;
    if raw.quantities.is_empty() {
        return Err(SceneError::field(
            format!("{path}.quantities"),
            "must name at least one quantity",
        ));
    }
    Ok((path, name, every))
}

/// The series of a run of bodies in `space`.
pub(super) fn body_record(raw: &RawRecord, space: &Space) -> Result<Vec<BodySeries>, SceneError> {
    let mut all: Vec<BodySeries> = Vec::with_capacity(raw.series.len());
    for (s, rs) in raw.series.iter().enumerate() {
        let one = body_series(s, rs, &all, space)?;
        all.push(one);
    }
    Ok(all)
}

/// Validates the section for a run of `rotors` with `integrator` (the
/// series of bodies, when `rotors` is empty, are read by [`body_record`]).
pub(super) fn record(
    raw: &RawRecord,
    integrator: &IntegratorSpec,
    rotors: &[Rotor],
) -> Result<Record, SceneError> {
    let mut all: Vec<Series> = Vec::with_capacity(raw.series.len());
    for (s, rs) in raw.series.iter().enumerate() {
        let one = series(s, rs, &all, integrator, rotors)?;
        all.push(one);
    }
    let trajectory = raw
        .trajectory
        .as_ref()
        .map(|t| {
            let format = t.format.unwrap_or_default();
            if format == TrajectoryFormat::Gsd && t.marker_length.is_some() {
                return Err(SceneError::field(
                    "record.trajectory.marker_length",
                    "only for format = \"dcd\" (GSD stores the orientations as quaternions)",
                ));
            }
            Ok::<_, SceneError>(TrajectorySpec {
                every: at_least_one(t.every).map_err(|e| e.at("record.trajectory.every"))?,
                format,
                marker_length: positive(t.marker_length.unwrap_or(DEFAULT_MARKER_LENGTH))
                    .map_err(|e| e.at("record.trajectory.marker_length"))?,
            })
        })
        .transpose()?;
    let checkpoint_every = raw
        .checkpoint_every
        .map(|c| at_least_one(c).map_err(|e| e.at("record.checkpoint_every")))
        .transpose()?;
    let energy_error_threshold = raw
        .energy_error_threshold
        .map(|t| positive(t).map_err(|e| e.at("record.energy_error_threshold")))
        .transpose()?;
    let check_every = raw
        .check_every
        .map(|c| at_least_one(c).map_err(|e| e.at("record.check_every")))
        .transpose()?
        .unwrap_or(DEFAULT_CHECK_EVERY);
    Ok(Record {
        series: all,
        trajectory,
        checkpoint_every,
        energy_error_threshold,
        check_every,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{DlmOptions, GearBOptions};

    fn check(table: &str, integrator: IntegratorSpec) -> Result<Record, String> {
        let raw: RawRecord = toml::from_str(table).expect("valid table");
        record(&raw, &integrator, &[]).map_err(|e| e.to_string())
    }

    /// Defaults: names `observables`, `observables1`; checks every 100 steps;
    /// markers at 0.3.
    #[test]
    fn defaults_fill_what_is_left_out() {
        let r = check(
            "[[series]]\nevery = 2\nquantities = ['q_dot_q']\n[[series]]\nevery = 3\nquantities = ['q_dot_n']\n[trajectory]\nevery = 5",
            IntegratorSpec::GearB(GearBOptions::default()),
        )
        .expect("valid");
        assert_eq!(r.series[0].name, "observables");
        assert_eq!(r.series[1].name, "observables1");
        assert_eq!(r.series[1].quantities, vec![Quantity::NormForce]);
        assert_eq!(r.check_every, DEFAULT_CHECK_EVERY);
        assert_eq!(
            r.trajectory,
            Some(TrajectorySpec {
                every: 5,
                format: TrajectoryFormat::Dcd,
                marker_length: DEFAULT_MARKER_LENGTH
            })
        );
    }

    /// `q_dot_n` needs an integrator that stores the quaternion force; a
    /// quantity may be listed once.
    #[test]
    fn quantities_are_checked_against_the_integrator() {
        let dlm = IntegratorSpec::Dlm(DlmOptions::default());
        assert_eq!(
            check("[[series]]\nevery = 1\nquantities = ['q_dot_n']", dlm).err().as_deref(),
            Some("record.series[0].quantities[0]: q_dot_n needs an integrator that stores the quaternion force (gear_b), got dlm")
        );
        assert_eq!(
            check(
                "[[series]]\nevery = 1\nquantities = ['norm_error', 'norm_error']",
                dlm
            )
            .err()
            .as_deref(),
            Some("record.series[0].quantities[1]: `norm_error` is listed twice")
        );
    }
}
