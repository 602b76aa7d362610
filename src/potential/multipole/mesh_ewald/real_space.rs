//! The real-space part of the mesh Ewald sum: every pair closer than `r_c`
//! (minimum image, `r_c <= L_a / 2`), found by a cell list rebuilt at each
//! evaluation into buffers sized once, the positions and coefficients copied
//! in cell order, each neighbour cell with the shift of its periodic image
//! (no minimum-image test per pair). Along each axis the cells are at least
//! `r_c / R` wide and a site's neighbours are within `R` cells (the axis's
//! reach): `R = 1` (27 cells, 6.4 times the sphere's volume) unless the
//! sites are crowded ([`CROWDED`]) or the axis holds fewer than 3 cells
//! `r_c` wide, then `R = 2` (125 cells of `r_c / 2`, 3.7 times the sphere):
//! a stencil cell costs a loop's overhead however few sites it holds, a
//! site in it a distance test, and at liquid densities with short cutoffs
//! the cells `r_c / 2` wide are mostly empty.
//!
//! Each pair is visited once (Newton's third law): a cell is paired with
//! itself and with the cells of the half stencil (offsets lexicographically
//! after its own: 13 at reach 1, 62 at reach 2), and the pair's kernel adds
//! to both sites, the source's sign flipped for the second (`d^N g(-r) =
//! (-1)^|N| d^N g(r)`). Threads take contiguous ranges of cells with about
//! equal numbers of sites, each summing into its own block; the blocks are
//! added in range order, so the sums are the same bits for a given number
//! of threads.
//!
//! A source `j` contributes `d^A phi(r_i) = sum_E c_E (-1)^|E| d^(A + E)
//! g(r_i - r_j)` with `g = erfc(alpha r) / r` (the Ewald real-space kernel
//! of [`crate::potential::multipole::ewald_terms`]).

use super::cartesian::{
    add_source, pair_force, radial_derivatives, Tables, DERIVATIVES, SOURCES, UP_TO,
};
use super::damped::ErfcTable;
#[cfg(target_arch = "x86_64")]
use crate::lanes::Avx;
use crate::lanes::{Lanes, F4, LANES, V4};
use crate::potential::multipole::ewald_terms::radial_functions;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Sites per cube of side `r_c / 2` above which every axis takes reach 2
/// (module doc): per site, reach 1 costs `13 / (8 m)` stencil cells and `13 * 8 m`
/// distance tests, reach 2 `62 / m` and `62 m` (`m` sites per cube), at
/// ~8 ns per cell and ~1.5 ns per test (the cell search's profile,
/// benchmarks/RESULTS.md), equal at `m` of about 3.
const CROWDED: f64 = 3.0;

/// The reach of each axis and the cells along it for `sites` sites in
/// `box_lengths` with `cutoff` (module doc).
fn layout(sites: f64, box_lengths: &Vector3<f64>, cutoff: f64) -> ([usize; 3], [usize; 3]) {
    let crowded = sites / box_lengths.product() * (cutoff / 2.0).powi(3) > CROWDED;
    let mut reach = [2; 3];
    let mut cells = [1; 3];
    for a in 0..3 {
        let wide = (box_lengths[a] / cutoff).floor() as usize;
        if !crowded && wide >= 3 {
            (reach[a], cells[a]) = (1, wide);
        } else {
            cells[a] = ((box_lengths[a] * 2.0 / cutoff).floor() as usize).max(1);
        }
    }
    (reach, cells)
}

/// The offsets (each from 0 to `2 reach[a]`, `reach` being the home cell's)
/// of the half stencil: those lexicographically after the home cell's.
fn half_stencil(reach: [usize; 3]) -> Vec<[usize; 3]> {
    let width = reach.map(|r| 2 * r + 1);
    let mut offsets = Vec::new();
    for x in 0..width[0] {
        for y in 0..width[1] {
            for z in 0..width[2] {
                if [x, y, z] > reach {
                    offsets.push([x, y, z]);
                }
            }
        }
    }
    offsets
}

/// One thread's sums: the derivatives of each site (in cell order) and the
/// virial `sum r_ij f_ij^T` of its pairs.
#[derive(Clone, Debug, Default)]
struct Block {
    derivatives: Vec<[f64; DERIVATIVES]>,
    virial: Matrix3<f64>,
}

