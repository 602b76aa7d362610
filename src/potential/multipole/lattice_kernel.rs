//! The kernel of the FFT lattice sum ([`super::lattice_fft`]), `K^`, built
//! once: the real-space (or truncated) tensor of each basis pair on the
//! cell grid with the Ewald self term, transformed; the reciprocal part
//! added at each frequency; the vacuum surface term at `q = 0`. The
//! formulas are in [`super::lattice_fft`]'s doc.

use super::ewald_parameters::EwaldParameters;
use super::ewald_terms::{
    mode_weight, pair_fields, radial, self_conjugate_per_quadrupole, self_field_per_dipole,
    surface_field_per_dipole,
};
use super::fft3::RealFft3;
use super::lattice_grid::LatticeGrid;
use super::periodic_sum::ChosenSum;
use super::{PeriodicSum, Surface};
use nalgebra::{Matrix3, Vector3};
use rustfft::num_complex::Complex;
use std::f64::consts::PI;

pub(super) type C64 = Complex<f64>;

/// The transformed lattice tensor `K^ / N_cells` of `sum` on `grid` in
/// `box_lengths`, laid out as `shape` says (see [`kernel_index`]), for the
/// multipole kinds `(dipoles, quadrupoles)` carried.
pub(super) fn build_kernel(
    grid: &LatticeGrid,
    box_lengths: &Vector3<f64>,
    sum: &ChosenSum,
    plan: &RealFft3,
    shape: &KernelShape,
    (dipoles, quadrupoles): (bool, bool),
) -> Vec<C64> {
    let b = shape.basis;
    let units = unit_sources(dipoles, quadrupoles);
    let mut kernel = vec![C64::default(); plan.spectrum_len() * b * b * shape.block()];
    for target in 0..b {
        for source in 0..b {
            let shift = grid.basis[target] - grid.basis[source];
            let pair = (target, source, &shift);
            let tensor = real_space_tensor(grid, sum, &units, (dipoles, quadrupoles), pair);
            add_transformed(&mut kernel, plan, shape, tensor, (target, source));
            if let Some(parameters) = sum.parameters {
                add_reciprocal(
                    &mut kernel,
                    plan,
                    grid,
                    box_lengths,
                    &parameters,
                    &units,
                    (dipoles, quadrupoles),
                    pair,
                );
            }
        }
    }
    if let (
        PeriodicSum::Ewald {
            surface: Surface::Vacuum,
            ..
        },
        true,
    ) = (sum.sum, dipoles)
    {
        add_vacuum_surface(&mut kernel, shape, box_lengths.product());
    }
    kernel
}

/// The source components (unit multipoles) of a system carrying dipoles
/// and/or quadrupoles: `mu = e_x, e_y, e_z`, then the traceless
/// `Theta` with one of `Theta_xx`, `Theta_yy`, `Theta_xy`, `Theta_xz`,
/// `Theta_yz` equal to 1 (and `Theta_zz = -Theta_xx - Theta_yy`).
fn unit_sources(dipoles: bool, quadrupoles: bool) -> Vec<(Vector3<f64>, Matrix3<f64>)> {
    let mut out = Vec::new();
    if dipoles {
        for a in 0..3 {
            out.push((
                Vector3::from_fn(|i, _| (i == a) as u8 as f64),
                Matrix3::zeros(),
            ));
        }
    }
    if quadrupoles {
        let mut units = vec![
            Matrix3::from_diagonal(&Vector3::new(1.0, 0.0, -1.0)),
            Matrix3::from_diagonal(&Vector3::new(0.0, 1.0, -1.0)),
        ];
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            let mut m = Matrix3::zeros();
            m[(a, b)] = 1.0;
            m[(b, a)] = 1.0;
            units.push(m);
        }
        out.extend(units.into_iter().map(|m| (Vector3::zeros(), m)));
    }
    out
}

/// The field components `(E_x, E_y, E_z)` and/or
/// `(W_xx, W_yy, W_zz, W_xy, W_xz, W_yz)` of `(E, W)`.
fn field_components<T: nalgebra::Scalar + Copy>(
    dipoles: bool,
    quadrupoles: bool,
    e: &Vector3<T>,
    w: &Matrix3<T>,
) -> Vec<T> {
    let mut out = Vec::with_capacity(9);
    if dipoles {
        out.extend([e[0], e[1], e[2]]);
    }
    if quadrupoles {
        out.extend([
            w[(0, 0)],
            w[(1, 1)],
            w[(2, 2)],
            w[(0, 1)],
            w[(0, 2)],
            w[(1, 2)],
        ]);
    }
    out
}

