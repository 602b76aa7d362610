//! The cell grid of a neighbour-list build: cells at least the list's
//! reach wide, the sites sorted by cell with their positions wrapped into
//! a periodic box stored by component (each cell's sites contiguous), and
//! the scan of the 27 cells around a site for the sites within reach.
//!
//! In a periodic box a neighbouring cell across a face is the cell at the
//! other end, shifted by a box length: the scan compares a site with the
//! wrapped positions of that cell's sites and that shift, so no separation
//! is rounded to its minimum image. With the box at least twice the reach
//! wide ([`Space::check`]) at most one image of a pair is within reach,
//! also where two or three cells across the box make neighbours repeat.

use super::space::Space;
use crate::lanes::LANES;
use nalgebra::Vector3;

/// Open space: at most this many cells per site (plus 27).
pub const CELLS_PER_SITE: usize = 8;
/// Sites of a cell compared at once (their squared distances on the stack,
/// those within reach as the bits of a `u64`).
const RUN: usize = 64;

/// The cells next to one (itself included) with their shifts, and how
/// many of the array's are ([`Cells::neighbours`]).
type Neighbours = ([(usize, [i8; 3]); 27], usize);

/// The cells next to a site's cell ([`Cells::near`]) with, in each, the
/// first slot whose site is above the last site scanned from them: sites of
/// one cell scanned in ascending order ([`Cells::scan_above`]) start where
/// the last left off, a few slots on at most, instead of searching the run.
pub(super) struct Near {
    /// The cell whose neighbours these are.
    pub cell: usize,
    cells: Neighbours,
    above: [usize; 27],
}

/// A grid of cells over the sites.
pub(super) struct Cells {
    counts: [usize; 3],
    /// Sites of cell `c` are the slots `first[c]..first[c + 1]`.
    first: Vec<usize>,
    /// Per slot: the site, and its wrapped position by component.
    site: Vec<u32>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    /// Per site: its cell, and the box lengths its wrapping took off.
    cell_of: Vec<usize>,
    wraps: Vec<[i32; 3]>,
    /// The box lengths (zero in open space).
    lengths: Vector3<f64>,
    periodic: bool,
}

