//! The direct Ewald sum of moving sites: [`WaveEwald`], the terms of
//! [`super::MeshEwald`] with the reciprocal part summed over the wave
//! vectors instead of a mesh, for systems too small for a mesh to pay
//! (`crate::potential::multipole::AutoChoice`).
//!
//! With `c_E` the coefficients of site `j`'s operator (`super::cartesian`)
//! and `w_k = (8 pi / V) exp(-k^2 / 4 alpha^2) / k^2` over the half space
//! of wave vectors `0 < |k| <= k_c`, the reciprocal potential derivatives
//! are
//!
//! `d^A phi(r_i) = sum_k w_k Re[(i k)^A exp(i k.r_i) S(k)]`, `S(k) = sum_j
//! exp(-i k.r_j) sum_E c_E (-i k)^E`,
//!
//! the derivatives of `(4 pi / V) sum_(k != 0) exp(-k^2 / 4 alpha^2) / k^2
//! S(k) exp(i k.r)` (the mesh sum's reciprocal potential, module doc of
//! [`super`]); its energy is `sum_k (w_k / 2) |S(k)|^2` and its virial that
//! of Essmann et al. (1995, eq 2.8) mode by mode, `(w_k / 2) |S(k)|^2 (I - 2
//! (1 / k^2 + 1 / (4 alpha^2)) k k^T)`, plus the multipoles' terms. The self,
//! background and surface terms are the mesh sum's ([`SiteTerms`]). Cost:
//! `N` times the wave vectors, twice (the structure factors, then each
//! site's derivatives); both loops are rayon loops whose sums do not depend
//! on the number of threads.

use super::cartesian::{Tables, DERIVATIVES, SOURCES, UP_TO};
use super::estimate::Carried;
use super::site_terms::{multipole_virial, SiteTerms};
use super::sites::Sources;
use crate::checks::num;
use crate::potential::multipole::ewald::{phase, phases, wave_vectors, WaveVector};
use crate::potential::multipole::ewald_parameters::{choose, EwaldParameters};
use crate::potential::multipole::{Accuracy, PotentialError, Surface, MAX_WAVE_VECTORS};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use rustfft::num_complex::Complex;

/// Sites per rayon task.
const SITES_PER_TASK: usize = 32;

/// The parameters of a direct Ewald sum of `sites` sites carrying `carried`
/// in `box_lengths` at `accuracy` (in (0, 1), the relative field accuracy of
/// the mesh sum's estimate module), its real-space cutoff at most `longest` (named
/// `what` when no splitting fits it), with the estimated seconds of one
/// evaluation: `alpha` minimises the model's real-space pairs `N n (2 pi /
/// 3) r_c^3` at `pair` seconds each plus the sites times the wave vectors
/// at `wave` seconds each (`crate::potential::multipole::ewald_parameters`'
/// estimates, each part half the accuracy).
pub fn for_waves(
    accuracy: f64,
    (carried, sites): (Carried, usize),
    box_lengths: &Vector3<f64>,
    (longest, what): (f64, &str),
    (pair, wave): (f64, f64),
) -> Result<(EwaldParameters, f64), PotentialError> {
    let accuracy = Accuracy::new(accuracy)?.get();
    let ranks: Vec<i32> = carried.orders().iter().map(|(s, g)| s + g).collect();
    let n = sites.max(1) as f64;
    let volume = box_lengths.product();
    let density = n / volume;
    let cost = |rc: f64, kc: f64| {
        if rc > longest {
            return f64::INFINITY;
        }
        let pairs = n * density * (2.0 * std::f64::consts::PI / 3.0) * rc.powi(3);
        let waves = volume * kc.powi(3) / (12.0 * std::f64::consts::PI.powi(2));
        pair * pairs + wave * n * waves
    };
    let parameters = choose(accuracy, density, &ranks, cost);
    let seconds = cost(parameters.real_cutoff, parameters.reciprocal_cutoff);
    if !seconds.is_finite() {
        return Err(PotentialError::new(
            "box_lengths",
            format!(
                "the direct Ewald sum at accuracy {} needs a real-space cutoff of at least \
                 {:.4}, more than {what} {longest}: use a larger box or a looser accuracy",
                num(accuracy),
                parameters.real_cutoff
            ),
        ));
    }
    Ok((parameters, seconds))
}

