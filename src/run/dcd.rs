//! A minimal writer of CHARMM-style DCD trajectories (as read by VMD and
//! mdtraj): Fortran unformatted records, little-endian, single precision,
//! no unit cell. The header's frame count is rewritten after every frame,
//! so the file is valid whenever the run stops.

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

/// An open DCD file.
pub struct DcdWriter {
    file: BufWriter<File>,
    atoms: usize,
    frames: i32,
    steps_per_frame: i32,
}

fn record(out: &mut impl Write, payload: &[u8]) -> io::Result<()> {
    let len = payload.len() as i32;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(payload)?;
    out.write_all(&len.to_le_bytes())
}

impl DcdWriter {
    /// Creates `path` for `atoms` atoms; frames are `steps_per_frame` steps
    /// of `dt` apart, starting at step `first_step`.
    pub fn create(
        path: &Path,
        atoms: usize,
        first_step: u64,
        steps_per_frame: u64,
        dt: f64,
        title: &str,
    ) -> io::Result<Self> {
        let clamp = |x: u64| i32::try_from(x).unwrap_or(i32::MAX);
        let steps_per_frame = clamp(steps_per_frame);
        let mut header = Vec::with_capacity(84);
        header.extend_from_slice(b"CORD");
        let mut icntrl = [0i32; 20];
        icntrl[1] = clamp(first_step);
        icntrl[2] = steps_per_frame;
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
        })
    }

    /// Appends one frame of `atoms` positions and updates the header.
    pub fn write_frame(&mut self, positions: &[[f32; 3]]) -> io::Result<()> {
        debug_assert_eq!(positions.len(), self.atoms);
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
