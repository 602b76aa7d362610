//! Recognising sites that lie on a periodic lattice of the box: a grid of
//! `M_x x M_y x M_z` orthorhombic cells (`M_a` cells along the box edge
//! `L_a`) with the same `B` basis offsets in each, some slots possibly
//! empty (vacancies). Any cubic lattice (sc, bcc, fcc) of any number of
//! cells and spacing is one, with or without vacancies, whatever multipoles
//! its sites carry.
//!
//! Detection: along each axis the sites' coordinates (relative to the first
//! site, modulo the box) must all be multiples of one grid step `L_a / G_a`
//! to within [`LATTICE_TOLERANCE`] of the box edge (the smallest such
//! `G_a`); then among the cells of `k_a` grid steps (`k_a` dividing `G_a`, at
//! most [`MAX_STEPS_PER_CELL`]) the one with the least estimated work per
//! evaluation is taken (FFTs of `B M_x M_y M_z` slots and `B^2` kernel
//! products per cell, see [`WORK_PER_SLOT`]): fcc gets 4 basis offsets in the
//! conventional cell, not 1 in a grid of half steps with half the slots
//! empty; a lattice with vacancies keeps its cell, not the whole box as one
//! cell of many offsets. Sites whose
//! slots would outnumber them by more than [`MAX_EMPTY_FACTOR`] are not a
//! lattice worth a grid.

use nalgebra::Vector3;
use rayon::prelude::*;

/// Coordinates within this fraction of the box edge of a grid point lie on it
/// (round-off of the lattice construction; a displaced site is not on a lattice).
pub const LATTICE_TOLERANCE: f64 = 1e-10;
/// The largest cell tried, in grid steps along each axis.
const MAX_STEPS_PER_CELL: usize = 8;
/// The work of one evaluation per slot (its FFTs), relative to that per
/// cell and basis pair (the kernel products): the cell with the least
/// `WORK_PER_SLOT B N_cells + B^2 N_cells` is chosen.
const WORK_PER_SLOT: usize = 10;
/// At most this many slots per site.
const MAX_EMPTY_FACTOR: usize = 8;

/// The sites as a lattice of the box (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct LatticeGrid {
    /// Cells along x, y, z.
    pub cells: [usize; 3],
    /// The cell edges (the box edges divided by `cells`).
    pub cell_lengths: Vector3<f64>,
    /// The basis offsets within a cell (relative to the first site's).
    pub basis: Vec<Vector3<f64>>,
    /// Each site's slot: (cell, basis offset), cells numbered
    /// `(m_x M_y + m_y) M_z + m_z`.
    pub slots: Vec<(usize, usize)>,
}

impl LatticeGrid {
    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells.iter().product()
    }
}

/// The grid step count `G` along one axis and each site's grid index, or
/// `None` when the coordinates are not all on one grid.
fn axis_grid(fractions: &[f64], most: usize) -> Option<(usize, Vec<usize>)> {
    let mut distinct: Vec<f64> = fractions.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup_by(|a, b| (*a - *b).abs() <= LATTICE_TOLERANCE);
    let on_grid = |g: usize| {
        distinct.iter().all(|v| {
            let x = v * g as f64;
            (x - x.round()).abs() <= LATTICE_TOLERANCE * g as f64
        })
    };
    let g = (distinct.len()..=most).find(|&g| on_grid(g))?;
    let index = fractions
        .iter()
        .map(|v| ((v * g as f64).round() as usize) % g)
        .collect();
    Some((g, index))
}

/// The cell (in grid steps along each axis, dividing `steps`) with the
/// least work per evaluation for the `sites` sites of grid indices `index`
/// (see [`WORK_PER_SLOT`]).
fn cheapest_cell(sites: usize, index: &[Vec<usize>; 3], steps: [usize; 3]) -> Option<[usize; 3]> {
    let divisors = |g: usize| -> Vec<usize> {
        (1..=MAX_STEPS_PER_CELL.min(g))
            .filter(|k| g % k == 0)
            .collect()
    };
    let mut candidates = Vec::new();
    for &kx in &divisors(steps[0]) {
        for &ky in &divisors(steps[1]) {
            for &kz in &divisors(steps[2]) {
                candidates.push([kx, ky, kz]);
            }
        }
    }
    // Each candidate cell priced on its own (a pass over the sites each),
    // the cheapest then chosen in the order above: the same on any number
    // of threads.
    let priced: Vec<(usize, usize, [usize; 3])> = candidates
        .into_par_iter()
        .map(|k| {
            let mut seen = vec![false; k.iter().product()];
            for i in 0..sites {
                seen[class(index, i, &k)] = true;
            }
            let basis = seen.iter().filter(|s| **s).count();
            let cells: usize = (0..3).map(|a| steps[a] / k[a]).product();
            (
                WORK_PER_SLOT * basis * cells + cells * basis * basis,
                basis,
                k,
            )
        })
        .collect();
    let mut best: Option<(usize, usize, [usize; 3])> = None;
    for (cost, basis, k) in priced {
        if best.is_none_or(|(c, b, _)| (cost, basis) < (c, b)) {
            best = Some((cost, basis, k));
        }
    }
    best.map(|(_, _, k)| k)
}

