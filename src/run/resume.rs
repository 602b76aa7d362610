//! What a restart does with the outputs an earlier run left in its folder:
//! it never destroys them.
//!
//! * No output file of the scene is there: the restart writes new files.
//! * Every output file is there and ends at the checkpoint's step (each
//!   series' last row, and the trajectory's last frame, is the last sample
//!   at or before that step, with no sample missing in between): the
//!   restart appends to them, from the first sample after their last one.
//!   The earlier `summary.json` is kept as `summary.until-STEP.json`.
//! * Anything else (files that go on past the checkpoint, as after a
//!   `kill -9`, files missing, other columns, a damaged trajectory, a GSD
//!   trajectory, which is never appended to): the
//!   restart writes to a new folder `restart-STEP` (or `restart-STEP-2`, ...)
//!   inside the output folder, and says so.

use super::body_outputs::body_columns;
use super::dcd::{read_header, DcdHeader};
use super::folder::{DCD_FILE, GSD_FILE, PDB_FILE, SUMMARY_FILE};
use super::series::SeriesObserver;
use crate::scene::{Scene, TrajectoryFormat};
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// The most bytes read from the end of a CSV file to find its last row.
const TAIL_BYTES: u64 = 1 << 16;

/// Where a run writes its outputs, and how.
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// New files in the output folder (replacing files of the same names).
    New,
    /// Appended to the files of an earlier run in the output folder.
    Append(AppendAfter),
    /// New files in a new folder inside the output folder, because the
    /// files there do not end at the checkpoint's step (`reason`).
    NewFolder {
        /// The new folder.
        dir: PathBuf,
        /// Why the earlier files could not be continued.
        reason: String,
    },
}

impl Placement {
    /// `"new"`, `"appended"` or `"new_folder"`, as the summary records it.
    pub fn as_str(&self) -> &'static str {
        match self {
            Placement::New => "new",
            Placement::Append(_) => "appended",
            Placement::NewFolder { .. } => "new_folder",
        }
    }
}

/// The steps of the last sample already in each file, when appending.
#[derive(Clone, Debug, PartialEq)]
pub struct AppendAfter {
    /// Per series of the scene, in order.
    pub series: Vec<u64>,
    /// The trajectory's DCD header, if the scene records one.
    pub trajectory: Option<DcdHeader>,
}

/// The name of the kept summary of the run that ended at `step`.
pub fn kept_summary_name(dir: &Path, step: u64) -> PathBuf {
    let mut k = 1;
    loop {
        let suffix = if k == 1 {
            String::new()
        } else {
            format!("-{k}")
        };
        let path = dir.join(format!("summary.until-{step}{suffix}.json"));
        if !path.exists() {
            return path;
        }
        k += 1;
    }
}

/// Decides where a restart of `scene` from the checkpoint at `step` writes
/// in the output folder `dir` (see the module doc).
pub fn plan(dir: &Path, scene: &Scene, step: u64) -> Placement {
    let record = &scene.record;
    let mut files: Vec<PathBuf> = series_files(scene)
        .iter()
        .map(|s| dir.join(format!("{}.csv", s.name)))
        .collect();
    match record.trajectory.as_ref().map(|t| t.format) {
        None => {}
        Some(TrajectoryFormat::Dcd) => files.extend([dir.join(DCD_FILE), dir.join(PDB_FILE)]),
        Some(TrajectoryFormat::Gsd) => files.push(dir.join(GSD_FILE)),
    }
    if !files
        .iter()
        .chain([&dir.join(SUMMARY_FILE)])
        .any(|f| f.exists())
    {
        return Placement::New;
    }
    match append_points(dir, scene, step) {
        Ok(after) => Placement::Append(after),
        Err(reason) => {
            let mut k = 1;
            let dir = loop {
                let suffix = if k == 1 {
                    String::new()
                } else {
                    format!("-{k}")
                };
                let candidate = dir.join(format!("restart-{step}{suffix}"));
                if !candidate.exists() {
                    break candidate;
                }
                k += 1;
            };
            Placement::NewFolder { dir, reason }
        }
    }
}

/// A series file of a scene: its name, interval and CSV header.
struct SeriesFile<'a> {
    name: &'a str,
    every: u64,
    header: String,
}

