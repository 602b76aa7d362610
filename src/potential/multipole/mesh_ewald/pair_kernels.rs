//! The real-space pair kernels of the mesh Ewald sum, four pairs at a
//! time ([`RealKernel`], lanes of [`crate::lanes`]): the unrolled kernels
//! of charges and of charges and dipoles (the radial functions in lanes,
//! [`ErfcTable::radial_lanes`]), and the general kernel of any sources by
//! the derivative tensors of `erfc(alpha r) / r`, pair by pair. Each adds
//! its pairs lane by lane in the chunk's order, so each site's sums are
//! those of a pair-by-pair sum, bit for bit.

use super::cartesian::{
    add_source, pair_force, radial_derivatives, Tables, DERIVATIVES, SOURCES, UP_TO,
};
use super::damped::ErfcTable;
use crate::lanes::{Lanes, LANES, V4};
use crate::potential::multipole::ewald_terms::radial_functions;
use nalgebra::{Matrix3, Vector3};

/// Up to four pairs for a kernel: the places of their sites in cell order
/// (`a`, `b`), `r = r_a - r_b` and `r^2`; the lanes from `len` on hold a
/// harmless separation (`r^2 = 1`) whose results are dropped.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chunk {
    pub a: [usize; LANES],
    pub b: [usize; LANES],
    pub r: [Vector3<f64>; LANES],
    pub r2: [f64; LANES],
    pub len: usize,
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
    pub fn push(&mut self, a: usize, b: usize, r: Vector3<f64>, r2: f64) -> bool {
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
pub(super) trait RealKernel {
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
pub(super) struct ChargeDipoleKernel<const L: usize, const DIPOLES: bool> {
    alpha: f64,
    virial: bool,
    erfc: &'static ErfcTable,
}

impl<const L: usize, const DIPOLES: bool> ChargeDipoleKernel<L, DIPOLES> {
    pub fn new(alpha: f64, virial: bool) -> Self {
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
pub(super) struct GeneralKernel {
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
    pub fn new(alpha: f64, (source_order, count): (usize, usize), virial: bool) -> Self {
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
