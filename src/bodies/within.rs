//! The partners of one site within reach of the pair terms, compacted: of
//! a site's listed partners (within the list's reach, `cutoff + skin`),
//! those closer than the terms' largest cutoff, with their separations by
//! component in contiguous rows, so that the pair kernels load four pairs'
//! separations in one instruction per component and spend no lanes on the
//! listed pairs beyond every cutoff (about 30 % of a list with a skin of
//! 0.3 at a cutoff of 2.5: the shell's share `1 - (2.5 / 2.8)^3`).
//!
//! A separation is `x_i - x_j - shift`, the shift `c L` of the pair's image
//! counts `c` (zero for most pairs, their own minimum image): the bits of
//! [`super::neighbours::NeighbourList::half_pairs`]' separations.
//!
//! On x86-64 CPUs with AVX2 the listed partners are taken four at a time
//! (their positions loaded, the four separations computed in lanes and
//! those within reach stored contiguously through a permutation of the
//! lanes chosen by their mask), the last few one by one: the same
//! partners, separations and padding as one by one throughout.

use crate::lanes::{Lanes, LANES, V4};
use nalgebra::Vector3;
/// One site's partners within reach and their separations, padded to whole
/// rows of [`LANES`] by repeating the last (the padding's results are
/// dropped by the kernels' mask of used lanes).
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Within {
    /// The partners.
    pub partner: Vec<usize>,
    /// The separations' components and squared lengths.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
    pub r2: Vec<f64>,
    /// How many partners are within reach (the rows hold more: padding).
    pub count: usize,
}

impl Within {
    /// Keeps the partners `partners` (image counts `images`) of the site at
    /// `x` among `positions` whose squared separation is below `reach2`,
    /// in their listed order; `lengths` are the box lengths of the image
    /// counts (zero in open space).
    #[inline(always)]
    pub fn collect(
        &mut self,
        x: &Vector3<f64>,
        (partners, images): (&[u32], &[[i8; 3]]),
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
            reach2,
        };
        let (mut done, mut n) = (0, 0);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            (done, n) = unsafe { self.keep_rows_avx2(&site, (partners, images)) };
        }
        let partner = &mut self.partner[..room];
        let (xs, ys, zs, r2s) = (
            &mut self.x[..room],
            &mut self.y[..room],
            &mut self.z[..room],
            &mut self.r2[..room],
        );
        for (&j, c) in partners[done..].iter().zip(&images[done..]) {
            let j = j as usize;
            let (r, r2) = site.separation(j, c);
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

    /// The row of four pairs from the kept pair `start`: the partners,
    /// the separations and their squared lengths.
    #[inline(always)]
    pub fn row<T: Lanes>(&self, start: usize) -> ([usize; LANES], V4<T>, T) {
        let row = start..start + LANES;
        let load = |v: &[f64]| T::from_array(v[row.clone()].try_into().unwrap_or_default());
        let r = V4 {
            x: load(&self.x),
            y: load(&self.y),
            z: load(&self.z),
        };
        let js = self.partner[row.clone()].try_into().unwrap_or_default();
        (js, r, load(&self.r2))
    }
}

/// The site whose partners are kept: its position, the positions of all
/// sites, the box lengths and the squared reach.
struct Site<'a> {
    x: &'a Vector3<f64>,
    positions: &'a [Vector3<f64>],
    lengths: &'a Vector3<f64>,
    reach2: f64,
}

