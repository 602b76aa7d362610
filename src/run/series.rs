//! A table of scalar observables (a [`Series`] of the scene), written as CSV
//! (a header, one row per sample) and/or kept in memory for Python.
//!
//! Rows reach the file whole: each is handed to the buffer in one write, so
//! the buffer only ever passes whole lines to the file, and a run killed at
//! any moment leaves a file that ends with a complete row.

use super::error::RunError;
use super::folder::{create_file, open_existing};
use crate::rotor::Rotor;
use crate::scene::{SceneError, Series};
use crate::simulation::{MultipoleInputs, Needs, Observer, Sample};
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Where a series' CSV goes.
#[derive(Clone, Copy, Debug)]
pub enum CsvTarget<'a> {
    /// A new file (the header is written now).
    Create(&'a Path),
    /// The file of an earlier run, whose last row is at step `after`: rows
    /// are appended from the first sample after it.
    Append {
        /// The file.
        path: &'a Path,
        /// The step of its last row.
        after: u64,
    },
}

/// The columns and rows of a finished series.
#[derive(Clone, Debug, PartialEq)]
pub struct SeriesTable {
    /// The series' name.
    pub name: String,
    /// `step`, `time`, then the quantities' columns.
    pub columns: Vec<String>,
    /// Row-major values, `columns.len()` per row.
    pub values: Vec<f64>,
}

impl SeriesTable {
    /// The table of a CSV file the run wrote (named after the file's stem).
    pub fn read_csv(path: &Path) -> Result<SeriesTable, RunError> {
        let text = std::fs::read_to_string(path).map_err(|e| RunError::io(path, e))?;
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .unwrap_or_default()
            .split(',')
            .map(str::to_string)
            .collect();
        let mut values = Vec::new();
        for (k, line) in lines.enumerate() {
            let row = line
                .split(',')
                .map(str::parse::<f64>)
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|e| RunError::io(path, format!("row {}: {e}", k + 1)))?;
            if row.len() != columns.len() {
                return Err(RunError::io(
                    path,
                    format!(
                        "row {}: {} values for {} columns",
                        k + 1,
                        row.len(),
                        columns.len()
                    ),
                ));
            }
            values.extend(row);
        }
        let name = path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        Ok(SeriesTable {
            name,
            columns,
            values,
        })
    }
}

/// Records a [`Series`].
pub struct SeriesObserver {
    spec: Series,
    multipoles: MultipoleInputs,
    rows: Rows,
    row: Vec<f64>,
}

/// The rows of one table, written to a CSV file and/or kept in memory.
pub(super) struct Rows {
    csv: Option<(PathBuf, BufWriter<File>)>,
    /// Samples at or before this step are already in the file.
    written_through: Option<u64>,
    table: Option<SeriesTable>,
}

impl Rows {
    /// The table `name` of `columns` (`step`, `time` first), written to
    /// `csv` (if given; a new file gets the header now) and kept in memory
    /// if `keep`.
    pub(super) fn open(
        name: &str,
        columns: Vec<String>,
        csv: Option<CsvTarget<'_>>,
        keep: bool,
    ) -> Result<Self, RunError> {
        let mut written_through = None;
        let csv = csv
            .map(|target| {
                let (path, file) = match target {
                    CsvTarget::Create(path) => {
                        let mut file = create_file(path).map_err(|e| RunError::io(path, e))?;
                        let header = columns.join(",") + "\n";
                        file.write_all(header.as_bytes())
                            .map_err(|e| RunError::io(path, e))?;
                        (path, file)
                    }
                    CsvTarget::Append { path, after } => {
                        written_through = Some(after);
                        let mut file = open_existing(path).map_err(|e| RunError::io(path, e))?;
                        let _ = file
                            .seek(SeekFrom::End(0))
                            .map_err(|e| RunError::io(path, e))?;
                        (path, file)
                    }
                };
                Ok::<_, RunError>((path.to_path_buf(), BufWriter::new(file)))
            })
            .transpose()?;
        Ok(Rows {
            csv,
            written_through,
            table: keep.then(|| SeriesTable {
                name: name.to_string(),
                columns,
                values: Vec::new(),
            }),
        })
    }

    /// Appends the row `values` of `step` at `time`.
    pub(super) fn push(&mut self, step: u64, time: f64, values: &[f64]) -> Result<(), RunError> {
        let in_file = self.written_through.is_some_and(|s| step <= s);
        if let (Some((path, writer)), false) = (&mut self.csv, in_file) {
            // `{:e}` is the shortest representation that reads back exactly.
            let mut line = format!("{step},{time:e}");
            for x in values {
                line.push_str(&format!(",{x:e}"));
            }
            line.push('\n');
            writer
                .write_all(line.as_bytes())
                .map_err(|e| RunError::io(path, e))?;
        }
        if let Some(table) = &mut self.table {
            table.values.push(step as f64);
            table.values.push(time);
            table.values.extend_from_slice(values);
        }
        Ok(())
    }

    /// Flushes the file.
    pub(super) fn flush(&mut self) -> Result<(), RunError> {
        if let Some((path, writer)) = &mut self.csv {
            writer.flush().map_err(|e| RunError::io(path, e))?;
        }
        Ok(())
    }

    /// The table kept in memory (`None` unless kept).
    pub(super) fn into_table(self) -> Option<SeriesTable> {
        self.table
    }
}

impl SeriesObserver {
    /// The CSV header of `spec`: `step,time,` then the quantities' columns.
    pub fn header(spec: &Series) -> String {
        Self::columns(spec).join(",")
    }

    fn columns(spec: &Series) -> Vec<String> {
        ["step".to_string(), "time".to_string()]
            .into_iter()
            .chain(spec.quantities.iter().flat_map(|q| q.columns()))
            .collect()
    }

    /// A series of `rotors` written to `csv` (if given) and kept in memory
    /// if `keep`.
    pub fn new(
        spec: &Series,
        rotors: &[Rotor],
        csv: Option<CsvTarget<'_>>,
        keep: bool,
    ) -> Result<Self, RunError> {
        let multipoles = MultipoleInputs::new(rotors, &spec.quantities)
            .map_err(|e| SceneError::from(e.at(&format!("series `{}`", spec.name))))?;
        let columns = Self::columns(spec);
        let row = Vec::with_capacity(columns.len());
        Ok(SeriesObserver {
            spec: spec.clone(),
            multipoles,
            rows: Rows::open(&spec.name, columns, csv, keep)?,
            row,
        })
    }

    /// The table kept in memory (empty unless `keep` was set).
    pub fn into_table(self) -> Option<SeriesTable> {
        self.rows.into_table()
    }
}

impl Observer for SeriesObserver {
    type Error = RunError;

    fn needs(&self) -> Needs {
        self.spec
            .quantities
            .iter()
            .fold(Needs::default(), |n, q| n.union(q.needs()))
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError> {
        self.row.clear();
        for q in &self.spec.quantities {
            q.write(sample, &mut self.multipoles, &mut self.row);
        }
        self.rows.push(sample.step, sample.time, &self.row)
    }

    fn flush(&mut self) -> Result<(), RunError> {
        self.rows.flush()
    }

    fn finish(&mut self) -> Result<(), RunError> {
        self.flush()
    }
}
