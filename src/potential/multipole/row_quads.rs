//! Dipole fields of translation-symmetric systems (periodic lattices), four
//! rows at a time, without scattered loads or stores.
//!
//! Each pair of the half list is entered in both of its rows (a self pair
//! `(i, i)` twice, once per image, as its derivative requires), and every row
//! is sorted by the pair offset `r_j - r_i`. On a lattice, rows `4b .. 4b + 3`
//! then see, slot by slot, the same offset (the same dipole tensor `T`, which
//! is even in the offset) and partners `j, j + 1, j + 2, j + 3` wherever the
//! offset does not wrap across the box, so one slot is three four-lane loads
//! of the dipoles (kept as separate x, y and z arrays) and nine multiply-adds
//! into the four rows' fields, which stay in registers for the whole quad
//! (the rows of a quad are merged by offset: a row lacking an offset of the
//! others misses that slot).
//! A slot whose four partners are not consecutive reads a *ghost* copy: the
//! extended dipole arrays hold, after the `n` rotors, copies of the partner
//! quadruples that occur out of order (each distinct quadruple once, sharing
//! entries with the previous quadruple where they overlap), refreshed at
//! every evaluation; a missing entry reads a zero dipole.
//!
//! Each row's field is its own sum in a fixed order, so the result does not
//! depend on how the quads are split among threads; it differs from the half
//! list kernel by rounding only (summation order).
//!
//! Selection rule: [`RowQuads::build`] returns the table only when every
//! slot's rows share one tensor and the ghost entries plus the padded lanes
//! are at most [`MAX_OVERHEAD`] of the directed pairs (the 10^3 simple-cubic
//! lattice with cutoff 3.1 needs 2.4 %); otherwise the half list kernel
//! serves (irregular sites mix tensors within slots at once).

use super::kernels::{Lanes, MulAdd};
use super::pairs::PairTable;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// Entries per rayon task when the dipoles are copied into component
/// arrays: a copy costs a few nanoseconds, so the 1000-rotor lattice stays
/// on one thread and larger ones split.
const ENTRIES_PER_TASK: usize = 2048;

/// Largest overhead (ghost entries plus padded lanes, as a fraction of the
/// directed pairs) for which the quad kernel is used.
pub(crate) const MAX_OVERHEAD: f64 = 0.125;

/// Ghost source of a missing entry: a zero dipole.
const NO_ROTOR: u32 = u32::MAX;

/// Offsets closer than this fraction of the shortest pair distance sort as
/// equal within a row (only the speed depends on it, not the result; a
/// fraction, so that the table is the same in any length unit).
const OFFSET_KEY_RESOLUTION: f64 = 1e-6;

/// The six entries of a symmetric dipole tensor (aligned so that none
/// straddles two cache lines).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
struct SymmetricTensor {
    xx: f64,
    yy: f64,
    zz: f64,
    xy: f64,
    xz: f64,
    yz: f64,
}

impl SymmetricTensor {
    /// Bit pattern identifying the tensor (`-0.0` and `0.0` are one value).
    fn key(&self) -> [u64; 6] {
        [self.xx, self.yy, self.zz, self.xy, self.xz, self.yz].map(|v| (v + 0.0).to_bits())
    }
}

/// One slot of a quad: the tensor shared by its four rows and the first of
/// four consecutive entries of the extended dipole arrays.
#[derive(Clone, Copy, Debug)]
struct Slot {
    tensor: u32,
    partner: u32,
}

/// The directed pairs regrouped in quads of rows (see the module doc).
#[derive(Clone, Debug)]
pub(crate) struct RowQuads {
    rotors: usize,
    /// Slots of quad `b` are `start[b]..start[b + 1]`.
    start: Vec<usize>,
    slots: Vec<Slot>,
    /// Distinct tensors; the last one is zero (padding).
    tensors: Vec<SymmetricTensor>,
    /// Rotor copied into each extended entry after the first `rotors`
    /// ([`NO_ROTOR`]: a zero dipole).
    ghosts: Vec<u32>,
}

/// A directed pair as a row holds it: the key of its offset, its partner
/// and its tensor's index.
type DirectedRow = ([i64; 3], u32, u32);