/// The cell list of one box (cells at least `r_c / reach[a]` wide).
#[derive(Clone, Debug)]
pub(crate) struct CellList {
    cells: [usize; 3],
    /// Cells searched on each side of a site's own, per axis.
    reach: [usize; 3],
    /// The offsets of [`half_stencil`].
    stencil: Vec<[usize; 3]>,
    /// First entry of each cell in `members` (`cells + 1` entries).
    start: Vec<usize>,
    /// Site indices, by cell, in increasing order within a cell.
    members: Vec<usize>,
    /// The wrapped positions in the order of `members`.
    sorted: Vec<Vector3<f64>>,
    /// The sources' coefficients in the order of `members`.
    sorted_coefficients: Vec<[f64; SOURCES]>,
    cell_of: Vec<usize>,
    /// One block per thread (sized at the first evaluation with that count).
    blocks: Vec<Block>,
}

impl CellList {
    /// Buffers for `sites` sites in `box_lengths` with cutoff `cutoff`
    /// (`cutoff <= L_a / 2`, checked by the caller).
    pub fn new(sites: usize, box_lengths: &Vector3<f64>, cutoff: f64) -> Self {
        let (reach, cells) = layout(sites as f64, box_lengths, cutoff);
        CellList {
            cells,
            reach,
            stencil: half_stencil(reach),
            start: vec![0; cells.iter().product::<usize>() + 1],
            members: vec![0; sites],
            sorted: vec![Vector3::zeros(); sites],
            sorted_coefficients: vec![[0.0; SOURCES]; sites],
            cell_of: vec![0; sites],
            blocks: Vec::new(),
        }
    }