/// A direct Ewald sum for a fixed number of moving sites in a fixed
/// orthorhombic box (module doc).
#[derive(Clone, Debug)]
pub struct WaveEwald {
    parameters: EwaldParameters,
    terms: SiteTerms,
    box_lengths: Vector3<f64>,
    waves: Vec<WaveVector>,
    max_index: [i32; 3],
    /// `k^A` of each wave vector for the first [`DERIVATIVES`] multi-indices.
    monomials: Vec<[f64; DERIVATIVES]>,
    wrapped: Vec<Vector3<f64>>,
    coefficients: Vec<[f64; SOURCES]>,
    structure: Vec<Complex<f64>>,
    derivatives: Vec<[f64; DERIVATIVES]>,
    reciprocal: Vec<[f64; DERIVATIVES]>,
    virial: bool,
}

impl WaveEwald {
    /// The sum of `sites` sites in `box_lengths` with `parameters`;
    /// refuses more than [`MAX_WAVE_VECTORS`] wave vectors and buffers over
    /// the memory limit (path `accuracy`, which sets the sizes).
    pub fn new(
        sites: usize,
        box_lengths: Vector3<f64>,
        parameters: EwaldParameters,
        surface: Surface,
    ) -> Result<Self, PotentialError> {
        let kc = parameters.reciprocal_cutoff;
        let max_index = [0, 1, 2].map(|a| (kc * box_lengths[a] / std::f64::consts::TAU) as i32);
        let count: f64 = max_index
            .iter()
            .map(|&m| (2 * m + 1) as f64)
            .product::<f64>()
            / 2.0;
        if count > MAX_WAVE_VECTORS as f64 {
            return Err(PotentialError::new(
                "accuracy",
                format!(
                    "needs about {count:.2e} reciprocal-space wave vectors (cutoff {kc:.3}), more \
                     than the limit {MAX_WAVE_VECTORS}"
                ),
            ));
        }
        let bytes = count * (size_of::<WaveVector>() + 8 * DERIVATIVES + 16) as f64
            + sites as f64 * (24 + 8 * (SOURCES + 2 * DERIVATIVES)) as f64;
        crate::memory::check("accuracy", bytes).map_err(|e| {
            PotentialError::new(
                "accuracy",
                format!(
                    "the direct Ewald sum of {sites} sites ({count:.2e} wave vectors) {}",
                    e.message
                ),
            )
        })?;
        let waves = wave_vectors(&box_lengths, max_index, parameters.alpha, kc);
        let tables = Tables::get();
        let monomials: Vec<[f64; DERIVATIVES]> = waves
            .iter()
            .map(|w| {
                std::array::from_fn(|a| {
                    let x = tables.exponents[a];
                    (0..3).map(|c| w.k[c].powi(x[c] as i32)).product::<f64>()
                })
            })
            .collect();
        Ok(WaveEwald {
            parameters,
            terms: SiteTerms::new(parameters.alpha, surface, box_lengths),
            box_lengths,
            structure: vec![Complex::new(0.0, 0.0); waves.len()],
            waves,
            max_index,
            monomials,
            wrapped: vec![Vector3::zeros(); sites],
            coefficients: vec![[0.0; SOURCES]; sites],
            derivatives: vec![[0.0; DERIVATIVES]; sites],
            reciprocal: vec![[0.0; DERIVATIVES]; sites],
            virial: false,
        })
    }

    /// The sum, its evaluations also computing the virial.
    pub fn with_virial(mut self) -> Self {
        self.virial = true;
        self
    }

    /// The sum, its vacuum surface term taking the positions as given
    /// (whole molecules), as [`super::MeshEwald::with_whole_molecules`].
    pub fn with_whole_molecules(mut self) -> Self {
        self.terms.whole_molecules = true;
        self
    }

    /// The parameters the sum was built with.
    pub fn parameters(&self) -> EwaldParameters {
        self.parameters
    }

