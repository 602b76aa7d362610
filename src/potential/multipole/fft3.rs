//! Three-dimensional real-to-complex FFTs on an `n_x x n_y x n_z` grid:
//! `realfft` along z, then `rustfft` along y and x, each axis as a batch of
//! contiguous lines (the data is transposed between the axes). Large grids
//! split their lines among the rayon threads.
//!
//! Layouts: a real field is `[x][y][z]`; its half spectrum (the `n_z / 2 + 1`
//! non-negative z frequencies) is `[k_z][k_y][k_x]`. The transforms are
//! unnormalised: `inverse(forward(f)) = n_x n_y n_z f`.

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// Grids with fewer points run on the calling thread (threads cost more).
const PARALLEL_MIN: usize = 1 << 15;

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

/// The inverse of [`rotate`]: `to[(a * n_b + b) * n_c + c] = from[(c * n_a + a) * n_b + b]`.
fn unrotate(from: &[C64], to: &mut [C64], n_a: usize, n_b: usize, n_c: usize) {
    let fill = |(ab, to): (usize, &mut [C64])| {
        for (c, value) in to.iter_mut().enumerate() {
            *value = from[c * n_a * n_b + ab];
        }
    };
    if from.len() < PARALLEL_MIN {
        to.chunks_mut(n_c).enumerate().for_each(fill);
    } else {
        to.par_chunks_mut(n_c).enumerate().for_each(fill);
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

    /// The half spectrum of `field` (destroyed) into `spectrum`, with `work`
    /// (both `spectrum_len()` long).
    pub fn forward(&self, field: &mut [f64], spectrum: &mut [C64], work: &mut [C64]) {
        let [nx, ny, nz] = self.n;
        let half = self.half;
        // z: [x][y][z] -> [x][y][kz]
        let r2c = &self.r2c;
        let mut pairs: Vec<(&mut [f64], &mut [C64])> = field
            .chunks_mut(nz)
            .zip(spectrum.chunks_mut(half))
            .collect();
        for_lines(&mut pairs, 1, r2c.get_scratch_len(), |lines, scratch| {
            for (input, output) in lines.iter_mut() {
                r2c.process_with_scratch(input, output, scratch)
                    .expect("line lengths match the plan");
            }
        });
        // y: -> [kz][x][y], transform, -> [kz][ky][x]... see below
        rotate(spectrum, work, nx, ny, half);
        self.lines(&self.y[0], work, ny);
        swap_inner(work, spectrum, nx, ny);
        self.lines(&self.x[0], spectrum, nx);
        debug_assert_eq!(spectrum.len(), nx * ny * half);
    }

    /// The real field (times `n_x n_y n_z`) of `spectrum` (destroyed), with
    /// `work`. The imaginary parts that a real field's spectrum lacks (its
    /// `k_z = 0` and `k_z = n_z / 2` planes after the x and y transforms)
    /// are dropped.
    pub fn inverse(&self, spectrum: &mut [C64], field: &mut [f64], work: &mut [C64]) {
        let [nx, ny, nz] = self.n;
        let half = self.half;
        self.lines(&self.x[1], spectrum, nx);
        swap_inner(spectrum, work, ny, nx);
        self.lines(&self.y[1], work, ny);
        unrotate(work, spectrum, nx, ny, half);
        let c2r = &self.c2r;
        let mut pairs: Vec<(&mut [C64], &mut [f64])> = spectrum
            .chunks_mut(half)
            .zip(field.chunks_mut(nz))
            .collect();
        for_lines(&mut pairs, 1, c2r.get_scratch_len(), |lines, scratch| {
            for (input, output) in lines.iter_mut() {
                input[0].im = 0.0;
                if nz % 2 == 0 {
                    input[half - 1].im = 0.0;
                }
                c2r.process_with_scratch(input, output, scratch)
                    .expect("line lengths match the plan");
            }
        });
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

    /// The forward transform equals the direct DFT `sum f(x) exp(-2 pi i k.x / n)`
    /// on an odd and an even grid, and the inverse returns `n f`.
    #[test]
    fn forward_matches_the_direct_dft_and_inverse_inverts() {
        for n in [[3, 4, 5], [4, 2, 6], [1, 1, 7]] {
            let plan = RealFft3::new(n);
            let total: usize = n.iter().product();
            let field: Vec<f64> = (0..total).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let mut input = field.clone();
            let mut spectrum = vec![C64::default(); plan.spectrum_len()];
            let mut work = spectrum.clone();
            plan.forward(&mut input, &mut spectrum, &mut work);
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
            let mut back = vec![0.0; total];
            plan.inverse(&mut spectrum, &mut back, &mut work);
            for (a, b) in back.iter().zip(&field) {
                assert!((a / total as f64 - b).abs() < 1e-13);
            }
        }
    }

    /// A grid above [`PARALLEL_MIN`] (48 x 40 x 64, and its half spectrum)
    /// takes the parallel paths. A sum of plane waves
    /// `a cos(2 pi k.x / n + phi)` has the closed-form spectrum
    /// `N a / 2 exp(i phi)` at `k` and its conjugate at `-k` (in the half
    /// spectrum only when `k_z = 0`), zero elsewhere; the inverse returns
    /// `N f`. Rounding: a few ulps of the largest entry per transform stage.
    /// Run in a pool of eight threads, as on a machine with more cores.
    #[test]
    fn large_grids_transform_plane_waves_exactly() {
        let n = [48, 40, 64];
        let plan = RealFft3::new(n);
        let total: usize = n.iter().product();
        assert!(total >= PARALLEL_MIN && plan.spectrum_len() >= PARALLEL_MIN);
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
        let mut input = field.clone();
        let mut spectrum = vec![C64::default(); plan.spectrum_len()];
        let mut work = spectrum.clone();
        // Eight threads, more than this machine's cores, as on a larger machine.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(8)
            .build()
            .unwrap();
        pool.install(|| plan.forward(&mut input, &mut spectrum, &mut work));
        let largest = total as f64 / 2.0;
        for (i, (got, want)) in spectrum.iter().zip(&expected).enumerate() {
            assert!(
                (got - want).norm() < 1e-12 * largest,
                "entry {i}: {got} vs {want}"
            );
        }
        let mut back = vec![0.0; total];
        pool.install(|| plan.inverse(&mut spectrum, &mut back, &mut work));
        for (a, b) in back.iter().zip(&field) {
            assert!((a / total as f64 - b).abs() < 1e-12);
        }
    }
}
