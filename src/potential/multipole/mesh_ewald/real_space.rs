//! The real-space part of the mesh Ewald sum: every pair closer than `r_c`
//! (minimum image, `r_c <= L_a / 2`), found by a cell list rebuilt at each
//! evaluation into buffers sized once; cells at least `r_c / 2` wide, so
//! that the 125 cells searched around a site hold about 3.7 times the
//! sphere's sites (27 cells `r_c` wide would hold 6.4 times). Each site sums its own partners
//! (every pair is visited from both ends), so sites are independent rayon
//! tasks and the sums do not depend on the number of threads.
//!
//! A source `j` contributes `d^A phi(r_i) = sum_E c_E (-1)^|E| d^(A + E)
//! g(r_i - r_j)` with `g = erfc(alpha r) / r` (the Ewald real-space kernel
//! of [`crate::potential::multipole::ewald_terms`]).

use super::cartesian::{
    add_source, pair_force, radial_derivatives, Tables, DERIVATIVES, SOURCES, UP_TO,
};
use super::damped::ErfcTable;
use crate::potential::multipole::ewald_terms::radial_functions;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Cells searched on each side of a site's own, along each axis.
const REACH: usize = 2;

/// The cell list of one box (cells at least `r_c / REACH` wide).
#[derive(Clone, Debug)]
pub(crate) struct CellList {
    cells: [usize; 3],
    /// The distinct neighbour offsets (`-REACH..=REACH` modulo the cell count) per axis.
    offsets: [Vec<usize>; 3],
    /// First entry of each cell in `members` (`cells + 1` entries).
    start: Vec<usize>,
    /// Site indices, by cell, in increasing order within a cell.
    members: Vec<usize>,
    cell_of: Vec<usize>,
}

impl CellList {
    /// Buffers for `sites` sites in `box_lengths` with cutoff `cutoff`
    /// (`cutoff <= L_a / 2`, checked by the caller).
    pub fn new(sites: usize, box_lengths: &Vector3<f64>, cutoff: f64) -> Self {
        let cells = Self::cells(box_lengths, cutoff);
        let offsets = std::array::from_fn(|a| {
            let mut out: Vec<usize> = (0..=2 * REACH)
                .map(|o| (o + cells[a] * REACH - REACH) % cells[a])
                .collect();
            out.sort_unstable();
            out.dedup();
            out
        });
        CellList {
            cells,
            offsets,
            start: vec![0; cells.iter().product::<usize>() + 1],
            members: vec![0; sites],
            cell_of: vec![0; sites],
        }
    }

    /// Cells along each axis for `cutoff` in `box_lengths`.
    pub fn cells(box_lengths: &Vector3<f64>, cutoff: f64) -> [usize; 3] {
        std::array::from_fn(|a| ((box_lengths[a] * REACH as f64 / cutoff).floor() as usize).max(1))
    }