impl Site<'_> {
    /// The separation from partner `j` with image counts `c` and its
    /// squared length.
    #[inline(always)]
    fn separation(&self, j: usize, c: &[i8; 3]) -> (Vector3<f64>, f64) {
        let l = self.lengths;
        let shift = Vector3::new(
            l.x * f64::from(c[0]),
            l.y * f64::from(c[1]),
            l.z * f64::from(c[2]),
        );
        let r = self.x - self.positions[j] - shift;
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

    /// Which byte of four pairs' image counts (three bytes each) is the
    /// count along each axis, in the low four bytes (the rest cleared).
    const AXIS_BYTES: [[i8; 16]; 3] = {
        let mut table = [[-1; 16]; 3];
        let mut k = 0;
        while k < 3 {
            let mut l = 0;
            while l < LANES {
                table[k][l] = (3 * l + k) as i8;
                l += 1;
            }
            k += 1;
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
            (partners, images): (&[u32], &[[i8; 3]]),
        ) -> (usize, usize) {
            let rows = partners.len().min(images.len()) / LANES * LANES;
            // The intrinsics need AVX2, which the CPU has (the caller's
            // promise for this function); each load and store says why it
            // stays in bounds.
            // SAFETY: a table row is 16 bytes.
            let [ax, ay, az] = AXIS_BYTES.map(|b| unsafe { _mm_loadu_si128(b.as_ptr().cast()) });
            let reach2 = _mm256_set1_pd(site.reach2);
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
            for (js, cs) in partners[..rows]
                .chunks_exact(LANES)
                .zip(images[..rows].chunks_exact(LANES))
            {
                // SAFETY: four u32 are 16 bytes.
                let j = unsafe { _mm_loadu_si128(js.as_ptr().cast()) };
                let [rx, ry, rz, r2] = row_separations(site, js, cs, [ax, ay, az]);
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

    /// The separations `x_i - x_j - L n` of four listed partners `js` with
    /// image counts `cs` (the byte shuffles `axes` pick each axis's counts),
    /// as rows by component, and their squares: each lane rounded as the
    /// one-by-one separation is (no fused multiply-add).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn row_separations(
        site: &Site<'_>,
        js: &[u32],
        cs: &[[i8; 3]],
        [ax, ay, az]: [__m128i; 3],
    ) -> [__m256d; 4] {
        let [lx, ly, lz] =
            [site.lengths.x, site.lengths.y, site.lengths.z].map(|l| _mm256_set1_pd(l));
        let [x, y, z] = [site.x.x, site.x.y, site.x.z].map(|c| _mm256_set1_pd(c));
        // Each partner's position loaded whole (`x, y` as a pair,
        // `z` alone), then turned into rows by component (no
        // gather instructions: slower than loads on some CPUs).
        let [p0, p1, p2, p3] = [0, 1, 2, 3].map(|l| &site.positions[js[l] as usize]);
        let xy = |p: &Vector3<f64>| _mm_set_pd(p.y, p.x);
        let (xy02, xy13) = (
            _mm256_set_m128d(xy(p2), xy(p0)),
            _mm256_set_m128d(xy(p3), xy(p1)),
        );
        let (px, py, pz) = (
            _mm256_unpacklo_pd(xy02, xy13),
            _mm256_unpackhi_pd(xy02, xy13),
            _mm256_set_pd(p3.z, p2.z, p1.z, p0.z),
        );
        assert_eq!(cs.len(), LANES, "a row of image counts");
        // SAFETY: four image counts are 12 bytes, read as 8 and 4.
        let counts = unsafe {
            let at = cs.as_ptr().cast::<u8>();
            _mm_insert_epi32::<2>(
                _mm_loadl_epi64(at.cast()),
                at.add(8).cast::<i32>().read_unaligned(),
            )
        };
        let count = |axis| _mm256_cvtepi32_pd(_mm_cvtepi8_epi32(_mm_shuffle_epi8(counts, axis)));
        let rx = _mm256_sub_pd(_mm256_sub_pd(x, px), _mm256_mul_pd(lx, count(ax)));
        let ry = _mm256_sub_pd(_mm256_sub_pd(y, py), _mm256_mul_pd(ly, count(ay)));
        let rz = _mm256_sub_pd(_mm256_sub_pd(z, pz), _mm256_mul_pd(lz, count(az)));
        let r2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(rx, rx), _mm256_mul_pd(ry, ry)),
            _mm256_mul_pd(rz, rz),
        );
        [rx, ry, rz, r2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Of five listed partners in a periodic box of side 10, those within
    /// reach 2 are kept in their order with the separations written out
    /// here (two of them through their images; two beyond reach, one
    /// across the box where its zero image counts leave it), and the last row is
    /// padded with the last kept; none is kept of a partner beyond reach.
    #[test]
    fn keeps_the_partners_within_reach_with_their_separations() {
        let positions = [
            Vector3::new(0.5, 0.5, 0.5),
            Vector3::new(1.5, 0.5, 0.5),
            Vector3::new(9.5, 0.5, 0.5),
            Vector3::new(3.0, 0.5, 0.5),
            Vector3::new(0.5, 9.0, 0.5),
            Vector3::new(0.5, 0.5, 9.0),
        ];
        let lengths = Vector3::repeat(10.0);
        let partners = [1, 2, 3, 4, 5];
        let images = [[0; 3], [-1, 0, 0], [0; 3], [0, 0, 0], [0, 0, -1]];
        let mut within = Within::default();
        within.collect(
            &positions[0],
            (&partners, &images),
            &positions,
            &lengths,
            4.0,
        );
        assert_eq!(within.count, 3);
        assert_eq!(&within.partner[..LANES], &[1, 2, 5, 5]);
        assert_eq!(&within.x[..LANES], &[-1.0, 1.0, 0.0, 0.0]);
        assert_eq!(&within.z[..LANES], &[0.0, 0.0, 1.5, 1.5]);
        assert_eq!(&within.r2[..LANES], &[1.0, 1.0, 2.25, 2.25]);
        within.collect(&positions[0], (&[3], &[[0; 3]]), &positions, &lengths, 4.0);
        assert_eq!(within.count, 0);
    }

    /// Taken four at a time (on CPUs with AVX2) or one by one, the kept
    /// partners, their separations (to the bit) and the padding are those
    /// of a plain loop over the listed partners, for lists of every length
    /// from 0 to 40 (whole rows and remainders) of random partners with
    /// image counts -1, 0 or 1 in a box of sides 7, 8 and 9.
    #[test]
    fn rows_of_four_keep_what_a_plain_loop_keeps() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(39);
        let lengths = Vector3::new(7.0, 8.0, 9.0);
        let positions: Vec<Vector3<f64>> = (0..300)
            .map(|_| Vector3::from_fn(|k, _| rng.random_range(0.0..lengths[k])))
            .collect();
        let mut within = Within::default();
        for listed in 0..=40 {
            let x = positions[rng.random_range(0..positions.len())];
            let partners: Vec<u32> = (0..listed).map(|_| rng.random_range(0..300)).collect();
            let images: Vec<[i8; 3]> = (0..listed)
                .map(|_| [0; 3].map(|_: i8| rng.random_range(-1..=1)))
                .collect();
            let reach2 = 9.0;
            within.collect(&x, (&partners, &images), &positions, &lengths, reach2);
            let mut expected = Vec::new();
            for (&j, c) in partners.iter().zip(&images) {
                let shift = Vector3::from_fn(|k, _| lengths[k] * f64::from(c[k]));
                let r = x - positions[j as usize] - shift;
                let r2 = r.x * r.x + r.y * r.y + r.z * r.z;
                if r2 < reach2 {
                    expected.push((j as usize, r.x, r.y, r.z, r2));
                }
            }
            assert_eq!(within.count, expected.len(), "{listed} listed");
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
            assert_eq!(kept, expected, "{listed} listed");
        }
    }
}
