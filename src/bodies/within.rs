//! The partners of one site within reach of the pair terms, compacted: of
//! a site's listed partners (within the list's reach, `cutoff + skin`),
//! those closer than the terms' largest cutoff, with their separations by
//! component in contiguous rows, so that the pair kernels load four pairs'
//! separations in one instruction per component and spend no lanes on the
//! listed pairs beyond every cutoff (about 30 % of a list with a skin of
//! 0.3 at a cutoff of 2.5: the shell's share `1 - (2.5 / 2.8)^3`).
//!
//! A separation is the minimum image `d - c L` of `d = x_i - x_j`, its
//! image counts `c = round(d / L)` computed here rather than read from the
//! list. For every pair within reach they are the list's image counts, so
//! a kept separation has the bits of
//! [`super::neighbours::NeighbourList::half_pairs`]': a periodic box is at
//! least twice the list's reach (`cutoff + skin`, [`super::space::Space::check`])
//! wide, so at most one image of a pair is within that reach; an image within
//! the cutoff now was within the list's reach at the last build (no site has
//! moved half the skin since), so it is the image listed; and with `|d - c
//! L| < cutoff < L / 2` along each axis, `c` is the nearest integer to `d /
//! L`. A listed pair beyond reach may take another image here; it is not
//! kept either way (no image of it is within reach).
//!
//! On x86-64 CPUs with AVX2 the listed partners are taken four at a time
//! (their positions loaded, the four separations computed in lanes and
//! those within reach stored contiguously through a permutation of the
//! lanes chosen by their mask), the last few one by one: the same
//! partners, separations and padding as one by one throughout.

use crate::lanes::{Lanes, Path, LANES, V4};
use nalgebra::Vector3;
/// One site's partners within reach and their separations, padded to whole
/// rows of [`LANES`] by repeating the last (the padding's results are
/// dropped by the kernels' mask of used lanes). Every partner of the rows
/// up to the count (its padding included) is an index of the positions
/// [`Within::collect`] was last given: the pair pass indexes its per-site
/// arrays with them unchecked.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Within {
    /// The partners (all five arrays are as long, and never shorter than
    /// the padded count: [`Within::row`] relies on it).
    partner: Vec<usize>,
    /// The separations' components and squared lengths.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    r2: Vec<f64>,
    /// How many partners are within reach (the rows hold more: padding).
    count: usize,
    /// The machine code that keeps them (the same partners on each).
    pub path: Path,
}

impl Within {
    /// Keeps the partners `partners` of the site at `x` among `positions`
    /// whose squared minimum-image separation is below `reach2`, in their
    /// listed order; `lengths` are the box lengths (zero in open space),
    /// and `reach2` below a quarter of the smallest's square.
    #[inline(always)]
    pub fn collect(
        &mut self,
        x: &Vector3<f64>,
        partners: &[u32],
        positions: &[Vector3<f64>],
        lengths: &Vector3<f64>,
        reach2: f64,
    ) {
        // Room for every listed partner and a row of padding: each partner
        // is stored at the count, which advances only if it is within reach
        // (no branch; the count, at most the partners so far, is clamped to
        // the rows only so that no write needs a bounds check).
        let room = partners.len() + LANES;
        if self.partner.len() < room {
            self.partner.resize(room, 0);
            for v in [&mut self.x, &mut self.y, &mut self.z, &mut self.r2] {
                v.resize(room, 0.0);
            }
        }
        let site = Site {
            x,
            positions,
            lengths,
            inverse_lengths: lengths.map(|l| if l > 0.0 { 1.0 / l } else { 0.0 }),
            reach2,
        };
        #[cfg(target_arch = "x86_64")]
        let (done, mut n) = match self.path {
            Path::Avx512 if Path::Avx512.runs() => {
                // SAFETY: the CPU has AVX-512 VL and AVX2, checked just above.
                unsafe { self.keep_rows_avx512(&site, partners) }
            }
            Path::Avx512 | Path::Avx2 if Path::Avx2.runs() => {
                // SAFETY: the CPU has AVX2, checked just above.
                unsafe { self.keep_rows_avx2(&site, partners) }
            }
            _ => (0, 0),
        };
        #[cfg(not(target_arch = "x86_64"))]
        let (done, mut n) = (0, 0);
        let partner = &mut self.partner[..room];
        let (xs, ys, zs, r2s) = (
            &mut self.x[..room],
            &mut self.y[..room],
            &mut self.z[..room],
            &mut self.r2[..room],
        );
        for &j in &partners[done..] {
            let j = j as usize;
            let (r, r2) = site.separation(j);
            let k = n.min(room - 1);
            (partner[k], xs[k], ys[k], zs[k], r2s[k]) = (j, r.x, r.y, r.z, r2);
            n += usize::from(r2 < reach2);
        }
        self.count = n;
        if n > 0 {
            for k in n..n.next_multiple_of(LANES) {
                (partner[k], xs[k], ys[k], zs[k], r2s[k]) =
                    (partner[n - 1], xs[n - 1], ys[n - 1], zs[n - 1], r2s[n - 1]);
            }
        }
    }