    /// Bytes held for `sites` sites in `box_lengths` with `cutoff`, the
    /// blocks of the current number of threads included.
    pub fn bytes(sites: f64, box_lengths: &Vector3<f64>, cutoff: f64) -> f64 {
        let cells: f64 = layout(sites, box_lengths, cutoff)
            .1
            .iter()
            .map(|&c| c as f64)
            .product();
        let threads = rayon::current_num_threads() as f64;
        (40.0 + 8.0 * SOURCES as f64 + threads * 8.0 * DERIVATIVES as f64) * sites + 8.0 * cells
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[0] * self.cells[1] + c[1]) * self.cells[2] + c[2]
    }

    /// Sorts the wrapped positions (in `[0, L)`) and the coefficients into cells.
    fn build(
        &mut self,
        wrapped: &[Vector3<f64>],
        box_lengths: &Vector3<f64>,
        coefficients: &[[f64; SOURCES]],
    ) {
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
        for (s, &i) in self.members.iter().enumerate() {
            self.sorted[s] = wrapped[i];
            self.sorted_coefficients[s] = coefficients[i];
        }
    }

    /// Calls `pairs.pair(a, b, r, r^2)` once for every pair of sites (`a`, `b`
    /// their places in cell order) closer than `sqrt(cutoff_squared)` with
    /// `a` in cell `c`, `r = r_a - r_b` at the image of `b` in reach: the
    /// pairs within `c`, and those with the cells of the half stencil.
    /// Inlined, so that `pair` is compiled with the caller's target features.
    #[inline(always)]
    fn for_each_pair_from(
        &self,
        c: usize,
        box_lengths: &Vector3<f64>,
        cutoff_squared: f64,
        pairs: &mut impl PairSink,
    ) {
        let cells = self.cells;
        let own = self.start[c]..self.start[c + 1];
        for a in own.clone() {
            for b in a + 1..own.end {
                let r = self.sorted[a] - self.sorted[b];
                let distance_squared = r.norm_squared();
                if distance_squared < cutoff_squared {
                    pairs.pair(a, b, r, distance_squared);
                }
            }
        }
        // The cell `h + o` of a home coordinate `h` and an offset `o` along
        // axis `a`, and the shift of its image: every offset is a distinct
        // image (at least 3 cells per axis at reach 1, 4 at reach 2), at
        // most one within `r_c <= L_a / 2`.
        let reach = self.reach;
        let neighbour = |a: usize, h: usize, o: usize| -> (usize, f64) {
            let c = h + o;
            if c < reach[a] {
                (c + cells[a] - reach[a], -box_lengths[a])
            } else if c - reach[a] >= cells[a] {
                (c - reach[a] - cells[a], box_lengths[a])
            } else {
                (c - reach[a], 0.0)
            }
        };
        let home = [
            c / (cells[1] * cells[2]),
            (c / cells[2]) % cells[1],
            c % cells[2],
        ];
        for &[ox, oy, oz] in &self.stencil {
            let (cx, sx) = neighbour(0, home[0], ox);
            let (cy, sy) = neighbour(1, home[1], oy);
            let (cz, sz) = neighbour(2, home[2], oz);
            let cell = self.cell_index([cx, cy, cz]);
            let range = self.start[cell]..self.start[cell + 1];
            if range.is_empty() {
                continue;
            }
            // r = r_a - (r_b + shift): the image of b in that cell.
            let shift = Vector3::new(sx, sy, sz);
            for a in own.clone() {
                let base = self.sorted[a] - shift;
                for (b, position) in self.sorted[range.clone()].iter().enumerate() {
                    let r = base - position;
                    let distance_squared = r.norm_squared();
                    if distance_squared < cutoff_squared {
                        pairs.pair(a, range.start + b, r, distance_squared);
                    }
                }
            }
        }
    }

    /// Sums the pairs into one block per thread (module doc), each thread's
    /// kernel made by `kernel()`, four pairs at a time ([`RealKernel`]), in
    /// AVX registers where the CPU has AVX2, else in arrays (the same bits).
    fn sum_pairs<K: RealKernel>(
        &mut self,
        box_lengths: &Vector3<f64>,
        cutoff: f64,
        kernel: impl Fn() -> K + Sync,
    ) {
        let sites = self.members.len();
        let cells = self.start.len() - 1;
        let threads = rayon::current_num_threads().clamp(1, cells);
        let mut blocks = std::mem::take(&mut self.blocks);
        blocks.resize_with(threads, Block::default);
        let start = &self.start;
        // The first cell of range k: the first with at least k sites / threads before it.
        let bound = |k: usize| {
            start
                .partition_point(|&s| s * threads < k * sites)
                .min(cells)
        };
        let this = &*self;
        blocks.par_iter_mut().enumerate().for_each(|(k, block)| {
            block.derivatives.clear();
            block.derivatives.resize(sites, [0.0; DERIVATIVES]);
            block.virial = Matrix3::zeros();
            let last = if k + 1 == threads {
                cells
            } else {
                bound(k + 1)
            };
            let range = (bound(k)..last, box_lengths, cutoff);
            let mut kernel = kernel();
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                unsafe { this.cells_avx2(range, &mut kernel, block) };
                return;
            }
            this.cells_in_lanes::<F4, K>(range, &mut kernel, block);
        });
        self.blocks = blocks;
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn cells_avx2<K: RealKernel>(
        &self,
        range: (std::ops::Range<usize>, &Vector3<f64>, f64),
        kernel: &mut K,
        block: &mut Block,
    ) {
        self.cells_in_lanes::<Avx, K>(range, kernel, block);
    }

    /// The pairs from the cells of `cells` (within `cutoff` in
    /// `box_lengths`) into `block` by `kernel`, four at a time in the order
    /// [`Self::for_each_pair_from`] finds them: each site's sums take the
    /// pairs in that order whatever the lanes, so they are the bits of a
    /// pair-by-pair sum.
    #[inline(always)]
    fn cells_in_lanes<T: Lanes, K: RealKernel>(
        &self,
        (cells, box_lengths, cutoff): (std::ops::Range<usize>, &Vector3<f64>, f64),
        kernel: &mut K,
        block: &mut Block,
    ) {
        let mut sink = ChunkSink {
            chunk: Chunk::default(),
            kernel,
            coefficients: &self.sorted_coefficients,
            block,
            lanes: std::marker::PhantomData::<T>,
        };
        for c in cells {
            self.for_each_pair_from(c, box_lengths, cutoff * cutoff, &mut sink);
        }
        if sink.chunk.len > 0 {
            sink.flush();
        }
    }
}

