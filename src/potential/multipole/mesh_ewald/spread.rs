//! Spreading the multipoles on the mesh (Essmann et al. 1995, eq 4.6;
//! multipoles as in Sagui, Pedersen & Darden, J. Chem. Phys. 120, 73
//! (2004)): `Q(l) = sum_j sum_E c_(j,E) d^E_(r_j) prod_a M_p(u_(j,a) - l_a)`,
//! periodic in `l`, with `u_a = K_a x_a / L_a` so that `d/dx_a = (K_a / L_a)
//! d/du_a`. Each x-plane of the mesh is one rayon task that takes the sites
//! whose stencil reaches it in a fixed order (sites sorted by their base
//! plane), so the mesh does not depend on the number of threads.

use super::bspline::AxisWeights;
use super::cartesian::{Tables, SOURCES, UP_TO};
use nalgebra::Vector3;
use rayon::prelude::*;

/// The spline weights of every site, and the sites sorted by base x-plane
/// (buffers sized once).
#[derive(Clone, Debug)]
pub(crate) struct SiteWeights {
    pub(super) order: usize,
    pub(super) grid: [usize; 3],
    /// Per site: the base point and the weights along each axis.
    pub axes: Vec<[AxisWeights; 3]>,
    /// First entry of each base x-plane in `by_plane` (`K_x + 1` entries).
    plane_start: Vec<usize>,
    by_plane: Vec<usize>,
}

impl SiteWeights {
    pub fn new(sites: usize, grid: [usize; 3], order: usize) -> Self {
        SiteWeights {
            order,
            grid,
            axes: vec![[AxisWeights::ZERO; 3]; sites],
            plane_start: vec![0; grid[0] + 1],
            by_plane: vec![0; sites],
        }
    }

    /// Bytes held per site.
    pub fn bytes_per_site() -> f64 {
        (size_of::<[AxisWeights; 3]>() + 8) as f64
    }

    /// The weights (derivatives up to `derivatives`) of the wrapped positions.
    pub fn compute(
        &mut self,
        wrapped: &[Vector3<f64>],
        box_lengths: &Vector3<f64>,
        derivatives: usize,
    ) {
        let (order, grid) = (self.order, self.grid);
        self.axes
            .par_iter_mut()
            .zip(wrapped)
            .with_min_len(256)
            .for_each(|(axes, r)| {
                for (a, weights) in axes.iter_mut().enumerate() {
                    let points = grid[a] as f64;
                    let u = r[a] / box_lengths[a] * points;
                    // A coordinate rounded up to L_a is the point 0.
                    weights.set(if u >= points { u - points } else { u }, order, derivatives);
                }
            });
        self.plane_start.fill(0);
        for axes in &self.axes {
            self.plane_start[axes[0].base + 1] += 1;
        }
        for x in 1..self.plane_start.len() {
            self.plane_start[x] += self.plane_start[x - 1];
        }
        for (i, axes) in self.axes.iter().enumerate() {
            let x = axes[0].base;
            self.by_plane[self.plane_start[x]] = i;
            self.plane_start[x] += 1;
        }
        for x in (1..self.plane_start.len()).rev() {
            self.plane_start[x] = self.plane_start[x - 1];
        }
        self.plane_start[0] = 0;
    }

    /// `Q` on `mesh` (layout `[x][y][z]`) from the coefficients scaled by
    /// `prod_a (K_a / L_a)^(E_a)`, of order at most `source_order`.
    pub fn spread(&self, scaled: &[[f64; SOURCES]], source_order: usize, mesh: &mut [f64]) {
        match self.order {
            4 => self.spread_order::<4>(scaled, source_order, mesh),
            5 => self.spread_order::<5>(scaled, source_order, mesh),
            6 => self.spread_order::<6>(scaled, source_order, mesh),
            7 => self.spread_order::<7>(scaled, source_order, mesh),
            _ => self.spread_order::<8>(scaled, source_order, mesh),
        }
    }

