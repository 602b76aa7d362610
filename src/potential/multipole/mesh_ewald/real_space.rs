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

use super::cartesian::{DERIVATIVES, SOURCES, UP_TO};
use super::pair_kernels::{ChargeDipoleKernel, Chunk, GeneralKernel, RealKernel};
#[cfg(target_arch = "x86_64")]
use crate::lanes::Avx;
use crate::lanes::{Lanes, F4};
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
        // The first cell of range k: the first with at least k sites / threads
        // before it (for k = threads, the first of the empty cells that end the list).
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
            let range = (bound(k)..bound(k + 1), box_lengths, cutoff);
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
    use crate::lanes::LANES;
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
            let mut found = pairs_found(&cells, &box_lengths, cutoff);
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

    /// The pairs `cells` (built) finds within `cutoff`, in the order found:
    /// the sites' indices `(i, j)`, `i < j`, their separation `r_i - r_j` and its square.
    fn pairs_found(
        cells: &CellList,
        box_lengths: &Vector3<f64>,
        cutoff: f64,
    ) -> Vec<(usize, usize, Vector3<f64>, f64)> {
        let mut found = Vec::new();
        for c in 0..cells.start.len() - 1 {
            cells.for_each_pair_from(
                c,
                box_lengths,
                cutoff * cutoff,
                &mut |a: usize, b: usize, r: Vector3<f64>, r2: f64| {
                    let (i, j) = (cells.members[a], cells.members[b]);
                    found.push((i.min(j), i.max(j), if i < j { r } else { -r }, r2));
                },
            );
        }
        found
    }

    /// A pair exactly at the cutoff is not a pair (the search takes `r <
    /// r_c`), in a site's own cell and in a neighbouring one: dyadic sites
    /// in a box of 3 cells 7/6 wide, at separations of exactly 1 (two
    /// pairs), 1.5 and 15/16 (the one pair found).
    #[test]
    fn a_pair_at_the_cutoff_is_not_found() {
        let box_lengths = Vector3::repeat(3.5);
        let cutoff = 1.0;
        let wrapped = [
            Vector3::new(0.0625, 0.0625, 0.0625),
            Vector3::new(1.0625, 0.0625, 0.0625),
            Vector3::new(2.0625, 0.0625, 0.0625),
            Vector3::new(0.0625, 1.0, 0.0625),
        ];
        let sites = wrapped.len();
        let mut cells = CellList::new(sites, &box_lengths, cutoff);
        assert_eq!((cells.reach, cells.cells), ([1; 3], [3; 3]));
        cells.build(&wrapped, &box_lengths, &vec![[0.0; SOURCES]; sites]);
        // Sites 0 and 1 share a cell, 1 and 2 are in neighbouring ones.
        assert_eq!(cells.cell_of[0], cells.cell_of[1]);
        assert_ne!(cells.cell_of[1], cells.cell_of[2]);
        assert_eq!((wrapped[1] - wrapped[0]).norm_squared(), cutoff * cutoff);
        assert_eq!((wrapped[2] - wrapped[1]).norm_squared(), cutoff * cutoff);
        let found = pairs_found(&cells, &box_lengths, cutoff);
        let r = Vector3::new(0.0, -0.9375, 0.0);
        assert_eq!(found, [(0, 3, r, 0.9375 * 0.9375)]);
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

    /// `kernel()`'s sums in arrays against `general`'s (its first `count`
    /// derivatives, the rest zero, and the virial, to `1e-12` of the
    /// largest), and (where the CPU has AVX2) in AVX registers the same bits.
    fn check_kernel<K: RealKernel>(
        cells: &CellList,
        (box_lengths, cutoff): (&Vector3<f64>, f64),
        kernel: impl Fn() -> K,
        (general, count): (&Block, usize),
        what: &str,
    ) {
        let lanes = pair_sums::<F4, _>(cells, box_lengths, cutoff, kernel());
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
            "{what}"
        );
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let avx = pair_sums::<Avx, _>(cells, box_lengths, cutoff, kernel());
            let bits = |x: &Block| -> Vec<u64> {
                x.derivatives
                    .iter()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect()
            };
            assert_eq!(bits(&avx), bits(&lanes), "{what}");
            assert_eq!(avx.virial, lanes.virial, "{what}");
        }
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
        let mut dipoles: Vec<[f64; SOURCES]> = vec![[0.0; SOURCES]; sites];
        for c in &mut dipoles {
            c[..4]
                .iter_mut()
                .for_each(|x| *x = rng.random_range(-1.0..1.0));
        }
        let charges: Vec<[f64; SOURCES]> = dipoles
            .iter()
            .map(|c| std::array::from_fn(|e| if e == 0 { c[0] } else { 0.0 }))
            .collect();
        let mut cells = CellList::new(sites, &box_lengths, cutoff);
        cells.build(&wrapped, &box_lengths, &charges);
        let mut pairs = 0;
        for c in 0..cells.start.len() - 1 {
            let count = &mut |_: usize, _: usize, _: Vector3<f64>, _: f64| pairs += 1;
            cells.for_each_pair_from(c, &box_lengths, cutoff * cutoff, count);
        }
        assert!(
            pairs % LANES != 0 && pairs > 500,
            "{pairs} pairs: a partial last chunk"
        );
        let space = (&box_lengths, cutoff);
        let general = |order, count, virial| {
            pair_sums::<F4, _>(
                &cells,
                &box_lengths,
                cutoff,
                GeneralKernel::new(alpha, (order, count), virial),
            )
        };
        // Charges: potential and field with the virial; with the field gradient.
        let field = general(0, UP_TO[1], true);
        let kernel = || ChargeDipoleKernel::<2, false>::new(alpha, true);
        check_kernel(&cells, space, kernel, (&field, UP_TO[1]), "charges");
        let gradient = general(0, UP_TO[2], false);
        let kernel = || ChargeDipoleKernel::<4, false>::new(alpha, false);
        check_kernel(
            &cells,
            space,
            kernel,
            (&gradient, UP_TO[2]),
            "charges, gradient",
        );
        cells.build(&wrapped, &box_lengths, &dipoles);
        let both = pair_sums::<F4, _>(
            &cells,
            &box_lengths,
            cutoff,
            GeneralKernel::new(alpha, (1, UP_TO[2]), false),
        );
        let kernel = || ChargeDipoleKernel::<4, true>::new(alpha, false);
        check_kernel(
            &cells,
            space,
            kernel,
            (&both, UP_TO[2]),
            "charges and dipoles",
        );
    }
}
