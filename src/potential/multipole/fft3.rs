//! Three-dimensional real-to-complex FFTs on an `n_x x n_y x n_z` grid:
//! `realfft` along z, then `rustfft` along y and x, each axis as a batch of
//! contiguous lines (the data is transposed between the axes). Large grids
//! split their lines among the rayon threads. [`RealFft3::convolve_into`] runs a
//! whole convolution (forward transforms, products per frequency, inverse
//! transforms of several grids) in five parallel passes.
//!
//! Layouts: a real field is `[x][y][z]`; its half spectrum (the `n_z / 2 + 1`
//! non-negative z frequencies) is `[k_z][k_y][k_x]`. The transforms are
//! unnormalised: the inverse of the forward transform is `n_x n_y n_z f`.

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// Grids with fewer points run on the calling thread (threads cost more).
const PARALLEL_MIN: usize = 1 << 15;

/// [`RealFft3::convolve_into`] runs on the calling thread below this many grid
/// points (over all its source and field grids).
const CONVOLVE_PARALLEL_MIN: usize = 2048;

/// Tasks per thread in a pass of [`RealFft3::convolve_into`].
const TASKS_PER_THREAD: usize = 2;

type C64 = Complex<f64>;

/// The plans for one grid (see the module doc).
#[derive(Clone)]
pub(crate) struct RealFft3 {
    n: [usize; 3],
    half: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    /// Forward and inverse transforms along x and along y.
    x: [Arc<dyn Fft<f64>>; 2],
    y: [Arc<dyn Fft<f64>>; 2],
}

impl std::fmt::Debug for RealFft3 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "RealFft3 {:?}", self.n)
    }
}

/// The buffers of [`RealFft3::convolve_into`]: two complex ones, used in
/// turn by its passes, and the real result, sized once and kept between
/// convolutions.
#[derive(Clone, Debug)]
pub(crate) struct ConvolveBuffers {
    a: Vec<C64>,
    b: Vec<C64>,
    real: Vec<f64>,
}

impl ConvolveBuffers {
    /// Buffers for convolutions of `(sources, fields)` grids with `plan`.
    pub fn new(plan: &RealFft3, (sources, fields): (usize, usize)) -> Self {
        let complex = plan.spectrum_len() * sources.max(fields);
        let points: usize = plan.n.iter().product();
        ConvolveBuffers {
            a: Vec::with_capacity(complex),
            b: Vec::with_capacity(complex),
            real: Vec::with_capacity(points * fields),
        }
    }
}

/// Makes `buffer` `len` long. Every value is overwritten by the pass, so
/// the values it keeps from the last convolution are left there (only a
/// buffer growing past its length is zeroed, in its new part).
fn ready<T: Clone + Default>(buffer: &mut Vec<T>, len: usize) {
    buffer.resize(len, T::default());
}

/// Runs `f(lines, scratch)` on batches of whole lines of `buffer`, in
/// parallel for large grids, each task with its own scratch.
fn for_lines<T: Send>(
    buffer: &mut [T],
    line: usize,
    scratch_len: usize,
    f: impl Fn(&mut [T], &mut [C64]) + Sync,
) {
    if buffer.len() < PARALLEL_MIN {
        let mut scratch = vec![C64::default(); scratch_len];
        f(buffer, &mut scratch);
        return;
    }
    let lines = buffer.len() / line;
    let per_task = lines.div_ceil(4 * rayon::current_num_threads()).max(1);
    buffer.par_chunks_mut(per_task * line).for_each_init(
        || vec![C64::default(); scratch_len],
        |scratch, chunk| f(chunk, scratch),
    );
}

/// Runs `f(first, units, scratch)` on runs of whole units (`unit` values
/// each) of `buffer`, `first` the index of the run's first unit: one call on
/// the calling thread when not `parallel` or on one thread, otherwise
/// [`TASKS_PER_THREAD`] runs per thread of the pool, each task with its own
/// scratch.
fn for_units<T: Send, S>(
    buffer: &mut [T],
    unit: usize,
    parallel: bool,
    scratch: impl Fn() -> S + Sync + Send,
    f: impl Fn(usize, &mut [T], &mut S) + Sync + Send,
) {
    let threads = rayon::current_num_threads();
    if !parallel || threads == 1 || buffer.is_empty() {
        f(0, buffer, &mut scratch());
        return;
    }
    let units = buffer.len() / unit;
    let per_task = units.div_ceil(TASKS_PER_THREAD * threads).max(1);
    buffer
        .par_chunks_mut(per_task * unit)
        .enumerate()
        .for_each_init(scratch, |s, (k, run)| f(k * per_task, run, s));
}

