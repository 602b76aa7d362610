//! A writer of GSD trajectories: HOOMD-blue's format (glotzerlab/gsd, file
//! layer 2.x, `hoomd` schema 1.4), read by the `gsd` Python package,
//! HOOMD-blue, OVITO and freud. Unlike DCD it stores orientations as
//! quaternions and the box in every file.
//!
//! # What a frame holds
//!
//! Frame 0: `configuration/step` (uint64), `configuration/dimensions`
//! (uint8, 3), `configuration/box` (6 float32: `Lx, Ly, Lz` and tilts 0),
//! `particles/N` (uint32), `particles/position` (N x 3 float32) and
//! `particles/orientation` (N x 4 float32). Later frames: the step and the
//! orientations only; the schema takes every chunk a frame lacks from frame
//! 0 (rotors never move), as `gsd.hoomd` does when reading.
//!
//! Moving bodies ([`GsdWriter::create_bodies`]): frame 0 adds
//! `particles/types` (`type0`, ...), `typeid`, `mass` and `moment_inertia`;
//! every frame holds `particles/position`, `orientation`, `velocity`,
//! `angmom` (HOOMD's quaternion `P = 2 Q (0, L_body)`) and `image` (int32).
//!
//! * Orientations are written normalised (the schema's unit quaternions),
//!   scalar first `(q0, q1, q2, q3)`: HOOMD's order and convention, the
//!   body-to-space rotation `v_s = Q (0, v_b) Q~` of `R(Q)`.
//! * HOOMD's box is centred at the origin, `-L/2 <= x < L/2`: a site `r` of
//!   a box `[corner, corner + L)` is written as `r - corner` wrapped into
//!   `[0, L)`, minus `L/2` (a translation, plus a lattice vector for sites
//!   outside the box; the same periodic system).
//! * float32 throughout: orientations and positions keep ~7 digits.
//!
//! # The file layout (GSD file layer 2.x, all little-endian)
//!
//! A 256-byte header (magic, index and name-list locations and sizes,
//! versions, application and schema names), an index of 32-byte entries
//! (frame, N, location, M, name id, type, flags; sorted by frame then id;
//! the first entry with location 0 ends it), a name list (the chunk names,
//! each ended by a 0 byte, padded with zeros to a multiple of 64 bytes),
//! then the data chunks. A frame's chunks are appended first and its index
//! entries written after them, so a file cut short by a crash still reads
//! up to its last complete frame; a full index moves to the end of the file
//! at twice the size, and only then does the header point to it.

mod bodies;

pub use bodies::{BodyFrame, BodyTypes};

use super::folder::create_file;
use crate::checks::{each, finite_and_positive, positive, InputError};
use crate::quaternion::Quat;
use nalgebra::Vector3;
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
/// File layer 2.0, `major << 16 | minor`.
const GSD_VERSION: u32 = 2 << 16;
/// The `hoomd` schema 1.4, readable by gsd 2.x to 5.x.
const SCHEMA_VERSION: u32 = (1 << 16) | 4;
const HEADER_BYTES: u64 = 256;
const ENTRY_BYTES: u64 = 32;
/// Index entries allocated at creation (doubled whenever full).
const INITIAL_INDEX_ENTRIES: u64 = 128;
/// The name list is allocated in segments of this many bytes.
const NAME_SEGMENT: usize = 64;
const APPLICATION: &str = concat!("quatrot ", env!("CARGO_PKG_VERSION"));

/// GSD's type codes.
#[derive(Clone, Copy)]
#[repr(u8)]
enum GsdType {
    Uint8 = 1,
    Uint32 = 3,
    Uint64 = 4,
    Int8 = 5,
    Int32 = 7,
    Float = 9,
}

/// The chunk names, in name-id order.
const NAMES: [&str; 6] = [
    "configuration/step",
    "configuration/dimensions",
    "configuration/box",
    "particles/N",
    "particles/position",
    "particles/orientation",
];
const STEP: u16 = 0;
const DIMENSIONS: u16 = 1;
const BOX: u16 = 2;
const PARTICLES: u16 = 3;
const POSITION: u16 = 4;
const ORIENTATION: u16 = 5;

/// An orthorhombic box `[corner, corner + lengths)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GsdBox {
    /// Edge lengths (> 0).
    pub lengths: Vector3<f64>,
    /// The lower corner.
    pub corner: Vector3<f64>,
}

