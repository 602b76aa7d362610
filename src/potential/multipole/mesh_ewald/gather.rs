//! Gathering the mesh potential at the sites (Essmann et al. 1995, eq 4.9;
//! derivatives as in Sagui, Pedersen & Darden 2004): the interpolated
//! potential and its derivatives up to the third order, by the derivatives
//! of the spline weights, contracted one axis at a time (z, then y, then
//! x). Sites are independent rayon tasks.

use super::cartesian::Tables;
use super::spread::{back, for_stencil, SiteWeights};
use nalgebra::Vector3;
use rayon::prelude::*;

impl SiteWeights {
    /// Adds `d^A phi(r_i) = sum_l d^A prod_a M_p(u_(i,a) - l_a) phi(l)` for
    /// the first `count` multi-indices to each site's `derivatives`, `scale`
    /// holding `(K_a / L_a)` (the mesh potential `phi`, layout `[x][y][z]`).
    pub fn gather<const D: usize>(
        &self,
        phi: &[f64],
        scale: &Vector3<f64>,
        count: usize,
        derivatives: &mut [[f64; D]],
    ) {
        // One monomorphised loop per count (the multi-indices up to an order,
        // which need the z-derivatives up to `Z - 1`) and spline order.
        match count {
            1 => self.gather_order::<D, 1, 1>(phi, scale, derivatives),
            4 => self.gather_order::<D, 4, 2>(phi, scale, derivatives),
            10 => self.gather_order::<D, 10, 3>(phi, scale, derivatives),
            _ => self.gather_order::<D, 20, 4>(phi, scale, derivatives),
        }
    }

    /// [`Self::gather_first`] at the spline order.
    fn gather_order<const D: usize, const N: usize, const Z: usize>(
        &self,
        phi: &[f64],
        scale: &Vector3<f64>,
        derivatives: &mut [[f64; D]],
    ) {
        match self.order {
            4 => self.gather_first::<D, N, Z, 4>(phi, scale, derivatives),
            5 => self.gather_first::<D, N, Z, 5>(phi, scale, derivatives),
            6 => self.gather_first::<D, N, Z, 6>(phi, scale, derivatives),
            7 => self.gather_first::<D, N, Z, 7>(phi, scale, derivatives),
            _ => self.gather_first::<D, N, Z, 8>(phi, scale, derivatives),
        }
    }

    /// [`Self::gather`] of the first `N` multi-indices (`N` of
    /// [`super::cartesian::UP_TO`], at most `D`; their z-derivatives below
    /// `Z`) at spline order `P`.
    fn gather_first<const D: usize, const N: usize, const Z: usize, const P: usize>(
        &self,
        phi: &[f64],
        scale: &Vector3<f64>,
        derivatives: &mut [[f64; D]],
    ) {
        let [kx, ky, kz] = self.grid;
        let tables = Tables::get();
        let exponents: [[usize; 3]; N] = std::array::from_fn(|a| tables.exponents[a]);
        debug_assert_eq!(Z, 1 + exponents.iter().map(|e| e[2]).max().unwrap_or(0));
        let factors: [f64; N] = std::array::from_fn(|a| {
            let e = exponents[a];
            (0..3).map(|k| scale[k].powi(e[k] as i32)).product()
        });
        derivatives
            .par_iter_mut()
            .zip(&self.axes)
            .with_min_len(64)
            .for_each(|(d, [wx, wy, wz])| {
                let mut sum = [0.0; N];
                for tx in 0..P {
                    let x = back(wx.base, tx, kx);
                    // Contract y next: by_yz[ey][ez] = sum_ty wy^(ey) by_z[ez],
                    // for ey + ez below Z (the orders of the multi-indices).
                    let mut by_yz = [[0.0; Z]; Z];
                    for ty in 0..P {
                        let y = back(wy.base, ty, ky);
                        let row = &phi[(x * ky + y) * kz..(x * ky + y + 1) * kz];
                        // Contract z first: by_z[n] = sum_tz wz^(n) phi.
                        let mut by_z = [0.0; Z];
                        for_stencil::<P>(wz.base, kz, |tz, z| {
                            let value = row[z];
                            for (n, out) in by_z.iter_mut().enumerate() {
                                *out += wz.weight[n][tz] * value;
                            }
                        });
                        for (ey, by_y) in by_yz.iter_mut().enumerate() {
                            let w = wy.weight[ey][ty];
                            for (out, z) in by_y.iter_mut().zip(&by_z).take(Z - ey) {
                                *out += w * z;
                            }
                        }
                    }
                    for (out, [ex, ey, ez]) in sum.iter_mut().zip(&exponents) {
                        *out += wx.weight[*ex][tx] * by_yz[*ey][*ez];
                    }
                }
                for ((d, s), f) in d.iter_mut().zip(&sum).zip(&factors) {
                    *d += s * f;
                }
            });
    }
}