/// The distinct dipole tensors of the pair geometries (equal bit patterns
/// shared) and the index of each geometry's tensor among them.
fn distinct_tensors(pairs: &PairTable) -> (Vec<u32>, Vec<SymmetricTensor>) {
    let mut tensor_index = Vec::with_capacity(pairs.geometry.len());
    let mut tensors: Vec<SymmetricTensor> = Vec::new();
    let mut by_key: FxHashMap<[u64; 6], u32> = FxHashMap::default();
    for g in &pairs.geometry {
        let t = &g.dipole_tensor;
        let s = SymmetricTensor {
            xx: t[0][0],
            yy: t[1][1],
            zz: t[2][2],
            xy: t[0][1],
            xz: t[0][2],
            yz: t[1][2],
        };
        let next = tensors.len() as u32;
        let index = *by_key.entry(s.key()).or_insert(next);
        if index == next {
            tensors.push(s);
        }
        tensor_index.push(index);
    }
    (tensor_index, tensors)
}

/// The directed rows of every rotor (each pair seen from both ends), each
/// sorted by offset: row `i` is `entries[start[i]..start[i + 1]]`.
struct DirectedRows {
    start: Vec<usize>,
    entries: Vec<DirectedRow>,
}

impl DirectedRows {
    fn new(pairs: &PairTable, tensor_index: &[u32]) -> Self {
        let rotors = pairs.start.len() - 1;
        let resolution =
            OFFSET_KEY_RESOLUTION / pairs.geometry.iter().fold(0.0, |m: f64, g| m.max(g.inv_r));
        // The key of each distinct offset, once (a pair's key is its offset's).
        let keys: Vec<[i64; 3]> = pairs
            .geometry
            .iter()
            .map(|geometry| {
                let offset = geometry.unit / (geometry.inv_r * resolution);
                offset.map(|x| x.round() as i64).into()
            })
            .collect();
        // Each row's length (its pairs from both ends), then their starts.
        let mut start = vec![0; rotors + 1];
        for (i, row) in pairs.start.windows(2).enumerate() {
            start[i + 1] += row[1] - row[0];
            for &j in &pairs.partner[row[0]..row[1]] {
                start[j as usize + 1] += 1;
            }
        }
        for i in 0..rotors {
            start[i + 1] += start[i];
        }
        let mut entries = vec![([0; 3], 0, 0); start[rotors]];
        let mut next = start[..rotors].to_vec();
        for (i, row) in pairs.start.windows(2).enumerate() {
            for p in row[0]..row[1] {
                let j = pairs.partner[p] as usize;
                let g = pairs.geometry_index[p] as usize;
                let key = keys[g];
                // One after the other: a self pair enters its row twice.
                entries[next[i]] = (key, j as u32, tensor_index[g]);
                next[i] += 1;
                entries[next[j]] = (key.map(|x| -x), i as u32, tensor_index[g]);
                next[j] += 1;
            }
        }
        // Each row sorted on its own: the same rows on any number of threads.
        let mut rows = Vec::with_capacity(rotors);
        let mut rest = &mut entries[..];
        for row in start.windows(2) {
            let (sorted, tail) = rest.split_at_mut(row[1] - row[0]);
            rows.push(sorted);
            rest = tail;
        }
        rows.into_par_iter().for_each(|row| row.sort_unstable());
        DirectedRows { start, entries }
    }

    /// Row `i`, empty past the last rotor.
    fn row(&self, i: usize) -> &[DirectedRow] {
        match self.start.get(i..i + 2) {
            Some(&[first, end]) => &self.entries[first..end],
            _ => &[],
        }
    }
}

/// The dipoles as separate component arrays, extended with the ghost copies
/// and with three trailing zeros (so four lanes from any entry are in bounds).
pub(crate) struct ExtendedDipoles {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
}

