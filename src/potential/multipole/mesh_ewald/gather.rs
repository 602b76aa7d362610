//! Gathering the mesh potential at the sites (Essmann et al. 1995, eq 4.9;
//! derivatives as in Sagui, Pedersen & Darden 2004): the interpolated
//! potential and its derivatives up to the third order, by the derivatives
//! of the spline weights. Sites are independent rayon tasks.

use super::bspline::MAX_DERIVATIVE;
use super::cartesian::Tables;
use super::spread::{mesh_points, SiteWeights};
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
        let [kx, ky, kz] = self.grid;
        let p = self.order;
        let tables = Tables::get();
        let factors: [f64; D] = std::array::from_fn(|a| {
            let e = tables.exponents[a];
            (0..3).map(|k| scale[k].powi(e[k] as i32)).product()
        });
        // The z-derivatives the first `count` multi-indices need.
        let z_orders = 1
            + (0..count)
                .map(|a| tables.exponents[a][2])
                .max()
                .unwrap_or(0);
        derivatives
            .par_iter_mut()
            .zip(&self.axes)
            .with_min_len(64)
            .for_each(|(d, [wx, wy, wz])| {
                let mut sum = [0.0; D];
                let zs = mesh_points(wz.base, kz, p);
                for tx in 0..p {
                    let x = (wx.base + kx - tx) % kx;
                    for ty in 0..p {
                        let y = (wy.base + ky - ty) % ky;
                        let row = &phi[(x * ky + y) * kz..(x * ky + y + 1) * kz];
                        // Contract z first: by_z[n] = sum_tz wz^(n) phi.
                        let mut by_z = [0.0; MAX_DERIVATIVE + 1];
                        for (tz, &z) in zs.iter().enumerate().take(p) {
                            let value = row[z];
                            for (n, out) in by_z.iter_mut().enumerate().take(z_orders) {
                                *out += wz.weight[n][tz] * value;
                            }
                        }
                        for (a, out) in sum.iter_mut().enumerate().take(count) {
                            let [ex, ey, ez] = tables.exponents[a];
                            *out += wx.weight[ex][tx] * wy.weight[ey][ty] * by_z[ez];
                        }
                    }
                }
                for a in 0..count {
                    d[a] += sum[a] * factors[a];
                }
            });
    }
}
