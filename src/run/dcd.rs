//! A minimal writer of CHARMM-style DCD trajectories (as read by VMD and
//! mdtraj): Fortran unformatted records, little-endian, single precision.
//! Each frame is written whole, then the header's frame count is rewritten,
//! so the file is valid up to its last counted frame however the run stops
//! (`kill -9` included); ISTART is the step of the first frame, so the step
//! of the last frame follows from the header (a restart appends only after
//! checking it).
//!
//! For a periodic box the header sets CHARMM's unit-cell flag (the 11th
//! control integer) and every frame starts with a record of six doubles
//! `[A, cos(gamma), B, cos(beta), cos(alpha), C]`: the cell lengths and the
//! cosines of the angles between the edges (0 for the orthorhombic box), the
//! order and cosine form CHARMM and NAMD write and VMD's DCD plugin (used by
//! mdtraj) reads as lengths and 90-degree angles.

use super::folder::{create_file, open_existing};
use nalgebra::Vector3;
use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
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
    file: File,
    atoms: usize,
    frames: i32,
    steps_per_frame: i32,
    /// The unit-cell record of every frame (periodic boxes only).
    unit_cell: Option<[u8; 48]>,
    /// One frame's bytes, reused.
    frame: Vec<u8>,
}

/// What the header of an existing DCD file says, and whether the file holds
/// exactly the frames it counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DcdHeader {
    /// Atoms per frame.
    pub atoms: usize,
    /// Frames counted in the header (NSET).
    pub frames: i32,
    /// The step of the first frame (ISTART).
    pub first_step: i32,
    /// Steps between frames (NSAVC).
    pub steps_per_frame: i32,
    /// Whether frames carry a unit-cell record.
    pub unit_cell: bool,
    /// The file's size is the header's plus exactly `frames` frames.
    pub complete: bool,
}

impl DcdHeader {
    /// The step of the last frame, if there is one.
    pub fn last_step(&self) -> Option<i64> {
        (self.frames > 0).then(|| {
            i64::from(self.first_step)
                + i64::from(self.frames - 1) * i64::from(self.steps_per_frame)
        })
    }
}

fn record(out: &mut Vec<u8>, payload: &[u8]) {
    let len = payload.len() as i32;
    out.extend_from_slice(&len.to_le_bytes());
    out.extend_from_slice(payload);
    out.extend_from_slice(&len.to_le_bytes());
}

/// Bytes of one frame of `atoms` atoms.
fn frame_bytes(atoms: usize, unit_cell: bool) -> u64 {
    let coordinates = 3 * (8 + 4 * atoms as u64);
    coordinates + if unit_cell { 8 + 48 } else { 0 }
}

/// Reads the header of the DCD file at `path` (as this writer writes it).
pub fn read_header(path: &Path) -> io::Result<DcdHeader> {
    let bad = |what: &str| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not a DCD file written by quatrot ({what})"),
        )
    };
    let mut file = File::open(path)?;
    let size = file.metadata()?.len();
    let mut head = [0u8; 92];
    file.read_exact(&mut head)?;
    let int = |at: usize| i32::from_le_bytes([head[at], head[at + 1], head[at + 2], head[at + 3]]);
    if int(0) != 84 || &head[4..8] != b"CORD" || int(88) != 84 {
        return Err(bad("first record"));
    }
    let icntrl = |k: usize| int(8 + 4 * k);
    let title_len = 4 + 80;
    let mut rest = [0u8; 4 + 4 + 4];
    let _ = file.seek(SeekFrom::Start(92 + 8 + title_len))?;
    file.read_exact(&mut rest)?;
    let atoms = i32::from_le_bytes([rest[4], rest[5], rest[6], rest[7]]);
    let header_len = 92 + 8 + title_len + 12;
    let atoms = usize::try_from(atoms).map_err(|_| bad("atom count"))?;
    let unit_cell = icntrl(UNIT_CELL_FLAG) != 0;
    let frames = icntrl(0);
    let expected = u64::try_from(frames)
        .ok()
        .map(|f| header_len + f * frame_bytes(atoms, unit_cell));
    Ok(DcdHeader {
        atoms,
        frames,
        first_step: icntrl(1),
        steps_per_frame: icntrl(2),
        unit_cell,
        complete: expected == Some(size),
    })
}