    /// The row of four pairs from the kept pair `start` (a row within the
    /// padded count): the partners, the separations and their squared
    /// lengths.
    #[inline(always)]
    pub fn row<T: Lanes>(&self, start: usize) -> ([usize; LANES], V4<T>, T) {
        // One check for the five arrays: none is shorter than the padded
        // count (`collect` makes room for the listed partners and a row).
        let end = start + LANES;
        assert!(
            end <= self.count.next_multiple_of(LANES),
            "a row beyond the kept"
        );
        // SAFETY: the row is within every array (just above).
        let read = |v: &[f64]| unsafe { *v.as_ptr().add(start).cast::<[f64; LANES]>() };
        let r = V4 {
            x: T::from_array(read(&self.x)),
            y: T::from_array(read(&self.y)),
            z: T::from_array(read(&self.z)),
        };
        // SAFETY: as for the separations.
        let js = unsafe { *self.partner.as_ptr().add(start).cast::<[usize; LANES]>() };
        (js, r, T::from_array(read(&self.r2)))
    }

    /// How many partners are within reach (the rows hold more: padding).
    #[inline(always)]
    pub fn count(&self) -> usize {
        self.count
    }

    /// The kept partners and their squared separations.
    pub fn kept(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let n = self.count;
        self.partner[..n]
            .iter()
            .copied()
            .zip(self.r2[..n].iter().copied())
    }
}

/// The site whose partners are kept: its position, the positions of all
/// sites, the box lengths and their inverses (zero in open space) and the
/// squared reach.
struct Site<'a> {
    x: &'a Vector3<f64>,
    positions: &'a [Vector3<f64>],
    lengths: &'a Vector3<f64>,
    inverse_lengths: Vector3<f64>,
    reach2: f64,
}