/// The position of `K^_{(target, f), (source, c)}(q) / N_cells` in the
/// kernel: per frequency, rows `(target, f)` of `b sources` entries.
pub(super) fn kernel_index(
    q: usize,
    (target, f): (usize, usize),
    (source, c): (usize, usize),
    b: usize,
    sources: usize,
    fields: usize,
) -> usize {
    ((q * b + target) * fields + f) * b * sources + source * sources + c
}

/// The sizes of the kernel: `basis` offsets, `sources` multipole and
/// `fields` field components (see [`kernel_index`]).
pub(super) struct KernelShape {
    pub basis: usize,
    pub sources: usize,
    pub fields: usize,
}

impl KernelShape {
    /// Entries of one basis pair's block at one frequency.
    pub fn block(&self) -> usize {
        self.sources * self.fields
    }

    /// [`kernel_index`] in this shape.
    fn index(&self, q: usize, target: (usize, usize), source: (usize, usize)) -> usize {
        kernel_index(q, target, source, self.basis, self.sources, self.fields)
    }
}

/// The real-space (or truncated) tensor of the basis pair `(target,
/// source)` at offset `shift` on the cell grid, as `[f][c][cell]`: every
/// lattice vector within the sum's reach, plus the Ewald self term on the
/// diagonal pairs.
fn real_space_tensor(
    grid: &LatticeGrid,
    sum: &ChosenSum,
    units: &[(Vector3<f64>, Matrix3<f64>)],
    (dipoles, quadrupoles): (bool, bool),
    (target, source, shift): (usize, usize, &Vector3<f64>),
) -> Vec<f64> {
    let cells = grid.cell_count();
    let sources = units.len();
    let alpha = sum.parameters.map_or(0.0, |p| p.alpha);
    let mut tensor = vec![0.0; sources * (3 * dipoles as usize + 6 * quadrupoles as usize) * cells];
    let mut add = |cell: usize, c: usize, e: &Vector3<f64>, w: &Matrix3<f64>| {
        for (f, v) in field_components(dipoles, quadrupoles, e, w)
            .into_iter()
            .enumerate()
        {
            tensor[(f * sources + c) * cells + cell] += v;
        }
    };
    for_lattice_vectors(grid, shift, sum.reach, |cell, r| {
        let rb = radial(alpha, r.norm());
        for (c, (mu, theta)) in units.iter().enumerate() {
            let (e, w) = pair_fields(r, &rb, Some(mu), Some(theta));
            add(cell, c, &e, &w);
        }
    });
    if target == source && sum.parameters.is_some() {
        let (a3, a5) = (
            self_field_per_dipole(alpha),
            self_conjugate_per_quadrupole(alpha),
        );
        for (c, (mu, theta)) in units.iter().enumerate() {
            add(0, c, &(mu * a3), &(theta * a5));
        }
    }
    tensor
}

/// Transforms each `(f, c)` grid of a basis pair's `tensor` and stores it,
/// divided by the number of cells, in the kernel.
fn add_transformed(
    kernel: &mut [C64],
    plan: &RealFft3,
    shape: &KernelShape,
    tensor: Vec<f64>,
    (target, source): (usize, usize),
) {
    let spectrum = plan.spectrum_len();
    let cells = tensor.len() / shape.block();
    let scale = 1.0 / cells as f64;
    let mut transformed = vec![C64::default(); spectrum];
    let mut work = vec![C64::default(); spectrum];
    for (fc, grid) in tensor.chunks_exact(cells).enumerate() {
        plan.forward(grid, &mut transformed, &mut work);
        let (f, c) = (fc / shape.sources, fc % shape.sources);
        for (q, value) in transformed.iter().enumerate() {
            kernel[shape.index(q, (target, f), (source, c))] = value * scale;
        }
    }
}

/// Adds the vacuum surface term `-4 pi / (3 V)` (as a field per dipole) to
/// the dipole-field block of every basis pair at `q = 0`.
fn add_vacuum_surface(kernel: &mut [C64], shape: &KernelShape, volume: f64) {
    let value = surface_field_per_dipole(volume);
    for target in 0..shape.basis {
        for source in 0..shape.basis {
            for a in 0..3 {
                kernel[shape.index(0, (target, a), (source, a))] += value;
            }
        }
    }
}