/// Where [`CellList::for_each_pair_from`] puts the pairs it finds: a
/// closure, or the chunks of a kernel (whose method is inlined into the
/// search, so that it is compiled with the search's target features).
trait PairSink {
    fn pair(&mut self, a: usize, b: usize, r: Vector3<f64>, r2: f64);
}

impl<F: FnMut(usize, usize, Vector3<f64>, f64)> PairSink for F {
    fn pair(&mut self, a: usize, b: usize, r: Vector3<f64>, r2: f64) {
        self(a, b, r, r2);
    }
}

/// The pairs into chunks of four, each full chunk through `kernel` in lanes `T`.
struct ChunkSink<'a, T, K> {
    chunk: Chunk,
    kernel: &'a mut K,
    coefficients: &'a [[f64; SOURCES]],
    block: &'a mut Block,
    lanes: std::marker::PhantomData<T>,
}

impl<T: Lanes, K: RealKernel> ChunkSink<'_, T, K> {
    #[inline(always)]
    fn flush(&mut self) {
        let block = &mut *self.block;
        self.kernel.add::<T>(
            &self.chunk,
            self.coefficients,
            &mut block.derivatives,
            &mut block.virial,
        );
        self.chunk.len = 0;
    }
}

impl<T: Lanes, K: RealKernel> PairSink for ChunkSink<'_, T, K> {
    #[inline(always)]
    fn pair(&mut self, a: usize, b: usize, r: Vector3<f64>, r2: f64) {
        if self.chunk.push(a, b, r, r2) {
            self.flush();
        }
    }
}

impl CellList {
    /// Adds the real-space derivatives of every site to `derivatives`
    /// (`count` of them), from the sources' coefficients `coefficients` (of
    /// order at most `source_order`); returns the pairs' virial `sum r_ij
    /// f_ij^T` with `virial` (else zero).
    #[allow(clippy::too_many_arguments)]
    pub fn add_derivatives(
        &mut self,
        wrapped: &[Vector3<f64>],
        box_lengths: &Vector3<f64>,
        alpha: f64,
        cutoff: f64,
        coefficients: &[[f64; SOURCES]],
        (source_order, count): (usize, usize),
        derivatives: &mut [[f64; DERIVATIVES]],
        virial: bool,
    ) -> Matrix3<f64> {
        self.build(wrapped, box_lengths, coefficients);
        // Charges and dipoles: the potential, field and field gradient by a
        // kernel of B_0 to B_3 (the sums of the general path, unrolled); the
        // virial's pair force of dipoles by the general path.
        let unrolled = count <= UP_TO[2] && (source_order == 0 || (source_order == 1 && !virial));
        match (unrolled, source_order, count > UP_TO[1]) {
            (true, 0, false) => self.sum_pairs(box_lengths, cutoff, || {
                ChargeDipoleKernel::<2, false>::new(alpha, virial)
            }),
            (true, 0, true) => self.sum_pairs(box_lengths, cutoff, || {
                ChargeDipoleKernel::<4, false>::new(alpha, virial)
            }),
            // Dipoles: their forces need the field gradient (count 10).
            (true, _, _) => self.sum_pairs(box_lengths, cutoff, || {
                ChargeDipoleKernel::<4, true>::new(alpha, virial)
            }),
            (false, _, _) => self.sum_pairs(box_lengths, cutoff, || {
                GeneralKernel::new(alpha, (source_order, count), virial)
            }),
        }
        let mut total = Matrix3::zeros();
        for block in &self.blocks {
            for (s, &i) in self.members.iter().enumerate() {
                for (d, b) in derivatives[i]
                    .iter_mut()
                    .zip(&block.derivatives[s])
                    .take(count)
                {
                    *d += b;
                }
            }
            total += block.virial;
        }
        total
    }
}

/// Up to four pairs for a kernel: the places of their sites in cell order
/// (`a`, `b`), `r = r_a - r_b` and `r^2`; the lanes from `len` on hold a
/// harmless separation (`r^2 = 1`) whose results are dropped.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    a: [usize; LANES],
    b: [usize; LANES],
    r: [Vector3<f64>; LANES],
    r2: [f64; LANES],
    len: usize,
}

impl Default for Chunk {
    fn default() -> Self {
        Chunk {
            a: [0; LANES],
            b: [0; LANES],
            r: [Vector3::x(); LANES],
            r2: [1.0; LANES],
            len: 0,
        }
    }
}