impl Site<'_> {
    /// The minimum-image separation from partner `j` and its squared
    /// length: `d - L round(d / L)`, the quotient as `d (1 / L)`, ties to
    /// even (as the lanes round).
    #[inline(always)]
    fn separation(&self, j: usize) -> (Vector3<f64>, f64) {
        let d = self.x - self.positions[j];
        let r = Vector3::from_fn(|k, _| {
            d[k] - self.lengths[k] * (d[k] * self.inverse_lengths[k]).round_ties_even()
        });
        (r, r.x * r.x + r.y * r.y + r.z * r.z)
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Site, Within, LANES};
    use nalgebra::Vector3;
    use std::arch::x86_64::*;

    /// For each mask of four lanes, the 32-bit halves that move the lanes
    /// where it holds to the front, in their order (the rest filled with
    /// lane 0).
    const FRONT: [[i32; 8]; 16] = {
        let mut table = [[0; 8]; 16];
        let mut mask = 0;
        while mask < 16 {
            let (mut to, mut lane) = (0, 0);
            while lane < LANES {
                if mask & (1 << lane) != 0 {
                    table[mask][2 * to] = 2 * lane as i32;
                    table[mask][2 * to + 1] = 2 * lane as i32 + 1;
                    to += 1;
                }
                lane += 1;
            }
            mask += 1;
        }
        table
    };

    impl Within {
        /// [`Within::collect`] of the first whole rows of four listed
        /// partners (the rows' room already made): how many partners were
        /// taken and how many kept. Each lane rounds as the one-by-one
        /// separation does (no fused multiply-add).
        #[target_feature(enable = "avx2")]
        pub(super) fn keep_rows_avx2(
            &mut self,
            site: &Site<'_>,
            partners: &[u32],
        ) -> (usize, usize) {
            // SAFETY: the CPU has AVX2 (this function's promise).
            unsafe { self.keep_rows(site, partners) }
        }

        /// [`Within::keep_rows_avx2`] with AVX-512 VL's 32 registers.
        #[target_feature(enable = "avx2,avx512f,avx512vl")]
        pub(super) fn keep_rows_avx512(
            &mut self,
            site: &Site<'_>,
            partners: &[u32],
        ) -> (usize, usize) {
            // SAFETY: the CPU has AVX-512 VL (this function's promise).
            unsafe { self.keep_rows(site, partners) }
        }

        /// The body of both.
        ///
        /// # Safety
        /// The CPU has AVX2.
        #[inline(always)]
        unsafe fn keep_rows(&mut self, site: &Site<'_>, partners: &[u32]) -> (usize, usize) {
            let rows = partners.len() / LANES * LANES;
            // The intrinsics need AVX2, which the CPU has (the caller's
            // promise for this function); each load and store says why it
            // stays in bounds.
            let reach2 = _mm256_set1_pd(site.reach2);
            // The site's position and the box in every lane, set once here:
            // the stores below go through raw pointers, so the compiler
            // would load them again for every row.
            let lanes = SiteLanes::new(site);
            // Every partner is a site (so no row needs a bounds check).
            let highest = partners[..rows].iter().fold(0, |m, &j| m.max(j));
            assert!(
                rows == 0 || (highest as usize) < site.positions.len(),
                "a partner beyond the sites"
            );
            // Every row is stored from the count `n <= k` (the kept of the
            // `k` partners before it), so within the room of the listed
            // partners and a row.
            assert!(
                self.partner
                    .len()
                    .min(self.x.len())
                    .min(self.y.len())
                    .min(self.z.len())
                    .min(self.r2.len())
                    >= rows + LANES,
                "no room for the rows"
            );
            let [px_out, py_out, pz_out, r2_out] =
                [&mut self.x, &mut self.y, &mut self.z, &mut self.r2].map(|v| v.as_mut_ptr());
            let partner_out = self.partner.as_mut_ptr();
            let mut n = 0;
            for js in partners[..rows].chunks_exact(LANES) {
                // SAFETY: four u32 are 16 bytes.
                let j = unsafe { _mm_loadu_si128(js.as_ptr().cast()) };
                // SAFETY: every partner indexes `positions` (asserted above).
                let [rx, ry, rz, r2] = unsafe { lanes.row_separations(site.positions, js) };
                let kept = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(r2, reach2)) as usize;
                // SAFETY: a table row is 32 bytes.
                let front = unsafe { _mm256_loadu_si256(FRONT[kept].as_ptr().cast()) };
                let to_front = |v: __m256d| {
                    _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), front))
                };
                let j64 = _mm256_permutevar8x32_epi32(_mm256_cvtepu32_epi64(j), front);
                // SAFETY: four lanes from `n`, within the room (asserted
                // above); the kept lanes first, the rest overwritten by the
                // next rows or the padding.
                unsafe {
                    _mm256_storeu_pd(px_out.add(n), to_front(rx));
                    _mm256_storeu_pd(py_out.add(n), to_front(ry));
                    _mm256_storeu_pd(pz_out.add(n), to_front(rz));
                    _mm256_storeu_pd(r2_out.add(n), to_front(r2));
                    _mm256_storeu_si256(partner_out.add(n).cast(), j64);
                }
                n += kept.count_ones() as usize;
            }
            (rows, n)
        }
    }

    /// [`Site`]'s position, box lengths and their inverses in every lane.
    struct SiteLanes {
        x: [__m256d; 3],
        lengths: [__m256d; 3],
        inverse: [__m256d; 3],
    }

    impl SiteLanes {
        #[inline]
        #[target_feature(enable = "avx2")]
        fn new(site: &Site<'_>) -> Self {
            let lanes = |v: &Vector3<f64>| [v.x, v.y, v.z].map(|c| _mm256_set1_pd(c));
            SiteLanes {
                x: lanes(site.x),
                lengths: lanes(site.lengths),
                inverse: lanes(&site.inverse_lengths),
            }
        }

        /// The minimum-image separations of four listed partners `js`
        /// among `positions`, as rows by component, and their squares:
        /// each lane rounded as [`Site::separation`] rounds (no fused
        /// multiply-add).
        ///
        /// # Safety
        /// The CPU has AVX2, and every partner is an index of `positions`.
        #[inline]
        #[target_feature(enable = "avx2")]
        unsafe fn row_separations(&self, positions: &[Vector3<f64>], js: &[u32]) -> [__m256d; 4] {
            // Each partner's position loaded whole (`x, y` as a pair,
            // `z` alone), then turned into rows by component (no
            // gather instructions: slower than loads on some CPUs).
            assert_eq!(js.len(), LANES, "a row of partners");
            // SAFETY: the caller's promise.
            let [p0, p1, p2, p3] =
                [0, 1, 2, 3].map(|l| unsafe { positions.get_unchecked(js[l] as usize) });
            let xy = |p: &Vector3<f64>| _mm_set_pd(p.y, p.x);
            let (xy02, xy13) = (
                _mm256_set_m128d(xy(p2), xy(p0)),
                _mm256_set_m128d(xy(p3), xy(p1)),
            );
            let p = [
                _mm256_unpacklo_pd(xy02, xy13),
                _mm256_unpackhi_pd(xy02, xy13),
                _mm256_set_pd(p3.z, p2.z, p1.z, p0.z),
            ];
            let [rx, ry, rz] = [0, 1, 2].map(|k| {
                let d = _mm256_sub_pd(self.x[k], p[k]);
                let c = _mm256_round_pd::<{ _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC }>(
                    _mm256_mul_pd(d, self.inverse[k]),
                );
                _mm256_sub_pd(d, _mm256_mul_pd(self.lengths[k], c))
            });
            let r2 = _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry)),
                _mm256_mul_pd(rz, rz),
            );
            [rx, ry, rz, r2]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Of five listed partners in a periodic box of side 10, those whose
    /// minimum image is within reach 2 are kept in their order with the
    /// separations written out here (three through an image across a face,
    /// one of them two boxes away; one beyond reach); none is kept of a
    /// partner beyond reach (the padding: `rows_of_four_keep_what_a_plain_loop_keeps`).
    #[test]
    fn keeps_the_partners_within_reach_with_their_separations() {
        let positions = [
            Vector3::new(0.5, 0.5, 0.5),
            Vector3::new(1.5, 0.5, 0.5),
            Vector3::new(9.5, 0.5, 0.5),
            Vector3::new(3.0, 0.5, 0.5),
            Vector3::new(0.5, 9.0, 0.5),
            Vector3::new(0.5, 0.5, 9.0),
            Vector3::new(0.5, 0.5, 19.5),
        ];
        let lengths = Vector3::repeat(10.0);
        let partners = [1, 2, 3, 4, 6];
        let mut within = Within::default();
        within.collect(&positions[0], &partners, &positions, &lengths, 4.0);
        assert_eq!(within.count, 4);
        assert_eq!(&within.partner[..LANES], &[1, 2, 4, 6]);
        assert_eq!(&within.x[..LANES], &[-1.0, 1.0, 0.0, 0.0]);
        assert_eq!(&within.y[..LANES], &[0.0, 0.0, 1.5, 0.0]);
        assert_eq!(&within.z[..LANES], &[0.0, 0.0, 0.0, 1.0]);
        assert_eq!(&within.r2[..LANES], &[1.0, 1.0, 2.25, 1.0]);
        within.collect(&positions[0], &[3], &positions, &lengths, 4.0);
        assert_eq!(within.count, 0);
    }

    /// In open space (zero box lengths) the separations are the plain
    /// differences.
    #[test]
    fn open_space_takes_no_image() {
        let positions = [Vector3::new(0.5, 0.5, 0.5), Vector3::new(30.5, -19.5, 0.5)];
        let mut within = Within::default();
        within.collect(&positions[0], &[1], &positions, &Vector3::zeros(), 2000.0);
        assert_eq!(within.count, 1);
        assert_eq!((within.x[0], within.y[0], within.z[0]), (-30.0, 20.0, 0.0));
    }

    /// A row of partners naming a site beyond the positions (the last one
    /// just past them) stops the pass rather than read beyond them.
    #[test]
    #[should_panic]
    fn a_partner_beyond_the_sites_is_refused() {
        let positions = [Vector3::new(0.5, 0.5, 0.5); 4];
        let mut within = Within::default();
        within.collect(
            &positions[0],
            &[1, 2, 3, 4],
            &positions,
            &Vector3::zeros(),
            2000.0,
        );
    }

    /// Taken four at a time (on every [`Path`] the CPU has: AVX2 with or
    /// without AVX-512 VL's registers) or one by one, the kept
    /// partners, their separations (to the bit) and the padding are those
    /// of a plain loop over the listed partners with the minimum image
    /// `d - L round(d / L)`, for lists of every length from 0 to 40 (whole
    /// rows and remainders) of random partners, some of them a few boxes
    /// away, in a box of sides 7, 8 and 9.
    #[test]
    fn rows_of_four_keep_what_a_plain_loop_keeps() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(39);
        let lengths = Vector3::new(7.0, 8.0, 9.0);
        let positions: Vec<Vector3<f64>> = (0..300)
            .map(|_| Vector3::from_fn(|k, _| rng.random_range(-2.0..3.0) * lengths[k]))
            .collect();
        let mut within = Within::default();
        for (listed, path) in
            (0..=40).flat_map(|l| Path::available().into_iter().map(move |p| (l, p)))
        {
            let x = positions[rng.random_range(0..positions.len())];
            let partners: Vec<u32> = (0..listed).map(|_| rng.random_range(0..300)).collect();
            let reach2 = 9.0;
            within.path = path;
            within.collect(&x, &partners, &positions, &lengths, reach2);
            let mut expected = Vec::new();
            for &j in &partners {
                let d = x - positions[j as usize];
                let r = Vector3::from_fn(|k, _| d[k] - lengths[k] * (d[k] / lengths[k]).round());
                let r2 = r.x * r.x + r.y * r.y + r.z * r.z;
                if r2 < reach2 {
                    expected.push((j as usize, r.x, r.y, r.z, r2));
                }
            }
            assert_eq!(within.count, expected.len(), "{listed} listed, {path:?}");
            if let Some(&last) = expected.last() {
                expected.resize(expected.len().next_multiple_of(LANES), last);
            }
            let kept: Vec<_> = (0..expected.len())
                .map(|k| {
                    (
                        within.partner[k],
                        within.x[k],
                        within.y[k],
                        within.z[k],
                        within.r2[k],
                    )
                })
                .collect();
            assert_eq!(kept, expected, "{listed} listed, {path:?}");
        }
    }

    /// The module's claim: after the sites have moved (each by less than
    /// half the skin, across the box's faces too), the partners each site
    /// keeps within the cutoff are the list's pairs within it, in the
    /// list's order, with the bits of its separations (through the image
    /// counts it stored at the build).
    #[test]
    fn the_kept_pairs_are_the_lists_within_the_cutoff() {
        use super::super::neighbours::NeighbourList;
        use super::super::space::Space;
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(41);
        // The box exactly twice the list's reach along x, the least allowed.
        let (n, lengths, cutoff, skin) = (400, Vector3::new(5.2, 6.5, 7.0), 2.0, 0.6);
        let space = Space::Periodic(lengths);
        let mut sites: Vec<Vector3<f64>> = (0..n)
            .map(|_| Vector3::from_fn(|k, _| rng.random::<f64>() * lengths[k]))
            .collect();
        let body: Vec<u32> = (0..n as u32).collect();
        let mut list = NeighbourList::new(cutoff, skin).unwrap();
        list.build(&sites, &body, &space);
        for x in &mut sites {
            *x += Vector3::from_fn(|_, _| (rng.random::<f64>() - 0.5) * 0.3);
        }
        assert!(!list.is_stale(&sites, &space));
        let mut within = Within::default();
        let mut kept = 0;
        for i in 0..n {
            within.collect(
                &sites[i],
                list.half_run(i),
                &sites,
                &lengths,
                cutoff * cutoff,
            );
            let expected: Vec<(usize, [u64; 4])> = list
                .half_pairs(i, &sites)
                .map(|(j, r)| (j, [r.x, r.y, r.z, r.norm_squared()]))
                .filter(|(_, r)| r[3] < cutoff * cutoff)
                .map(|(j, r)| (j, r.map(f64::to_bits)))
                .collect();
            let found: Vec<(usize, [u64; 4])> = (0..within.count)
                .map(|k| {
                    let r = [within.x[k], within.y[k], within.z[k], within.r2[k]];
                    (within.partner[k], r.map(f64::to_bits))
                })
                .collect();
            assert_eq!(
                found.iter().map(|p| p.0).collect::<Vec<_>>(),
                expected.iter().map(|p| p.0).collect::<Vec<_>>(),
                "site {i}"
            );
            for ((j, a), (_, b)) in found.iter().zip(&expected) {
                assert_eq!(a[..3], b[..3], "site {i}, partner {j}");
            }
            kept += within.count;
        }
        assert!(kept > 5 * n, "{kept} pairs within the cutoff");
    }
}