/// `to[(a * n_c + c) * n_b + b] = from[(a * n_b + b) * n_c + c]`: swaps the
/// two inner axes of an `n_a x n_b x n_c` array.
fn swap_inner(from: &[C64], to: &mut [C64], n_b: usize, n_c: usize) {
    let plane = n_b * n_c;
    let swap = |(from, to): (&[C64], &mut [C64])| {
        for b in 0..n_b {
            for c in 0..n_c {
                to[c * n_b + b] = from[b * n_c + c];
            }
        }
    };
    if from.len() < PARALLEL_MIN {
        from.chunks(plane).zip(to.chunks_mut(plane)).for_each(swap);
    } else {
        from.par_chunks(plane)
            .zip(to.par_chunks_mut(plane))
            .for_each(swap);
    }
}

/// `to[(c * n_a + a) * n_b + b] = from[(a * n_b + b) * n_c + c]`: moves the
/// innermost axis of an `n_a x n_b x n_c` array to the outside.
fn rotate(from: &[C64], to: &mut [C64], n_a: usize, n_b: usize, n_c: usize) {
    let move_plane = |(c, to): (usize, &mut [C64])| {
        for a in 0..n_a {
            for b in 0..n_b {
                to[a * n_b + b] = from[(a * n_b + b) * n_c + c];
            }
        }
    };
    if from.len() < PARALLEL_MIN {
        to.chunks_mut(n_a * n_b).enumerate().for_each(move_plane);
    } else {
        to.par_chunks_mut(n_a * n_b)
            .enumerate()
            .for_each(move_plane);
    }
}

impl RealFft3 {
    pub fn new(n: [usize; 3]) -> Self {
        let mut real = RealFftPlanner::<f64>::new();
        let mut complex = FftPlanner::<f64>::new();
        RealFft3 {
            n,
            half: n[2] / 2 + 1,
            r2c: real.plan_fft_forward(n[2]),
            c2r: real.plan_fft_inverse(n[2]),
            x: [
                complex.plan_fft_forward(n[0]),
                complex.plan_fft_inverse(n[0]),
            ],
            y: [
                complex.plan_fft_forward(n[1]),
                complex.plan_fft_inverse(n[1]),
            ],
        }
    }

    /// Number of half-spectrum points, `n_x n_y (n_z / 2 + 1)`.
    pub fn spectrum_len(&self) -> usize {
        self.n[0] * self.n[1] * self.half
    }

    /// [`Self::spectrum_len`] of the plan for the grid `n`, without planning.
    pub fn spectrum_len_of(n: [usize; 3]) -> usize {
        n[0] * n[1] * (n[2] / 2 + 1)
    }

    /// The grid size.
    pub fn dims(&self) -> [usize; 3] {
        self.n
    }

    /// The half-spectrum index of frequencies `(k_x, k_y, k_z)` (non-negative, `k_z <= n_z / 2`).
    pub fn spectrum_index(&self, k: [usize; 3]) -> usize {
        (k[2] * self.n[1] + k[1]) * self.n[0] + k[0]
    }

    /// The half spectrum of `field` into `spectrum`, with `work` (both
    /// `spectrum_len()` long).
    pub fn forward(&self, field: &[f64], spectrum: &mut [C64], work: &mut [C64]) {
        let [nx, ny, nz] = self.n;
        let half = self.half;
        // z: [x][y][z] -> [x][y][kz]
        let r2c = &self.r2c;
        for_units(
            spectrum,
            half,
            field.len() >= PARALLEL_MIN,
            || (vec![0.0; nz], vec![C64::default(); r2c.get_scratch_len()]),
            |first, out, (line, scratch)| {
                for (l, output) in out.chunks_mut(half).enumerate() {
                    line.copy_from_slice(&field[(first + l) * nz..][..nz]);
                    r2c.process_with_scratch(line, output, scratch)
                        .expect("line lengths match the plan");
                }
            },
        );
        // y: -> [kz][x][y], transform, -> [kz][ky][x]... see below
        rotate(spectrum, work, nx, ny, half);
        self.lines(&self.y[0], work, ny);
        swap_inner(work, spectrum, nx, ny);
        self.lines(&self.x[0], spectrum, nx);
        debug_assert_eq!(spectrum.len(), nx * ny * half);
    }