impl GsdBox {
    /// The box of a trajectory of rotors on `sites`: the periodic box
    /// `[0, box_lengths)` when given (each edge finite and > 0, as a
    /// periodic boundary's), else the enclosing box grown by `margin`
    /// (finite and > 0). The error names `box_lengths[k]` or `margin`.
    pub fn new(
        box_lengths: Option<Vector3<f64>>,
        sites: &[Vector3<f64>],
        margin: f64,
    ) -> Result<GsdBox, InputError> {
        let (cell, what) = match box_lengths {
            Some(l) => {
                each(l.as_slice(), positive).map_err(|e| e.at("box_lengths"))?;
                (GsdBox::periodic(l), "box_lengths")
            }
            None => (
                GsdBox::enclosing(sites, finite_and_positive("margin", margin)?),
                "sites",
            ),
        };
        // The format stores float32: the box, and the positions wrapped
        // into it, must be within its range.
        match cell.lengths.iter().position(|&l| l > f64::from(f32::MAX)) {
            None => Ok(cell),
            Some(k) => Err(InputError::new(
                what,
                format!(
                    "the box edge {k} ({}) is beyond the range of GSD's float32 ({:e})",
                    crate::checks::num(cell.lengths[k]),
                    f32::MAX
                ),
            )),
        }
    }

    /// A periodic box `[0, lengths)` (the lattices' box).
    fn periodic(lengths: Vector3<f64>) -> GsdBox {
        GsdBox {
            lengths,
            corner: Vector3::zeros(),
        }
    }

    /// For an open cluster: the bounding box of `sites` grown by `margin`
    /// (> 0) on every side, so that no site is near a face.
    fn enclosing(sites: &[Vector3<f64>], margin: f64) -> GsdBox {
        let lo = sites
            .iter()
            .fold(Vector3::repeat(f64::INFINITY), |m, s| m.inf(s));
        let hi = sites
            .iter()
            .fold(Vector3::repeat(f64::NEG_INFINITY), |m, s| m.sup(s));
        GsdBox {
            lengths: hi - lo + Vector3::repeat(2.0 * margin),
            corner: lo - Vector3::repeat(margin),
        }
    }

    /// The position HOOMD sees for `site`: wrapped into the box, centred.
    pub fn hoomd_position(&self, site: &Vector3<f64>) -> Vector3<f64> {
        Vector3::from_fn(|a, _| {
            let l = self.lengths[a];
            let x = site[a] - self.corner[a];
            x - l * (x / l).floor() - 0.5 * l
        })
    }
}

/// The chunks every frame 0 holds after the step: dimensions, box, N.
fn frame_zero(cell: &GsdBox, particles: usize) -> Vec<Chunk> {
    let l = cell.lengths;
    let box_chunk = [l.x as f32, l.y as f32, l.z as f32, 0.0, 0.0, 0.0];
    vec![
        (DIMENSIONS, GsdType::Uint8, 1, 1, vec![3u8]),
        (BOX, GsdType::Float, 6, 1, floats(&box_chunk)),
        (
            PARTICLES,
            GsdType::Uint32,
            1,
            1,
            (particles as u32).to_le_bytes().to_vec(),
        ),
    ]
}

/// One index entry (32 bytes on disk).
#[derive(Clone, Copy)]
struct Entry {
    frame: u64,
    n: u64,
    location: u64,
    m: u32,
    id: u16,
    kind: GsdType,
}

impl Entry {
    fn bytes(&self) -> [u8; ENTRY_BYTES as usize] {
        let mut b = [0u8; ENTRY_BYTES as usize];
        b[0..8].copy_from_slice(&self.frame.to_le_bytes());
        b[8..16].copy_from_slice(&self.n.to_le_bytes());
        b[16..24].copy_from_slice(&self.location.to_le_bytes());
        b[24..28].copy_from_slice(&self.m.to_le_bytes());
        b[28..30].copy_from_slice(&self.id.to_le_bytes());
        b[30] = self.kind as u8;
        // b[31]: flags, 0.
        b
    }
}

/// A chunk to write: name id, type, rows, columns, bytes.
type Chunk = (u16, GsdType, u64, u32, Vec<u8>);

/// An open GSD trajectory of a fixed set of rotors or of moving bodies.
pub struct GsdWriter {
    file: BufWriter<File>,
    /// The chunks of frame 0 only (in name-id order, before the frame's).
    first: Vec<Chunk>,
    rotors: usize,
    frames: u64,
    entries: u64,
    index_location: u64,
    index_allocated: u64,
    namelist_location: u64,
    namelist_segments: u64,
    end: u64,
}

fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn rows<const M: usize, T: Copy>(values: &[[T; M]], bytes: fn(T) -> [u8; 4]) -> Vec<u8> {
    values.iter().flatten().flat_map(|&x| bytes(x)).collect()
}