    /// The reciprocal, self, background and surface terms, as
    /// [`super::MeshEwald::long_range_derivatives`]: each site's potential
    /// derivatives (to which the caller adds its real-space pairs) and
    /// their virial (zero without [`Self::with_virial`]).
    pub(crate) fn long_range_derivatives(
        &mut self,
        sources: &Sources<'_>,
    ) -> Result<(&mut [[f64; DERIVATIVES]], Matrix3<f64>), PotentialError> {
        let (source_order, count) = self.terms.prepare(
            sources,
            sources.len(),
            (&mut self.wrapped, &mut self.coefficients),
            &mut self.derivatives,
        )?;
        let mut virial = self.reciprocal(sources, UP_TO[source_order], count);
        virial += self.terms.add(
            sources,
            (&self.wrapped, &self.coefficients),
            (source_order, count),
            &mut self.derivatives,
        );
        let virial = if self.virial {
            virial
        } else {
            Matrix3::zeros()
        };
        Ok((&mut self.derivatives, virial))
    }

    /// The structure factors, then each site's reciprocal derivatives
    /// (added into `derivatives`); their virial when asked.
    fn reciprocal(&mut self, sources: &Sources<'_>, carried: usize, count: usize) -> Matrix3<f64> {
        let tables = Tables::get();
        // i^n for n = |A| mod 4.
        let power = |n: usize| match n % 4 {
            0 => Complex::new(1.0, 0.0),
            1 => Complex::new(0.0, 1.0),
            2 => Complex::new(-1.0, 0.0),
            _ => Complex::new(0.0, -1.0),
        };
        let (box_lengths, max_index) = (self.box_lengths, self.max_index);
        let (waves, monomials, coefficients) = (&self.waves, &self.monomials, &self.coefficients);
        let positions = &self.wrapped;
        let n = positions.len();
        let chunks: Vec<Vec<Complex<f64>>> = (0..n)
            .collect::<Vec<_>>()
            .par_chunks(SITES_PER_TASK)
            .map(|chunk| {
                let mut s = vec![Complex::new(0.0, 0.0); waves.len()];
                for &j in chunk {
                    let p = phases(&positions[j], &box_lengths, max_index);
                    let c = &coefficients[j];
                    for ((s, wave), m) in s.iter_mut().zip(waves).zip(monomials) {
                        let operator: Complex<f64> = (0..carried)
                            .map(|e| power(3 * tables.order(e)) * (c[e] * m[e]))
                            .sum();
                        *s += operator * phase(&p, max_index, wave.index).conj();
                    }
                }
                s
            })
            .collect();
        self.structure.fill(Complex::new(0.0, 0.0));
        for chunk in &chunks {
            for (s, c) in self.structure.iter_mut().zip(chunk) {
                *s += c;
            }
        }
        let structure = &self.structure;
        self.reciprocal
            .par_iter_mut()
            .with_min_len(SITES_PER_TASK)
            .enumerate()
            .for_each(|(i, d)| {
                *d = [0.0; DERIVATIVES];
                let p = phases(&positions[i], &box_lengths, max_index);
                for ((s, wave), m) in structure.iter().zip(waves).zip(monomials) {
                    let z = s * phase(&p, max_index, wave.index) * wave.weight;
                    for (a, d) in d.iter_mut().enumerate().take(count) {
                        *d += (power(tables.order(a)) * z).re * m[a];
                    }
                }
            });
        for (d, r) in self.derivatives.iter_mut().zip(&self.reciprocal) {
            for (d, r) in d.iter_mut().zip(r).take(count) {
                *d += r;
            }
        }
        if !self.virial {
            return Matrix3::zeros();
        }
        let inverse_4alpha2 = 0.25 / self.parameters.alpha.powi(2);
        let mut virial = Matrix3::zeros();
        for (s, wave) in structure.iter().zip(waves) {
            let energy = 0.5 * wave.weight * s.norm_sqr();
            let b = 2.0 * (1.0 / wave.k.norm_squared() + inverse_4alpha2);
            virial += (Matrix3::identity() - wave.k * wave.k.transpose() * b) * energy;
        }
        virial + multipole_virial(sources, &self.reciprocal)
    }
}
