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

/// Geometry of one offset `r = r_j - r_i`. Laid out with the tensor first and
/// aligned to 32 bytes, so that no four-lane column straddles two cache lines
/// (unaligned columns made the dipole pair loop 5 to 15 % slower, depending
/// on where the allocator placed the table).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
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

/// Sites binned into cells at least `cutoff` wide (periodic boxes only), so
/// that every partner within the cutoff lies in the 27 cells around a site's
/// own: building the pair list costs O(n) instead of O(n^2).
struct CellGrid {
    cells: [usize; 3],
    box_lengths: Vector3<f64>,
    /// Site indices of each cell, ascending.
    members: Vec<Vec<u32>>,
}

impl CellGrid {
    /// `None` when an axis has fewer than 3 cells (the 27 neighbours would
    /// repeat): all pairs are then examined.
    fn new(sites: &[Vector3<f64>], box_lengths: &Vector3<f64>, cutoff: f64) -> Option<Self> {
        let cells = [0, 1, 2].map(|a| (box_lengths[a] / cutoff).floor() as usize);
        if cells.iter().any(|&c| c < 3) {
            return None;
        }
        let mut grid = CellGrid {
            cells,
            box_lengths: *box_lengths,
            members: vec![Vec::new(); cells.iter().product()],
        };
        for (i, site) in sites.iter().enumerate() {
            let cell = grid.flat(grid.cell_of(site));
            grid.members[cell].push(i as u32);
        }
        Some(grid)
    }

    fn cell_of(&self, site: &Vector3<f64>) -> [usize; 3] {
        [0, 1, 2].map(|a| {
            let l = self.box_lengths[a];
            let wrapped = site[a] - l * (site[a] / l).floor();
            ((wrapped / l * self.cells[a] as f64) as usize).min(self.cells[a] - 1)
        })
    }

    fn flat(&self, [x, y, z]: [usize; 3]) -> usize {
        (x * self.cells[1] + y) * self.cells[2] + z
    }

    /// The sites `j > i` in the 27 cells around site `i`, ascending.
    fn partners_after(&self, i: usize, site: &Vector3<f64>, out: &mut Vec<u32>) {
        out.clear();
        let home = self.cell_of(site);
        for dx in 0..3 {
            for dy in 0..3 {
                for dz in 0..3 {
                    let cell = [(dx, 0), (dy, 1), (dz, 2)]
                        .map(|(d, a)| (home[a] + self.cells[a] + d - 1) % self.cells[a]);
                    let members = &self.members[self.flat(cell)];
                    out.extend(members.iter().filter(|&&j| j as usize > i));
                }
            }
        }
        out.sort_unstable();
    }
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
        let grid = match *boundary {
            Boundary::Periodic {
                box_lengths,
                cutoff,
            } => CellGrid::new(sites, &box_lengths, cutoff),
            Boundary::Open => None,
        };
        let mut candidates = Vec::new();
        for i in 0..n {
            table.start.push(table.partner.len());
            match &grid {
                Some(grid) => grid.partners_after(i, &sites[i], &mut candidates),
                None => {
                    candidates.clear();
                    candidates.extend(i as u32 + 1..n as u32);
                }
            }
            for j in candidates.iter().map(|&j| j as usize) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The cell grid finds exactly the pairs of the all-pairs minimum-image
    /// search, in the same order, for sites scattered inside and outside an
    /// orthorhombic box.
    #[test]
    fn cell_grid_matches_all_pairs() {
        let box_lengths = Vector3::new(7.0, 8.5, 9.3);
        let boundary = Boundary::Periodic {
            box_lengths,
            cutoff: 2.3,
        };
        // A deterministic scatter, some sites one box length outside.
        let sites: Vec<Vector3<f64>> = (0..300)
            .map(|k| {
                let t = k as f64;
                let inside = Vector3::new(
                    (t * 0.6180339887).fract() * 7.0,
                    (t * 0.4142135623).fract() * 8.5,
                    (t * 0.7320508075).fract() * 9.3,
                );
                inside + Vector3::new(7.0 * ((k % 3) as f64 - 1.0), 0.0, -9.3 * ((k % 2) as f64))
            })
            .collect();
        assert!(CellGrid::new(&sites, &box_lengths, 2.3).is_some());
        let table = PairTable::build(&sites, &boundary).unwrap();
        let mut expected = Vec::new();
        for i in 0..sites.len() {
            for j in i + 1..sites.len() {
                if boundary.interacting_offset(&sites[i], &sites[j]).is_some() {
                    expected.push((i, j));
                }
            }
        }
        let found: Vec<(usize, usize)> = (0..sites.len())
            .flat_map(|i| {
                let row = table.start[i]..table.start[i + 1];
                table.partner[row].iter().map(move |&j| (i, j as usize))
            })
            .collect();
        assert!(expected.len() > 1000);
        assert_eq!(found, expected);
    }
}