impl Chunk {
    /// Adds a pair; whether the chunk is full.
    #[inline(always)]
    fn push(&mut self, a: usize, b: usize, r: Vector3<f64>, r2: f64) -> bool {
        let l = self.len;
        (self.a[l], self.b[l], self.r[l], self.r2[l]) = (a, b, r, r2);
        self.len += 1;
        self.len == LANES
    }

    /// The lanes of the sources' coefficients `e` of the sites `sites`.
    #[inline(always)]
    fn sources<T: Lanes, const E: usize>(
        sites: &[usize; LANES],
        coefficients: &[[f64; SOURCES]],
    ) -> [T; E] {
        std::array::from_fn(|e| T::from_array(sites.map(|i| coefficients[i][e])))
    }
}

/// A real-space pair kernel, four pairs at a time: adds each pair's share
/// to the derivatives of both its sites (`d_a` from the coefficients of
/// `b` at `r`, `d_b` from those of `a` at `-r`) and its `r f^T` to the
/// virial, lane by lane in the chunk's order.
trait RealKernel {
    fn add<T: Lanes>(
        &mut self,
        chunk: &Chunk,
        coefficients: &[[f64; SOURCES]],
        derivatives: &mut [[f64; DERIVATIVES]],
        virial: &mut Matrix3<f64>,
    );
}

/// The pair kernel of charges and (with `DIPOLES`) dipoles by
/// [`charge_dipole_terms`], the radial functions `B_0..B_(L-1)` (`L = 2`:
/// the potential and field; 4: and the field gradient) from [`ErfcTable`];
/// the virial of charges only (the general kernel has that of dipoles).
struct ChargeDipoleKernel<const L: usize, const DIPOLES: bool> {
    alpha: f64,
    virial: bool,
    erfc: &'static ErfcTable,
}

impl<const L: usize, const DIPOLES: bool> ChargeDipoleKernel<L, DIPOLES> {
    fn new(alpha: f64, virial: bool) -> Self {
        ChargeDipoleKernel {
            alpha,
            virial,
            erfc: ErfcTable::get(),
        }
    }
}

impl<const L: usize, const DIPOLES: bool> RealKernel for ChargeDipoleKernel<L, DIPOLES> {
    #[inline(always)]
    fn add<T: Lanes>(
        &mut self,
        chunk: &Chunk,
        coefficients: &[[f64; SOURCES]],
        derivatives: &mut [[f64; DERIVATIVES]],
        virial: &mut Matrix3<f64>,
    ) {
        let r = V4::<T>::gather(chunk.r.each_ref());
        let b = self
            .erfc
            .radial_lanes::<T, L>(self.alpha, T::from_array(chunk.r2));
        let c_a = Chunk::sources::<T, 4>(&chunk.a, coefficients);
        let c_b = Chunk::sources::<T, 4>(&chunk.b, coefficients);
        let to_a = charge_dipole_terms::<T, L, DIPOLES>(&c_b, &r, &b).map(T::to_array);
        let to_b = charge_dipole_terms::<T, L, DIPOLES>(&c_a, &-r, &b).map(T::to_array);
        let count = if L > 2 { UP_TO[2] } else { UP_TO[1] };
        let b1 = b[1].to_array();
        for l in 0..chunk.len {
            let d_a = &mut derivatives[chunk.a[l]];
            for (d, t) in d_a.iter_mut().zip(&to_a).take(count) {
                *d += t[l];
            }
            let d_b = &mut derivatives[chunk.b[l]];
            for (d, t) in d_b.iter_mut().zip(&to_b).take(count) {
                *d += t[l];
            }
            if self.virial {
                let (r, q_a, q_b) = (
                    chunk.r[l],
                    coefficients[chunk.a[l]][0],
                    coefficients[chunk.b[l]][0],
                );
                let f = r * (q_a * q_b * b1[l]);
                *virial += r * f.transpose();
            }
        }
    }
}

