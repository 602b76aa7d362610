//! Trajectory frames, written as DCD with a PDB topology (for each rotor
//! its centre and three markers at `marker_length` along its body axes,
//! `r_s = R(Q) e_a`, the columns of `A^T`) or as GSD (the sites, the
//! orientation quaternions, the box, the step), and/or the orientations and
//! body angular velocities kept in memory for Python.

use super::dcd::{DcdHeader, DcdWriter};
use super::error::RunError;
use super::gsd::{GsdBox, GsdWriter};
use super::pdb::write_topology;
use crate::quaternion::Quat;
use crate::rotor::Rotor;
use crate::scene::{TrajectoryFormat, TrajectorySpec};
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

/// Margin around the sites of an open cluster in its GSD box (length
/// units; GSD files always carry a box, [`GsdBox::new`]).
pub const GSD_OPEN_MARGIN: f64 = 1.0;

/// Records trajectory frames.
pub struct TrajectoryObserver {
    sites: Vec<Vector3<f64>>,
    marker_length: f64,
    dcd: Option<(PathBuf, DcdWriter)>,
    gsd: Option<(PathBuf, GsdWriter)>,
    /// Frames at or before this step are already in the DCD.
    written_through: Option<u64>,
    frames: Option<TrajectoryFrames>,
    positions: Vec<[f32; 3]>,
}

/// Where the files of a trajectory go (the DCD and PDB files, or the GSD
/// file, as the format says).
pub struct TrajectoryFiles<'a> {
    /// The DCD file of the frames.
    pub dcd: &'a Path,
    /// The PDB file of the topology.
    pub pdb: &'a Path,
    /// The GSD file of the frames.
    pub gsd: &'a Path,
    /// The periodic box, if any (the PDB's CRYST1 record, the DCD's unit
    /// cell, the GSD box; an open cluster's GSD box encloses its sites with
    /// [`GSD_OPEN_MARGIN`]).
    pub box_lengths: Option<&'a Vector3<f64>>,
    /// The step of the first frame.
    pub first_step: u64,
    /// The time step (the integrator's).
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
            gsd: None,
            written_through: None,
            frames: keep.then(TrajectoryFrames::default),
            positions: Vec::new(),
        };
        match (files, spec.format) {
            (None, _) => {}
            (Some(f), TrajectoryFormat::Gsd) => {
                let cell = GsdBox::new(f.box_lengths.copied(), &observer.sites, GSD_OPEN_MARGIN)
                    .map_err(|e| RunError::Scene(e.into()))?;
                let gsd = GsdWriter::create(f.gsd, &observer.sites, &cell)
                    .map_err(|e| RunError::io(f.gsd, e))?;
                observer.gsd = Some((f.gsd.to_path_buf(), gsd));
            }
            (Some(f), TrajectoryFormat::Dcd) => observer.open_dcd(spec, initial, &f)?,
        }
        Ok(observer)
    }

    /// Writes the PDB topology (with the `initial` orientations) and opens
    /// the DCD file, or appends to the DCD of an earlier run (`f.append`;
    /// the PDB is kept).
    fn open_dcd(
        &mut self,
        spec: &TrajectorySpec,
        initial: &[Quat],
        f: &TrajectoryFiles<'_>,
    ) -> Result<(), RunError> {
        self.positions = vec![[0.0; 3]; 4 * self.sites.len()];
        let dcd = match &f.append {
            Some(header) => {
                self.written_through = header.last_step().and_then(|s| u64::try_from(s).ok());
                DcdWriter::append(f.dcd, header, f.box_lengths)
            }
            None => {
                self.fill_positions(initial);
                write_topology(f.pdb, &self.positions, f.box_lengths, f.title)
                    .map_err(|e| RunError::io(f.pdb, e))?;
                DcdWriter::create(
                    f.dcd,
                    self.positions.len(),
                    f.first_step,
                    spec.every,
                    f.dt,
                    f.title,
                    f.box_lengths,
                )
            }
        }
        .map_err(|e| RunError::io(f.dcd, e))?;
        self.dcd = Some((f.dcd.to_path_buf(), dcd));
        Ok(())
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
        if let Some((path, gsd)) = &mut self.gsd {
            gsd.write_frame(sample.step, sample.orientations)
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
        if let Some((path, gsd)) = &mut self.gsd {
            gsd.flush().map_err(|e| RunError::io(path, e))?;
        }
        Ok(())
    }

    fn finish(&mut self) -> Result<(), RunError> {
        self.flush()
    }
}
