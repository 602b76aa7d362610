//! The lattice sum by FFT: on a lattice of the box ([`super::lattice_grid`])
//! the fields at slot `(m, b)` (cell `m`, basis offset `b`) are a discrete
//! circular convolution over the cells,
//! `F_b(m) = sum_{m', b'} K_{b b'}(m - m') p_{b'}(m')`, of the multipoles
//! `p` (zero in empty slots) with one fixed tensor per basis pair,
//! `K_{b b'}(d) = sum_n T(d c + s_b - s_b' + n L)`, `T` the linear map from
//! a source's dipole and quadrupole to a target's `E` and `W` at their
//! offset. So `F^_b(q) = sum_b' K^_{b b'}(q) p^_{b'}(q)` on the FFT grid of
//! the cells, and one evaluation is `B C` forward and `B F` inverse real 3D
//! FFTs (`C` = 3 dipole and/or 5 quadrupole components, `F` = 3 field and/or
//! 6 gradient components) and `B^2 C F` products per frequency: `O(N log N)`
//! whatever the cutoff or accuracy.
//!
//! `K^` is built once:
//!
//! * truncated sum: `T` is the bare interaction tensor over every image with
//!   `0 < |r| <= cutoff`, placed on the cell grid and transformed;
//! * Ewald sum (Laino & Hutter 2008, for the reciprocal part per basis
//!   pair): the real-space tensor on `erfc(alpha r)/r` within `r_c` and the
//!   self term on the grid, transformed, plus the reciprocal part added at
//!   each frequency `q` directly,
//!   `(4 pi / V) sum_K exp(-k^2 / 4 alpha^2) / k^2 P(k) exp(i k.(s_b - s_b'))`
//!   over `k = q + K != 0`, `|k| <= k_c`, `K` the cell's reciprocal lattice,
//!   `P(k)` the mode response of [`super::ewald_terms`]; the vacuum surface
//!   term adds `-4 pi / (3 V)` to the dipole-field block at `q = 0`.
//!
//! The memory is estimated before anything is allocated and refused above
//! [`MAX_FFT_BYTES`] or the memory limit of [`crate::memory`].

use super::ewald_parameters::{Cost, EwaldParameters};
use super::fft3::{ConvolveBuffers, RealFft3};
use super::kernels::{Lanes, MultipoleKind, SiteFields, SpaceMultipoles};
use super::lattice_grid::LatticeGrid;
use super::lattice_kernel::{build_kernel, KernelShape, C64};
use super::periodic_sum::ChosenSum;
use super::PotentialError;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::sync::{Mutex, PoisonError};

/// The most memory (bytes) the FFT lattice sum may hold: its kernel, the
/// buffers of one evaluation and those of the kernel's construction.
pub const MAX_FFT_BYTES: usize = 1 << 30;

/// The source components of one space-frame multipole (in the order of the
/// kernel's unit sources, `lattice_kernel.rs`).
fn source_components(
    dipoles: bool,
    mu: &Lanes,
    theta: Option<&Matrix3<f64>>,
) -> impl Iterator<Item = f64> {
    let d = dipoles.then(|| [mu[0], mu[1], mu[2]]);
    let q = theta.map(|t| [t.m11, t.m22, t.m12, t.m13, t.m23]);
    d.into_iter().flatten().chain(q.into_iter().flatten())
}

/// The FFT lattice sum of one lattice (see the module doc).
#[derive(Debug)]
pub(crate) struct LatticeFft {
    grid: LatticeGrid,
    plan: RealFft3,
    dipoles: bool,
    quadrupoles: bool,
    sources: usize,
    fields: usize,
    /// `K^ / N_cells` per frequency, as `[b][f][b'][c]`
    /// (see [`super::lattice_kernel::kernel_index`]).
    kernel: Vec<C64>,
    /// The site in each slot `(cell, basis)` at `cell * B + basis`, or [`EMPTY`].
    occupants: Vec<usize>,
    parameters: Option<EwaldParameters>,
    /// The convolution's buffers, sized once and kept between evaluations
    /// (no allocation, zeroing or page faults per evaluation), behind a
    /// lock: an evaluation writes them, and the potential evaluates through
    /// `&self`.
    buffers: Mutex<ConvolveBuffers>,
}

impl Clone for LatticeFft {
    fn clone(&self) -> Self {
        LatticeFft {
            grid: self.grid.clone(),
            plan: self.plan.clone(),
            kernel: self.kernel.clone(),
            occupants: self.occupants.clone(),
            buffers: Mutex::new(self.lock().clone()),
            ..*self
        }
    }
}

