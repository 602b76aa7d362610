//! Stand-in for `crate::lattice` until it lands in main (to be replaced).

use nalgebra::Vector3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatticeKind {
    SimpleCubic,
    Bcc,
    Fcc,
}

impl LatticeKind {
    fn basis(&self) -> &'static [[f64; 3]] {
        match self {
            LatticeKind::SimpleCubic => &[[0.0; 3]],
            LatticeKind::Bcc => &[[0.0; 3], [0.5; 3]],
            LatticeKind::Fcc => &[[0.0; 3], [0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]],
        }
    }
    pub fn sites_per_cell(&self) -> usize {
        self.basis().len()
    }
}

pub struct Lattice {
    kind: LatticeKind,
    cells: usize,
    spacing: f64,
}

impl Lattice {
    pub fn new(kind: LatticeKind, cells: usize, spacing: f64) -> Self {
        Lattice {
            kind,
            cells,
            spacing,
        }
    }
    pub fn sites(&self) -> Vec<Vector3<f64>> {
        let n = self.cells;
        let mut out = Vec::with_capacity(n * n * n * self.kind.sites_per_cell());
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    for b in self.kind.basis() {
                        let c = Vector3::new(i as f64 + b[0], j as f64 + b[1], k as f64 + b[2]);
                        out.push(c * self.spacing);
                    }
                }
            }
        }
        out
    }
    pub fn box_lengths(&self) -> Vector3<f64> {
        Vector3::repeat(self.cells as f64 * self.spacing)
    }
}
