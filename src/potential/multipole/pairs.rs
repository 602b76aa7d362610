//! The pair list and the pair geometry, computed once: sites never move.
//!
//! Each interacting pair is stored once, grouped by its first rotor `i` (CSR),
//! with one entry per image inside the cutoff (periodic boxes: see
//! [`super::PeriodicSum::Cutoff`] for the sum): `(i, j)` with `i < j` for every image
//! `r_j - r_i + n L` within the cutoff, and `(i, i)` for every pair of
//! opposite self images `±n L` (`n != 0`), once, which is the self term
//! `1/2 sum_{n != 0} v(n L)` since `n` and `-n` give equal terms. The kernels
//! add both ends of a pair to the rotors' fields, so a self pair adds both
//! ends to rotor `i`, as the derivative of `v(n L)` in rotor `i` requires.
//!
//! The geometry is kept in a table indexed by the distinct offsets, keyed by
//! their exact bit patterns (a cache never changes a result: only pairs
//! whose computed offsets are the same numbers share an entry): on a
//! periodic lattice of exactly representable sites all pairs with the same
//! offset share one entry (122 entries serve the 61,000 pairs of the 10^3
//! simple-cubic lattice with cutoff 3.1), so the tables stay in the L1 cache.

use super::boundary::{pair_memory, too_many_pairs, MAX_PAIRS};
use super::image_grid::ImageGrid;
use super::PotentialError;
use nalgebra::Vector3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Sites closer than this (length unit, periodic images included) are
/// refused as coincident.
const COINCIDENT: f64 = 1e-9;

/// The exact key of an offset: the bit patterns of its components (`-0.0`
/// and `0.0` are one value).
fn offset_key(offset: &Vector3<f64>) -> [u64; 3] {
    [0, 1, 2].map(|a| (offset[a] + 0.0).to_bits())
}

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

/// Interacting pairs `i <= j` (one entry per image) in CSR form, with shared geometry.
#[derive(Clone, Debug)]
pub(crate) struct PairTable {
    /// Pairs of rotor `i` are `start[i]..start[i + 1]`.
    pub start: Vec<usize>,
    /// The partner `j >= i` of each pair (`j == i`: a self image, periodic only).
    pub partner: Vec<u32>,
    /// Index into `geometry` of each pair.
    pub geometry_index: Vec<u32>,
    /// One entry per distinct offset `r_j - r_i (+ n L)`.
    pub geometry: Vec<PairGeometry>,
}

/// Rows per task of [`PairTable::build`]: a fixed count, so that the table
/// (the order of its geometries included) is the same on any number of
/// threads. A 64,000-rotor lattice with cutoff 3.1 has 125 tasks of about
/// 60,000 pairs.
const ROWS_PER_TASK: usize = 512;

/// The pairs of one task's rows, their offsets numbered by first appearance
/// within the task.
#[derive(Default)]
struct RowsFound {
    /// Pairs of each row scanned.
    row_lengths: Vec<usize>,
    partner: Vec<u32>,
    /// Index into `offsets` of each pair.
    local_index: Vec<u32>,
    /// The distinct offsets (key and value of their first pair).
    offsets: Vec<([u64; 3], Vector3<f64>)>,
    /// Why the scan stopped early: a coincident pair (in the last row
    /// scanned), or more pairs found by all tasks than the limits allow.
    stop: Option<PotentialError>,
}

/// The limits of a periodic table ([`MAX_PAIRS`] and the memory limit):
/// the error for `count` pairs, if it exceeds them.
fn over_limits(cutoff: f64, sites: usize, count: usize) -> Result<(), PotentialError> {
    if count > MAX_PAIRS {
        return Err(too_many_pairs(cutoff, sites, &format!("more than {count}")));
    }
    pair_memory(cutoff, sites, count as f64)
}

