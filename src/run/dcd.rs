//! A minimal writer of CHARMM-style DCD trajectories (as read by VMD and
//! mdtraj): Fortran unformatted records, little-endian, single precision.
//! The header's frame count is rewritten after every frame, so the file is
//! valid whenever the run stops.
//!
//! For a periodic box the header sets CHARMM's unit-cell flag (the 11th
//! control integer) and every frame starts with a record of six doubles
//! `[A, cos(gamma), B, cos(beta), cos(alpha), C]`: the cell lengths and the
//! cosines of the angles between the edges (0 for the orthorhombic box), the
//! order and cosine form CHARMM and NAMD write and VMD's DCD plugin (used by
//! mdtraj) reads as lengths and 90-degree angles.

use nalgebra::Vector3;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

/// Byte offset of the frame count (NSET) in the header.
const NSET_OFFSET: u64 = 8;
/// Byte offset of the total step count (NSTEP) in the header.
const NSTEP_OFFSET: u64 = 20;
/// The CHARMM version written in the last header integer (24 marks the
/// CHARMM variant, whose DELTA is single precision).
const CHARMM_VERSION: i32 = 24;
/// Index of the unit-cell flag among the header's 20 control integers.
const UNIT_CELL_FLAG: usize = 10;

/// An open DCD file.
pub struct DcdWriter {
    file: BufWriter<File>,
    atoms: usize,
    frames: i32,
    steps_per_frame: i32,
    /// The unit-cell record of every frame (periodic boxes only).
    unit_cell: Option<[u8; 48]>,
}

fn record(out: &mut impl Write, payload: &[u8]) -> io::Result<()> {
    let len = payload.len() as i32;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(payload)?;
    out.write_all(&len.to_le_bytes())
}

impl DcdWriter {
    /// Creates `path` for `atoms` atoms; frames are `steps_per_frame` steps
    /// of `dt` apart, starting at step `first_step`, in the orthorhombic
    /// periodic box `box_lengths` if given.
    pub fn create(
        path: &Path,
        atoms: usize,
        first_step: u64,
        steps_per_frame: u64,
        dt: f64,
        title: &str,
        box_lengths: Option<&Vector3<f64>>,
    ) -> io::Result<Self> {
        let clamp = |x: u64| i32::try_from(x).unwrap_or(i32::MAX);
        let steps_per_frame = clamp(steps_per_frame);
        let mut header = Vec::with_capacity(84);
        header.extend_from_slice(b"CORD");
        let mut icntrl = [0i32; 20];
        icntrl[1] = clamp(first_step);
        icntrl[2] = steps_per_frame;
        icntrl[UNIT_CELL_FLAG] = i32::from(box_lengths.is_some());
        icntrl[19] = CHARMM_VERSION;
        for (k, v) in icntrl.iter().enumerate() {
            if k == 9 {
                header.extend_from_slice(&(dt as f32).to_le_bytes());
            } else {
                header.extend_from_slice(&v.to_le_bytes());
            }
        }
        let mut file = BufWriter::new(File::create(path)?);
        record(&mut file, &header)?;
        let mut title_record = 1i32.to_le_bytes().to_vec();
        let mut line = format!("{title:<80}").into_bytes();
        line.truncate(80);
        title_record.extend_from_slice(&line);
        record(&mut file, &title_record)?;
        record(&mut file, &(atoms as i32).to_le_bytes())?;
        Ok(DcdWriter {
            file,
            atoms,
            frames: 0,
            steps_per_frame,
            unit_cell: box_lengths.map(|b| {
                let mut cell = [0u8; 48];
                for (k, v) in [b.x, 0.0, b.y, 0.0, 0.0, b.z].into_iter().enumerate() {
                    cell[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes());
                }
                cell
            }),
        })
    }

    /// Appends one frame of `atoms` positions and updates the header.
    pub fn write_frame(&mut self, positions: &[[f32; 3]]) -> io::Result<()> {
        debug_assert_eq!(positions.len(), self.atoms);
        if let Some(cell) = &self.unit_cell {
            record(&mut self.file, cell)?;
        }
        let mut payload = Vec::with_capacity(4 * positions.len());
        for axis in 0..3 {
            payload.clear();
            for p in positions {
                payload.extend_from_slice(&p[axis].to_le_bytes());
            }
            record(&mut self.file, &payload)?;
        }
        self.frames += 1;
        let _ = self.file.seek(SeekFrom::Start(NSET_OFFSET))?;
        self.file.write_all(&self.frames.to_le_bytes())?;
        let _ = self.file.seek(SeekFrom::Start(NSTEP_OFFSET))?;
        let steps = self.frames.saturating_mul(self.steps_per_frame);
        self.file.write_all(&steps.to_le_bytes())?;
        let _ = self.file.seek(SeekFrom::End(0))?;
        Ok(())
    }

    /// Flushes to disk.
    pub fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn i32_at(b: &[u8], at: usize) -> i32 {
        i32::from_le_bytes(b[at..at + 4].try_into().unwrap())
    }

    /// The file's records, each checked for equal leading and trailing lengths.
    fn records(bytes: &[u8]) -> Vec<&[u8]> {
        let mut out = Vec::new();
        let mut at = 0;
        while at < bytes.len() {
            let len = i32_at(bytes, at) as usize;
            assert_eq!(i32_at(bytes, at + 4 + len) as usize, len);
            out.push(&bytes[at + 4..at + 4 + len]);
            at += len + 8;
        }
        out
    }

    /// A periodic box sets the flag and puts the 48-byte cell record
    /// `[A, 0, B, 0, 0, C]` before each frame's coordinates; an open system
    /// has neither.
    #[test]
    fn unit_cell_record_for_periodic_boxes_only() {
        let dir = tempfile::tempdir().unwrap();
        let box_lengths = Vector3::new(4.5, 3.0, 6.0);
        for periodic in [true, false] {
            let path = dir.path().join(format!("{periodic}.dcd"));
            let cell = periodic.then_some(&box_lengths);
            let mut dcd = DcdWriter::create(&path, 2, 0, 10, 0.01, "t", cell).unwrap();
            for f in 0..3 {
                dcd.write_frame(&[[f as f32, 1.0, 2.0], [3.0, 4.0, 5.0]])
                    .unwrap();
            }
            dcd.flush().unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let r = records(&bytes);
            assert_eq!(i32_at(r[0], 4 + 4 * UNIT_CELL_FLAG), i32::from(periodic));
            assert_eq!(i32_at(r[0], 4), 3, "frame count");
            let per_frame = if periodic { 4 } else { 3 };
            assert_eq!(r.len(), 3 + 3 * per_frame);
            for f in 0..3 {
                let frame = &r[3 + f * per_frame..3 + (f + 1) * per_frame];
                if periodic {
                    let cell: Vec<f64> = frame[0]
                        .chunks(8)
                        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                        .collect();
                    assert_eq!(cell, [4.5, 0.0, 3.0, 0.0, 0.0, 6.0]);
                }
                let x = frame[per_frame - 3];
                assert_eq!(f32::from_le_bytes(x[0..4].try_into().unwrap()), f as f32);
            }
        }
    }
}
