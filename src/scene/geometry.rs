//! Stand-in for `crate::lattice` (same API) until it lands in main.

use nalgebra::Vector3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeKind {
    SimpleCubic,
    Bcc,
    Fcc,
}

#[derive(Debug)]
pub struct LatticeError;

impl std::fmt::Display for LatticeError {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("bad lattice")
    }
}

pub struct Lattice {
    pub sites: Vec<Vector3<f64>>,
    pub box_lengths: Vector3<f64>,
}

impl Lattice {
    pub fn cubic(kind: LatticeKind, cells: usize, spacing: f64) -> Result<Lattice, LatticeError> {
        let basis: &[[f64; 3]] = match kind {
            LatticeKind::SimpleCubic => &[[0.0; 3]],
            LatticeKind::Bcc => &[[0.0; 3], [0.5; 3]],
            LatticeKind::Fcc => &[[0.0; 3], [0.0, 0.5, 0.5], [0.5, 0.0, 0.5], [0.5, 0.5, 0.0]],
        };
        let mut sites = Vec::new();
        for x in 0..cells {
            for y in 0..cells {
                for z in 0..cells {
                    for b in basis {
                        let c = Vector3::new(x as f64 + b[0], y as f64 + b[1], z as f64 + b[2]);
                        sites.push(c * spacing);
                    }
                }
            }
        }
        Ok(Lattice {
            sites,
            box_lengths: Vector3::repeat(cells as f64 * spacing),
        })
    }
}