/// The lattice the sites form in the box, if any (see the module doc).
pub fn detect(sites: &[Vector3<f64>], box_lengths: &Vector3<f64>) -> Option<LatticeGrid> {
    let first = *sites.first()?;
    let most = (MAX_EMPTY_FACTOR * sites.len()).min(1 << 20);
    let mut steps = [0usize; 3];
    let mut index: [Vec<usize>; 3] = Default::default();
    for a in 0..3 {
        let fractions: Vec<f64> = sites
            .iter()
            .map(|s| {
                let u = (s[a] - first[a]) / box_lengths[a];
                let f = u - u.floor();
                if f > 1.0 - LATTICE_TOLERANCE {
                    0.0
                } else {
                    f
                }
            })
            .collect();
        (steps[a], index[a]) = axis_grid(&fractions, most)?;
    }
    if steps.iter().product::<usize>() > MAX_EMPTY_FACTOR * sites.len() {
        return None;
    }
    let k = cheapest_cell(sites.len(), &index, steps)?;
    let cells = [0, 1, 2].map(|a| steps[a] / k[a]);
    let step = Vector3::from_fn(|a, _| box_lengths[a] / steps[a] as f64);
    let mut basis_of_class = vec![usize::MAX; k.iter().product()];
    let mut basis = Vec::new();
    let slots = (0..sites.len())
        .map(|i| {
            let c = class(&index, i, &k);
            if basis_of_class[c] == usize::MAX {
                basis_of_class[c] = basis.len();
                basis.push(Vector3::from_fn(|a, _| {
                    (index[a][i] % k[a]) as f64 * step[a]
                }));
            }
            let m = [0, 1, 2].map(|a| index[a][i] / k[a]);
            (
                (m[0] * cells[1] + m[1]) * cells[2] + m[2],
                basis_of_class[c],
            )
        })
        .collect();
    Some(LatticeGrid {
        cells,
        cell_lengths: Vector3::from_fn(|a, _| box_lengths[a] / cells[a] as f64),
        basis,
        slots,
    })
}