impl PairTable {
    /// Enumerates the interacting pairs: all pairs `i < j` when `images` is
    /// `None` (open); every image within the cutoff when it is
    /// `Some((box_lengths, cutoff))` (periodic, see the module doc).
    /// Coincident sites (images included) and more than [`MAX_PAIRS`]
    /// periodic pairs are errors.
    ///
    /// The rows are scanned in parallel, [`ROWS_PER_TASK`] a task, and the
    /// tasks' finds joined in row order, so the table and the first error
    /// in row order are those of one scan from the first row to the last. A
    /// scan that outgrows the limits stops all tasks (the pairs counted so
    /// far, over all tasks, are the count its error quotes).
    pub fn build(
        sites: &[Vector3<f64>],
        images: Option<(Vector3<f64>, f64)>,
    ) -> Result<Self, PotentialError> {
        let n = sites.len();
        if u32::try_from(n).is_err() {
            return Err(PotentialError::new(
                "rotors",
                format!("at most {} rotors, got {n}", u32::MAX),
            ));
        }
        let grid = images.map(|(box_lengths, cutoff)| ImageGrid::new(sites, &box_lengths, cutoff));
        let found_so_far = AtomicUsize::new(0);
        let tasks: Vec<RowsFound> = (0..n.div_ceil(ROWS_PER_TASK))
            .into_par_iter()
            .map(|t| {
                let rows = t * ROWS_PER_TASK..n.min((t + 1) * ROWS_PER_TASK);
                scan_rows(sites, grid.as_ref(), rows, &found_so_far)
            })
            .collect();
        Self::joined(tasks, grid.map(|g| g.cutoff), n)
    }

    /// The table of the tasks' finds in row order: the limits checked row
    /// by row and the offsets numbered by first appearance, as one scan
    /// would.
    fn joined(
        tasks: Vec<RowsFound>,
        cutoff: Option<f64>,
        n: usize,
    ) -> Result<Self, PotentialError> {
        let mut start = Vec::with_capacity(n + 1);
        let mut count = 0;
        let mut geometry = Vec::new();
        let mut by_offset: FxHashMap<[u64; 3], u32> = FxHashMap::default();
        let mut global_index = Vec::with_capacity(tasks.len());
        for task in &tasks {
            for &length in &task.row_lengths {
                start.push(count);
                count += length;
                if let Some(cutoff) = cutoff {
                    over_limits(cutoff, n, count)?;
                }
            }
            if let Some(e) = &task.stop {
                return Err(e.clone());
            }
            let global: Vec<u32> = task
                .offsets
                .iter()
                .map(|(key, offset)| {
                    let next = geometry.len() as u32;
                    let index = *by_offset.entry(*key).or_insert(next);
                    if index == next {
                        geometry.push(PairGeometry::new(offset));
                    }
                    index
                })
                .collect();
            global_index.push(global);
        }
        start.push(count);
        let mut partner = vec![0; count];
        let mut geometry_index = vec![0; count];
        let mut pieces = Vec::with_capacity(tasks.len());
        let (mut partner_rest, mut index_rest) = (&mut partner[..], &mut geometry_index[..]);
        for (task, global) in tasks.iter().zip(&global_index) {
            let (p, p_rest) = partner_rest.split_at_mut(task.partner.len());
            let (g, g_rest) = index_rest.split_at_mut(task.partner.len());
            (partner_rest, index_rest) = (p_rest, g_rest);
            pieces.push((p, g, task, global));
        }
        pieces.into_par_iter().for_each(|(p, g, task, global)| {
            p.copy_from_slice(&task.partner);
            for (g, &local) in g.iter_mut().zip(&task.local_index) {
                *g = global[local as usize];
            }
        });
        Ok(PairTable {
            start,
            partner,
            geometry_index,
            geometry,
        })
    }

    /// Number of interacting pairs.
    pub fn len(&self) -> usize {
        self.partner.len()
    }
}