/// The pair kernel of any sources (order at most `source_order`, `count`
/// derivatives) by the derivative tensors of `erfc(alpha r) / r`, pair by
/// pair: those at `-r` for the second site are `(-1)^|N|` times those at
/// `r`.
struct GeneralKernel {
    alpha: f64,
    source_order: usize,
    count: usize,
    virial: bool,
    /// The multi-indices the pair needs (one order above the sources'
    /// derivatives: enough for the pair forces too).
    needed: usize,
    signs: [f64; 56],
    t: [[f64; 56]; 6],
    flipped: [f64; 56],
}

impl GeneralKernel {
    fn new(alpha: f64, (source_order, count): (usize, usize), virial: bool) -> Self {
        let tables = Tables::get();
        GeneralKernel {
            alpha,
            source_order,
            count,
            virial,
            needed: UP_TO[tables.order(count - 1) + source_order],
            signs: std::array::from_fn(|n| if tables.order(n) % 2 == 1 { -1.0 } else { 1.0 }),
            t: [[0.0; 56]; 6],
            flipped: [0.0; 56],
        }
    }
}

impl RealKernel for GeneralKernel {
    fn add<T: Lanes>(
        &mut self,
        chunk: &Chunk,
        coefficients: &[[f64; SOURCES]],
        derivatives: &mut [[f64; DERIVATIVES]],
        virial: &mut Matrix3<f64>,
    ) {
        let (sources, count, needed) = (UP_TO[self.source_order], self.count, self.needed);
        for l in 0..chunk.len {
            let (a, b, r) = (chunk.a[l], chunk.b[l], &chunk.r[l]);
            let (c_a, c_b) = (&coefficients[a], &coefficients[b]);
            let t = &mut self.t;
            radial_derivatives(
                r,
                &radial_functions(self.alpha, chunk.r2[l].sqrt()),
                needed,
                t,
            );
            add_source(&t[0], c_b, sources, count, &mut derivatives[a]);
            for ((f, t), s) in self
                .flipped
                .iter_mut()
                .zip(&t[0])
                .zip(&self.signs)
                .take(needed)
            {
                *f = t * s;
            }
            add_source(&self.flipped, c_a, sources, count, &mut derivatives[b]);
            if self.virial {
                let f = pair_force(&t[0], c_a, sources, c_b, sources);
                *virial += r * f.transpose();
            }
        }
    }
}