impl RowQuads {
    /// Regroups `pairs` into quads, or `None` when a slot would mix tensors
    /// or the extra lanes exceed [`MAX_OVERHEAD`] (the selection rule above).
    pub fn build(pairs: &PairTable) -> Option<Self> {
        let rotors = pairs.start.len() - 1;
        let directed = 2 * pairs.len();
        if rotors == 0 || directed == 0 {
            return None;
        }
        let (tensor_index, mut tensors) = distinct_tensors(pairs);
        let zero = tensors.len() as u32;
        tensors.push(SymmetricTensor::default());

        let rows = DirectedRows::new(pairs, &tensor_index);

        let quads = rotors.div_ceil(4);
        let mut table = RowQuads {
            rotors,
            start: Vec::with_capacity(quads + 1),
            slots: Vec::new(),
            tensors,
            ghosts: Vec::new(),
        };
        table.start.push(0);
        let mut placed: FxHashMap<[u32; 4], u32> = FxHashMap::default();
        let mut padded = 0;
        for b in 0..quads {
            let lanes: Vec<&[DirectedRow]> = (4 * b..4 * b + 4).map(|i| rows.row(i)).collect();
            // Merge the four rows by offset: a row lacking the offset misses the slot.
            let mut next = [0usize; 4];
            while let Some(key) = (0..4)
                .filter_map(|l| lanes[l].get(next[l]))
                .map(|e| e.0)
                .min()
            {
                let entries: [(u32, u32); 4] =
                    std::array::from_fn(|l| match lanes[l].get(next[l]) {
                        Some(e) if e.0 == key => {
                            next[l] += 1;
                            (e.1, e.2)
                        }
                        _ => (NO_ROTOR, zero),
                    });
                let missing = entries.iter().filter(|e| e.1 == zero).count();
                padded += missing;
                let tensor = entries
                    .iter()
                    .map(|e| e.1)
                    .find(|&t| t != zero)
                    .unwrap_or(zero);
                if entries.iter().any(|e| e.1 != tensor && e.1 != zero) {
                    // Different tensors within one slot: no shared broadcast.
                    return None;
                }
                let partners = entries.map(|e| e.0);
                let consecutive =
                    missing == 0 && (1..4).all(|l| partners[l] == partners[0] + l as u32);
                let partner = if consecutive {
                    partners[0]
                } else {
                    *placed
                        .entry(partners)
                        .or_insert_with(|| table.place_ghost(&partners))
                };
                table.slots.push(Slot { tensor, partner });
            }
            table.start.push(table.slots.len());
        }
        let overhead = (table.ghosts.len() + padded) as f64 / directed as f64;
        (overhead <= MAX_OVERHEAD).then_some(table)
    }

    /// Appends `partners` to the ghost entries (reusing the longest tail of
    /// the current ghosts that starts the quadruple); returns its first entry.
    fn place_ghost(&mut self, partners: &[u32; 4]) -> u32 {
        let ghosts = &self.ghosts;
        let shared = (1..4)
            .rev()
            .find(|&k| ghosts.len() >= k && ghosts[ghosts.len() - k..] == partners[..k])
            .unwrap_or(0);
        let first = self.rotors + ghosts.len() - shared;
        self.ghosts.extend_from_slice(&partners[shared..]);
        first as u32
    }

    /// Number of quads of rows.
    pub fn quads(&self) -> usize {
        self.start.len() - 1
    }

    /// The dipoles in component arrays, with the ghost copies (the three
    /// entries after them stay zero), in parallel chunks of
    /// [`ENTRIES_PER_TASK`] entries.
    pub fn extend(&self, dipoles: &[Lanes]) -> ExtendedDipoles {
        let len = self.rotors + self.ghosts.len() + 3;
        let (mut x, mut y, mut z) = (vec![0.0; len], vec![0.0; len], vec![0.0; len]);
        let zero = Lanes::default();
        let source = |k: usize| match dipoles.get(k) {
            Some(mu) => Some(mu),
            None => self
                .ghosts
                .get(k - dipoles.len())
                .map(|&j| dipoles.get(j as usize).unwrap_or(&zero)),
        };
        x.par_chunks_mut(ENTRIES_PER_TASK)
            .zip(y.par_chunks_mut(ENTRIES_PER_TASK))
            .zip(z.par_chunks_mut(ENTRIES_PER_TASK))
            .enumerate()
            .for_each(|(c, ((x, y), z))| {
                let entries = x.iter_mut().zip(y).zip(z).enumerate();
                for (k, ((x, y), z)) in entries {
                    if let Some(mu) = source(c * ENTRIES_PER_TASK + k) {
                        (*x, *y, *z) = (mu[0], mu[1], mu[2]);
                    }
                }
            });
        ExtendedDipoles { x, y, z }
    }

    /// Writes the pair field of the rows of quads `first_quad ..` into
    /// `field` (four rows per quad, `field[0]` being row `4 first_quad`;
    /// `field` may end within the last quad). Dispatches once to a build for
    /// AVX and FMA when the CPU has them.
    pub fn fields(&self, dipoles: &ExtendedDipoles, first_quad: usize, field: &mut [Lanes]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX and FMA, checked just above.
            unsafe { self.fields_avx_fma(dipoles, first_quad, field) };
            return;
        }
        self.fields_with::<super::kernels::Separate>(dipoles, first_quad, field);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,fma")]
    fn fields_avx_fma(&self, dipoles: &ExtendedDipoles, first_quad: usize, field: &mut [Lanes]) {
        for (b, rows) in (first_quad..).zip(field.chunks_mut(4)) {
            let slots = &self.slots[self.start[b]..self.start[b + 1]];
            let sum = self.quad_avx_fma(dipoles, slots);
            for (l, row) in rows.iter_mut().enumerate() {
                *row = Lanes([sum[0][l], sum[1][l], sum[2][l], 0.0]);
            }
        }
    }