/// Calls `f(cell, r)` for every lattice vector `r = m c + shift` (`m`
/// integer, any size) with `0 < |r| <= reach`, `cell` being `m` modulo the
/// cells.
fn for_lattice_vectors(
    grid: &LatticeGrid,
    shift: &Vector3<f64>,
    reach: f64,
    mut f: impl FnMut(usize, &Vector3<f64>),
) {
    let c = &grid.cell_lengths;
    let range = |a: usize| {
        let lo = ((-reach - shift[a]) / c[a]).ceil() as i64;
        let hi = ((reach - shift[a]) / c[a]).floor() as i64;
        lo..=hi
    };
    let m_count = grid.cells.map(|m| m as i64);
    for mx in range(0) {
        for my in range(1) {
            for mz in range(2) {
                let r = Vector3::new(
                    mx as f64 * c.x + shift.x,
                    my as f64 * c.y + shift.y,
                    mz as f64 * c.z + shift.z,
                );
                let r2 = r.norm_squared();
                if r2 == 0.0 || r2 > reach * reach {
                    continue;
                }
                let wrap = |m: i64, a: usize| m.rem_euclid(m_count[a]) as usize;
                let cell =
                    (wrap(mx, 0) * grid.cells[1] + wrap(my, 1)) * grid.cells[2] + wrap(mz, 2);
                f(cell, &r);
            }
        }
    }
}

/// Adds the reciprocal-space part of `K^_{target, source}(q) / N_cells` at every frequency.
#[allow(clippy::too_many_arguments)]
fn add_reciprocal(
    kernel: &mut [C64],
    plan: &RealFft3,
    grid: &LatticeGrid,
    box_lengths: &Vector3<f64>,
    p: &EwaldParameters,
    units: &[(Vector3<f64>, Matrix3<f64>)],
    (dipoles, quadrupoles): (bool, bool),
    (target, source, shift): (usize, usize, &Vector3<f64>),
) {
    let b = grid.basis.len();
    let fields = 3 * dipoles as usize + 6 * quadrupoles as usize;
    let sources = units.len();
    let [nx, ny, nz] = plan.dims();
    let volume = box_lengths.product();
    // The frequency index folded into (-n/2, n/2], so that k = q + K is
    // formed without cancellation (any representative of q modulo the
    // cells' reciprocal lattice gives the same wave vectors k).
    let signed = |j: usize, n: usize| {
        if 2 * j <= n {
            j as f64
        } else {
            j as f64 - n as f64
        }
    };
    for jz in 0..nz / 2 + 1 {
        for jy in 0..ny {
            for jx in 0..nx {
                let q = Vector3::new(
                    2.0 * PI * signed(jx, nx) / box_lengths.x,
                    2.0 * PI * signed(jy, ny) / box_lengths.y,
                    2.0 * PI * jz as f64 / box_lengths.z,
                );
                let index = plan.spectrum_index([jx, jy, jz]);
                for_reciprocal_vectors(&q, p.reciprocal_cutoff, &grid.cell_lengths, |k, k2| {
                    let weight = 4.0 * PI / volume * mode_weight(p.alpha, k2);
                    let phase = C64::from_polar(weight, k.dot(shift));
                    let kk = k * k.transpose();
                    for (ci, (mu, theta)) in units.iter().enumerate() {
                        // phi = -i mu.k - 1/3 k.Theta.k; E = -i k phi; W = -1/3 k k^T phi.
                        let phi = C64::new(-k.dot(&(theta * k)) / 3.0, -mu.dot(k));
                        let e = k.map(|x| C64::new(0.0, -x) * phi);
                        let w = kk.map(|x| C64::new(-x / 3.0, 0.0) * phi);
                        for (f, v) in field_components(dipoles, quadrupoles, &e, &w)
                            .into_iter()
                            .enumerate()
                        {
                            let at =
                                kernel_index(index, (target, f), (source, ci), b, sources, fields);
                            kernel[at] += v * phase;
                        }
                    }
                });
            }
        }
    }
}

/// Calls `f(k, |k|^2)` for every wave vector `k = q + K` (`K` of the
/// reciprocal lattice of the cells of edges `c`) with `0 < |k| <= kc`.
fn for_reciprocal_vectors(
    q: &Vector3<f64>,
    kc: f64,
    c: &Vector3<f64>,
    mut f: impl FnMut(&Vector3<f64>, f64),
) {
    let range = |a: usize| {
        let step = 2.0 * PI / c[a];
        (((-kc - q[a]) / step).ceil() as i64)..=(((kc - q[a]) / step).floor() as i64)
    };
    for hx in range(0) {
        for hy in range(1) {
            for hz in range(2) {
                let k = q + Vector3::new(
                    2.0 * PI * hx as f64 / c.x,
                    2.0 * PI * hy as f64 / c.y,
                    2.0 * PI * hz as f64 / c.z,
                );
                let k2 = k.norm_squared();
                if k2 == 0.0 || k2 > kc * kc {
                    continue;
                }
                f(&k, k2);
            }
        }
    }
}