/// The potential of a source with charge `q = c[0]` and dipole `mu =
/// c[1..4]` (with `DIPOLES`, which needs `L = 4`) and its first 4 (`L =
/// 2`) or 10 (`L = 4`) derivatives at offset `r`, four pairs at once, from
/// the radial functions `b` at `|r|` (the sums of [`add_source`] for these
/// sources, unrolled): `phi = q B_0 + (mu.r) B_1`, `d_a phi = -q r_a B_1 +
/// mu_a B_1 - r_a (mu.r) B_2`, `d_ac phi = q (r_a r_c B_2 - delta_ac B_1) +
/// (mu.r) r_a r_c B_3 - (mu_a r_c + mu_c r_a + delta_ac mu.r) B_2`.
#[inline(always)]
fn charge_dipole_terms<T: Lanes, const L: usize, const DIPOLES: bool>(
    c: &[T; 4],
    r: &V4<T>,
    b: &[T; L],
) -> [T; UP_TO[2]] {
    let mut d = [T::default(); UP_TO[2]];
    let q = c[0];
    let r = [r.x, r.y, r.z];
    let mu = if DIPOLES {
        [c[1], c[2], c[3]]
    } else {
        [T::default(); 3]
    };
    let mu_r = mu[0] * r[0] + mu[1] * r[1] + mu[2] * r[2];
    if DIPOLES {
        d[0] = q * b[0] + mu_r * b[1];
        for a in 0..3 {
            d[1 + a] = (mu[a] - q * r[a]) * b[1] - r[a] * mu_r * b[2];
        }
    } else {
        d[0] = q * b[0];
        for a in 0..3 {
            // d - x is d + (-x), bit for bit.
            d[1 + a] = -(q * r[a] * b[1]);
        }
    }
    if L > 2 {
        let mut k = UP_TO[1];
        for a in 0..3 {
            for e in a..3 {
                let rr = r[a] * r[e];
                let delta = T::splat(if a == e { 1.0 } else { 0.0 });
                d[k] = q * (rr * b[2] - delta * b[1]) + mu_r * rr * b[3]
                    - (mu[a] * r[e] + mu[e] * r[a] + delta * mu_r) * b[2];
                k += 1;
            }
        }
    }
    d
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    /// Every layout finds each pair within the cutoff exactly once, with the
    /// minimum-image separation: sparse sites (reach 1 on every axis),
    /// crowded ones (reach 2), and a box with an axis of 3 cells `r_c` wide
    /// (reach 1) and one of 2 (reach 2 there), against all pairs by the
    /// minimum image.
    #[test]
    fn every_layout_finds_each_pair_within_the_cutoff_once() {
        for (box_lengths, sites, cutoff, reach) in [
            (Vector3::new(5.0, 5.0, 5.0), 400, 1.0, [1, 1, 1]),
            (Vector3::new(5.0, 5.0, 5.0), 4000, 1.0, [2, 2, 2]),
            (Vector3::new(3.2, 2.5, 4.1), 60, 1.05, [1, 2, 1]),
        ] {
            let mut rng = ChaCha20Rng::seed_from_u64(3);
            let wrapped: Vec<Vector3<f64>> = (0..sites)
                .map(|_| Vector3::from_fn(|a, _| rng.random_range(0.0..box_lengths[a])))
                .collect();
            let mut cells = CellList::new(sites, &box_lengths, cutoff);
            assert_eq!(cells.reach, reach, "{box_lengths:?} with {sites} sites");
            cells.build(&wrapped, &box_lengths, &vec![[0.0; SOURCES]; sites]);
            let mut found = Vec::new();
            for c in 0..cells.start.len() - 1 {
                cells.for_each_pair_from(
                    c,
                    &box_lengths,
                    cutoff * cutoff,
                    &mut |a: usize, b: usize, r: Vector3<f64>, r2: f64| {
                        let (i, j) = (cells.members[a], cells.members[b]);
                        found.push((i.min(j), i.max(j), if i < j { r } else { -r }, r2));
                    },
                );
            }
            found.sort_by_key(|x| (x.0, x.1));
            let mut expected = Vec::new();
            for i in 0..sites {
                for j in i + 1..sites {
                    let r = Vector3::from_fn(|a, _| {
                        let d = wrapped[i][a] - wrapped[j][a];
                        d - box_lengths[a] * (d / box_lengths[a]).round()
                    });
                    if r.norm_squared() < cutoff * cutoff {
                        expected.push((i, j, r));
                    }
                }
            }
            assert_eq!(found.len(), expected.len(), "{box_lengths:?}");
            for ((i, j, r, r2), (ei, ej, er)) in found.iter().zip(&expected) {
                assert_eq!((i, j), (ei, ej));
                assert!((r - er).norm() < 1e-12, "{i} {j}: {r:?} against {er:?}");
                assert!((r2 - r.norm_squared()).abs() < 1e-12);
            }
        }
    }

    /// The sums of `kernel` over every pair of `cells` (built) in lanes `T`.
    fn pair_sums<T: Lanes, K: RealKernel>(
        cells: &CellList,
        box_lengths: &Vector3<f64>,
        cutoff: f64,
        mut kernel: K,
    ) -> Block {
        let mut block = Block::default();
        block
            .derivatives
            .resize(cells.members.len(), [0.0; DERIVATIVES]);
        let all = 0..cells.start.len() - 1;
        cells.cells_in_lanes::<T, K>((all, box_lengths, cutoff), &mut kernel, &mut block);
        block
    }

    /// The unrolled kernels of charges and of charges and dipoles, four
    /// pairs at a time, sum what the general kernel sums pair by pair (by
    /// the derivative tensors of `erfc(alpha r) / r`, to round-off), the
    /// charges' virial too, and the last chunk of fewer than four pairs
    /// with the rest; in arrays and (where the CPU has AVX2) in AVX
    /// registers, the same bits.
    #[test]
    fn lane_kernels_sum_what_the_general_kernel_sums() {
        let (box_lengths, sites, cutoff, alpha) = (Vector3::new(4.0, 4.5, 5.0), 153, 1.7, 1.3);
        let mut rng = ChaCha20Rng::seed_from_u64(11);
        let wrapped: Vec<Vector3<f64>> = (0..sites)
            .map(|_| Vector3::from_fn(|a, _| rng.random_range(0.0..box_lengths[a])))
            .collect();
        let coefficients: Vec<[f64; SOURCES]> = (0..sites)
            .map(|_| {
                std::array::from_fn(|e| {
                    if e < 4 {
                        rng.random_range(-1.0..1.0)
                    } else {
                        0.0
                    }
                })
            })
            .collect();
        let charges: Vec<[f64; SOURCES]> = coefficients
            .iter()
            .map(|c| std::array::from_fn(|e| if e == 0 { c[0] } else { 0.0 }))
            .collect();
        let mut pairs = 0;
        let mut cells = CellList::new(sites, &box_lengths, cutoff);
        cells.build(&wrapped, &box_lengths, &coefficients);
        for c in 0..cells.start.len() - 1 {
            cells.for_each_pair_from(
                c,
                &box_lengths,
                cutoff * cutoff,
                &mut |_: usize, _: usize, _: Vector3<f64>, _: f64| pairs += 1,
            );
        }
        assert!(
            pairs % LANES != 0 && pairs > 500,
            "{pairs} pairs: a partial last chunk"
        );
        let close = |lanes: &Block, general: &Block, count: usize, what: &str| {
            let scale = general
                .derivatives
                .iter()
                .flatten()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            for (i, (l, g)) in lanes
                .derivatives
                .iter()
                .zip(&general.derivatives)
                .enumerate()
            {
                for k in 0..DERIVATIVES {
                    let expected = if k < count { g[k] } else { 0.0 };
                    assert!(
                        (l[k] - expected).abs() < 1e-12 * scale,
                        "{what}: site {i} derivative {k}: {} against {expected}",
                        l[k]
                    );
                }
            }
            let virial_scale = general.virial.abs().max().max(1.0);
            assert!(
                (lanes.virial - general.virial).abs().max() < 1e-12 * virial_scale,
                "{what}: virial"
            );
        };
        let same_bits = |a: &Block, b: &Block| {
            let bits = |x: &Block| {
                x.derivatives
                    .iter()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(a), bits(b));
            assert_eq!(a.virial, b.virial);
        };
        // Charges (potential and field, with the virial), charges with the field gradient.
        cells.build(&wrapped, &box_lengths, &charges);
        for (count, virial) in [(UP_TO[1], true), (UP_TO[2], false)] {
            let general = pair_sums::<F4, _>(
                &cells,
                &box_lengths,
                cutoff,
                GeneralKernel::new(alpha, (0, count), virial),
            );
            let lanes = if count == UP_TO[1] {
                pair_sums::<F4, _>(
                    &cells,
                    &box_lengths,
                    cutoff,
                    ChargeDipoleKernel::<2, false>::new(alpha, virial),
                )
            } else {
                pair_sums::<F4, _>(
                    &cells,
                    &box_lengths,
                    cutoff,
                    ChargeDipoleKernel::<4, false>::new(alpha, virial),
                )
            };
            close(&lanes, &general, count, "charges");
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                let avx = if count == UP_TO[1] {
                    pair_sums::<Avx, _>(
                        &cells,
                        &box_lengths,
                        cutoff,
                        ChargeDipoleKernel::<2, false>::new(alpha, virial),
                    )
                } else {
                    pair_sums::<Avx, _>(
                        &cells,
                        &box_lengths,
                        cutoff,
                        ChargeDipoleKernel::<4, false>::new(alpha, virial),
                    )
                };
                same_bits(&avx, &lanes);
            }
        }
        // Charges and dipoles.
        cells.build(&wrapped, &box_lengths, &coefficients);
        let general = pair_sums::<F4, _>(
            &cells,
            &box_lengths,
            cutoff,
            GeneralKernel::new(alpha, (1, UP_TO[2]), false),
        );
        let lanes = pair_sums::<F4, _>(
            &cells,
            &box_lengths,
            cutoff,
            ChargeDipoleKernel::<4, true>::new(alpha, false),
        );
        close(&lanes, &general, UP_TO[2], "charges and dipoles");
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let avx = pair_sums::<Avx, _>(
                &cells,
                &box_lengths,
                cutoff,
                ChargeDipoleKernel::<4, true>::new(alpha, false),
            );
            same_bits(&avx, &lanes);
        }
    }
}