/// An empty slot in [`LatticeFft::occupants`].
const EMPTY: usize = usize::MAX;

/// Sites per rayon task when the fields are gathered.
const SITES_PER_TASK: usize = 256;

impl LatticeFft {
    /// The cost model of the kernel on `grid` in `box_lengths` (see
    /// [`Cost::LatticeFft`]), for [`super::PeriodicSum::choose`].
    pub fn cost(grid: &LatticeGrid, box_lengths: &Vector3<f64>) -> Cost {
        let b = grid.basis.len();
        Cost::LatticeFft {
            basis_pairs: (b * b) as f64,
            cell_volume: box_lengths.product() / grid.cell_count() as f64,
            spectrum: RealFft3::spectrum_len_of(grid.cells) as f64,
        }
    }

    /// Builds the transformed lattice tensor of `sum` (its Ewald parameters
    /// chosen with [`Self::cost`]), after checking its memory.
    pub fn new(
        grid: LatticeGrid,
        box_lengths: &Vector3<f64>,
        sum: ChosenSum,
        (dipoles, quadrupoles): (bool, bool),
    ) -> Result<Self, PotentialError> {
        let shape = KernelShape {
            basis: grid.basis.len(),
            sources: 3 * dipoles as usize + 5 * quadrupoles as usize,
            fields: 3 * dipoles as usize + 6 * quadrupoles as usize,
        };
        let plan = RealFft3::new(grid.cells);
        check_memory(&grid, &plan, &shape, (dipoles, quadrupoles))?;
        let occupants = occupants(&grid)?;
        let kernel = build_kernel(
            &grid,
            box_lengths,
            &sum,
            &plan,
            &shape,
            (dipoles, quadrupoles),
        );
        let b = grid.basis.len();
        let buffers = ConvolveBuffers::new(&plan, (b * shape.sources, b * shape.fields));
        Ok(LatticeFft {
            buffers: Mutex::new(buffers),
            grid,
            plan,
            dipoles,
            quadrupoles,
            sources: shape.sources,
            fields: shape.fields,
            kernel,
            occupants,
            parameters: sum.parameters,
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, ConvolveBuffers> {
        // A panic elsewhere leaves the buffers valid: each evaluation rewrites them.
        self.buffers.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The Ewald parameters of the kernel (`None` for a truncated sum).
    pub fn parameters(&self) -> Option<EwaldParameters> {
        self.parameters
    }

    /// The lattice the sum runs on.
    pub fn grid(&self) -> &LatticeGrid {
        &self.grid
    }

    /// The fields of every site: the multipoles scattered onto the grid
    /// lines, convolved with the kernel ([`RealFft3::convolve_into`], parallel
    /// on large grids), and gathered per site in parallel.
    pub fn fields<K: MultipoleKind>(&self, multipoles: &SpaceMultipoles) -> SiteFields {
        debug_assert_eq!(
            (K::DIPOLES, K::QUADRUPOLES),
            (self.dipoles, self.quadrupoles)
        );
        let b = self.grid.basis.len();
        let nz = self.grid.cells[2];
        let (c_count, f_count) = (self.sources, self.fields);
        let (bc, bf) = (b * c_count, b * f_count);
        let zero = Lanes::default();
        // The z lines of grid line l, one per (basis offset, component).
        let fill = |l: usize, lines: &mut [f64]| {
            lines.fill(0.0);
            for z in 0..nz {
                let cell = l * nz + z;
                for basis in 0..b {
                    let Some(i) = self.occupant(cell, basis) else {
                        continue;
                    };
                    let mu = if K::DIPOLES {
                        &multipoles.dipoles[i]
                    } else {
                        &zero
                    };
                    let theta = K::QUADRUPOLES.then(|| &multipoles.quadrupoles[i]);
                    for (c, v) in source_components(K::DIPOLES, mu, theta).enumerate() {
                        lines[(basis * c_count + c) * nz + z] = v;
                    }
                }
            }
        };
        // Each row of the kernel ([b][f] fixed) against the sources
        // ([b'][c]), frequency by frequency along the x line m.
        let nx = self.grid.cells[0];
        let multiply = |m: usize, sources: &[C64], fields: &mut [C64]| {
            for kx in 0..nx {
                let kernel = &self.kernel[(m * nx + kx) * bf * bc..][..bf * bc];
                for (tf, row) in kernel.chunks_exact(bc).enumerate() {
                    fields[tf * nx + kx] = row
                        .iter()
                        .enumerate()
                        .fold(C64::default(), |sum, (k, v)| sum + v * sources[k * nx + kx]);
                }
            }
        };
        let mut buffers = self.lock();
        let real = self
            .plan
            .convolve_into(&mut buffers, (bc, bf), fill, multiply);
        let mut out = SiteFields::zeros::<K>(self.grid.slots.len());
        let at = |i: usize, f: usize| {
            let (cell, basis) = self.grid.slots[i];
            real[((cell / nz) * bf + basis * f_count + f) * nz + cell % nz]
        };
        if K::DIPOLES {
            out.field
                .par_iter_mut()
                .with_min_len(SITES_PER_TASK)
                .enumerate()
                .for_each(|(i, e)| *e = Lanes([at(i, 0), at(i, 1), at(i, 2), 0.0]));
        }
        if K::QUADRUPOLES {
            let f = if K::DIPOLES { 3 } else { 0 };
            out.quadrupole_conjugate
                .par_iter_mut()
                .with_min_len(SITES_PER_TASK)
                .enumerate()
                .for_each(|(i, w)| {
                    let w_i = [0, 1, 2, 3, 4, 5].map(|k| at(i, f + k));
                    *w = Matrix3::new(
                        w_i[0], w_i[3], w_i[4], w_i[3], w_i[1], w_i[5], w_i[4], w_i[5], w_i[2],
                    );
                });
        }
        out
    }

    /// The site in slot `(cell, basis)`, if any.
    fn occupant(&self, cell: usize, basis: usize) -> Option<usize> {
        let i = self.occupants[cell * self.grid.basis.len() + basis];
        (i != EMPTY).then_some(i)
    }
}

/// Refuses a sum whose kernel and buffers would exceed [`MAX_FFT_BYTES`]
/// or the memory limit of [`crate::memory`] (path `rotors`).
fn check_memory(
    grid: &LatticeGrid,
    plan: &RealFft3,
    shape: &KernelShape,
    (dipoles, quadrupoles): (bool, bool),
) -> Result<(), PotentialError> {
    let KernelShape {
        basis: b,
        sources,
        fields,
    } = *shape;
    let output = grid.slots.len() * output_bytes_per_site(dipoles, quadrupoles);
    let [construction, evaluation] =
        memory_peaks(b, grid.cells, plan.spectrum_len(), sources, fields, output);
    let bytes = construction.max(evaluation);
    let [mx, my, mz] = grid.cells;
    if bytes > MAX_FFT_BYTES as f64 {
        return Err(PotentialError::new(
            "rotors",
            format!(
                "the FFT lattice sum of these {} rotors ({mx} x {my} x {mz} cells of {b} sites, \
                 {sources} multipole and {fields} field components) needs about {:.2} GB, \
                 more than the limit {:.2} GB",
                grid.slots.len(),
                bytes / 1e9,
                MAX_FFT_BYTES as f64 / 1e9
            ),
        ));
    }
    crate::memory::check("rotors", bytes).map_err(|e| {
        PotentialError::new(
            "rotors",
            format!(
                "the FFT lattice sum of these {} rotors ({mx} x {my} x {mz} cells of {b} sites) {}",
                grid.slots.len(),
                e.message
            ),
        )
    })
}

/// The site in each slot (see [`LatticeFft::occupants`]); refuses two
/// sites in one slot (the same site up to a lattice vector).
fn occupants(grid: &LatticeGrid) -> Result<Vec<usize>, PotentialError> {
    let b = grid.basis.len();
    let mut occupants = vec![EMPTY; grid.cell_count() * b];
    for (i, &(cell, basis)) in grid.slots.iter().enumerate() {
        let j = std::mem::replace(&mut occupants[cell * b + basis], i);
        if j != EMPTY {
            return Err(PotentialError::new(
                format!("rotors[{j}].site and rotors[{i}].site"),
                "coincide (periodic images included)",
            ));
        }
    }
    Ok(occupants)
}

/// Bytes of one site's fields as an evaluation returns them ([`SiteFields`]).
fn output_bytes_per_site(dipoles: bool, quadrupoles: bool) -> usize {
    dipoles as usize * size_of::<Lanes>() + quadrupoles as usize * size_of::<Matrix3<f64>>()
}

/// The bytes held at the two peaks of the sum on a grid of `axes` cells:
/// while it is built (the kernel with the construction's buffers, or with
/// the convolution's buffers, allocated at its end, [`ConvolveBuffers::new`])
/// and while it evaluates (the kernel, the convolution's buffers and the
/// fields an evaluation returns, `output`). The kernel includes the slots' occupants
/// and the plans (two complex twiddle factors per point of each axis).
fn memory_peaks(
    b: usize,
    axes: [usize; 3],
    spectrum: usize,
    sources: usize,
    fields: usize,
    output: usize,
) -> [f64; 2] {
    let cells = axes.iter().product::<usize>() as f64;
    let plans = axes.iter().sum::<usize>() as f64 * 2.0 * 16.0;
    let (b, spectrum) = (b as f64, spectrum as f64);
    let (c, f) = (sources as f64, fields as f64);
    let kernel = spectrum * b * b * c * f * 16.0 + cells * b * 8.0 + plans;
    let buffers = 2.0 * c.max(f) * b * spectrum * 16.0 + f * b * cells * 8.0;
    let construction = c * f * cells * 8.0 + 2.0 * spectrum * 16.0;
    [
        kernel + construction.max(buffers),
        kernel + buffers + output as f64,
    ]
}

#[cfg(test)]
mod tests {
    use super::super::ewald::EwaldSum;
    use super::super::kernels::{Dipoles, DipolesAndQuadrupoles, Quadrupoles};
    use super::super::lattice_grid::detect;
    use super::super::{Accuracy, PeriodicSum, Surface};
    use super::*;
    use crate::allocation_meter::peak_above_start;
    use crate::lattice::{Lattice, LatticeKind};

    /// The estimates and the measured peaks of the bytes a sum holds: while
    /// it is built, and while it evaluates (its kernel held).
    fn estimate_and_peak<K: MultipoleKind>(
        kind: LatticeKind,
        cells: usize,
    ) -> ([f64; 2], [usize; 2]) {
        let lattice = Lattice::cubic(kind, cells, 1.0).unwrap();
        let grid = detect(&lattice.sites, &lattice.box_lengths).unwrap();
        let n = grid.slots.len();
        let multipoles = SpaceMultipoles {
            dipoles: if K::DIPOLES {
                (0..n)
                    .map(|i| Lanes([1.0, (i as f64).sin(), 0.5, 0.0]))
                    .collect()
            } else {
                Vec::new()
            },
            quadrupoles: if K::QUADRUPOLES {
                vec![Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0)); n]
            } else {
                Vec::new()
            },
        };
        let kinds = (K::DIPOLES, K::QUADRUPOLES);
        let cost = LatticeFft::cost(&grid, &lattice.box_lengths);
        let tensor = PeriodicSum::Cutoff { cutoff: 2.0 }
            .choose(0.0, kinds, cost, &lattice.box_lengths)
            .unwrap();
        let (sum, built_peak, held) =
            peak_above_start(|| LatticeFft::new(grid, &lattice.box_lengths, tensor, kinds));
        let sum = sum.unwrap();
        let one_thread = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let (out, evaluation_peak, _) =
            one_thread.install(|| peak_above_start(|| sum.fields::<K>(&multipoles)));
        assert_eq!(
            out.field.len() + out.quadrupole_conjugate.len(),
            n * (kinds.0 as usize + kinds.1 as usize)
        );
        let estimates = memory_peaks(
            sum.grid.basis.len(),
            sum.grid.cells,
            sum.plan.spectrum_len(),
            sum.sources,
            sum.fields,
            n * output_bytes_per_site(kinds.0, kinds.1),
        );
        (estimates, [built_peak, held + evaluation_peak])
    }

    /// The estimates that the memory limits are checked against (the larger
    /// of the two) are the peaks the sum really holds, measured by the test
    /// build's counting allocator, within 1 %, the construction's and the
    /// evaluation's each: they leave out only the plans' headers, the
    /// transforms' scratch lines and a few vectors of a hundred bytes. All
    /// on one thread.
    #[test]
    fn the_memory_estimate_is_the_measured_peak() {
        const LEFT_OUT: f64 = 0.01;
        for (name, (estimates, peaks)) in [
            (
                "sc dipoles",
                estimate_and_peak::<Dipoles>(LatticeKind::SimpleCubic, 8),
            ),
            (
                "sc quadrupoles",
                estimate_and_peak::<Quadrupoles>(LatticeKind::SimpleCubic, 8),
            ),
            (
                "sc both",
                estimate_and_peak::<DipolesAndQuadrupoles>(LatticeKind::SimpleCubic, 8),
            ),
            (
                "fcc both",
                estimate_and_peak::<DipolesAndQuadrupoles>(LatticeKind::Fcc, 4),
            ),
            (
                "bcc dipoles",
                estimate_and_peak::<Dipoles>(LatticeKind::Bcc, 6),
            ),
        ] {
            for (stage, (estimate, peak)) in ["built", "evaluating"]
                .iter()
                .zip(estimates.iter().zip(peaks))
            {
                assert!(
                    (peak as f64 - estimate).abs() <= LEFT_OUT * estimate,
                    "{name}, {stage}: estimate {estimate}, peak {peak}"
                );
            }
        }
    }

    /// Dipoles and traceless quadrupoles of `n` sites, varied from site to site.
    fn mixed_multipoles(n: usize) -> SpaceMultipoles {
        SpaceMultipoles {
            dipoles: (0..n)
                .map(|i| {
                    let t = i as f64;
                    Lanes([t.sin(), (1.7 * t).cos(), 0.3 - (0.4 * t).sin(), 0.0])
                })
                .collect(),
            quadrupoles: (0..n)
                .map(|i| {
                    let t = 0.9 * i as f64;
                    let (a, b) = (t.sin(), t.cos());
                    Matrix3::new(
                        a,
                        0.2 * b,
                        -0.4,
                        0.2 * b,
                        b - 0.5,
                        0.3 * a,
                        -0.4,
                        0.3 * a,
                        0.5 - a - b,
                    )
                })
                .collect(),
        }
    }

    /// At any accuracy, the FFT lattice sum is the direct Ewald sum with the
    /// same parameters (the same real-space images within `r_c`, the same
    /// wave vectors within `k_c`, self and surface terms), to round-off:
    /// here at accuracy 1e-3, where a wave-vector shell missed at `k_c`
    /// changes the fields by 4e-7 to 1e-5 of their largest entry (measured
    /// by dropping one), far above round-off. Cells
    /// of 0.55 (reciprocal steps above 2 pi) and of 7.5 (below 1), fcc, a
    /// vacancy, both surfaces.
    #[test]
    fn equals_the_direct_ewald_sum_with_its_parameters() {
        const ROUND_OFF: f64 = 1e-11;
        let sc = |m: usize, a: f64| Lattice::cubic(LatticeKind::SimpleCubic, m, a).unwrap();
        for (name, lattice) in [
            ("sc of 7.5", sc(3, 7.5)),
            (
                "bcc of 0.55",
                Lattice::cubic(LatticeKind::Bcc, 2, 0.55).unwrap(),
            ),
            (
                "fcc of 1.4",
                Lattice::cubic(LatticeKind::Fcc, 2, 1.4).unwrap(),
            ),
        ] {
            let mut sites = lattice.sites.clone();
            let _vacancy = sites.remove(3);
            let n = sites.len();
            let multipoles = mixed_multipoles(n);
            for surface in [Surface::Conducting, Surface::Vacuum] {
                let grid = detect(&sites, &lattice.box_lengths).unwrap();
                let density = n as f64 / lattice.box_lengths.product();
                let cost = LatticeFft::cost(&grid, &lattice.box_lengths);
                let sum = PeriodicSum::Ewald {
                    accuracy: Accuracy::new(1e-3).unwrap(),
                    surface,
                }
                .choose(density, (true, true), cost, &lattice.box_lengths)
                .unwrap();
                let fft = LatticeFft::new(grid, &lattice.box_lengths, sum, (true, true)).unwrap();
                let parameters = fft.parameters().unwrap();
                let direct =
                    EwaldSum::with_parameters(&sites, lattice.box_lengths, parameters, surface)
                        .unwrap();
                let (a, b) = (
                    fft.fields::<DipolesAndQuadrupoles>(&multipoles),
                    direct.fields::<DipolesAndQuadrupoles>(&multipoles),
                );
                let e_scale = b
                    .field
                    .iter()
                    .flat_map(|e| e.0)
                    .fold(0.0, |m: f64, x| m.max(x.abs()));
                let w_scale = b
                    .quadrupole_conjugate
                    .iter()
                    .fold(0.0, |m: f64, w| m.max(w.amax()));
                assert!(e_scale > 0.0 && w_scale > 0.0, "{name}");
                for i in 0..n {
                    for k in 0..3 {
                        let d = (a.field[i][k] - b.field[i][k]).abs();
                        assert!(
                            d <= ROUND_OFF * e_scale,
                            "{name}, {surface:?}: E of {i}: {d:e} of {e_scale:e}"
                        );
                    }
                    let d = (a.quadrupole_conjugate[i] - b.quadrupole_conjugate[i]).amax();
                    assert!(
                        d <= ROUND_OFF * w_scale,
                        "{name}, {surface:?}: W of {i}: {d:e} of {w_scale:e}"
                    );
                }
            }
        }
    }
}