impl Cells {
    /// The grid of `sites` in `space` for pairs within `reach`, holding
    /// the sites `listed` (all for `None`; the others are found by no scan).
    pub fn new(
        sites: &[Vector3<f64>],
        listed: Option<&[bool]>,
        space: &Space,
        reach: f64,
    ) -> Cells {
        let (origin, width, counts, lengths) = match space {
            Space::Periodic(l) => {
                let counts = [0, 1, 2].map(|k| ((l[k] / reach).floor() as usize).max(1));
                let width = Vector3::from_fn(|k, _| l[k] / counts[k] as f64);
                (Vector3::zeros(), width, counts, *l)
            }
            Space::Open => {
                let (lo, hi) = sites.iter().fold(
                    (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                    |(lo, hi), x| (lo.inf(x), hi.sup(x)),
                );
                let extent = (hi - lo).sup(&Vector3::zeros());
                let limit = 27 + CELLS_PER_SITE * sites.len();
                let mut size = reach;
                let count = |size: f64| [0, 1, 2].map(|k| (extent[k] / size) as usize + 1);
                while count(size).iter().product::<usize>() > limit {
                    size *= 1.5;
                }
                (lo, Vector3::repeat(size), count(size), Vector3::zeros())
            }
        };
        let periodic = matches!(space, Space::Periodic(_));
        let mut wrapped = Vec::with_capacity(sites.len());
        let mut wraps = Vec::with_capacity(sites.len());
        let mut cell_of = Vec::with_capacity(sites.len());
        for x in sites {
            let (mut w, mut a, mut c) = (*x, [0; 3], [0; 3]);
            for k in 0..3 {
                if periodic {
                    let shift = (x[k] / lengths[k]).floor();
                    w[k] = x[k] - shift * lengths[k];
                    a[k] = shift as i32;
                }
                let u = (w[k] - origin[k]) / width[k];
                c[k] = (u.max(0.0) as usize).min(counts[k] - 1);
            }
            wrapped.push(w);
            wraps.push(a);
            cell_of.push((c[0] * counts[1] + c[1]) * counts[2] + c[2]);
        }
        let (first, site) = sort_by_cell(&cell_of, listed, counts.iter().product());
        // Each component padded with `LANES - 1` NaNs, so that a run's last
        // lanes load in bounds (their distances compare false, and are
        // masked off anyway).
        let component = |k: usize| {
            let wrapped = site.iter().map(|&i| wrapped[i as usize][k]);
            wrapped.chain([f64::NAN; LANES - 1]).collect()
        };
        Cells {
            counts,
            x: component(0),
            y: component(1),
            z: component(2),
            first,
            site,
            cell_of,
            wraps,
            lengths,
            periodic,
        }
    }

    /// The number of cells.
    #[cfg(test)]
    pub fn cells(&self) -> usize {
        self.first.len() - 1
    }

    /// The cell of site `i`.
    pub fn cell_of(&self, i: usize) -> usize {
        self.cell_of[i]
    }

    /// The cells next to cell `c` (itself included) with the box lengths
    /// each is shifted by across the faces: the first `count` of the array,
    /// the first axis slowest.
    fn neighbours(&self, c: usize) -> Neighbours {
        let [_, ny, nz] = self.counts;
        let own = [c / (ny * nz), (c / nz) % ny, c % nz];
        // Along each axis, the cells one below, at and one above the own
        // (those inside) with their shifts.
        let along = |k: usize| {
            let n = self.counts[k] as i64;
            let (mut out, mut count) = ([(0, 0i8); 3], 0);
            for step in -1..=1 {
                let u = own[k] as i64 + step;
                if self.periodic {
                    // `u` is within one cell of `0..n`.
                    let wrap = i64::from(u >= n) - i64::from(u < 0);
                    out[count] = ((u - wrap * n) as usize, wrap as i8);
                    count += 1;
                } else if (0..n).contains(&u) {
                    out[count] = (u as usize, 0);
                    count += 1;
                }
            }
            (out, count)
        };
        let ((xs, cx), (ys, cy), (zs, cz)) = (along(0), along(1), along(2));
        let (mut out, mut count) = ([(0, [0; 3]); 27], 0);
        for &(a, sa) in &xs[..cx] {
            for &(b, sb) in &ys[..cy] {
                for &(d, sd) in &zs[..cz] {
                    out[count] = ((a * ny + b) * nz + d, [sa, sb, sd]);
                    count += 1;
                }
            }
        }
        (out, count)
    }

    /// The neighbours of cell `c` seen from site `i` of it, each cell's
    /// run searched once for its first site above `i`.
    pub fn near(&self, c: usize, i: usize) -> Near {
        let cells = self.neighbours(c);
        let mut above = [0; 27];
        for (above, &(c, _)) in above.iter_mut().zip(&cells.0[..cells.1]) {
            let run = &self.site[self.first[c]..self.first[c + 1]];
            *above = self.first[c] + run.partition_point(|&j| j as usize <= i);
        }
        Near {
            cell: c,
            cells,
            above,
        }
    }

    /// Bit `k` set for each slot `slots.start + k` (at most [`RUN`] slots)
    /// whose squared distance from `p` is below `reach2`: four slots at a
    /// time on CPUs with AVX2 (the same squares, rounded alike: no fused
    /// multiply-add), one by one elsewhere.
    #[inline(always)]
    fn within_bits(&self, p: &Vector3<f64>, slots: std::ops::Range<usize>, reach2: f64) -> u64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            return unsafe { self.within_bits_avx2(p, slots, reach2) };
        }
        self.within_bits_one_by_one(p, slots, reach2)
    }

    /// [`Cells::within_bits`] one slot at a time (CPUs without AVX2).
    fn within_bits_one_by_one(
        &self,
        p: &Vector3<f64>,
        slots: std::ops::Range<usize>,
        reach2: f64,
    ) -> u64 {
        let mut within = 0u64;
        for (k, s) in slots.enumerate() {
            let d = [p.x - self.x[s], p.y - self.y[s], p.z - self.z[s]];
            within |= u64::from(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach2) << k;
        }
        within
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn within_bits_avx2(
        &self,
        p: &Vector3<f64>,
        slots: std::ops::Range<usize>,
        reach2: f64,
    ) -> u64 {
        use std::arch::x86_64::*;
        let n = slots.len();
        // The components hold `LANES - 1` slots of padding past the last,
        // so the last load ends within them.
        let len = self.x.len().min(self.y.len()).min(self.z.len());
        assert!(
            n <= RUN && slots.start + n.next_multiple_of(LANES) <= len,
            "slots out of bounds"
        );
        let [px, py, pz] = [p.x, p.y, p.z].map(|c| _mm256_set1_pd(c));
        let reach2 = _mm256_set1_pd(reach2);
        let mut within = 0u64;
        for k in (0..n).step_by(LANES) {
            let at = slots.start + k;
            // SAFETY: four slots from `at` are within the padded components
            // (asserted above).
            let [x, y, z] =
                [&self.x, &self.y, &self.z].map(|c| unsafe { _mm256_loadu_pd(c.as_ptr().add(at)) });
            let (dx, dy, dz) = (
                _mm256_sub_pd(px, x),
                _mm256_sub_pd(py, y),
                _mm256_sub_pd(pz, z),
            );
            let d2 = _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                _mm256_mul_pd(dz, dz),
            );
            let bits = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(d2, reach2)) as u64;
            within |= bits << k;
        }
        // Only the run's slots (the last lanes may be the next cell's).
        within & u64::MAX.checked_shr((RUN - n) as u32).unwrap_or(0)
    }

    /// Calls `found(j, counts)` for every site `j > i` within `reach2 =
    /// reach^2` of site `i` (at `x`; `near` the neighbours of its cell,
    /// from [`Cells::near`] for a site of the cell not above `i`, and
    /// since then scanned for sites of the cell below `i` only, in
    /// ascending order) that `wanted(j)` accepts, `counts` the box lengths
    /// between `x_i - x_j` and that separation's minimum image. A cell's
    /// sites are in ascending order: those above `i` are the end of its run.
    #[inline(always)]
    pub fn scan_above(
        &self,
        (i, x): (usize, &Vector3<f64>),
        near: &mut Near,
        reach2: f64,
        wanted: impl Fn(usize) -> bool,
        mut found: impl FnMut(u32, [i8; 3]),
    ) {
        let a = self.wraps[i];
        let w = x - Vector3::from_fn(|k, _| f64::from(a[k]) * self.lengths[k]);
        let (cells, count) = &near.cells;
        for (&(c, shift), above) in cells[..*count].iter().zip(&mut near.above) {
            // `w` seen from the cell's image: `x_i - x_j - L shift` is `p - w_j`.
            let p = w - Vector3::from_fn(|k, _| f64::from(shift[k]) * self.lengths[k]);
            // The first site above `i`: at or after the first above the
            // last site scanned (not above `i`).
            let end = self.first[c + 1];
            while *above < end && self.site[*above] as usize <= i {
                *above += 1;
            }
            let mut start = *above;
            while start < end {
                let stop = (start + RUN).min(end);
                // The sites within reach as bits (no branch per site: most
                // are beyond reach), then those sites in order.
                let mut within = self.within_bits(&p, start..stop, reach2);
                let slots = &self.site[start..stop];
                while within != 0 {
                    let j = slots[within.trailing_zeros() as usize];
                    within &= within - 1;
                    if wanted(j as usize) {
                        let b = self.wraps[j as usize];
                        found(
                            j,
                            [0, 1, 2].map(|k| (i32::from(shift[k]) + a[k] - b[k]) as i8),
                        );
                    }
                }
                start = stop;
            }
        }
    }
}