    /// Bytes held for `sites` sites in `box_lengths` with `cutoff`.
    pub fn bytes(sites: f64, box_lengths: &Vector3<f64>, cutoff: f64) -> f64 {
        let cells: f64 = Self::cells(box_lengths, cutoff)
            .iter()
            .map(|&c| c as f64)
            .product();
        16.0 * sites + 8.0 * cells
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[0] * self.cells[1] + c[1]) * self.cells[2] + c[2]
    }

    /// Sorts the wrapped positions (in `[0, L)`) into cells.
    fn build(&mut self, wrapped: &[Vector3<f64>], box_lengths: &Vector3<f64>) {
        let cells = self.cells;
        for (i, r) in wrapped.iter().enumerate() {
            let c = std::array::from_fn(|a| {
                ((r[a] / box_lengths[a] * cells[a] as f64) as usize).min(cells[a] - 1)
            });
            self.cell_of[i] = self.cell_index(c);
        }
        self.start.fill(0);
        for &c in &self.cell_of {
            self.start[c + 1] += 1;
        }
        for c in 1..self.start.len() {
            self.start[c] += self.start[c - 1];
        }
        // Place each site at the next free slot of its cell (start shifted back after).
        for (i, &c) in self.cell_of.iter().enumerate() {
            self.members[self.start[c]] = i;
            self.start[c] += 1;
        }
        for c in (1..self.start.len()).rev() {
            self.start[c] = self.start[c - 1];
        }
        self.start[0] = 0;
    }

    /// Adds the real-space derivatives of every site to `derivatives`
    /// (`count` of them), from the sources' coefficients `coefficients` (of
    /// order at most `source_order`); with `virial`, sets each site's half
    /// of its pairs' virials `1/2 sum_j r_ij f_ij^T` in `virials`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_derivatives(
        &mut self,
        wrapped: &[Vector3<f64>],
        box_lengths: &Vector3<f64>,
        alpha: f64,
        cutoff: f64,
        coefficients: &[[f64; SOURCES]],
        source_order: usize,
        count: usize,
        derivatives: &mut [[f64; DERIVATIVES]],
        (virials, virial): (&mut [Matrix3<f64>], bool),
    ) {
        self.build(wrapped, box_lengths);
        let tables = Tables::get();
        let erfc = ErfcTable::get();
        let sources = UP_TO[source_order];
        // `count` reaches one order above the sources: enough for the pair forces too.
        let needed = UP_TO[tables.order(count - 1) + source_order];
        let half = box_lengths / 2.0;
        let cutoff_squared = cutoff * cutoff;
        // Charges: the potential, field and field gradient by a kernel of
        // B_0, B_1 and B_2 (the sums of the general path, unrolled).
        let charges_only = source_order == 0 && count <= UP_TO[2];
        let this = &*self;
        derivatives
            .par_iter_mut()
            .zip(virials.par_iter_mut())
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, (d, w))| {
                *w = Matrix3::zeros();
                let cells = this.cells;
                let c = this.cell_of[i];
                let home = [
                    c / (cells[1] * cells[2]),
                    (c / cells[2]) % cells[1],
                    c % cells[2],
                ];
                let mut t = [[0.0; 56]; 6];
                for &ox in &this.offsets[0] {
                    for &oy in &this.offsets[1] {
                        for &oz in &this.offsets[2] {
                            let o = [ox, oy, oz];
                            let neighbour = this
                                .cell_index(std::array::from_fn(|a| (home[a] + o[a]) % cells[a]));
                            for &j in
                                &this.members[this.start[neighbour]..this.start[neighbour + 1]]
                            {
                                if j == i {
                                    continue;
                                }
                                let r = minimum_image(wrapped[i] - wrapped[j], box_lengths, &half);
                                let distance_squared = r.norm_squared();
                                if distance_squared >= cutoff_squared {
                                    continue;
                                }
                                let cj = &coefficients[j];
                                if charges_only {
                                    let b = erfc.radial(alpha, distance_squared);
                                    add_charge(cj[0], &r, &b, count, d);
                                    if virial {
                                        let f = r * (coefficients[i][0] * cj[0] * b[1]);
                                        *w += r * f.transpose() * 0.5;
                                    }
                                    continue;
                                }
                                radial_derivatives(
                                    &r,
                                    &radial_functions(alpha, distance_squared.sqrt()),
                                    needed,
                                    &mut t,
                                );
                                add_source(&t[0], cj, sources, count, d);
                                if virial {
                                    let f =
                                        pair_force(&t[0], &coefficients[i], sources, cj, sources);
                                    *w += r * f.transpose() * 0.5;
                                }
                            }
                        }
                    }
                }
            });
    }
}

/// The minimum image of the offset `r` of two wrapped sites (less than
/// `L_a` apart along each axis), `half` holding `L_a / 2`.
fn minimum_image(
    mut r: Vector3<f64>,
    box_lengths: &Vector3<f64>,
    half: &Vector3<f64>,
) -> Vector3<f64> {
    for a in 0..3 {
        if r[a] > half[a] {
            r[a] -= box_lengths[a];
        } else if r[a] < -half[a] {
            r[a] += box_lengths[a];
        }
    }
    r
}

/// Adds a charge `q`'s potential and its first `count` (at most 10)
/// derivatives at offset `r` to `d` from the radial functions `b` at
/// `|r|`: `q (B_0, -r B_1, r r^T B_2 - I B_1)`, the sums of [`add_source`]
/// for a charge, unrolled.
fn add_charge(q: f64, r: &Vector3<f64>, b: &[f64; 3], count: usize, d: &mut [f64; DERIVATIVES]) {
    d[0] += q * b[0];
    for a in 0..3 {
        d[1 + a] += q * -(r[a] * b[1]);
    }
    if count > UP_TO[1] {
        let mut k = UP_TO[1];
        for a in 0..3 {
            for c in a..3 {
                let delta = if a == c { b[1] } else { 0.0 };
                d[k] += q * (r[a] * r[c] * b[2] - delta);
                k += 1;
            }
        }
    }
}
