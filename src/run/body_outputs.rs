//! What a run of bodies writes: the series' CSV rows (in the scene's
//! units) and the GSD frames of the bodies.

use super::error::RunError;
use super::gsd::{BodyFrame, BodyTypes, GsdBox, GsdWriter};
use super::resume::Placement;
use super::scene_run::Outputs;
use super::series::{CsvTarget, Rows};
use super::trajectory::GSD_OPEN_MARGIN;
use crate::bodies::{BodyQuantity, BodySystem, Evaluation, Space};
use crate::integrators::{NoSquishOptions, Splitting};
use crate::scene::{BodyScene, BodySeries, Scene, SceneError};
use crate::units::{quantity_dimension, Dimension, Units};
use std::path::{Path, PathBuf};

/// A GSD trajectory being written.
pub(super) struct Trajectory {
    pub every: u64,
    pub path: PathBuf,
    pub writer: GsdWriter,
    pub cell: GsdBox,
}

/// The CSV columns of a series of bodies: `step`, `time`, then the
/// quantities'.
pub(super) fn body_columns(series: &BodySeries) -> Vec<String> {
    ["step", "time"]
        .into_iter()
        .map(String::from)
        .chain(series.quantities.iter().flat_map(|q| q.columns()))
        .collect()
}

/// The series' CSV files in the folder `dir` (none without one), created,
/// or continued after the rows a restart placed (`placement`).
pub(super) fn open_series(
    bodies: &BodyScene,
    (dir, placement): (Option<&Path>, Option<&Placement>),
    outputs: &Outputs,
) -> Result<Vec<Rows>, RunError> {
    let after = |k: usize| match placement {
        Some(Placement::Append(after)) => Some(after.series[k]),
        _ => None,
    };
    bodies
        .series
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let path = dir.map(|d| d.join(format!("{}.csv", s.name)));
            let target = path.as_deref().map(|path| match after(k) {
                Some(after) => CsvTarget::Append { path, after },
                None => CsvTarget::Create(path),
            });
            Rows::open(&s.name, body_columns(s), target, outputs.keep)
        })
        .collect()
}

/// Appends the row of every series due at `step` (at `time`), from the
/// state `system` and its evaluation `e` (with the thermostat's share).
pub(super) fn record(
    (scene, bodies): (&Scene, &BodyScene),
    (system, e, thermostat): (&BodySystem, &Evaluation, f64),
    (step, time): (u64, f64),
    series: &mut [Rows],
    row: &mut Vec<f64>,
) -> Result<(), RunError> {
    for (rows, spec) in series.iter_mut().zip(&bodies.series) {
        if step % spec.every == 0 {
            write_row(&spec.quantities, (system, e, thermostat), scene.units, row);
            rows.push(step, time, row)?;
        }
    }
    Ok(())
}

/// Writes the values of `quantities` for `system` after its evaluation
/// `e` (with the thermostat's share `thermostat` of the conserved energy)
/// into `row`, in `units`.
pub(super) fn write_row(
    quantities: &[BodyQuantity],
    (system, e, thermostat): (&BodySystem, &Evaluation, f64),
    units: Units,
    row: &mut Vec<f64>,
) {
    row.clear();
    for q in quantities {
        let start = row.len();
        q.write(system, e, thermostat, row);
        let dimension = quantity_dimension(*q);
        for value in &mut row[start..] {
            *value = units.from_internal(*value, dimension);
        }
    }
}

/// A GSD file at `path` for the bodies of `system`, a frame every `every`
/// steps.
pub(super) fn trajectory(
    system: &BodySystem,
    every: u64,
    path: PathBuf,
) -> Result<Trajectory, RunError> {
    let centres: Vec<_> = system.bodies.iter().map(|b| b.position).collect();
    let box_lengths = match system.space {
        Space::Periodic(l) => Some(l),
        Space::Open => None,
    };
    let cell = GsdBox::new(box_lengths, &centres, GSD_OPEN_MARGIN).map_err(SceneError::from)?;
    let types = &system.types;
    let typeid: Vec<u32> = system.bodies.iter().map(|b| b.kind as u32).collect();
    let mass: Vec<f32> = system
        .bodies
        .iter()
        .map(|b| types[b.kind].mass as f32)
        .collect();
    let moment_inertia: Vec<[f32; 3]> = system
        .bodies
        .iter()
        .map(|b| types[b.kind].moments.map(|m| m as f32).into())
        .collect();
    let body_types = BodyTypes {
        types: types.len(),
        typeid: &typeid,
        mass: &mass,
        moment_inertia: &moment_inertia,
    };
    let writer =
        GsdWriter::create_bodies(&path, &cell, &body_types).map_err(|e| RunError::io(&path, e))?;
    Ok(Trajectory {
        every,
        path,
        writer,
        cell,
    })
}

/// Writes the frame of `system` at `step`: centres wrapped into the box
/// with their image counts (open space: the centres as they are, relative
/// to the box of the first frame), HOOMD's centred coordinates; velocities
/// and angular momenta in the scene's `units`.
pub(super) fn write_frame(
    writer: &mut GsdWriter,
    system: &BodySystem,
    (step, units): (u64, Units),
    cell: &GsdBox,
) -> std::io::Result<()> {
    let rate = |c: f64| units.from_internal(c, Dimension::Rate) as f32;
    let n = system.bodies.len();
    let (mut position, mut orientation) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut velocity, mut angmom, mut image) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for b in &system.bodies {
        let (mut x, mut images) = (b.position, b.image);
        system.space.wrap(&mut x, &mut images);
        let centred = x - cell.corner - cell.lengths * 0.5;
        position.push(centred.map(|c| c as f32).into());
        orientation.push(b.orientation.0.map(|c| c as f32));
        velocity.push(b.velocity.map(rate).into());
        let p = NoSquishOptions::momentum(&b.orientation, &b.angular_momentum_body);
        angmom.push(p.0.map(rate));
        image.push(images.map(|i| i as i32));
    }
    writer.write_bodies(
        step,
        &BodyFrame {
            position: &position,
            orientation: &orientation,
            velocity: &velocity,
            angmom: &angmom,
            image: &image,
        },
    )
}