/// The series files of `scene`: its rotor series, or its body series.
fn series_files(scene: &Scene) -> Vec<SeriesFile<'_>> {
    match &scene.bodies {
        Some(bodies) => bodies
            .series
            .iter()
            .map(|s| SeriesFile {
                name: &s.name,
                every: s.every,
                header: body_columns(s).join(","),
            })
            .collect(),
        None => scene
            .record
            .series
            .iter()
            .map(|s| SeriesFile {
                name: &s.name,
                every: s.every,
                header: SeriesObserver::header(s),
            })
            .collect(),
    }
}

/// Whether a file whose last sample is at `last` (samples every `every`
/// steps) ends at the checkpoint's `step`: no sample after it, none missing.
fn ends_at(last: u64, every: u64, step: u64) -> bool {
    last <= step && (last / every + 1).saturating_mul(every) >= step
}

/// The last samples of every output file, if all end at `step`; otherwise
/// the reason, naming the first file that does not.
fn append_points(dir: &Path, scene: &Scene, step: u64) -> Result<AppendAfter, String> {
    let mut series = Vec::new();
    for s in series_files(scene) {
        let path = dir.join(format!("{}.csv", s.name));
        let last =
            last_row_step(&path, &s.header).map_err(|why| format!("{}: {why}", path.display()))?;
        if !ends_at(last, s.every, step) {
            return Err(format!(
                "{}: its last row is at step {last}, not the last sample at or before the checkpoint's step {step}",
                path.display()
            ));
        }
        series.push(last);
    }
    let trajectory = match &scene.record.trajectory {
        None => None,
        Some(spec) if spec.format == TrajectoryFormat::Gsd => {
            return Err(format!(
                "{}: a GSD trajectory is not continued by a restart",
                dir.join(GSD_FILE).display()
            ));
        }
        Some(spec) => {
            let path = dir.join(DCD_FILE);
            let pdb = dir.join(PDB_FILE);
            if !pdb.is_file() {
                return Err(format!("{}: missing", pdb.display()));
            }
            let header = read_header(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let fits = header.complete
                && header.atoms == 4 * scene.rotors.len()
                && header.unit_cell == scene.box_lengths().is_some()
                && i64::from(header.steps_per_frame) == i64::try_from(spec.every).unwrap_or(-1)
                && header
                    .last_step()
                    .and_then(|l| u64::try_from(l).ok())
                    .is_some_and(|l| ends_at(l, spec.every, step));
            if !fits {
                return Err(format!(
                    "{}: its frames do not end at the checkpoint's step {step} (or it is another trajectory)",
                    path.display()
                ));
            }
            Some(header)
        }
    };
    Ok(AppendAfter { series, trajectory })
}

/// The step of the last row of the CSV at `path`, whose first line must be
/// `header` and whose last row must be complete.
fn last_row_step(path: &Path, header: &str) -> Result<u64, String> {
    let mut file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut first = String::new();
    let _ = BufReader::new(&mut file)
        .take(TAIL_BYTES)
        .read_line(&mut first)
        .map_err(|e| e.to_string())?;
    if first.trim_end_matches('\n') != header {
        return Err("other columns than this scene records".to_string());
    }
    let size = file.metadata().map_err(|e| e.to_string())?.len();
    let _ = file
        .seek(SeekFrom::Start(size.saturating_sub(TAIL_BYTES)))
        .map_err(|e| e.to_string())?;
    let mut tail = Vec::new();
    let _ = file.read_to_end(&mut tail).map_err(|e| e.to_string())?;
    let tail = String::from_utf8_lossy(&tail);
    let Some(body) = tail.strip_suffix('\n') else {
        return Err("its last row is incomplete".to_string());
    };
    let last = body.rsplit('\n').next().unwrap_or_default();
    last.split(',')
        .next()
        .and_then(|s| s.parse::<u64>().ok())
        .ok_or_else(|| "it has no complete row".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file ends at the checkpoint when no sample lies between its last
    /// row and the checkpoint's step.
    #[test]
    fn files_end_at_the_checkpoint_when_no_sample_is_missing() {
        assert!(ends_at(1000, 10, 1000));
        assert!(ends_at(990, 10, 1000), "the sample at 1000 is redone");
        assert!(ends_at(1000, 10, 1005));
        assert!(!ends_at(980, 10, 1000), "the sample at 990 is missing");
        assert!(!ends_at(1010, 10, 1000), "a row past the checkpoint");
        assert!(ends_at(u64::MAX - 1, u64::MAX, u64::MAX - 1));
    }
}
