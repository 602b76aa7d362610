//! The real-space pairs of an Ewald sum of charges as a kernel of the pair
//! pass (`super::pair_pass`): each pair once, in lanes of four, with the
//! Lennard-Jones term in the same pass.
//!
//! A pair of charges `q_t`, `q_s` at `r = r_t - r_s` within the real-space
//! cutoff has the energy `q_t q_s B_0` with Smith's radial functions of
//! `erfc(alpha r) / r`, `B_0 = erfc(alpha r) / r` and `B_1 = (B_0 + 2
//! alpha exp(-alpha^2 r^2) / sqrt(pi)) / r^2` (`grad B_0 = -r B_1`;
//! Smith, CCP5 Newsletter 46 (1998)), both from the shared tabulated
//! `erfc` (`crate::potential::multipole::mesh_ewald::ErfcTable::radial`,
//! the same bits as the per-site path): the target's potential `q_s B_0`
//! and field `q_s B_1 r`, the source's `q_t B_0` and `-q_t B_1 r`, the
//! force on the target `q_t q_s B_1 r`. The table is read lane by lane
//! (one `exp` each), so the lanes hold the scalar bits in any [`Lanes`].

use super::electrostatics_shifted::ChargeDipoles;
use super::lanes::{Lanes, V4};
use super::pair_kernels::{BothEnds, ChargeKernel};
use crate::potential::multipole::mesh_ewald::ErfcTable;

/// The real-space pairs of charges of an Ewald sum with splitting `alpha`.
pub(super) struct EwaldCharges {
    alpha: f64,
    table: &'static ErfcTable,
}

impl ChargeKernel for EwaldCharges {
    const ON: bool = true;
    const CHARGES: bool = true;
    fn new(alpha: f64) -> Self {
        EwaldCharges {
            alpha,
            table: ErfcTable::get(),
        }
    }
    /// The pairs of module doc (dipoles, which the pass never gives this
    /// kernel, are not read).
    #[inline(always)]
    fn pair<T: Lanes>(
        &self,
        r: &V4<T>,
        r2: T,
        _: f64,
        target: &ChargeDipoles<T>,
        source: &ChargeDipoles<T>,
    ) -> BothEnds<T> {
        let b = r2
            .to_array()
            .map(|r2| self.table.radial::<2>(self.alpha, r2));
        let (b0, b1) = (
            T::from_array(b.map(|b| b[0])),
            T::from_array(b.map(|b| b[1])),
        );
        let (q_t, q_s) = (target.charge, source.charge);
        let g_s = q_s * b1;
        BothEnds {
            potential: q_s * b0,
            field: *r * g_s,
            force: *r * (q_t * g_s),
            source_potential: q_t * b0,
            source_field: -*r * (q_t * b1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "x86_64")]
    use crate::bodies::lanes::Avx;
    use crate::bodies::lanes::{F4, LANES};
    use nalgebra::Vector3;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every output of the kernel on four pairs, lane by lane.
    fn outputs<T: Lanes>(
        r: &[Vector3<f64>; LANES],
        q_t: f64,
        q_s: [f64; LANES],
    ) -> Vec<[f64; LANES]> {
        let r = V4::<T>::gather(std::array::from_fn(|l| &r[l]));
        let charges = |q: T| ChargeDipoles {
            charge: q,
            dipole: V4::default(),
        };
        let pair = EwaldCharges::new(0.3).pair(
            &r,
            r.dot(&r),
            9.0,
            &charges(T::splat(q_t)),
            &charges(T::from_array(q_s)),
        );
        let mut out = vec![pair.potential, pair.source_potential];
        for v in [pair.field, pair.force, pair.source_field] {
            out.extend([v.x, v.y, v.z]);
        }
        out.into_iter().map(T::to_array).collect()
    }

    /// Each lane is the pair of the module doc with the scalar table's
    /// `B_0`, `B_1`, to the bit, in arrays and in AVX registers.
    #[test]
    fn lanes_are_the_scalar_pair() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let table = ErfcTable::get();
        for _ in 0..50 {
            let r: [Vector3<f64>; LANES] =
                std::array::from_fn(|_| Vector3::from_fn(|_, _| rng.random_range(-6.0..6.0)));
            let (q_t, q_s) = (0.8, std::array::from_fn(|_| rng.random_range(-1.0..1.0)));
            let array = outputs::<F4>(&r, q_t, q_s);
            for l in 0..LANES {
                let [b0, b1] = table.radial::<2>(0.3, r[l].norm_squared());
                let field = r[l] * (q_s[l] * b1);
                let force = r[l] * (q_t * (q_s[l] * b1));
                let source_field = -r[l] * (q_t * b1);
                let mut expected = vec![q_s[l] * b0, q_t * b0];
                expected.extend(field.iter().chain(&force).chain(&source_field));
                let got: Vec<f64> = array.iter().map(|o| o[l]).collect();
                assert_eq!(got, expected, "lane {l}");
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                let bits = |o: Vec<[f64; LANES]>| -> Vec<[u64; LANES]> {
                    o.into_iter().map(|x| x.map(f64::to_bits)).collect()
                };
                assert_eq!(bits(array), bits(outputs::<Avx>(&r, q_t, q_s)));
            }
        }
    }
}