impl GsdWriter {
    /// Creates `path` for rotors on `sites` in `cell` (positions written
    /// once, in frame 0); the frames follow with [`GsdWriter::write_frame`].
    pub fn create(path: &Path, sites: &[Vector3<f64>], cell: &GsdBox) -> io::Result<Self> {
        let positions: Vec<f32> = sites
            .iter()
            .flat_map(|s| {
                let p = cell.hoomd_position(s);
                [p.x as f32, p.y as f32, p.z as f32]
            })
            .collect();
        let n = sites.len() as u64;
        let mut first = frame_zero(cell, sites.len());
        first.push((POSITION, GsdType::Float, n, 3, floats(&positions)));
        Self::open(path, &NAMES, first, sites.len())
    }

    /// Creates `path` with the chunk `names` for `particles` particles,
    /// `first` the chunks of frame 0 alone.
    fn open(path: &Path, names: &[&str], first: Vec<Chunk>, particles: usize) -> io::Result<Self> {
        let mut names: Vec<u8> = names
            .iter()
            .flat_map(|n| n.bytes().chain(std::iter::once(0)))
            .collect();
        // At least one zero byte after the last name, in whole segments.
        names.resize((names.len() / NAME_SEGMENT + 1) * NAME_SEGMENT, 0);
        let index_location = HEADER_BYTES;
        let namelist_location = index_location + INITIAL_INDEX_ENTRIES * ENTRY_BYTES;
        let mut writer = GsdWriter {
            file: BufWriter::new(create_file(path)?),
            first,
            rotors: particles,
            frames: 0,
            entries: 0,
            index_location,
            index_allocated: INITIAL_INDEX_ENTRIES,
            namelist_location,
            namelist_segments: (names.len() / NAME_SEGMENT) as u64,
            end: namelist_location + names.len() as u64,
        };
        writer.write_header()?;
        writer
            .file
            .write_all(&vec![0u8; (INITIAL_INDEX_ENTRIES * ENTRY_BYTES) as usize])?;
        writer.file.write_all(&names)?;
        writer.file.flush()?;
        Ok(writer)
    }

    fn write_header(&mut self) -> io::Result<()> {
        let mut h = Vec::with_capacity(HEADER_BYTES as usize);
        for v in [
            MAGIC,
            self.index_location,
            self.index_allocated,
            self.namelist_location,
            self.namelist_segments,
        ] {
            h.extend_from_slice(&v.to_le_bytes());
        }
        h.extend_from_slice(&SCHEMA_VERSION.to_le_bytes());
        h.extend_from_slice(&GSD_VERSION.to_le_bytes());
        for name in [APPLICATION, "hoomd"] {
            let mut field = [0u8; 64];
            let bytes = &name.as_bytes()[..name.len().min(63)];
            field[..bytes.len()].copy_from_slice(bytes);
            h.extend_from_slice(&field);
        }
        h.resize(HEADER_BYTES as usize, 0);
        self.file.rewind()?;
        self.file.write_all(&h)
    }

