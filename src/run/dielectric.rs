//! The static dielectric constant of a recorded run
//! ([`crate::analysis::dielectric`]): the formula of the run's boundary and
//! its volume from the summary's `interactions` (conducting or vacuum Ewald
//! surroundings; open clusters, truncated sums and runs without
//! interactions are refused), the total dipole `M` from a recorded series
//! (the columns `M_x`, `M_y`, `M_z` of the quantity `M`), and the
//! temperature given or, by default, the mean of the `temperature` column
//! recorded with `M` (the kinetic temperature of an NVE run).

use super::error::RunError;
use super::folder::SUMMARY_FILE;
use super::series::SeriesTable;
use super::summary::InteractionsSummary;
use crate::analysis::{dielectric_constant, DielectricBoundary, DielectricConstant};
use crate::checks::InputError;
use crate::potential::{SumKind, Surface};
use nalgebra::Vector3;
use std::path::Path;

/// The columns of `M` in a series.
const DIPOLE_COLUMNS: [&str; 3] = ["M_x", "M_y", "M_z"];

/// The formula's boundary and the volume of a run that summed its pair
/// interactions as `interactions` says (`None`: no interactions, refused).
fn boundary_and_volume(
    interactions: Option<&InteractionsSummary>,
) -> Result<(DielectricBoundary, f64), InputError> {
    let Some(i) = interactions else {
        return Err(InputError::new(
            "boundary",
            "the run has no pair interactions, so no boundary gives a fluctuation formula",
        ));
    };
    let boundary = match (i.sum, i.surface) {
        (Some(SumKind::Ewald), Some(Surface::Vacuum)) => DielectricBoundary::Vacuum,
        (Some(SumKind::Ewald), _) => DielectricBoundary::Conducting,
        (Some(SumKind::Cutoff), _) => DielectricBoundary::Cutoff,
        (None, _) => DielectricBoundary::Open,
    };
    let volume = i.box_lengths.map_or(f64::NAN, |l| l.iter().product());
    Ok((boundary, volume))
}

/// The dielectric constant of a run whose interactions were summed as
/// `interactions` says, from its recorded `series` (which must record `M`),
/// at `temperature` (default: the mean of the series' `temperature` column).
pub fn dielectric_of_run(
    interactions: Option<&InteractionsSummary>,
    series: &SeriesTable,
    temperature: Option<f64>,
) -> Result<DielectricConstant, InputError> {
    let (boundary, volume) = boundary_and_volume(interactions)?;
    let column = |name: &str| -> Option<Vec<f64>> {
        let c = series.columns.iter().position(|c| c == name)?;
        let width = series.columns.len();
        Some(
            series
                .values
                .iter()
                .skip(c)
                .step_by(width)
                .copied()
                .collect(),
        )
    };
    let [x, y, z] = DIPOLE_COLUMNS.map(column);
    let (Some(x), Some(y), Some(z)) = (x, y, z) else {
        return Err(InputError::new(
            "series",
            format!(
                "`{}` records no total dipole (add \"M\" to its quantities)",
                series.name
            ),
        ));
    };
    let dipoles: Vec<Vector3<f64>> = (0..x.len())
        .map(|k| Vector3::new(x[k], y[k], z[k]))
        .collect();
    let temperature = match (temperature, column("temperature")) {
        (Some(t), _) => t,
        (None, Some(t)) if !t.is_empty() => t.iter().sum::<f64>() / t.len() as f64,
        (None, _) => {
            return Err(InputError::new(
                "temperature",
                format!(
                    "give it, or record \"temperature\" in the series `{}` with \"M\"",
                    series.name
                ),
            ))
        }
    };
    dielectric_constant(&dipoles, volume, temperature, boundary).map_err(|e| {
        // The total dipoles and the volume are the run's: named by their
        // series and by the summary's field.
        let path = if let Some(row) = e.path.strip_prefix("dipoles") {
            format!("series `{}`: M{row}", series.name)
        } else if let Some(rest) = e.path.strip_prefix("volume") {
            format!("interactions.box{rest}")
        } else {
            return e;
        };
        InputError { path, ..e }
    })
}

/// The series among `tables` that records `M`: the one called `name`, or
/// the only one with `M` when no name is given.
pub fn dipole_series<'a>(
    tables: &'a [SeriesTable],
    name: Option<&str>,
) -> Result<&'a SeriesTable, InputError> {
    if let Some(name) = name {
        return tables.iter().find(|t| t.name == name).ok_or_else(|| {
            let names: Vec<&str> = tables.iter().map(|t| t.name.as_str()).collect();
            InputError::new(
                "series",
                format!(
                    "no series `{name}` in the run (it has {})",
                    names.join(", ")
                ),
            )
        });
    }
    let with_dipole: Vec<&SeriesTable> = tables
        .iter()
        .filter(|t| t.columns.iter().any(|c| c == DIPOLE_COLUMNS[0]))
        .collect();
    match with_dipole[..] {
        [one] => Ok(one),
        [] => Err(InputError::new(
            "series",
            "no series of the run records the total dipole (add \"M\" to a series' quantities)",
        )),
        _ => {
            let names: Vec<&str> = with_dipole.iter().map(|t| t.name.as_str()).collect();
            Err(InputError::new(
                "series",
                format!(
                    "several series record \"M\" ({}): name one",
                    names.join(", ")
                ),
            ))
        }
    }
}

/// A run's outputs in `dir`: the `interactions` of its `summary.json` and
/// every series (`*.csv`).
pub fn read_run(dir: &Path) -> Result<(Option<InteractionsSummary>, Vec<SeriesTable>), RunError> {
    #[derive(serde::Deserialize)]
    struct Part {
        interactions: Option<InteractionsSummary>,
    }
    let path = dir.join(SUMMARY_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| RunError::io(&path, e))?;
    let part: Part = serde_json::from_str(&text).map_err(|e| RunError::io(&path, e))?;
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| RunError::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    paths.sort();
    let tables = paths
        .iter()
        .map(|p| SeriesTable::read_csv(p))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((part.interactions, tables))
}
