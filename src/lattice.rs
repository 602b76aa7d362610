//! Cubic lattices of fixed rotor sites: simple cubic, body-centred and
//! face-centred cubic, `n x n x n` conventional cells in a periodic box.
//!
//! Explicit site lists need no type of their own: they are `Vec<Vector3<f64>>`.

use crate::checks::{positive, InputError};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The most sites a lattice may have (a guard on memory, checked before
/// anything is allocated).
pub const MAX_SITES: usize = 1_000_000;

/// The Bravais lattice of a [`Lattice`]: the basis of the conventional cubic
/// cell. Scene files name it `"simple_cubic"`, `"bcc"` or `"fcc"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LatticeKind {
    /// One site per cell, at `(0, 0, 0)`.
    SimpleCubic,
    /// Two sites per cell, at `(0, 0, 0)` and `(1/2, 1/2, 1/2)`.
    Bcc,
    /// Four sites per cell, at `(0, 0, 0)` and the three face centres.
    Fcc,
}

impl LatticeKind {
    /// The sites of the conventional cell, in units of the lattice constant.
    pub fn basis(self) -> &'static [[f64; 3]] {
        match self {
            LatticeKind::SimpleCubic => &[[0.0, 0.0, 0.0]],
            LatticeKind::Bcc => &[[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]],
            LatticeKind::Fcc => &[
                [0.0, 0.0, 0.0],
                [0.0, 0.5, 0.5],
                [0.5, 0.0, 0.5],
                [0.5, 0.5, 0.0],
            ],
        }
    }
}

/// The sites of a cubic lattice and the lengths of its periodic box.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// Site positions, cell by cell (x slowest, then y, then z), basis order within a cell.
    pub sites: Vec<Vector3<f64>>,
    /// Edge lengths of the periodic box, `cells * spacing` along each axis.
    pub box_lengths: Vector3<f64>,
}

impl Lattice {
    /// `cells x cells x cells` conventional cells (>= 1) of lattice constant
    /// `spacing` (length unit of the scene, > 0): `cells^3 * (1, 2, 4)` sites
    /// for (sc, bcc, fcc), all inside `[0, cells * spacing)^3`, at most
    /// [`MAX_SITES`]. The error's path names the parameter (`cells`,
    /// `spacing`).
    pub fn cubic(kind: LatticeKind, cells: usize, spacing: f64) -> Result<Lattice, InputError> {
        if cells == 0 {
            return Err(InputError::new("cells", "must be >= 1, got 0"));
        }
        let _ = positive(spacing).map_err(|e| e.at("spacing"))?;
        // The sums divide by cell and box volumes: both must be normal
        // numbers (a spacing of 1e-212 gives a cell volume of 0).
        let (cell, whole) = (spacing.powi(3), (cells as f64 * spacing).powi(3));
        if !(cell.is_normal() && whole.is_normal()) {
            return Err(InputError::new(
                "spacing",
                format!(
                    "must give cell and box volumes between {:e} and {:e}, got {} and {}",
                    f64::MIN_POSITIVE,
                    f64::MAX,
                    crate::checks::num(cell),
                    crate::checks::num(whole)
                ),
            ));
        }
        let basis = kind.basis();
        let count = cells
            .checked_pow(3)
            .and_then(|c| c.checked_mul(basis.len()))
            .filter(|&c| c <= MAX_SITES)
            .ok_or_else(|| {
                let count = (cells as f64).powi(3) * basis.len() as f64;
                InputError::new(
                    "cells",
                    format!(
                        "{cells} cells give {} rotors, more than the limit {MAX_SITES}",
                        crate::checks::num(count)
                    ),
                )
            })?;
        let mut sites = Vec::with_capacity(count);
        for x in 0..cells {
            for y in 0..cells {
                for z in 0..cells {
                    let corner = Vector3::new(x as f64, y as f64, z as f64);
                    for b in basis {
                        sites.push((corner + Vector3::from(*b)) * spacing);
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