/// Scans `rows` of the table (see [`PairTable::build`]); `found_so_far`
/// counts the pairs of all tasks, so that a table over the limits stops
/// every task soon.
fn scan_rows(
    sites: &[Vector3<f64>],
    grid: Option<&ImageGrid>,
    rows: std::ops::Range<usize>,
    found_so_far: &AtomicUsize,
) -> RowsFound {
    let n = sites.len();
    let mut found = RowsFound::default();
    let mut by_offset: FxHashMap<[u64; 3], u32> = FxHashMap::default();
    let mut row = Vec::new();
    for i in rows {
        match grid {
            Some(grid) => {
                grid.row(i, &mut row);
                let total = found_so_far.fetch_add(row.len(), Ordering::Relaxed) + row.len();
                if let Err(e) = over_limits(grid.cutoff, n, total) {
                    found.stop = Some(e);
                    return found;
                }
            }
            None => {
                row.clear();
                row.extend((i + 1..n).map(|j| (j as u32, [0; 3], sites[j] - sites[i])));
            }
        }
        found.row_lengths.push(row.len());
        for &(j, _, offset) in &row {
            if offset.norm() <= COINCIDENT {
                found.stop = Some(coincident(i, j as usize, offset.norm()));
                return found;
            }
            let key = offset_key(&offset);
            let next = found.offsets.len() as u32;
            let index = *by_offset.entry(key).or_insert(next);
            if index == next {
                found.offsets.push((key, offset));
            }
            found.partner.push(j);
            found.local_index.push(index);
        }
    }
    found
}

/// Splits the rows `0..n` of a source whose row `i` starts at `start[i]`
/// into `blocks` contiguous ranges of about equal pair counts.
pub(crate) fn balanced_blocks(start: &[usize], blocks: usize) -> Vec<std::ops::Range<usize>> {
    let n = start.len() - 1;
    let blocks = blocks.clamp(1, n.max(1));
    let total = start[n];
    let mut ranges = Vec::with_capacity(blocks);
    let mut begin = 0;
    for b in 1..=blocks {
        let end = if b == blocks {
            n
        } else {
            let target = total * b / blocks;
            start.partition_point(|&s| s < target).min(n).max(begin)
        };
        ranges.push(begin..end);
        begin = end;
    }
    ranges
}

/// A source of the rows of pairs the kernels sum: for row `i`, the
/// partners `j`, the index of each pair's geometry, and the geometries
/// indexed (see [`super::kernels`]).
pub(crate) trait PairRows: Sync {
    /// Per-thread scratch space for the rows.
    type Scratch: Default + Send;
    /// `(partners, geometry_index, geometry)` of row `i`.
    fn row<'a>(
        &'a self,
        i: usize,
        scratch: &'a mut Self::Scratch,
    ) -> (&'a [u32], &'a [u32], &'a [PairGeometry]);
    /// Pairs of row `i` are `starts()[i]..starts()[i + 1]` (in a full
    /// enumeration), for splitting the rows into blocks.
    fn starts(&self) -> &[usize];
}

impl PairRows for PairTable {
    type Scratch = ();
    #[inline(always)]
    fn row<'a>(&'a self, i: usize, _: &'a mut ()) -> (&'a [u32], &'a [u32], &'a [PairGeometry]) {
        let range = self.start[i]..self.start[i + 1];
        (
            &self.partner[range.clone()],
            &self.geometry_index[range],
            &self.geometry,
        )
    }
    fn starts(&self) -> &[usize] {
        &self.start
    }
}

/// Every pair `i < j` of an open cluster, in the order of a [`PairTable`]
/// built for open boundaries, with each row's geometry computed when the row
/// is summed (the same numbers the table would hold, so the same sums bit
/// for bit): `O(N)` memory instead of `O(N^2)`.
#[derive(Clone, Debug)]
pub(crate) struct OpenPairs {
    sites: Vec<Vector3<f64>>,
    /// `0, 1, ..., n - 1`: the partners of row `i` are `indices[i + 1..]`,
    /// its geometry indices `indices[..n - 1 - i]`.
    indices: Vec<u32>,
    /// Pairs before row `i`.
    start: Vec<usize>,
}

impl OpenPairs {
    /// The pairs of `sites`; coincident sites (closer than 1e-9) are an
    /// error, found with a grid of cells in `O(N)`.
    pub fn new(sites: &[Vector3<f64>]) -> Result<Self, PotentialError> {
        let n = sites.len();
        let indices = (0..n)
            .map(u32::try_from)
            .collect::<Result<Vec<u32>, _>>()
            .map_err(|_| {
                PotentialError::new("rotors", format!("at most {} rotors, got {n}", u32::MAX))
            })?;
        if let Some((i, j, d)) = first_coincident(sites) {
            return Err(coincident(i, j, d));
        }
        let mut start = Vec::with_capacity(n + 1);
        let mut count = 0usize;
        for i in 0..n {
            start.push(count);
            count += n - 1 - i;
        }
        start.push(count);
        Ok(OpenPairs {
            sites: sites.to_vec(),
            indices,
            start,
        })
    }