/// The listed sites (all for `None`) sorted by their cells `cell_of`
/// (`total` cells), in ascending order within each: where each cell's run
/// starts (and the end, `first[total]`), and the runs' sites.
fn sort_by_cell(
    cell_of: &[usize],
    listed: Option<&[bool]>,
    total: usize,
) -> (Vec<usize>, Vec<u32>) {
    let is_listed = |i: usize| listed.is_none_or(|l| l[i]);
    let mut first = vec![0; total + 1];
    for (i, &c) in cell_of.iter().enumerate() {
        first[c + 1] += usize::from(is_listed(i));
    }
    for c in 0..total {
        first[c + 1] += first[c];
    }
    let mut fill = first.clone();
    let mut site = vec![0; first[total]];
    for (i, &c) in cell_of.iter().enumerate().filter(|&(i, _)| is_listed(i)) {
        site[fill[c]] = i as u32;
        fill[c] += 1;
    }
    (first, site)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// Scanning the sites in ascending order with each cell's cursors
    /// carried from the last site of the same cell (as a build does) finds
    /// the partners, in the same order, that a fresh search of every run for
    /// each site finds: rigid three-site molecules (so that consecutive
    /// sites share cells) in periodic boxes of 2 to 5 cells per edge, and in
    /// open space.
    #[test]
    fn carried_cursors_find_what_fresh_searches_find() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(44);
        for (lengths, molecules, reach) in [(6.0, 60, 2.9), (13.0, 250, 2.6), (9.5, 120, 4.0)] {
            let lengths = Vector3::repeat(lengths);
            let mut sites = Vec::new();
            for _ in 0..molecules {
                let centre = Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k]);
                for _ in 0..3 {
                    sites.push(centre + Vector3::from_fn(|_, _| rng.random_range(-0.6..0.6)));
                }
            }
            for space in [Space::Periodic(lengths), Space::Open] {
                let cells = Cells::new(&sites, None, &space, reach);
                let scan = |i: usize, near: &mut Near| {
                    let mut found = Vec::new();
                    cells.scan_above(
                        (i, &sites[i]),
                        near,
                        reach * reach,
                        |j| j / 3 != i / 3,
                        |j, c| found.push((j, c)),
                    );
                    found
                };
                let mut carried: Option<Near> = None;
                let mut pairs = 0;
                for i in 0..sites.len() {
                    let cell = cells.cell_of(i);
                    let near = match &mut carried {
                        Some(n) if n.cell == cell => n,
                        _ => carried.insert(cells.near(cell, i)),
                    };
                    let found = scan(i, near);
                    assert_eq!(
                        found,
                        scan(i, &mut cells.near(cell, i)),
                        "site {i} in {space:?}"
                    );
                    pairs += found.len();
                }
                assert!(
                    pairs > 5 * sites.len(),
                    "{pairs} pairs of {} sites",
                    sites.len()
                );
            }
        }
    }

    /// The bits of the sites within reach are those of a plain loop over
    /// the slots, four at a time (on CPUs with AVX2) and one by one (the
    /// path of CPUs without it), for runs of every
    /// length from 1 to `RUN` starting anywhere, the last slots included
    /// (whose lanes load the padding), and none beyond the run.
    #[test]
    fn within_bits_are_those_of_a_plain_loop() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let lengths = Vector3::new(9.0, 9.0, 9.0);
        let sites: Vec<Vector3<f64>> = (0..150)
            .map(|_| Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k]))
            .collect();
        let cells = Cells::new(&sites, None, &Space::Periodic(lengths), 4.5);
        let n = sites.len();
        for _ in 0..400 {
            let p = Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k]);
            let len = rng.random_range(1..=RUN.min(n));
            let start = if rng.random::<bool>() {
                n - len
            } else {
                rng.random_range(0..=n - len)
            };
            let reach2 = rng.random_range(1.0..30.0);
            let mut expected = 0u64;
            for k in 0..len {
                let s = start + k;
                let d = p - Vector3::new(cells.x[s], cells.y[s], cells.z[s]);
                expected |= u64::from(d.x * d.x + d.y * d.y + d.z * d.z < reach2) << k;
            }
            let slots = start..start + len;
            assert_eq!(cells.within_bits(&p, slots.clone(), reach2), expected);
            assert_eq!(cells.within_bits_one_by_one(&p, slots, reach2), expected);
        }
    }
}
