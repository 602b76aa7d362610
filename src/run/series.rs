//! A table of scalar observables (a [`Series`] of the scene), written as CSV
//! (a header, one row per sample) and/or kept in memory for Python.

use super::error::RunError;
use super::observer::{Needs, Observer, Sample};
use crate::observables;
use crate::scene::{Quantity, Series};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The columns and rows of a finished series.
#[derive(Clone, Debug, PartialEq)]
pub struct SeriesTable {
    pub name: String,
    /// `step`, `time`, then the quantities' names.
    pub columns: Vec<String>,
    /// Row-major values, `columns.len()` per row.
    pub values: Vec<f64>,
}

/// Records a [`Series`].
pub struct SeriesObserver {
    spec: Series,
    csv: Option<(PathBuf, BufWriter<File>)>,
    table: Option<SeriesTable>,
    row: Vec<f64>,
}

impl SeriesObserver {
    /// A series written to `csv_path` (if given; the header is written now)
    /// and kept in memory if `keep`.
    pub fn new(spec: &Series, csv_path: Option<&Path>, keep: bool) -> Result<Self, RunError> {
        let columns: Vec<String> = ["step", "time"]
            .into_iter()
            .chain(spec.quantities.iter().map(|q| q.name()))
            .map(str::to_string)
            .collect();
        let csv = csv_path
            .map(|path| {
                let file = File::create(path).map_err(|e| RunError::io(path, e))?;
                let mut writer = BufWriter::new(file);
                writeln!(writer, "{}", columns.join(",")).map_err(|e| RunError::io(path, e))?;
                Ok::<_, RunError>((path.to_path_buf(), writer))
            })
            .transpose()?;
        Ok(SeriesObserver {
            spec: spec.clone(),
            csv,
            table: keep.then(|| SeriesTable {
                name: spec.name.clone(),
                columns,
                values: Vec::new(),
            }),
            row: Vec::with_capacity(spec.quantities.len()),
        })
    }

    /// The table kept in memory (empty unless `keep` was set).
    pub fn into_table(self) -> Option<SeriesTable> {
        self.table
    }
}

/// The largest magnitude of a per-rotor diagnostic (NaN if any is NaN).
fn max_abs(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(
        0.0,
        |m: f64, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
    )
}

fn value(q: Quantity, sample: &Sample<'_>) -> f64 {
    let energies = sample.energies;
    let energy = |f: fn(&super::observer::Energies) -> f64| energies.as_ref().map_or(f64::NAN, f);
    match q {
        Quantity::KineticEnergy => energy(|e| e.kinetic),
        Quantity::PotentialEnergy => energy(|e| e.potential),
        Quantity::TotalEnergy => energy(|e| e.total),
        Quantity::EnergyError => energy(|e| e.error),
        // Three rotational degrees of freedom per rotor, k_B = 1.
        Quantity::Temperature => {
            let dof = 3.0 * sample.orientations.len() as f64;
            energy(|e| e.kinetic) * 2.0 / dof
        }
        Quantity::NormError => max_abs(sample.orientations.iter().map(observables::norm_error)),
        Quantity::NormVelocity => sample.q_dot.map_or(f64::NAN, |q_dot| {
            max_abs(
                sample
                    .orientations
                    .iter()
                    .zip(q_dot)
                    .map(|(q, d)| observables::norm_velocity(q, d)),
            )
        }),
        Quantity::NormForce => sample
            .q_dot_n
            .map_or(f64::NAN, |qn| max_abs(qn.iter().copied())),
    }
}

impl Observer for SeriesObserver {
    fn needs(&self) -> Needs {
        let has = |qs: &[Quantity]| self.spec.quantities.iter().any(|q| qs.contains(q));
        Needs {
            energies: has(&[
                Quantity::KineticEnergy,
                Quantity::PotentialEnergy,
                Quantity::TotalEnergy,
                Quantity::EnergyError,
                Quantity::Temperature,
            ]),
            omega_body: false,
            q_dot: has(&[Quantity::NormVelocity]),
            q_dot_n: has(&[Quantity::NormForce]),
        }
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError> {
        self.row.clear();
        self.row
            .extend(self.spec.quantities.iter().map(|&q| value(q, sample)));
        if let Some((path, writer)) = &mut self.csv {
            // `{:e}` is the shortest representation that reads back exactly.
            let mut line = format!("{},{:e}", sample.step, sample.time);
            for x in &self.row {
                line.push_str(&format!(",{x:e}"));
            }
            writeln!(writer, "{line}").map_err(|e| RunError::io(path, e))?;
        }
        if let Some(table) = &mut self.table {
            table.values.push(sample.step as f64);
            table.values.push(sample.time);
            table.values.extend_from_slice(&self.row);
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        if let Some((path, writer)) = &mut self.csv {
            writer.flush().map_err(|e| RunError::io(path, e))?;
        }
        Ok(())
    }
}