    /// Number of pairs, `n (n - 1) / 2`.
    pub fn len(&self) -> usize {
        self.start.last().copied().unwrap_or(0)
    }
}

impl PairRows for OpenPairs {
    type Scratch = Vec<PairGeometry>;
    #[inline(always)]
    fn row<'a>(
        &'a self,
        i: usize,
        scratch: &'a mut Vec<PairGeometry>,
    ) -> (&'a [u32], &'a [u32], &'a [PairGeometry]) {
        let site = self.sites[i];
        scratch.clear();
        scratch.extend(
            self.sites[i + 1..]
                .iter()
                .map(|s| PairGeometry::new(&(s - site))),
        );
        let partners = &self.indices[i + 1..];
        (partners, &self.indices[..partners.len()], scratch)
    }
    fn starts(&self) -> &[usize] {
        &self.start
    }
}

/// The error for sites `i` and `j` at distance `d` (<= [`COINCIDENT`]).
fn coincident(i: usize, j: usize, d: f64) -> PotentialError {
    PotentialError::new(
        format!("rotors[{i}].site and rotors[{j}].site"),
        format!("coincide (distance {d:e}, periodic images included)"),
    )
}

/// The first pair `(i, j)`, `i < j` in row order, of sites closer than
/// [`COINCIDENT`], and their distance: sites are binned into cells of that
/// width (keys saturate for huge coordinates, which only merges far cells)
/// and compared with the sites of the 27 cells around them.
fn first_coincident(sites: &[Vector3<f64>]) -> Option<(usize, usize, f64)> {
    let cell =
        |s: &Vector3<f64>| -> [i64; 3] { [0, 1, 2].map(|a| (s[a] / COINCIDENT).floor() as i64) };
    let mut cells: FxHashMap<[i64; 3], Vec<u32>> =
        FxHashMap::with_capacity_and_hasher(sites.len(), Default::default());
    for (k, s) in sites.iter().enumerate() {
        cells.entry(cell(s)).or_default().push(k as u32);
    }
    let mut best: Option<(usize, usize, f64)> = None;
    for (i, s) in sites.iter().enumerate() {
        let home = cell(s);
        for d in 0..27i64 {
            let shift = [d / 9 - 1, (d / 3) % 3 - 1, d % 3 - 1];
            let key = [0, 1, 2].map(|a| home[a].saturating_add(shift[a]));
            let Some(members) = cells.get(&key) else {
                continue;
            };
            for &j in members {
                let j = j as usize;
                let distance = (sites[j] - s).norm();
                if j > i && distance <= COINCIDENT && best.is_none_or(|(_, bj, _)| j < bj) {
                    best = Some((i, j, distance));
                }
            }
        }
        if best.is_some() {
            return best;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Offsets are compared on this grid (length unit): far finer than the
    /// distinct offsets of the scatters below, far coarser than the round-off
    /// of `unit / inv_r` (~1e-15).
    const KEY_RESOLUTION: f64 = 1e-6;

    type Found = Vec<(usize, usize, [i64; 3])>;

    fn key(offset: &Vector3<f64>) -> [i64; 3] {
        offset.map(|x| (x / KEY_RESOLUTION).round() as i64).into()
    }

    /// Every `(i, j, offset)` of the table, in table order.
    fn table_entries(table: &PairTable) -> Found {
        (0..table.start.len() - 1)
            .flat_map(|i| {
                (table.start[i]..table.start[i + 1]).map(move |p| {
                    let g = &table.geometry[table.geometry_index[p] as usize];
                    (i, table.partner[p] as usize, key(&(g.unit / g.inv_r)))
                })
            })
            .collect()
    }

    /// The direct image loop over the unwrapped sites: `i < j` with every
    /// shift, `i == j` with one of each `±n`, shifts up to `m` boxes.
    fn image_loop(sites: &[Vector3<f64>], box_lengths: &Vector3<f64>, cutoff: f64) -> Found {
        // Sites lie up to one box outside `[0, L)`: two more boxes of shifts.
        let m = [0, 1, 2].map(|a| (cutoff / box_lengths[a]).ceil() as i64 + 2);
        let mut out = Vec::new();
        for i in 0..sites.len() {
            for j in i..sites.len() {
                for nx in -m[0]..=m[0] {
                    for ny in -m[1]..=m[1] {
                        for nz in -m[2]..=m[2] {
                            let shift = [nx, ny, nz];
                            let n = Vector3::new(nx as f64, ny as f64, nz as f64);
                            let offset = sites[j] - sites[i] + n.component_mul(box_lengths);
                            let counted = i < j || (shift > [0; 3]);
                            if counted && offset.norm() <= cutoff {
                                out.push((i, j, key(&offset)));
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// A deterministic scatter in the box, some sites one box length outside.
    fn scatter(count: usize, l: &Vector3<f64>) -> Vec<Vector3<f64>> {
        (0..count)
            .map(|k| {
                let t = k as f64;
                let inside = Vector3::new(
                    (t * 0.6180339887).fract() * l.x,
                    (t * 0.4142135623).fract() * l.y,
                    (t * 0.7320508075).fract() * l.z,
                );
                inside + Vector3::new(l.x * ((k % 3) as f64 - 1.0), 0.0, -l.z * ((k % 2) as f64))
            })
            .collect()
    }

    /// The cell scan finds exactly the images of the direct image loop, rows
    /// ascending in `j`, for a large box (27 cells, one image per pair), a
    /// sparse box (cells capped, wider than the cutoff), a box smaller than
    /// the cutoff (many images, self images) and a slab (one thin axis).
    #[test]
    fn image_grid_matches_the_direct_image_loop() {
        for (box_lengths, cutoff, count, least_pairs) in [
            (Vector3::new(7.0, 8.5, 9.3), 2.3, 300, 1000),
            (Vector3::new(20.0, 21.0, 19.0), 2.0, 300, 100),
            (Vector3::new(1.3, 1.7, 1.1), 2.9, 6, 500),
            (Vector3::new(9.0, 8.0, 0.7), 1.9, 120, 1000),
        ] {
            let sites = scatter(count, &box_lengths);
            let table = PairTable::build(&sites, Some((box_lengths, cutoff))).unwrap();
            let found = table_entries(&table);
            assert!(found
                .windows(2)
                .all(|w| (w[0].0, w[0].1) <= (w[1].0, w[1].1)));
            let mut found_sorted = found.clone();
            found_sorted.sort_unstable();
            let mut expected = image_loop(&sites, &box_lengths, cutoff);
            expected.sort_unstable();
            assert!(expected.len() > least_pairs, "{}", expected.len());
            assert_eq!(found_sorted, expected, "box {box_lengths:?}");
        }
    }

    /// A cutoff far beyond the box is refused by the estimated size of the
    /// sum, before any pair is built (not by running out of memory).
    #[test]
    fn huge_cutoffs_are_refused_before_building() {
        let boundary = crate::potential::Boundary::periodic_cutoff(Vector3::repeat(1.0), 1e4);
        let e = boundary.validate(1).unwrap_err();
        assert_eq!(e.path, "cutoff");
        assert!(e.message.contains("more than the limit"), "{e}");
    }

    /// The open rows computed on the fly hold exactly the partners and
    /// geometries (bit for bit) of the stored open table, and the same
    /// blocks; coincident sites are found by the grid as the table finds
    /// them (the first pair in row order).
    #[test]
    fn open_rows_are_the_stored_table_bit_for_bit() {
        let sites = scatter(60, &Vector3::new(3.0, 4.0, 5.0));
        let table = PairTable::build(&sites, None).unwrap();
        let open = OpenPairs::new(&sites).unwrap();
        assert_eq!(open.starts(), &table.start[..]);
        let (mut none, mut scratch) = ((), Vec::new());
        for i in 0..sites.len() {
            let (pt, gt, geometry_t) = table.row(i, &mut none);
            let (po, go, geometry_o) = open.row(i, &mut scratch);
            assert_eq!(pt, po);
            for (a, b) in gt.iter().zip(go) {
                let (a, b) = (&geometry_t[*a as usize], &geometry_o[*b as usize]);
                assert_eq!(a.dipole_tensor, b.dipole_tensor);
                assert_eq!((a.unit, a.inv_r), (b.unit, b.inv_r));
            }
        }
        let mut clash = sites.clone();
        clash[41] = clash[7] + Vector3::new(0.0, 4e-10, 0.0);
        clash[50] = clash[3];
        let by_table = PairTable::build(&clash, None).unwrap_err();
        let by_grid = OpenPairs::new(&clash).unwrap_err();
        assert_eq!(by_grid, by_table);
        assert_eq!(by_grid.path, "rotors[3].site and rotors[50].site");
    }

    /// The blocks cover the rows in order, and each holds the pairs of its
    /// share of the total to within one row: rows of 1 to 40 pairs (and
    /// empty ones) in 1 to 7 blocks, more blocks than rows, no rows.
    #[test]
    fn blocks_split_the_pairs_evenly() {
        let counts: Vec<usize> = (0..50)
            .map(|i| (i * 37 % 41) * (i % 5 != 2) as usize)
            .collect();
        let mut start = vec![0];
        for c in &counts {
            start.push(start.last().unwrap() + c);
        }
        let (total, longest) = (start[50], *counts.iter().max().unwrap());
        for blocks in 1..=7 {
            let ranges = balanced_blocks(&start, blocks);
            assert_eq!(ranges.len(), blocks);
            assert_eq!((ranges[0].start, ranges[blocks - 1].end), (0, 50));
            for (b, r) in ranges.iter().enumerate() {
                if b > 0 {
                    assert_eq!(r.start, ranges[b - 1].end);
                }
                // The pairs before the block's end are its share, to a row.
                let share = total * (b + 1) / blocks;
                assert!(
                    start[r.end] >= share && start[r.end] < share + longest.max(1),
                    "{blocks} blocks: {b}: {r:?}"
                );
            }
        }
        let few = balanced_blocks(&[0, 3, 5], 4);
        assert_eq!(few, vec![0..1, 1..2]);
        assert_eq!(balanced_blocks(&[0], 3), vec![0..0]);
    }

    /// The grid finds the coincident pair the full table finds (the first
    /// in row order), whichever of the 26 neighbouring cells (of width
    /// `COINCIDENT`) holds the later site; of three coincident sites, the
    /// pair of the first two.
    #[test]
    fn coincident_sites_are_found_in_every_neighbouring_cell() {
        let spread = scatter(30, &Vector3::new(3.0, 4.0, 5.0));
        for d in 0..27 {
            let dir = Vector3::new(
                (d / 9) as f64 - 1.0,
                ((d / 3) % 3) as f64 - 1.0,
                (d % 3) as f64 - 1.0,
            );
            if dir == Vector3::zeros() {
                continue;
            }
            // Near the face (or the middle) of cell 3 that `dir` points through.
            let base = dir.map(|x| (3.5 + 0.49 * x) * COINCIDENT);
            let mut sites = spread.clone();
            sites[6] = base;
            sites[21] = base + dir.normalize() * (0.6 * COINCIDENT);
            let cell = |s: &Vector3<f64>| s.map(|x| (x / COINCIDENT).floor());
            assert_eq!(cell(&sites[21]) - cell(&sites[6]), dir);
            let by_table = PairTable::build(&sites, None).unwrap_err();
            assert_eq!(by_table.path, "rotors[6].site and rotors[21].site");
            assert_eq!(OpenPairs::new(&sites).unwrap_err(), by_table, "{dir:?}");
        }
        // The later site in site 5's own cell, scanned before the earlier
        // one in the next cell along z.
        let mut three = spread.clone();
        three[5] = Vector3::new(3.5, 3.5, 3.9) * COINCIDENT;
        three[20] = three[5];
        three[11] = three[5] + Vector3::new(0.0, 0.0, 0.5 * COINCIDENT);
        let by_table = PairTable::build(&three, None).unwrap_err();
        assert_eq!(by_table.path, "rotors[5].site and rotors[11].site");
        assert_eq!(OpenPairs::new(&three).unwrap_err(), by_table);
    }
}