/// The class (position within a cell of `k` grid steps) of site `i`.
fn class(index: &[Vec<usize>; 3], i: usize, k: &[usize; 3]) -> usize {
    ((index[0][i] % k[0]) * k[1] + index[1][i] % k[1]) * k[2] + index[2][i] % k[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{Lattice, LatticeKind};

    /// sc, bcc and fcc lattices are found with their conventional cells and
    /// bases (1, 2, 4 offsets), also shifted, with a vacancy, and with a
    /// non-unit spacing; every slot is used once.
    #[test]
    fn cubic_lattices_are_recognised() {
        for (kind, basis) in [
            (LatticeKind::SimpleCubic, 1),
            (LatticeKind::Bcc, 2),
            (LatticeKind::Fcc, 4),
        ] {
            let lattice = Lattice::cubic(kind, 3, 1.6).unwrap();
            let shift = Vector3::new(0.3, -2.0, 7.1);
            let mut sites: Vec<_> = lattice.sites.iter().map(|s| s + shift).collect();
            let _removed = sites.remove(5);
            let grid = detect(&sites, &lattice.box_lengths).expect("a lattice");
            assert_eq!(grid.cells, [3, 3, 3], "{kind:?}");
            assert_eq!(grid.basis.len(), basis, "{kind:?}");
            let mut slots = grid.slots.clone();
            slots.sort_unstable();
            slots.dedup();
            assert_eq!(slots.len(), sites.len());
        }
    }

    /// A site displaced by 1e-6 (far above round-off) breaks the lattice.
    #[test]
    fn displaced_sites_are_not_a_lattice() {
        let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 4, 1.0).unwrap();
        let mut sites = lattice.sites.clone();
        sites[7].y += 1e-6;
        assert!(detect(&sites, &lattice.box_lengths).is_none());
    }

    /// Every site is its slot: the first site plus its cell's corner plus
    /// its basis offset, modulo the box, with every basis offset inside one
    /// cell; sites in reverse order (so the first site seen of a basis
    /// offset need not lie in cell 0), shifted, with a vacancy.
    #[test]
    fn slots_and_basis_rebuild_every_site() {
        for kind in [LatticeKind::SimpleCubic, LatticeKind::Bcc, LatticeKind::Fcc] {
            let lattice = Lattice::cubic(kind, 3, 1.3).unwrap();
            let l = lattice.box_lengths;
            let shift = Vector3::new(-0.4, 2.2, 0.9);
            let mut sites: Vec<_> = lattice.sites.iter().rev().map(|s| s + shift).collect();
            let _removed = sites.remove(4);
            let grid = detect(&sites, &l).expect("a lattice");
            let c = grid.cell_lengths;
            for offset in &grid.basis {
                assert!(
                    (0..3).all(|a| offset[a] >= 0.0 && offset[a] < c[a] * (1.0 - 1e-9)),
                    "{kind:?}: {offset:?}"
                );
            }
            for (site, &(cell, b)) in sites.iter().zip(&grid.slots) {
                let [_, my, mz] = grid.cells;
                let m = Vector3::new(
                    (cell / (my * mz)) as f64,
                    ((cell / mz) % my) as f64,
                    (cell % mz) as f64,
                );
                let rebuilt = sites[0] + m.component_mul(&c) + grid.basis[b];
                let boxes = (site - rebuilt).component_div(&l);
                assert!(
                    boxes.iter().all(|x| (x - x.round()).abs() < 1e-12),
                    "{kind:?}: {site:?} from {rebuilt:?}"
                );
            }
        }
    }

    /// Coordinates within `LATTICE_TOLERANCE` of the box edge of a grid point
    /// are on it, farther ones are not: a plane of sites moved by 0.5e-10 of
    /// the edge stays on the lattice, one moved by 2e-10 breaks it; a site at
    /// round-off below a grid point across the box face counts as that grid
    /// point, also in a diluted lattice (12 sites on 64 slots, every grid
    /// coordinate used) that a grid of twice the steps would take beyond 8
    /// slots a site.
    #[test]
    fn the_tolerance_is_a_fraction_of_the_box_edge() {
        let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 5, 1.3).unwrap();
        let l = lattice.box_lengths;
        // A whole plane moved (one site alone would merge with its plane's
        // coordinate before the grid is tried).
        let moved = |fraction: f64| {
            let mut sites = lattice.sites.clone();
            for s in sites.iter_mut().filter(|s| (s.y - 2.6).abs() < 1e-9) {
                s.y += fraction * l.y;
            }
            detect(&sites, &l)
        };
        let grid = moved(0.5 * LATTICE_TOLERANCE).expect("a lattice within the tolerance");
        assert_eq!((grid.cells, grid.basis.len()), ([5, 5, 5], 1));
        assert!(moved(2.0 * LATTICE_TOLERANCE).is_none());
        let mut diluted: Vec<Vector3<f64>> = (0..4)
            .flat_map(|i| {
                [
                    (i, i, i),
                    (i, (i + 1) % 4, (i + 2) % 4),
                    (i, (i + 2) % 4, (i + 1) % 4),
                ]
                .map(|(x, y, z)| Vector3::new(x as f64, y as f64, z as f64))
            })
            .collect();
        let l = Vector3::repeat(4.0);
        let exact = detect(&diluted, &l).expect("a diluted lattice");
        assert_eq!(diluted[1], Vector3::new(0.0, 1.0, 2.0));
        diluted[1].x = -1e-13;
        let grid = detect(&diluted, &l).expect("round-off across the face is on the grid");
        assert_eq!(
            (grid.cells, grid.basis.len()),
            (exact.cells, exact.basis.len())
        );
    }

    /// Sites whose slots would outnumber them more than `MAX_EMPTY_FACTOR`
    /// times are not a lattice: two sites 1/16 of the edge apart (16 slots,
    /// 8 a site) are one, 1/17 apart are not; two sites on a 4 x 4 x 1 grid
    /// are one, on a 4 x 4 x 2 grid (32 slots) not.
    #[test]
    fn at_most_eight_slots_a_site() {
        let l = Vector3::new(3.0, 2.0, 5.0);
        let pair = |x: f64, y: f64, z: f64| {
            detect(
                &[Vector3::zeros(), Vector3::new(x * l.x, y * l.y, z * l.z)],
                &l,
            )
        };
        assert_eq!(pair(1.0 / 16.0, 0.0, 0.0).expect("16 slots").slots.len(), 2);
        assert!(pair(1.0 / 17.0, 0.0, 0.0).is_none());
        assert!(pair(0.25, 0.25, 0.0).is_some());
        assert!(pair(0.25, 0.25, 0.5).is_none());
    }
}
