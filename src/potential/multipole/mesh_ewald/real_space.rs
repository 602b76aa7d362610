//! The real-space part of the mesh Ewald sum: every pair closer than `r_c`
//! (minimum image, `r_c <= L_a / 2`), found by a cell list rebuilt at each
//! evaluation into buffers sized once, the positions copied in cell order;
//! cells at least `r_c / 2` wide, so that the 125 cells searched around a
//! site hold about 3.7 times the sphere's sites (27 cells `r_c` wide would
//! hold 6.4 times), each neighbour cell with the shift of its periodic
//! image (no minimum-image test per pair). Each site sums its own partners
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
    /// First entry of each cell in `members` (`cells + 1` entries).
    start: Vec<usize>,
    /// Site indices, by cell, in increasing order within a cell.
    members: Vec<usize>,
    /// The wrapped positions in the order of `members`.
    sorted: Vec<Vector3<f64>>,
    cell_of: Vec<usize>,
}

impl CellList {
    /// Buffers for `sites` sites in `box_lengths` with cutoff `cutoff`
    /// (`cutoff <= L_a / 2`, checked by the caller).
    pub fn new(sites: usize, box_lengths: &Vector3<f64>, cutoff: f64) -> Self {
        let cells = Self::cells(box_lengths, cutoff);
        CellList {
            cells,
            start: vec![0; cells.iter().product::<usize>() + 1],
            members: vec![0; sites],
            sorted: vec![Vector3::zeros(); sites],
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
        40.0 * sites + 8.0 * cells
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
        for (sorted, &i) in self.sorted.iter_mut().zip(&self.members) {
            *sorted = wrapped[i];
        }
    }

    /// Calls `pair(j, r, r^2)` for every site `j != i` closer than
    /// `sqrt(cutoff_squared)` to site `i`, `r = r_i - r_j` at the image of
    /// `j` in reach (the cells of the last build).
    fn for_each_partner(
        &self,
        i: usize,
        wrapped: &[Vector3<f64>],
        box_lengths: &Vector3<f64>,
        cutoff_squared: f64,
        mut pair: impl FnMut(usize, Vector3<f64>, f64),
    ) {
        let cells = self.cells;
        // The cell `h + o` of a home coordinate `h` and an offset `o` along
        // axis `a`, and the shift of its image: every offset is a distinct
        // image (at least 4 cells per axis), at most one within `r_c <= L_a / 2`.
        let neighbour = |a: usize, h: usize, o: usize| -> (usize, f64) {
            let c = h + o;
            if c < REACH {
                (c + cells[a] - REACH, -box_lengths[a])
            } else if c - REACH >= cells[a] {
                (c - REACH - cells[a], box_lengths[a])
            } else {
                (c - REACH, 0.0)
            }
        };
        let c = self.cell_of[i];
        let home = [
            c / (cells[1] * cells[2]),
            (c / cells[2]) % cells[1],
            c % cells[2],
        ];
        for ox in 0..=2 * REACH {
            let (cx, sx) = neighbour(0, home[0], ox);
            for oy in 0..=2 * REACH {
                let (cy, sy) = neighbour(1, home[1], oy);
                for oz in 0..=2 * REACH {
                    let (cz, sz) = neighbour(2, home[2], oz);
                    // r = r_i - (r_j + shift): the image of j in that cell.
                    let base = wrapped[i] - Vector3::new(sx, sy, sz);
                    let cell = self.cell_index([cx, cy, cz]);
                    let range = self.start[cell]..self.start[cell + 1];
                    for (&j, position) in
                        self.members[range.clone()].iter().zip(&self.sorted[range])
                    {
                        let r = base - position;
                        let distance_squared = r.norm_squared();
                        if distance_squared < cutoff_squared && j != i {
                            pair(j, r, distance_squared);
                        }
                    }
                }
            }
        }
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
        // Charges and dipoles: the potential, field and field gradient by a
        // kernel of B_0 to B_3 (the sums of the general path, unrolled); the
        // virial's pair force of dipoles by the general path.
        let unrolled = count <= UP_TO[2] && (source_order == 0 || (source_order == 1 && !virial));
        let this = &*self;
        per_site(derivatives, virials, |i, d, w| {
            *w = Matrix3::zeros();
            let mut t = [[0.0; 56]; 6];
            this.for_each_partner(
                i,
                wrapped,
                box_lengths,
                cutoff * cutoff,
                |j, r, distance_squared| {
                    let cj = &coefficients[j];
                    if unrolled {
                        let b = erfc.radial(alpha, distance_squared);
                        add_charge_dipole(cj, &r, &b, count, d);
                        if virial {
                            let f = r * (coefficients[i][0] * cj[0] * b[1]);
                            *w += r * f.transpose() * 0.5;
                        }
                        return;
                    }
                    radial_derivatives(
                        &r,
                        &radial_functions(alpha, distance_squared.sqrt()),
                        needed,
                        &mut t,
                    );
                    add_source(&t[0], cj, sources, count, d);
                    if virial {
                        let f = pair_force(&t[0], &coefficients[i], sources, cj, sources);
                        *w += r * f.transpose() * 0.5;
                    }
                },
            );
        });
    }
}

/// Adds the potential of a source with charge `q = c[0]` and dipole `mu =
/// c[1..4]` and its first `count` (at most 10) derivatives at offset `r` to
/// `d`, from the radial functions `b` at `|r|` (the sums of [`add_source`]
/// for these sources, unrolled): `phi = q B_0 + (mu.r) B_1`, `d_a phi = -q
/// r_a B_1 + mu_a B_1 - r_a (mu.r) B_2`, `d_ac phi = q (r_a r_c B_2 -
/// delta_ac B_1) + (mu.r) r_a r_c B_3 - (mu_a r_c + mu_c r_a + delta_ac
/// mu.r) B_2`.
fn add_charge_dipole(
    c: &[f64; SOURCES],
    r: &Vector3<f64>,
    b: &[f64; 4],
    count: usize,
    d: &mut [f64; DERIVATIVES],
) {
    let q = c[0];
    let mu = [c[1], c[2], c[3]];
    let mu_r = mu[0] * r[0] + mu[1] * r[1] + mu[2] * r[2];
    d[0] += q * b[0] + mu_r * b[1];
    for a in 0..3 {
        d[1 + a] += (mu[a] - q * r[a]) * b[1] - r[a] * mu_r * b[2];
    }
    if count > UP_TO[1] {
        let mut k = UP_TO[1];
        for a in 0..3 {
            for e in a..3 {
                let rr = r[a] * r[e];
                let delta = if a == e { 1.0 } else { 0.0 };
                d[k] += q * (rr * b[2] - delta * b[1]) + mu_r * rr * b[3]
                    - (mu[a] * r[e] + mu[e] * r[a] + delta * mu_r) * b[2];
                k += 1;
            }
        }
    }
}

/// Runs `f(i, derivatives[i], virials[i])` for every site, sites as rayon
/// tasks (each site's sums are its own, so they do not depend on the number of
/// threads).
pub(crate) fn per_site(
    derivatives: &mut [[f64; DERIVATIVES]],
    virials: &mut [Matrix3<f64>],
    f: impl Fn(usize, &mut [f64; DERIVATIVES], &mut Matrix3<f64>) + Sync + Send,
) {
    derivatives
        .par_iter_mut()
        .zip(virials.par_iter_mut())
        .enumerate()
        .with_min_len(64)
        .for_each(|(i, (d, w))| f(i, d, w));
}