    /// [`Self::quad`] in AVX and FMA instructions (the same operations in the
    /// same order as its fused build; the compiler did not vectorise that one
    /// well: twice slower).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,fma")]
    fn quad_avx_fma(&self, dipoles: &ExtendedDipoles, slots: &[Slot]) -> [[f64; 4]; 3] {
        use std::arch::x86_64::*;
        let len = dipoles.x.len();
        let (x, y, z) = (dipoles.x.as_ptr(), dipoles.y.as_ptr(), dipoles.z.as_ptr());
        let add = |sum: &mut [__m256d; 3], slot: &Slot| {
            let t = &self.tensors[slot.tensor as usize];
            let j = slot.partner as usize;
            assert!(j + 4 <= len);
            // SAFETY: lanes j..j + 4 of the three arrays (all `len` long) are in bounds.
            let (mx, my, mz) = unsafe {
                (
                    _mm256_loadu_pd(x.add(j)),
                    _mm256_loadu_pd(y.add(j)),
                    _mm256_loadu_pd(z.add(j)),
                )
            };
            let row = |a: f64, b: f64, c: f64, s: __m256d| {
                let (a, b, c) = (_mm256_set1_pd(a), _mm256_set1_pd(b), _mm256_set1_pd(c));
                _mm256_fmadd_pd(c, mz, _mm256_fmadd_pd(b, my, _mm256_fmadd_pd(a, mx, s)))
            };
            sum[0] = row(t.xx, t.xy, t.xz, sum[0]);
            sum[1] = row(t.xy, t.yy, t.yz, sum[1]);
            sum[2] = row(t.xz, t.yz, t.zz, sum[2]);
        };
        let zero = _mm256_setzero_pd();
        let [mut s0, mut s1, mut s2, mut s3] = [[zero; 3]; 4];
        let chunks = slots.chunks_exact(4);
        let rest = chunks.remainder();
        for four in chunks {
            add(&mut s0, &four[0]);
            add(&mut s1, &four[1]);
            add(&mut s2, &four[2]);
            add(&mut s3, &four[3]);
        }
        for slot in rest {
            add(&mut s0, slot);
        }
        std::array::from_fn(|c| {
            let total = _mm256_add_pd(_mm256_add_pd(s0[c], s1[c]), _mm256_add_pd(s2[c], s3[c]));
            let mut lanes = [0.0; 4];
            // SAFETY: `lanes` holds four f64.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), total) };
            lanes
        })
    }

    #[inline(always)]
    fn fields_with<M: MulAdd>(
        &self,
        dipoles: &ExtendedDipoles,
        first_quad: usize,
        field: &mut [Lanes],
    ) {
        for (b, rows) in (first_quad..).zip(field.chunks_mut(4)) {
            let sum = self.quad::<M>(dipoles, &self.slots[self.start[b]..self.start[b + 1]]);
            for (l, row) in rows.iter_mut().enumerate() {
                *row = Lanes([sum[0][l], sum[1][l], sum[2][l], 0.0]);
            }
        }
    }

