//! Trajectories of moving bodies in the GSD format: frame 0 carries each
//! body's type, mass and principal moments; every frame the centres,
//! orientations, velocities, HOOMD's angular momentum quaternions and the
//! images.

use super::{floats, frame_zero, rows, GsdBox, GsdType, GsdWriter};
use std::io;
use std::path::Path;

/// The chunk names of a trajectory of moving bodies, in name-id order
/// (the first four as [`super::NAMES`]).
const BODY_NAMES: [&str; 13] = [
    "configuration/step",
    "configuration/dimensions",
    "configuration/box",
    "particles/N",
    "particles/types",
    "particles/typeid",
    "particles/mass",
    "particles/moment_inertia",
    "particles/position",
    "particles/orientation",
    "particles/velocity",
    "particles/angmom",
    "particles/image",
];

/// One frame of moving bodies, each array one row per body.
pub struct BodyFrame<'a> {
    /// Centres, HOOMD's centred box ([`GsdBox::hoomd_position`]).
    pub position: &'a [[f32; 3]],
    /// Unit quaternions, scalar first, principal frame to space.
    pub orientation: &'a [[f32; 4]],
    /// Centre velocities.
    pub velocity: &'a [[f32; 3]],
    /// HOOMD's angular momentum quaternion `P = 2 Q (0, L_body)`.
    pub angmom: &'a [[f32; 4]],
    /// Box lengths crossed (unwrapped centre `position + image * L`).
    pub image: &'a [[i32; 3]],
}

/// What frame 0 of a trajectory of bodies holds besides the state: each
/// body's type (named `type0`, `type1`, ...), mass and principal moments.
pub struct BodyTypes<'a> {
    /// The number of body types.
    pub types: usize,
    /// Each body's type.
    pub typeid: &'a [u32],
    /// Each body's mass.
    pub mass: &'a [f32],
    /// Each body's principal moments.
    pub moment_inertia: &'a [[f32; 3]],
}

impl GsdWriter {
    /// Creates `path` for moving bodies in `cell` of the types `types`;
    /// the frames follow with [`GsdWriter::write_bodies`].
    pub fn create_bodies(path: &Path, cell: &GsdBox, types: &BodyTypes<'_>) -> io::Result<Self> {
        let n = types.typeid.len();
        let mut first = frame_zero(cell, n);
        // Names of at most 11 characters and a 0 byte, one row per type.
        let mut names = vec![0u8; types.types * 12];
        for (t, row) in names.chunks_mut(12).enumerate() {
            let name = format!("type{t}");
            row[..name.len()].copy_from_slice(name.as_bytes());
        }
        let ids: Vec<u8> = types.typeid.iter().flat_map(|t| t.to_le_bytes()).collect();
        let masses = floats(types.mass);
        let moments = rows(types.moment_inertia, f32::to_le_bytes);
        first.extend([
            (4, GsdType::Int8, types.types as u64, 12, names),
            (5, GsdType::Uint32, n as u64, 1, ids),
            (6, GsdType::Float, n as u64, 1, masses),
            (7, GsdType::Float, n as u64, 3, moments),
        ]);
        Self::open(path, &BODY_NAMES, first, n)
    }

    /// Appends one frame of moving bodies at `step` and commits it.
    pub fn write_bodies(&mut self, step: u64, frame: &BodyFrame<'_>) -> io::Result<()> {
        let n = self.rotors as u64;
        let lengths = [
            frame.position.len(),
            frame.orientation.len(),
            frame.velocity.len(),
            frame.angmom.len(),
            frame.image.len(),
        ];
        if lengths.iter().any(|&l| l != self.rotors) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("a frame of {lengths:?} rows for {} bodies", self.rotors),
            ));
        }
        self.commit(
            step,
            vec![
                (
                    8,
                    GsdType::Float,
                    n,
                    3,
                    rows(frame.position, f32::to_le_bytes),
                ),
                (
                    9,
                    GsdType::Float,
                    n,
                    4,
                    rows(frame.orientation, f32::to_le_bytes),
                ),
                (
                    10,
                    GsdType::Float,
                    n,
                    3,
                    rows(frame.velocity, f32::to_le_bytes),
                ),
                (
                    11,
                    GsdType::Float,
                    n,
                    4,
                    rows(frame.angmom, f32::to_le_bytes),
                ),
                (
                    12,
                    GsdType::Int32,
                    n,
                    3,
                    rows(frame.image, i32::to_le_bytes),
                ),
            ],
        )
    }
}
