//! Trajectory frames: for each rotor its centre and three markers at
//! `marker_length` along its body axes (`r_s = R(Q) e_a`, the columns of
//! `A^T`), written as DCD with a PDB topology, and/or the orientations and
//! body angular velocities kept in memory for Python.

use super::dcd::{DcdHeader, DcdWriter};
use super::error::RunError;
use super::pdb::write_topology;
use crate::quaternion::Quat;
use crate::rotor::Rotor;
use crate::scene::TrajectorySpec;
use crate::simulation::{Needs, Observer, Sample};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// Orientations and angular velocities kept in memory, frame-major.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrajectoryFrames {
    /// The step of each frame.
    pub steps: Vec<u64>,
    /// The time of each frame.
    pub times: Vec<f64>,
    /// `frames x rotors x 4`, scalar first.
    pub orientations: Vec<f64>,
    /// `frames x rotors x 3`, body frame.
    pub omega_body: Vec<f64>,
}

/// Records trajectory frames.
pub struct TrajectoryObserver {
    sites: Vec<Vector3<f64>>,
    marker_length: f64,
    dcd: Option<(PathBuf, DcdWriter)>,
    /// Frames at or before this step are already in the DCD.
    written_through: Option<u64>,
    frames: Option<TrajectoryFrames>,
    positions: Vec<[f32; 3]>,
}

/// Where the files of a trajectory go.
pub struct TrajectoryFiles<'a> {
    /// The DCD file of the frames.
    pub dcd: &'a Path,
    /// The PDB file of the topology.
    pub pdb: &'a Path,
    /// The periodic box, if any (the PDB's CRYST1 record).
    pub box_lengths: Option<&'a Vector3<f64>>,
    /// The step of the first frame.
    pub first_step: u64,
    /// The time step.
    pub dt: f64,
    /// The title of both files.
    pub title: &'a str,
    /// Append to the DCD of an earlier run with this header (the PDB is
    /// kept); `None` writes new files.
    pub append: Option<DcdHeader>,
}

impl TrajectoryObserver {
    /// A trajectory of `rotors`, written to `files` if given (the PDB now,
    /// with the `initial` orientations) and kept in memory if `keep`.
    pub fn new(
        spec: &TrajectorySpec,
        rotors: &[Rotor],
        initial: &[Quat],
        files: Option<TrajectoryFiles<'_>>,
        keep: bool,
    ) -> Result<Self, RunError> {
        let mut observer = TrajectoryObserver {
            sites: rotors.iter().map(|r| r.site).collect(),
            marker_length: spec.marker_length,
            dcd: None,
            written_through: None,
            frames: keep.then(TrajectoryFrames::default),
            positions: vec![[0.0; 3]; 4 * rotors.len()],
        };
        if let Some(f) = files {
            let dcd = match &f.append {
                Some(header) => {
                    observer.written_through =
                        header.last_step().and_then(|s| u64::try_from(s).ok());
                    DcdWriter::append(f.dcd, header, f.box_lengths)
                }
                None => {
                    observer.fill_positions(initial);
                    write_topology(f.pdb, &observer.positions, f.box_lengths, f.title)
                        .map_err(|e| RunError::io(f.pdb, e))?;
                    DcdWriter::create(
                        f.dcd,
                        observer.positions.len(),
                        f.first_step,
                        spec.every,
                        f.dt,
                        f.title,
                        f.box_lengths,
                    )
                }
            }
            .map_err(|e| RunError::io(f.dcd, e))?;
            observer.dcd = Some((f.dcd.to_path_buf(), dcd));
        }
        Ok(observer)
    }

    /// The frames kept in memory (none unless `keep` was set).
    pub fn into_frames(self) -> Option<TrajectoryFrames> {
        self.frames
    }

    /// Centre and markers of every rotor; the markers use the normalised
    /// orientation so that the frame stays rigid for schemes whose `|Q|`
    /// drifts.
    fn fill_positions(&mut self, orientations: &[Quat]) {
        for ((site, q), out) in self
            .sites
            .iter()
            .zip(orientations)
            .zip(self.positions.chunks_exact_mut(4))
        {
            let q = q.try_normalize().unwrap_or(*q);
            let body_to_space = q.body_to_space_matrix();
            let to_f32 = |v: Vector3<f64>| [v.x as f32, v.y as f32, v.z as f32];
            out[0] = to_f32(*site);
            for axis in 0..3 {
                out[axis + 1] = to_f32(site + body_to_space.column(axis) * self.marker_length);
            }
        }
    }
}

impl Observer for TrajectoryObserver {
    type Error = RunError;

    fn needs(&self) -> Needs {
        Needs {
            omega_body: self.frames.is_some(),
            ..Needs::default()
        }
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), RunError> {
        let in_file = self.written_through.is_some_and(|s| sample.step <= s);
        if self.dcd.is_some() && !in_file {
            self.fill_positions(sample.orientations);
        }
        if let (Some((path, dcd)), false) = (&mut self.dcd, in_file) {
            dcd.write_frame(&self.positions)
                .map_err(|e| RunError::io(path, e))?;
        }
        if let Some(frames) = &mut self.frames {
            frames.steps.push(sample.step);
            frames.times.push(sample.time);
            frames
                .orientations
                .extend(sample.orientations.iter().flat_map(|q| q.0));
            match sample.omega_body {
                Some(w) => frames
                    .omega_body
                    .extend(w.iter().flat_map(|w| [w.x, w.y, w.z])),
                None => frames
                    .omega_body
                    .extend(std::iter::repeat_n(f64::NAN, 3 * sample.orientations.len())),
            }
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), RunError> {
        if let Some((path, dcd)) = &mut self.dcd {
            dcd.flush().map_err(|e| RunError::io(path, e))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        if let Some((path, dcd)) = &mut self.dcd {
            dcd.flush().map_err(|e| RunError::io(path, e))?;
        }
        Ok(())
    }
}
