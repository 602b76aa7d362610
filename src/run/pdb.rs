//! The PDB topology of a trajectory: per rotor one residue `ROT` with four
//! atoms, the centre `C` and markers `O`, `N`, `S` at the marker length along
//! body axes 1, 2, 3 (so VMD colours the axes red, blue, yellow), bonded by
//! CONECT records. Lengths are written as they are in the scene (Angstrom
//! for the readers).

use super::folder::create_file;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::{self, Write as _};
use std::path::Path;

/// Atom names and elements of one rotor's four atoms, in file order.
pub const ROTOR_ATOMS: [&str; 4] = ["C", "O", "N", "S"];
/// PDB serial numbers have five digits; CONECT records need unique ones.
const MAX_SERIAL: usize = 99_999;
/// Atoms per rayon task when the ATOM records are formatted (their text is
/// joined in order: the file does not depend on the thread count).
const ATOMS_PER_TASK: usize = 4096;

/// Writes the topology with the atom positions of the first frame.
pub fn write_topology(
    path: &Path,
    positions: &[[f32; 3]],
    box_lengths: Option<&Vector3<f64>>,
    title: &str,
) -> io::Result<()> {
    let mut text = String::new();
    let _ = writeln!(text, "REMARK   1 {title}");
    if let Some(b) = box_lengths {
        let _ = writeln!(
            text,
            "CRYST1{:9.3}{:9.3}{:9.3}{:7.2}{:7.2}{:7.2} P 1           1",
            b.x, b.y, b.z, 90.0, 90.0, 90.0
        );
    }
    let atoms: Vec<String> = positions
        .par_chunks(ATOMS_PER_TASK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut lines = String::new();
            for (k, p) in (c * ATOMS_PER_TASK..).zip(chunk) {
                let serial = (k + 1) % (MAX_SERIAL + 1);
                let residue = (k / 4 + 1) % 10_000;
                let name = ROTOR_ATOMS[k % 4];
                let _ = writeln!(
                    lines,
                    "ATOM  {serial:5} {name:^4} ROT A{residue:4}    {:8.3}{:8.3}{:8.3}  1.00  0.00          {name:>2}",
                    p[0], p[1], p[2]
                );
            }
            lines
        })
        .collect();
    text.extend(atoms);
    let _ = writeln!(text, "TER");
    if positions.len() <= MAX_SERIAL {
        for centre in (0..positions.len()).step_by(4) {
            let _ = writeln!(
                text,
                "CONECT{:5}{:5}{:5}{:5}",
                centre + 1,
                centre + 2,
                centre + 3,
                centre + 4
            );
        }
    }
    let _ = writeln!(text, "END");
    create_file(path)?.write_all(text.as_bytes())
}