    /// [`Self::spread`] at spline order `P`.
    fn spread_order<const P: usize>(
        &self,
        scaled: &[[f64; SOURCES]],
        source_order: usize,
        mesh: &mut [f64],
    ) {
        let [kx, ky, kz] = self.grid;
        let tables = Tables::get();
        let sources = UP_TO[source_order];
        mesh.par_chunks_mut(ky * kz)
            .enumerate()
            .for_each(|(x, plane)| {
                plane.fill(0.0);
                for t in 0..P {
                    // Sites with base plane x + t reach plane x at stencil index t.
                    let base = (x + t) % kx;
                    for &i in &self.by_plane[self.plane_start[base]..self.plane_start[base + 1]] {
                        let [wx, wy, wz] = &self.axes[i];
                        let c = &scaled[i];
                        // The z-weights in increasing z (point base - P + 1 + j at j).
                        let reversed: [[f64; P]; 3] = std::array::from_fn(|n| {
                            std::array::from_fn(|j| wz.weight[n][P - 1 - j])
                        });
                        for ty in 0..P {
                            let y = back(wy.base, ty, ky);
                            // sum_E c_E wx^(E_x) wy^(E_y), per z-derivative order.
                            let mut by_z = [0.0; 3];
                            for (e, c) in c.iter().enumerate().take(sources) {
                                let [ex, ey, ez] = tables.exponents[e];
                                by_z[ez] += c * wx.weight[ex][t] * wy.weight[ey][ty];
                            }
                            let row = &mut plane[y * kz..(y + 1) * kz];
                            let charges = source_order == 0;
                            if wz.base + 1 >= P {
                                // A stencil that does not wrap: contiguous, in vector registers.
                                let segment = &mut row[wz.base + 1 - P..=wz.base];
                                if charges {
                                    for (q, w) in segment.iter_mut().zip(&reversed[0]) {
                                        *q += by_z[0] * w;
                                    }
                                } else {
                                    for (j, q) in segment.iter_mut().enumerate() {
                                        *q += by_z[0] * reversed[0][j]
                                            + by_z[1] * reversed[1][j]
                                            + by_z[2] * reversed[2][j];
                                    }
                                }
                                continue;
                            }
                            for tz in 0..P {
                                let z = back(wz.base, tz, kz);
                                row[z] += if charges {
                                    by_z[0] * wz.weight[0][tz]
                                } else {
                                    by_z[0] * wz.weight[0][tz]
                                        + by_z[1] * wz.weight[1][tz]
                                        + by_z[2] * wz.weight[2][tz]
                                };
                            }
                        }
                    }
                }
            });
    }
}

/// Calls `f(t, base - t)` for `t = 0..P` (mesh points modulo `points >=
/// P`), in that order: a stencil that does not wrap (`base >= P - 1`, most
/// of them) without the modulo, in a loop the compiler unrolls.
#[inline(always)]
pub(super) fn for_stencil<const P: usize>(
    base: usize,
    points: usize,
    mut f: impl FnMut(usize, usize),
) {
    if base + 1 >= P {
        for t in 0..P {
            f(t, base - t);
        }
    } else {
        for t in 0..P {
            f(t, back(base, t, points));
        }
    }
}

/// `base - t` modulo `points` for `base < points` and `t <= points`,
/// without an integer division.
#[inline]
pub(super) fn back(base: usize, t: usize, points: usize) -> usize {
    if base >= t {
        base - t
    } else {
        base + points - t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wrapped coordinate of `L_a` (a position just below 0 wraps to it
    /// in floating point) is the mesh point 0: its weights are those of a
    /// coordinate of 0, base point and every weight, on each axis.
    #[test]
    fn a_coordinate_rounded_up_to_the_box_length_is_the_point_zero() {
        let box_lengths = Vector3::new(3.0, 2.5, 4.0);
        let at = |position: Vector3<f64>| {
            let mut weights = SiteWeights::new(1, [8, 9, 10], 5);
            weights.compute(&[position], &box_lengths, 2);
            weights.axes[0]
        };
        let wrapped = at(Vector3::new(3.0, 2.5, 4.0));
        let origin = at(Vector3::zeros());
        for a in 0..3 {
            assert_eq!(wrapped[a].base, origin[a].base, "axis {a}");
            assert_eq!(wrapped[a].weight, origin[a].weight, "axis {a}");
        }
        assert_eq!(origin[0].base, 0);
    }

    /// The partition of unity of the B-splines on the smallest meshes each
    /// order allows (as many points as the order: every stencil wraps):
    /// spread charges sum to the total charge, and a constant mesh
    /// potential gathers to itself with zero field, at every order.
    #[test]
    fn the_smallest_meshes_keep_the_partition_of_unity() {
        let box_lengths = Vector3::new(1.0, 1.3, 0.8);
        let positions = [
            Vector3::new(0.1, 0.2, 0.3),
            Vector3::new(0.95, 1.25, 0.01),
            Vector3::new(0.5, 0.0, 0.79),
        ];
        let charges = [1.5, -0.7, 0.3];
        for order in 4..=8 {
            let grid = [order, order + 1, order];
            let mut weights = SiteWeights::new(3, grid, order);
            weights.compute(&positions, &box_lengths, 1);
            let scaled: Vec<[f64; SOURCES]> = charges
                .iter()
                .map(|&q| std::array::from_fn(|e| if e == 0 { q } else { 0.0 }))
                .collect();
            let mut mesh = vec![f64::NAN; grid.iter().product()];
            weights.spread(&scaled, 0, &mut mesh);
            let total: f64 = mesh.iter().sum();
            assert!((total - 1.1).abs() < 1e-13, "order {order}: {total}");
            let scale = Vector3::from_fn(|a, _| grid[a] as f64 / box_lengths[a]);
            let mut derivatives = vec![[0.0; 4]; 3];
            weights.gather(&vec![1.0; mesh.len()], &scale, 4, &mut derivatives);
            for d in &derivatives {
                assert!((d[0] - 1.0).abs() < 1e-13, "order {order}: {d:?}");
                assert!(
                    d[1..].iter().all(|f| f.abs() < 1e-12),
                    "order {order}: {d:?}"
                );
            }
        }
    }
}