impl DcdWriter {
    /// Creates `path` for `atoms` atoms; frames are `steps_per_frame` steps
    /// of `dt` apart, the first at step `first_step`, in the orthorhombic
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
        let mut bytes = Vec::new();
        record(&mut bytes, &header);
        let mut title_record = 1i32.to_le_bytes().to_vec();
        let mut line = format!("{title:<80}").into_bytes();
        line.truncate(80);
        title_record.extend_from_slice(&line);
        record(&mut bytes, &title_record);
        record(&mut bytes, &(atoms as i32).to_le_bytes());
        let mut file = create_file(path)?;
        file.write_all(&bytes)?;
        Ok(DcdWriter {
            file,
            atoms,
            frames: 0,
            steps_per_frame,
            unit_cell: box_lengths.map(unit_cell_record),
            frame: Vec::new(),
        })
    }

    /// Opens the existing file at `path` to append frames after the
    /// `header.frames` it holds (the caller checked `header`, read by
    /// [`read_header`], against the run).
    pub fn append(
        path: &Path,
        header: &DcdHeader,
        box_lengths: Option<&Vector3<f64>>,
    ) -> io::Result<Self> {
        let mut file = open_existing(path)?;
        let _ = file.seek(SeekFrom::End(0))?;
        Ok(DcdWriter {
            file,
            atoms: header.atoms,
            frames: header.frames,
            steps_per_frame: header.steps_per_frame,
            unit_cell: box_lengths.map(unit_cell_record),
            frame: Vec::new(),
        })
    }

    /// Appends one frame of `atoms` positions (one write), then updates the
    /// header's frame count: a run killed between the two leaves a file
    /// whose header counts only complete frames.
    pub fn write_frame(&mut self, positions: &[[f32; 3]]) -> io::Result<()> {
        debug_assert_eq!(positions.len(), self.atoms);
        self.frame.clear();
        if let Some(cell) = &self.unit_cell {
            record(&mut self.frame, cell);
        }
        let mut payload = Vec::with_capacity(4 * positions.len());
        for axis in 0..3 {
            payload.clear();
            for p in positions {
                payload.extend_from_slice(&p[axis].to_le_bytes());
            }
            record(&mut self.frame, &payload);
        }
        self.file.write_all(&self.frame)?;
        self.frames += 1;
        let mut counts = self.frames.to_le_bytes().to_vec();
        let steps = self.frames.saturating_mul(self.steps_per_frame);
        let _ = self.file.seek(SeekFrom::Start(NSET_OFFSET))?;
        self.file.write_all(&counts)?;
        counts.clear();
        counts.extend_from_slice(&steps.to_le_bytes());
        let _ = self.file.seek(SeekFrom::Start(NSTEP_OFFSET))?;
        self.file.write_all(&counts)?;
        let _ = self.file.seek(SeekFrom::End(0))?;
        Ok(())
    }

    /// Flushes to disk (every frame is written as it comes: nothing is
    /// buffered here).
    pub fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

/// The unit-cell record `[A, cos(gamma), B, cos(beta), cos(alpha), C]`.
fn unit_cell_record(b: &Vector3<f64>) -> [u8; 48] {
    let mut cell = [0u8; 48];
    for (k, v) in [b.x, 0.0, b.y, 0.0, 0.0, b.z].into_iter().enumerate() {
        cell[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes());
    }
    cell
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

    /// The header read back gives the frames, the step of the last one and
    /// the layout; a file cut inside a frame is not complete.
    #[test]
    fn the_header_reads_back_and_a_cut_file_is_incomplete() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.dcd");
        let box_lengths = Vector3::repeat(2.0);
        let mut dcd = DcdWriter::create(&path, 2, 30, 10, 0.01, "t", Some(&box_lengths)).unwrap();
        for _ in 0..3 {
            dcd.write_frame(&[[0.0; 3]; 2]).unwrap();
        }
        let header = read_header(&path).unwrap();
        assert_eq!(
            (header.atoms, header.frames, header.unit_cell),
            (2, 3, true)
        );
        assert_eq!(header.last_step(), Some(50));
        assert!(header.complete);
        let len = std::fs::metadata(&path).unwrap().len();
        std::fs::OpenOptions::new()
            .write(true)
            .open(&path)
            .unwrap()
            .set_len(len - 4)
            .unwrap();
        assert!(!read_header(&path).unwrap().complete);
    }
}
