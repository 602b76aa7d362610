//! The pair list and the pair geometry, computed once: sites never move.
//!
//! Pairs are stored once (`i < j`), grouped by `i` (CSR). Their geometry is
//! kept in a table indexed by the distinct offsets `r_j - r_i`: on a periodic
//! lattice all pairs with the same offset share one entry (122 entries serve
//! the 61,000 pairs of the 10^3 simple-cubic lattice with cutoff 3.1), so the
//! tables stay in the L1 cache.

use super::{Boundary, PotentialError};
use nalgebra::Vector3;
use std::collections::HashMap;

/// Offsets closer than this (length unit) share one geometry entry.
const OFFSET_RESOLUTION: f64 = 1e-9;

/// Geometry of one offset `r = r_j - r_i`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairGeometry {
    /// Columns of the dipole-dipole tensor `T = (3 n n^T - I) / r^3`, padded to
    /// four lanes: the field at `i` of a dipole `mu` at `j` is `T mu`.
    pub dipole_tensor: [[f64; 4]; 3],
    /// `n = r / |r|`, pointing from `i` to `j`.
    pub unit: Vector3<f64>,
    /// `1 / |r|`.
    pub inv_r: f64,
}

impl PairGeometry {
    fn new(offset: &Vector3<f64>) -> Self {
        let inv_r = 1.0 / offset.norm();
        let unit = offset * inv_r;
        let inv_r3 = inv_r * inv_r * inv_r;
        let column = |c: usize| {
            let mut col = [0.0; 4];
            for (r, v) in col.iter_mut().take(3).enumerate() {
                let delta = if r == c { 1.0 } else { 0.0 };
                *v = (3.0 * unit[r] * unit[c] - delta) * inv_r3;
            }
            col
        };
        PairGeometry {
            dipole_tensor: [column(0), column(1), column(2)],
            unit,
            inv_r,
        }
    }
}

/// Interacting pairs `i < j` in CSR form, with shared geometry.
#[derive(Clone, Debug)]
pub(crate) struct PairTable {
    /// Pairs of rotor `i` are `start[i]..start[i + 1]`.
    pub start: Vec<usize>,
    /// The partner `j > i` of each pair.
    pub partner: Vec<u32>,
    /// Index into `geometry` of each pair.
    pub geometry_index: Vec<u32>,
    /// One entry per distinct offset.
    pub geometry: Vec<PairGeometry>,
}

impl PairTable {
    /// Enumerates the interacting pairs (all of them when open; minimum image
    /// within the cutoff when periodic). Coincident sites are an error.
    pub fn build(sites: &[Vector3<f64>], boundary: &Boundary) -> Result<Self, PotentialError> {
        let n = sites.len();
        if u32::try_from(n).is_err() {
            return Err(PotentialError::new(
                "rotors",
                format!("at most {} rotors, got {n}", u32::MAX),
            ));
        }
        let mut table = PairTable {
            start: Vec::with_capacity(n + 1),
            partner: Vec::new(),
            geometry_index: Vec::new(),
            geometry: Vec::new(),
        };
        let mut by_offset: HashMap<[i64; 3], u32> = HashMap::new();
        for i in 0..n {
            table.start.push(table.partner.len());
            for j in i + 1..n {
                let Some(offset) = boundary.interacting_offset(&sites[i], &sites[j]) else {
                    continue;
                };
                if offset.norm() <= OFFSET_RESOLUTION {
                    return Err(PotentialError::new(
                        format!("rotors[{i}].site and rotors[{j}].site"),
                        format!(
                            "coincide (distance {:e}, periodic images included)",
                            offset.norm()
                        ),
                    ));
                }
                let key = offset
                    .map(|x| (x / OFFSET_RESOLUTION).round() as i64)
                    .into();
                let next = table.geometry.len() as u32;
                let index = *by_offset.entry(key).or_insert(next);
                if index == next {
                    table.geometry.push(PairGeometry::new(&offset));
                }
                table.partner.push(j as u32);
                table.geometry_index.push(index);
            }
        }
        table.start.push(table.partner.len());
        Ok(table)
    }

    /// Number of interacting pairs.
    pub fn len(&self) -> usize {
        self.partner.len()
    }

    /// Splits `0..n_rotors` into `blocks` contiguous ranges of about equal pair counts.
    pub fn balanced_blocks(&self, blocks: usize) -> Vec<std::ops::Range<usize>> {
        let n = self.start.len() - 1;
        let blocks = blocks.clamp(1, n.max(1));
        let total = self.len();
        let mut ranges = Vec::with_capacity(blocks);
        let mut begin = 0;
        for b in 1..=blocks {
            let end = if b == blocks {
                n
            } else {
                let target = total * b / blocks;
                self.start
                    .partition_point(|&s| s < target)
                    .min(n)
                    .max(begin)
            };
            ranges.push(begin..end);
            begin = end;
        }
        ranges
    }
}