    /// Appends one frame at `step` with the rotors' `orientations` (one per
    /// site, in order) and commits it.
    pub fn write_frame(&mut self, step: u64, orientations: &[Quat]) -> io::Result<()> {
        if orientations.len() != self.rotors {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "orientations: {} given for {} rotors",
                    orientations.len(),
                    self.rotors
                ),
            ));
        }
        let n = self.rotors as u64;
        let quaternions: Vec<f32> = orientations
            .iter()
            .flat_map(|q| q.try_normalize().unwrap_or(*q).0.map(|x| x as f32))
            .collect();
        self.commit(
            step,
            vec![(ORIENTATION, GsdType::Float, n, 4, floats(&quaternions))],
        )
    }

    /// Writes the step, frame 0's own chunks (in the first frame) and
    /// `chunks` (in name-id order), then their index entries.
    fn commit(&mut self, step: u64, chunks: Vec<Chunk>) -> io::Result<()> {
        let mut all: Vec<Chunk> = vec![(STEP, GsdType::Uint64, 1, 1, step.to_le_bytes().to_vec())];
        if self.frames == 0 {
            all.append(&mut self.first);
        }
        all.extend(chunks);
        // The data first, at the end of the file ...
        let _position = self.file.seek(SeekFrom::Start(self.end))?;
        let mut entries = Vec::with_capacity(all.len());
        for (id, kind, rows, columns, data) in all {
            entries.push(Entry {
                frame: self.frames,
                n: rows,
                location: self.end,
                m: columns,
                id,
                kind,
            });
            self.file.write_all(&data)?;
            self.end += data.len() as u64;
        }
        // ... then the index entries (the ids are already in order).
        if self.entries + entries.len() as u64 > self.index_allocated {
            self.grow_index()?;
        }
        let _position = self.file.seek(SeekFrom::Start(
            self.index_location + self.entries * ENTRY_BYTES,
        ))?;
        for e in &entries {
            self.file.write_all(&e.bytes())?;
        }
        self.entries += entries.len() as u64;
        self.frames += 1;
        self.file.flush()
    }

    /// Copies the index to the end of the file at twice its size, then
    /// points the header to it.
    fn grow_index(&mut self) -> io::Result<()> {
        self.file.flush()?;
        let used = (self.entries * ENTRY_BYTES) as usize;
        let mut index = vec![0u8; 2 * (self.index_allocated * ENTRY_BYTES) as usize];
        {
            let file = self.file.get_mut();
            let _position = file.seek(SeekFrom::Start(self.index_location))?;
            io::Read::read_exact(file, &mut index[..used])?;
        }
        let _position = self.file.seek(SeekFrom::Start(self.end))?;
        self.file.write_all(&index)?;
        self.file.flush()?;
        self.index_location = self.end;
        self.index_allocated *= 2;
        self.end += index.len() as u64;
        self.write_header()
    }

    /// Flushes to disk.
    pub fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u64_at(b: &[u8], at: usize) -> u64 {
        u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
    }

    /// A minimal reader of what the writer promises: the header, the sorted
    /// index up to the first zero location, the names, and chunk data.
    struct Parsed {
        names: Vec<String>,
        entries: Vec<(u64, u64, u64, u32, u16, u8)>,
        bytes: Vec<u8>,
    }

    fn parse(path: &Path) -> Parsed {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(u64_at(&bytes, 0), MAGIC);
        let (index_at, allocated) = (u64_at(&bytes, 8) as usize, u64_at(&bytes, 16) as usize);
        let (names_at, segments) = (u64_at(&bytes, 24) as usize, u64_at(&bytes, 32) as usize);
        assert_eq!(&bytes[40..48], &[4, 0, 1, 0, 0, 0, 2, 0]);
        assert_eq!(&bytes[112..118], b"hoomd\0");
        let names_block = &bytes[names_at..names_at + segments * NAME_SEGMENT];
        assert_eq!(*names_block.last().unwrap(), 0);
        let names = names_block
            .split(|&c| c == 0)
            .take_while(|n| !n.is_empty())
            .map(|n| String::from_utf8(n.to_vec()).unwrap())
            .collect();
        let entries = (0..allocated)
            .map(|k| {
                let e = &bytes[index_at + 32 * k..index_at + 32 * (k + 1)];
                (
                    u64_at(e, 0),
                    u64_at(e, 8),
                    u64_at(e, 16),
                    u32::from_le_bytes(e[24..28].try_into().unwrap()),
                    u16::from_le_bytes(e[28..30].try_into().unwrap()),
                    e[30],
                )
            })
            .take_while(|e| e.2 != 0)
            .collect();
        Parsed {
            names,
            entries,
            bytes,
        }
    }

    fn f32s(bytes: &[u8], at: u64, count: u64) -> Vec<f32> {
        (0..count as usize)
            .map(|k| {
                let i = at as usize + 4 * k;
                f32::from_le_bytes(bytes[i..i + 4].try_into().unwrap())
            })
            .collect()
    }

    /// 100 frames of 3 rotors (the index grows from 128 entries past 256):
    /// the names, one sorted entry list, frame 0 with every chunk and the
    /// later frames with step and orientation, data where the entries say.
    #[test]
    fn frames_index_and_chunks_as_the_format_says() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.gsd");
        let sites = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.5, 0.0, 2.9),
            Vector3::new(3.1, 0.5, 1.0),
        ];
        let cell = GsdBox::periodic(Vector3::new(3.0, 2.0, 3.0));
        let mut gsd = GsdWriter::create(&path, &sites, &cell).unwrap();
        let frames = 100u64;
        let q = |f: u64, i: usize| Quat::new(1.0 + f as f64, i as f64, -0.5, 0.25) * 2.0;
        for f in 0..frames {
            let orientations: Vec<Quat> = (0..3).map(|i| q(f, i)).collect();
            gsd.write_frame(10 * f + 5, &orientations).unwrap();
        }
        let p = parse(&path);
        assert_eq!(p.names, NAMES);
        assert_eq!(p.entries.len() as u64, 6 + 2 * (frames - 1));
        let mut sorted = p.entries.clone();
        sorted.sort_by_key(|e| (e.0, e.4));
        assert_eq!(sorted, p.entries);
        let find = |frame: u64, id: u16| {
            *p.entries
                .iter()
                .find(|e| e.0 == frame && e.4 == id)
                .unwrap()
        };
        let box_entry = find(0, BOX);
        assert_eq!((box_entry.1, box_entry.3, box_entry.5), (6, 1, 9));
        assert_eq!(
            f32s(&p.bytes, box_entry.2, 6),
            [3.0, 2.0, 3.0, 0.0, 0.0, 0.0]
        );
        let positions = find(0, POSITION);
        assert_eq!((positions.1, positions.3), (3, 3));
        // Wrapped into [0, L) and centred: 3.1 -> 0.1 -> -1.4; 2.9 -> 1.4.
        let expected = [-1.5, -1.0, -1.5, 0.0, -1.0, 1.4, -1.4, -0.5, -0.5];
        for (x, e) in f32s(&p.bytes, positions.2, 9).iter().zip(expected) {
            assert!((x - e).abs() < 1e-6, "{x} vs {e}");
        }
        for f in [0, 1, 57, frames - 1] {
            let step = find(f, STEP);
            assert_eq!((step.5, u64_at(&p.bytes, step.2 as usize)), (4, 10 * f + 5));
            let o = find(f, ORIENTATION);
            let values = f32s(&p.bytes, o.2, 12);
            for i in 0..3 {
                let unit = q(f, i).try_normalize().unwrap();
                for c in 0..4 {
                    assert!((values[4 * i + c] as f64 - unit.0[c]).abs() < 1e-7);
                }
            }
        }
        assert!(p
            .entries
            .iter()
            .all(|e| e.0 == 0 || [STEP, ORIENTATION].contains(&e.4)));
    }

    /// An enclosing box keeps every site at least the margin from a face.
    #[test]
    fn enclosing_box_has_the_margin() {
        let sites = [Vector3::new(-1.0, 2.0, 0.0), Vector3::new(3.0, 2.5, 1.0)];
        let cell = GsdBox::enclosing(&sites, 0.5);
        assert_eq!(cell.lengths, Vector3::new(5.0, 1.5, 2.0));
        for s in &sites {
            let p = cell.hoomd_position(s);
            for a in 0..3 {
                assert!(p[a].abs() <= 0.5 * cell.lengths[a] - 0.5 + 1e-12);
            }
        }
    }

    /// A box edge or a margin that is not finite and > 0, or a box beyond
    /// float32's range, is refused by name; a given box is periodic, from
    /// the origin.
    #[test]
    fn bad_boxes_and_margins_are_refused() {
        let sites = [Vector3::zeros()];
        assert_eq!(
            GsdBox::new(Some(Vector3::new(1.0, 0.0, 1.0)), &sites, 1.0)
                .unwrap_err()
                .to_string(),
            "box_lengths[1]: must be > 0, got 0"
        );
        assert_eq!(
            GsdBox::new(None, &sites, -1.0).unwrap_err().to_string(),
            "margin: must be finite and > 0, got -1"
        );
        let cell = GsdBox::new(Some(Vector3::repeat(2.0)), &sites, -1.0).unwrap();
        assert_eq!(cell, GsdBox::periodic(Vector3::repeat(2.0)));
        // Beyond float32, which the format stores (issue 37: written as inf).
        assert_eq!(
            GsdBox::new(Some(Vector3::new(1.0, 1e39, 1.0)), &sites, 1.0)
                .unwrap_err()
                .to_string(),
            "box_lengths: the box edge 1 (1e39) is beyond the range of GSD's float32 (3.4028235e38)"
        );
        let far = [Vector3::zeros(), Vector3::new(0.0, 0.0, 1e39)];
        assert!(GsdBox::new(None, &far, 1.0)
            .unwrap_err()
            .to_string()
            .starts_with("sites: the box edge 2 (1e39) is beyond the range"));
    }

    /// A frame with the wrong number of orientations is refused.
    #[test]
    fn wrong_rotor_count_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let cell = GsdBox::periodic(Vector3::repeat(1.0));
        let mut gsd =
            GsdWriter::create(&dir.path().join("t.gsd"), &[Vector3::zeros()], &cell).unwrap();
        let err = gsd.write_frame(0, &[Quat::IDENTITY; 2]).unwrap_err();
        assert_eq!(err.to_string(), "orientations: 2 given for 1 rotors");
    }
}