    /// The batched circular convolution of `sources` real grids into
    /// `fields` real grids, in five passes over grid lines (each one parallel
    /// section on large grids, see [`for_units`]): `fill(l, lines)` writes
    /// the `sources` real z lines `[g][z]` of grid line `l = x n_y + y`; each
    /// is transformed along z, then y, then x; `multiply(m, s, f)` turns the
    /// x lines `s` (`[g][k_x]`) of `m = k_z n_y + k_y` into the field x lines
    /// `f` (`[t][k_x]`); those are transformed back along x, y and z.
    /// Returns the real fields (times `n_x n_y n_z`) as `[l][t][z]`, in
    /// `buffers` (nothing mesh-sized is allocated when they were made for
    /// these grids by [`ConvolveBuffers::new`]; the transforms' line
    /// scratch still is).
    ///
    /// Each line is transformed on its own and the gathers are copies, so
    /// the result does not depend on the number of threads or tasks. The
    /// imaginary parts that a real field's spectrum lacks (its `k_z = 0` and
    /// `k_z = n_z / 2` planes after the x and y transforms) are dropped.
    pub fn convolve_into<'a>(
        &self,
        buffers: &'a mut ConvolveBuffers,
        (sources, fields): (usize, usize),
        fill: impl Fn(usize, &mut [f64]) + Sync,
        multiply: impl Fn(usize, &[C64], &mut [C64]) + Sync,
    ) -> &'a [f64] {
        let [nx, ny, nz] = self.n;
        let half = self.half;
        let parallel = (sources + fields) * nx * ny * nz >= CONVOLVE_PARALLEL_MIN;
        let ConvolveBuffers { a, b, real } = buffers;
        let source_len = nx * ny * sources * half;
        let field_len = nx * ny * fields * half;
        // z: [x y][g][kz] in a.
        ready(a, source_len);
        self.forward_z(sources, parallel, fill, a);
        // y: [kz x][g][y] in b, gathered from [x y][g][kz].
        ready(b, source_len);
        self.y_pass(&self.y[0], sources, parallel, b, |kz, x, g, y| {
            a[((x * ny + y) * sources + g) * half + kz]
        });
        // x and the products: [kz ky][t][x] in a.
        ready(a, field_len);
        self.x_products(b, (sources, fields), parallel, multiply, a);
        // y back: [kz x][t][y] in b, gathered from [kz ky][t][x].
        ready(b, field_len);
        self.y_pass(&self.y[1], fields, parallel, b, |kz, x, t, ky| {
            a[((kz * ny + ky) * fields + t) * nx + x]
        });
        ready(real, nx * ny * fields * nz);
        self.inverse_z(b, fields, parallel, real);
        real
    }

    /// The first pass of [`Self::convolve_into`]: the `sources` real z lines of
    /// each grid line `l`, written by `fill`, transformed along z, as
    /// `[l][g][kz]`.
    fn forward_z(
        &self,
        sources: usize,
        parallel: bool,
        fill: impl Fn(usize, &mut [f64]) + Sync,
        along_z: &mut [C64],
    ) {
        let nz = self.n[2];
        let half = self.half;
        let r2c = &self.r2c;
        for_units(
            along_z,
            sources * half,
            parallel,
            || {
                (
                    vec![0.0; sources * nz],
                    vec![C64::default(); r2c.get_scratch_len()],
                )
            },
            |first, out, (real, scratch)| {
                for (l, out) in out.chunks_mut(sources * half).enumerate() {
                    fill(first + l, real);
                    for (input, output) in real.chunks_mut(nz).zip(out.chunks_mut(half)) {
                        r2c.process_with_scratch(input, output, scratch)
                            .expect("line lengths match the plan");
                    }
                }
            },
        );
    }

    /// The middle pass of [`Self::convolve_into`]: x transforms of the sources'
    /// lines gathered from `along_y` (`[kz x][g][y]`), the products
    /// `multiply`, and the fields' x lines transformed back, as
    /// `[kz ky][t][x]`.
    fn x_products(
        &self,
        along_y: &[C64],
        (sources, fields): (usize, usize),
        parallel: bool,
        multiply: impl Fn(usize, &[C64], &mut [C64]) + Sync,
        spectra: &mut [C64],
    ) {
        let [nx, ny, _] = self.n;
        let x_scratch =
            (self.x[0].get_inplace_scratch_len()).max(self.x[1].get_inplace_scratch_len());
        for_units(
            spectra,
            fields * nx,
            parallel,
            || {
                (
                    vec![C64::default(); sources * nx],
                    vec![C64::default(); x_scratch],
                )
            },
            |first, out, (s, scratch)| {
                for (m, out) in out.chunks_mut(fields * nx).enumerate() {
                    let (kz, ky) = ((first + m) / ny, (first + m) % ny);
                    for (g, line) in s.chunks_mut(nx).enumerate() {
                        for (x, v) in line.iter_mut().enumerate() {
                            *v = along_y[((kz * nx + x) * sources + g) * ny + ky];
                        }
                    }
                    self.x[0].process_with_scratch(s, scratch);
                    multiply(first + m, s, out);
                }
                self.x[1].process_with_scratch(out, scratch);
            },
        );
    }

    /// The last pass of [`Self::convolve_into`]: the `fields` real z lines of
    /// each grid line, gathered from `back_y` (`[kz x][t][y]`) and
    /// transformed back along z, as `[l][t][z]`.
    fn inverse_z(&self, back_y: &[C64], fields: usize, parallel: bool, real: &mut [f64]) {
        let [nx, ny, nz] = self.n;
        let half = self.half;
        let c2r = &self.c2r;
        for_units(
            real,
            fields * nz,
            parallel,
            || {
                (
                    vec![C64::default(); half],
                    vec![C64::default(); c2r.get_scratch_len()],
                )
            },
            |first, out, (line, scratch)| {
                for (l, out) in out.chunks_mut(fields * nz).enumerate() {
                    let (x, y) = ((first + l) / ny, (first + l) % ny);
                    for (t, output) in out.chunks_mut(nz).enumerate() {
                        for (kz, v) in line.iter_mut().enumerate() {
                            *v = back_y[((kz * nx + x) * fields + t) * ny + y];
                        }
                        line[0].im = 0.0;
                        if nz % 2 == 0 {
                            line[half - 1].im = 0.0;
                        }
                        c2r.process_with_scratch(line, output, scratch)
                            .expect("line lengths match the plan");
                    }
                }
            },
        );
    }

    /// A y pass of [`Self::convolve_into`]: the `[kz x][g][y]` lines of `grids`
    /// grids, each value `at(kz, x, g, y)`, transformed by `fft`.
    fn y_pass(
        &self,
        fft: &Arc<dyn Fft<f64>>,
        grids: usize,
        parallel: bool,
        out: &mut [C64],
        at: impl Fn(usize, usize, usize, usize) -> C64 + Sync,
    ) {
        let [nx, ny, _] = self.n;
        for_units(
            out,
            grids * ny,
            parallel,
            || vec![C64::default(); fft.get_inplace_scratch_len()],
            |first, out, scratch| {
                for (p, out) in out.chunks_mut(grids * ny).enumerate() {
                    let (kz, x) = ((first + p) / nx, (first + p) % nx);
                    for (g, line) in out.chunks_mut(ny).enumerate() {
                        for (y, v) in line.iter_mut().enumerate() {
                            *v = at(kz, x, g, y);
                        }
                    }
                }
                fft.process_with_scratch(out, scratch);
            },
        );
    }

    /// `fft` on every line of `len` points of `buffer`.
    fn lines(&self, fft: &Arc<dyn Fft<f64>>, buffer: &mut [C64], len: usize) {
        for_lines(
            buffer,
            len,
            fft.get_inplace_scratch_len(),
            |lines, scratch| {
                fft.process_with_scratch(lines, scratch);
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    impl RealFft3 {
        /// [`RealFft3::convolve_into`] into buffers of its own.
        fn convolve(
            &self,
            grids: (usize, usize),
            fill: impl Fn(usize, &mut [f64]) + Sync,
            multiply: impl Fn(usize, &[C64], &mut [C64]) + Sync,
        ) -> Vec<f64> {
            let mut buffers = ConvolveBuffers::new(self, grids);
            let _ = self.convolve_into(&mut buffers, grids, fill, multiply);
            buffers.real
        }
    }

    /// `a f + b g` for two grids `f`, `g` (the linear map of a convolution
    /// with a constant kernel), as `convolve` returns them, divided by `N`.
    fn linear_map(plan: &RealFft3, grids: [&[f64]; 2], weights: &[[f64; 2]]) -> Vec<Vec<f64>> {
        let [nx, ny, nz] = plan.dims();
        let fields = weights.len();
        let real = plan.convolve(
            (2, fields),
            |l, lines| {
                for (g, line) in lines.chunks_mut(nz).enumerate() {
                    line.copy_from_slice(&grids[g][l * nz..(l + 1) * nz]);
                }
            },
            |_, s, f| {
                for (t, w) in weights.iter().enumerate() {
                    for kx in 0..nx {
                        f[t * nx + kx] = s[kx] * w[0] + s[nx + kx] * w[1];
                    }
                }
            },
        );
        let total = (nx * ny * nz) as f64;
        (0..fields)
            .map(|t| {
                (0..nx * ny * nz)
                    .map(|cell| real[((cell / nz) * fields + t) * nz + cell % nz] / total)
                    .collect()
            })
            .collect()
    }

    /// Every value of the kept buffers is overwritten by the passes: buffers
    /// holding NaN from end to end, or left by a convolution of other grid
    /// counts, give the result of new buffers bit for bit (on an odd and an
    /// even z length, serial and parallel).
    #[test]
    fn kept_buffers_give_the_result_of_new_ones() {
        for n in [[3, 4, 5], [16, 16, 18]] {
            let plan = RealFft3::new(n);
            let [nx, _, nz] = n;
            let fill = |l: usize, lines: &mut [f64]| {
                for (g, line) in lines.chunks_mut(nz).enumerate() {
                    for (z, v) in line.iter_mut().enumerate() {
                        *v = ((l * 31 + z * 7 + g * 3) % 11) as f64 - 5.0;
                    }
                }
            };
            let multiply = |m: usize, s: &[C64], f: &mut [C64]| {
                for (t, out) in f.chunks_mut(nx).enumerate() {
                    for (kx, v) in out.iter_mut().enumerate() {
                        *v = s[kx] * (1.0 + (m + t) as f64) - s[nx + kx] * 0.5;
                    }
                }
            };
            let fresh = plan.convolve((2, 3), fill, multiply);
            let mut kept = ConvolveBuffers::new(&plan, (2, 3));
            kept.a
                .resize(kept.a.capacity(), C64::new(f64::NAN, f64::NAN));
            kept.b
                .resize(kept.b.capacity(), C64::new(f64::NAN, f64::NAN));
            kept.real.resize(kept.real.capacity(), f64::NAN);
            let first = plan
                .convolve_into(&mut kept, (2, 3), fill, multiply)
                .to_vec();
            let _ = plan.convolve_into(&mut kept, (2, 1), fill, |_, s, f| {
                f.copy_from_slice(&s[..nx])
            });
            let again = plan.convolve_into(&mut kept, (2, 3), fill, multiply);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&first), bits(&fresh), "{n:?}: buffers of NaN");
            assert_eq!(
                bits(again),
                bits(&fresh),
                "{n:?}: buffers of another convolution"
            );
        }
    }

    /// Three linear maps of two grids, `convolve` against the values computed
    /// directly, to the rounding of two transforms.
    fn assert_linear_maps(plan: &RealFft3, f: &[f64], g: &[f64], tolerance: f64) {
        let weights = [[1.0, 0.0], [0.0, 1.0], [0.5, -2.0]];
        for (t, got) in linear_map(plan, [f, g], &weights).iter().enumerate() {
            let [a, b] = weights[t];
            for (cell, v) in got.iter().enumerate() {
                let want = a * f[cell] + b * g[cell];
                assert!((v - want).abs() < tolerance, "field {t}, cell {cell}");
            }
        }
    }

    /// The forward transform equals the direct DFT `sum f(x) exp(-2 pi i k.x / n)`
    /// on odd and even grids; `convolve` with a constant kernel returns `N`
    /// times the linear map of its source grids, for each field grid.
    #[test]
    fn forward_matches_the_direct_dft_and_convolve_maps_grids() {
        for n in [[3, 4, 5], [4, 2, 6], [1, 1, 7]] {
            let plan = RealFft3::new(n);
            let total: usize = n.iter().product();
            let field: Vec<f64> = (0..total).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let other: Vec<f64> = (0..total).map(|i| ((i * 31) % 7) as f64 * 0.5).collect();
            let mut spectrum = vec![C64::default(); plan.spectrum_len()];
            let mut work = spectrum.clone();
            plan.forward(&field, &mut spectrum, &mut work);
            for kx in 0..n[0] {
                for ky in 0..n[1] {
                    for kz in 0..n[2] / 2 + 1 {
                        let mut direct = C64::default();
                        for x in 0..n[0] {
                            for y in 0..n[1] {
                                for z in 0..n[2] {
                                    let phase = -2.0
                                        * PI
                                        * ((kx * x) as f64 / n[0] as f64
                                            + (ky * y) as f64 / n[1] as f64
                                            + (kz * z) as f64 / n[2] as f64);
                                    direct += C64::from_polar(1.0, phase)
                                        * field[(x * n[1] + y) * n[2] + z];
                                }
                            }
                        }
                        let got = spectrum[plan.spectrum_index([kx, ky, kz])];
                        assert!((got - direct).norm() < 1e-12, "{n:?} {kx} {ky} {kz}");
                    }
                }
            }
            assert_linear_maps(&plan, &field, &other, 1e-13);
        }
    }

    /// A grid above [`PARALLEL_MIN`] and [`CONVOLVE_PARALLEL_MIN`]
    /// (48 x 40 x 64, and its half spectrum) takes the parallel paths. A sum
    /// of plane waves `a cos(2 pi k.x / n + phi)` has the closed-form
    /// spectrum `N a / 2 exp(i phi)` at `k` and its conjugate at `-k` (in
    /// the half spectrum only when `k_z = 0`), zero elsewhere; `convolve`
    /// returns `N` times the linear maps of two grids, and the same bits on
    /// one thread and on eight. Rounding: a few ulps of the largest entry per
    /// transform stage. Run in a pool of eight threads, as on a machine with
    /// more cores.
    #[test]
    fn large_grids_transform_plane_waves_exactly() {
        let n = [48, 40, 64];
        let plan = RealFft3::new(n);
        let total: usize = n.iter().product();
        assert!(total >= PARALLEL_MIN && plan.spectrum_len() >= PARALLEL_MIN);
        assert!(total >= CONVOLVE_PARALLEL_MIN);
        let waves = [
            ([3, 5, 7], 1.0, 0.3),
            ([47, 1, 20], 0.5, -1.1),
            ([10, 0, 0], 0.25, 0.7),
        ];
        let phase = |k: &[usize; 3], x: usize, y: usize, z: usize| {
            2.0 * PI
                * ((k[0] * x) as f64 / n[0] as f64
                    + (k[1] * y) as f64 / n[1] as f64
                    + (k[2] * z) as f64 / n[2] as f64)
        };
        let mut field = vec![0.0; total];
        for (x, y, z) in
            (0..n[0]).flat_map(|x| (0..n[1]).flat_map(move |y| (0..n[2]).map(move |z| (x, y, z))))
        {
            field[(x * n[1] + y) * n[2] + z] = waves
                .iter()
                .map(|(k, a, phi)| a * (phase(k, x, y, z) + phi).cos())
                .sum();
        }
        let mut expected = vec![C64::default(); plan.spectrum_len()];
        for (k, a, phi) in waves {
            let half = total as f64 * a / 2.0;
            expected[plan.spectrum_index(k)] += C64::from_polar(half, phi);
            if k[2] == 0 {
                let minus = [(n[0] - k[0]) % n[0], (n[1] - k[1]) % n[1], 0];
                expected[plan.spectrum_index(minus)] += C64::from_polar(half, -phi);
            }
        }
        let mut spectrum = vec![C64::default(); plan.spectrum_len()];
        let mut work = spectrum.clone();
        // Eight threads, more than this machine's cores, as on a larger machine.
        let pool = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
        };
        pool(8).install(|| plan.forward(&field, &mut spectrum, &mut work));
        let largest = total as f64 / 2.0;
        for (i, (got, want)) in spectrum.iter().zip(&expected).enumerate() {
            assert!(
                (got - want).norm() < 1e-12 * largest,
                "entry {i}: {got} vs {want}"
            );
        }
        let other: Vec<f64> = field.iter().map(|v| v * v - 0.25).collect();
        pool(8).install(|| assert_linear_maps(&plan, &field, &other, 1e-12));
        let weights = [[0.5, -2.0]];
        let on_eight = pool(8).install(|| linear_map(&plan, [&field, &other], &weights));
        let on_one = pool(1).install(|| linear_map(&plan, [&field, &other], &weights));
        assert!(on_eight[0]
            .iter()
            .zip(&on_one[0])
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