    /// The fields `[x, y, z]` (four lanes: the quad's rows) of `slots`,
    /// accumulated in four interleaved sums so that consecutive slots do not
    /// wait on each other's multiply-adds.
    #[inline(always)]
    fn quad<M: MulAdd>(&self, dipoles: &ExtendedDipoles, slots: &[Slot]) -> [[f64; 4]; 3] {
        let mut sums = [[[0.0; 4]; 3]; 4];
        let add = |sum: &mut [[f64; 4]; 3], slot: &Slot| {
            let t = &self.tensors[slot.tensor as usize];
            let j = slot.partner as usize;
            let (x, y, z) = (
                &dipoles.x[j..j + 4],
                &dipoles.y[j..j + 4],
                &dipoles.z[j..j + 4],
            );
            for l in 0..4 {
                let row = |a: f64, b: f64, c: f64, s: f64| {
                    M::mul_add(c, z[l], M::mul_add(b, y[l], M::mul_add(a, x[l], s)))
                };
                sum[0][l] = row(t.xx, t.xy, t.xz, sum[0][l]);
                sum[1][l] = row(t.xy, t.yy, t.yz, sum[1][l]);
                sum[2][l] = row(t.xz, t.yz, t.zz, sum[2][l]);
            }
        };
        let chunks = slots.chunks_exact(4);
        let rest = chunks.remainder();
        let [s0, s1, s2, s3] = &mut sums;
        for four in chunks {
            add(s0, &four[0]);
            add(s1, &four[1]);
            add(s2, &four[2]);
            add(s3, &four[3]);
        }
        for slot in rest {
            add(s0, slot);
        }
        std::array::from_fn(|c| {
            std::array::from_fn(|l| (s0[c][l] + s1[c][l]) + (s2[c][l] + s3[c][l]))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::potential::multipole::kernels::SpaceMultipoles;
    use crate::potential::multipole::kernels::{pair_fields, Dipoles, Separate, SiteFields};
    use nalgebra::Vector3;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha20Rng;

    /// The quad kernel sums each row in another order than the half list:
    /// relative differences of a few ulps times ~100 terms.
    const SUMMATION_ORDER: f64 = 1e-13;

    /// Sites of a simple-cubic lattice of `cells^3` sites, spacing 1, with
    /// the sites listed in `vacancies` left out.
    fn simple_cubic(cells: usize, vacancies: &[usize]) -> Vec<Vector3<f64>> {
        (0..cells.pow(3))
            .filter(|k| !vacancies.contains(k))
            .map(|k| {
                let c = |a: usize| ((k / cells.pow(a as u32)) % cells) as f64;
                Vector3::new(c(2), c(1), c(0))
            })
            .collect()
    }

    fn periodic(cells: usize, cutoff: f64) -> Option<(Vector3<f64>, f64)> {
        Some((Vector3::repeat(cells as f64), cutoff))
    }

    /// Unit dipoles in random directions.
    fn random_dipoles(n: usize, seed: u64) -> Vec<Lanes> {
        let mut rng = ChaCha20Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                let z: f64 = rng.random_range(-1.0..1.0);
                let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let s = (1.0 - z * z).sqrt();
                Lanes([s * phi.cos(), s * phi.sin(), z, 0.0])
            })
            .collect()
    }

    /// The quad kernel (dispatched build, and the portable build) gives the
    /// fields of the portable half list kernel; split into two calls at an
    /// odd quad, as two threads would.
    fn check_against_half_list(
        sites: &[Vector3<f64>],
        images: Option<(Vector3<f64>, f64)>,
    ) -> RowQuads {
        let pairs = PairTable::build(sites, images).unwrap();
        let quads = RowQuads::build(&pairs).expect("the quad kernel is selected");
        let n = sites.len();
        let multipoles = SpaceMultipoles {
            dipoles: random_dipoles(n, n as u64),
            quadrupoles: Vec::new(),
        };
        let mut reference = SiteFields::zeros::<Dipoles>(n);
        pair_fields::<Dipoles, Separate, _>(&pairs, 0..n, &multipoles, &mut reference);
        let scale = reference
            .field
            .iter()
            .flat_map(|e| e.iter())
            .fold(0.0, |m: f64, x| m.max(x.abs()));
        assert!(scale > 0.1);
        let extended = quads.extend(&multipoles.dipoles);
        let split = 4 * ((quads.quads() / 2) | 1).min(quads.quads() - 1);
        let mut dispatched = vec![Lanes::default(); n];
        let (head, tail) = dispatched.split_at_mut(split.min(n));
        quads.fields(&extended, 0, head);
        quads.fields(&extended, split / 4, tail);
        let mut portable = vec![Lanes::default(); n];
        quads.fields_with::<Separate>(&extended, 0, &mut portable);
        for got in [&dispatched, &portable] {
            for (i, (a, b)) in got.iter().zip(&reference.field).enumerate() {
                for k in 0..4 {
                    let error = (a[k] - b[k]).abs();
                    assert!(
                        error <= SUMMATION_ORDER * scale,
                        "rotor {i}: {a:?} vs {b:?}"
                    );
                }
            }
        }
        quads
    }

    /// The 10^3 simple-cubic lattice with cutoff 3.1 (the benchmark scene):
    /// selected, with few ghost entries.
    #[test]
    fn lattice_fields_match_the_half_list() {
        let quads = check_against_half_list(&simple_cubic(10, &[]), periodic(10, 3.1));
        assert!(quads.ghosts.len() < 3000, "{}", quads.ghosts.len());
    }

    /// A box of 2^3 cells with cutoff 3.1: every rotor meets its own images
    /// (self pairs counting both ends) and each partner many times.
    #[test]
    fn self_images_match_the_half_list() {
        let _ = check_against_half_list(&simple_cubic(2, &[]), periodic(2, 3.1));
    }

    /// A 10^3 lattice with two vacancies: rows of different lengths (missing
    /// entries), partners out of step (ghost quadruples) and a last quad with
    /// two rows (998 rotors).
    #[test]
    fn lattice_with_vacancies_matches_the_half_list() {
        let quads = check_against_half_list(&simple_cubic(10, &[17, 600]), periodic(10, 3.1));
        assert!(!quads.ghosts.is_empty());
        assert!(quads.ghosts.contains(&NO_ROTOR));
    }

    /// Irregular sites would need a ghost quadruple for nearly every slot (or
    /// mix tensors within one): the half list kernel serves.
    #[test]
    fn irregular_sites_keep_the_half_list() {
        let mut rng = ChaCha20Rng::seed_from_u64(3);
        let sites: Vec<_> = (0..64)
            .map(|_| Vector3::from_fn(|_, _| rng.random_range(0.0..4.0)))
            .collect();
        let pairs = PairTable::build(&sites, periodic(4, 1.9)).unwrap();
        assert!(pairs.len() > 100);
        assert!(RowQuads::build(&pairs).is_none());
    }

    /// The table is the same in any length unit: the 10^3 lattice with cutoff
    /// 1.5 (nearest and next-nearest neighbours) scaled by 1e-7 (a spacing
    /// below the old absolute key resolution of 1e-6, which merged every
    /// offset and lost the quad kernel) and 1e7 regroups its pairs slot for
    /// slot as at spacing 1, with the quad kernel selected.
    #[test]
    fn the_table_does_not_depend_on_the_length_unit() {
        let table = |scale: f64| {
            let sites: Vec<_> = simple_cubic(10, &[]).iter().map(|s| s * scale).collect();
            let pairs =
                PairTable::build(&sites, Some((Vector3::repeat(10.0 * scale), 1.5 * scale)));
            let quads = RowQuads::build(&pairs.unwrap()).expect("the quad kernel is selected");
            let slots: Vec<_> = quads.slots.iter().map(|s| (s.tensor, s.partner)).collect();
            (quads.start, slots, quads.ghosts)
        };
        let unit = table(1.0);
        assert!(!unit.2.is_empty());
        for scale in [1e-7, 1e7] {
            assert!(table(scale) == unit, "scale {scale}");
        }
    }

    /// The table is the same on any number of threads (a 12^3 lattice less
    /// four sites: 431 quads, with missing lanes and ghosts; a build that
    /// merged or placed in parallel tasks would have to keep this).
    #[test]
    fn the_table_does_not_depend_on_the_thread_count() {
        let sites = simple_cubic(12, &[5, 77, 300, 1201]);
        let pairs = PairTable::build(&sites, periodic(12, 2.1)).unwrap();
        let table = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let quads = pool
                .install(|| RowQuads::build(&pairs))
                .expect("the quad kernel is selected");
            let slots: Vec<_> = quads.slots.iter().map(|s| (s.tensor, s.partner)).collect();
            let tensors: Vec<_> = quads.tensors.iter().map(SymmetricTensor::key).collect();
            (quads.start, slots, quads.ghosts, tensors)
        };
        let one = table(1);
        assert_eq!(one.0.len() - 1, 431);
        assert!(!one.2.is_empty() && one.2.contains(&NO_ROTOR));
        for threads in [2, 3, 8] {
            assert!(table(threads) == one, "{threads} threads");
        }
    }

    /// Two layers of four sites, one above the other (periodic lattice of
    /// spacings 3, 12 and 1): every slot of both quads reads four consecutive
    /// partners, so the table needs no ghost entry, and the extended arrays
    /// are the dipoles themselves (plus the trailing zeros).
    #[test]
    fn consecutive_partners_need_no_ghosts() {
        let sites: Vec<_> = (0..8)
            .map(|k| Vector3::new(3.0 * (k % 4) as f64, 0.0, (k / 4) as f64))
            .collect();
        let quads = check_against_half_list(&sites, Some((Vector3::new(12.0, 12.0, 2.0), 1.5)));
        assert!(quads.ghosts.is_empty());
        assert_eq!(quads.quads(), 2);
    }
}
