//! The smooth PME sum of one box: plans, influence function and buffers
//! built once, positions taken at each evaluation.

use super::cartesian::{Tables, DERIVATIVES, SOURCES, UP_TO};
use super::influence::influence;
use super::parameters::MeshParameters;
use super::real_space::CellList;
use super::site_terms::{multipole_virial, SiteTerms};
use super::sites::{SiteResponse, Sources};
use super::spread::SiteWeights;
use crate::potential::multipole::fft3::{ConvolveBuffers, RealFft3};
use crate::potential::multipole::{PotentialError, Surface};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;
use std::sync::{Mutex, PoisonError};

/// Bytes of the buffers of a `grid` mesh, all held: the mesh, the influence
/// function, and the two complex half spectra and the real result of
/// [`RealFft3::convolve_into`].
pub(crate) fn mesh_bytes(grid: [usize; 3]) -> f64 {
    let points: f64 = grid.iter().map(|&k| k as f64).product();
    // RealFft3::spectrum_len_of in floating point: a forced grid's count may overflow.
    let spectrum = grid[0] as f64 * grid[1] as f64 * (grid[2] / 2 + 1) as f64;
    16.0 * points + spectrum * (8.0 + 2.0 * 16.0)
}

/// A smooth particle-mesh Ewald sum for a fixed number of sites in a fixed
/// orthorhombic box (see the module doc for the terms).
#[derive(Clone, Debug)]
pub struct MeshEwald {
    parameters: MeshParameters,
    box_lengths: Vector3<f64>,
    fft: RealFft3,
    convolution: ConvolveBuffers,
    influence: Vec<f64>,
    mesh: Vec<f64>,
    weights: SiteWeights,
    cells: CellList,
    wrapped: Vec<Vector3<f64>>,
    coefficients: Vec<[f64; SOURCES]>,
    scaled: Vec<[f64; SOURCES]>,
    derivatives: Vec<[f64; DERIVATIVES]>,
    /// The reciprocal-space part of `derivatives` (the virial's multipole terms).
    reciprocal: Vec<[f64; DERIVATIVES]>,
    /// Each half-spectrum line's share of the reciprocal virial (upper triangle).
    line_virials: Vec<[f64; 6]>,
    /// Whether evaluations compute the virial ([`Self::with_virial`]).
    virial: bool,
    /// Whether evaluations of charges compute the field gradient
    /// ([`Self::without_field_gradient`]).
    gradient: bool,
    /// The self, background and surface terms.
    terms: SiteTerms,
}

impl MeshEwald {
    /// The sum of `sites` sites in `box_lengths` (every side finite and > 0,
    /// path `box_lengths`), after [`MeshParameters::check`], refusing
    /// buffers above the memory limit (path `grid`).
    pub fn new(
        sites: usize,
        box_lengths: Vector3<f64>,
        parameters: MeshParameters,
        surface: Surface,
    ) -> Result<Self, PotentialError> {
        if !box_lengths.iter().all(|l| l.is_finite() && *l > 0.0) {
            return Err(PotentialError::new(
                "box_lengths",
                format!("every side must be finite and > 0, got {box_lengths:?}"),
            ));
        }
        parameters.check(&box_lengths)?;
        let grid = parameters.grid;
        let points: f64 = grid.iter().map(|&k| k as f64).product();
        let bytes = mesh_bytes(grid)
            + sites as f64
                * (SiteWeights::bytes_per_site()
                    + 24.0
                    + 8.0 * (2 * SOURCES + 2 * DERIVATIVES) as f64)
            + CellList::bytes(sites as f64, &box_lengths, parameters.real_cutoff);
        crate::memory::check("grid", bytes).map_err(|e| {
            PotentialError::new(
                "grid",
                format!(
                    "the mesh Ewald sum of {sites} sites on a {}x{}x{} mesh {}",
                    grid[0], grid[1], grid[2], e.message
                ),
            )
        })?;
        let fft = RealFft3::new(grid);
        let influence = influence(&fft, &box_lengths, parameters.alpha, parameters.order);
        Ok(MeshEwald {
            parameters,
            box_lengths,
            influence,
            mesh: vec![0.0; points as usize],
            convolution: ConvolveBuffers::new(&fft, (1, 1)),
            fft,
            weights: SiteWeights::new(sites, grid, parameters.order),
            cells: CellList::new(sites, &box_lengths, parameters.real_cutoff),
            wrapped: vec![Vector3::zeros(); sites],
            coefficients: vec![[0.0; SOURCES]; sites],
            scaled: vec![[0.0; SOURCES]; sites],
            derivatives: vec![[0.0; DERIVATIVES]; sites],
            reciprocal: vec![[0.0; DERIVATIVES]; sites],
            line_virials: vec![[0.0; 6]; grid[1] * (grid[2] / 2 + 1)],
            virial: false,
            gradient: true,
            terms: SiteTerms::new(parameters.alpha, surface, box_lengths),
        })
    }

    /// The sum, its evaluations also computing the virial (see
    /// [`SiteResponse::virial`]; it costs one pair force per real-space pair).
    pub fn with_virial(mut self) -> Self {
        self.set_virial(true);
        self
    }

    /// Whether the next evaluations compute the virial (as
    /// [`Self::with_virial`]; without it the virial is zero, and the forces
    /// of charges alone the same bits, those of dipoles not: their
    /// real-space kernel differs).
    pub(crate) fn set_virial(&mut self, virial: bool) {
        self.virial = virial;
    }

    /// The sum, its evaluations of charges alone leaving
    /// [`SiteResponse::quadrupole_conjugate`] zero: the energy, potentials,
    /// fields and forces of charges need no field gradient, and without it
    /// the real-space kernel needs `B_0` and `B_1` only and the gathering 4
    /// derivatives instead of 10. Sums with dipoles or quadrupoles are
    /// unchanged (their forces need the gradient).
    pub fn without_field_gradient(mut self) -> Self {
        self.gradient = false;
        self
    }

    /// The sum, its vacuum surface term taking the box dipole `M` of the
    /// positions as given instead of each site wrapped on its own: with each
    /// molecule's sites given whole (relative to its wrapped centre), a
    /// molecule crossing the box edge leaves `M`, the energy and the forces
    /// unchanged (ESPResSo #4758 is the trap of the wrapped sites).
    pub fn with_whole_molecules(mut self) -> Self {
        self.terms.whole_molecules = true;
        self
    }

    /// The parameters the sum was built with.
    pub fn parameters(&self) -> MeshParameters {
        self.parameters
    }

    /// Number of sites the sum was built for.
    pub fn sites(&self) -> usize {
        self.wrapped.len()
    }

    /// Evaluates the sum of `sources` into `response` (both sized for
    /// [`Self::sites`] sites; path `positions` otherwise, or
    /// `positions[i]` for a non-finite position).
    pub fn evaluate(
        &mut self,
        sources: &Sources<'_>,
        response: &mut SiteResponse,
    ) -> Result<(), PotentialError> {
        let virial = self.sum(sources, response.potential.len())?;
        response.fill(sources, &self.derivatives);
        response.virial = virial;
        Ok(())
    }

    /// The whole sum without [`SiteResponse::fill`], for a caller that
    /// corrects it before (moving bodies: their exclusions): each site's
    /// potential derivatives `d^A phi` (the first
    /// [`super::cartesian::DERIVATIVES`]) and the virial (zero without
    /// [`Self::with_virial`]). Errors as [`Self::evaluate`].
    pub(crate) fn derivatives(
        &mut self,
        sources: &Sources<'_>,
    ) -> Result<(&mut [[f64; DERIVATIVES]], Matrix3<f64>), PotentialError> {
        let virial = self.sum(sources, sources.len())?;
        Ok((&mut self.derivatives, virial))
    }

    /// The real-space pairs and the long-range terms into `derivatives`
    /// (`responses` sites asked for); returns the virial.
    fn sum(
        &mut self,
        sources: &Sources<'_>,
        responses: usize,
    ) -> Result<Matrix3<f64>, PotentialError> {
        let (source_order, count) = self.prepare(sources, responses)?;
        let box_lengths = self.box_lengths;
        let real = self.cells.add_derivatives(
            &self.wrapped,
            &box_lengths,
            self.parameters.alpha,
            self.parameters.real_cutoff,
            &self.coefficients,
            (source_order, count),
            &mut self.derivatives,
            self.virial,
        );
        let long_range = self.long_range(sources, source_order, count);
        Ok(if self.virial {
            real + long_range
        } else {
            Matrix3::zeros()
        })
    }

    /// The sum without its real-space part, for a caller that sums the
    /// real-space pairs itself (moving bodies, with their neighbour lists and
    /// exclusions): each site's potential derivatives `d^A phi` (the first
    /// [`super::cartesian::DERIVATIVES`]) of the reciprocal, self,
    /// background and surface terms, to which the caller adds its pairs
    /// before [`SiteResponse::fill`], and the virial of these terms (zero
    /// without [`Self::with_virial`]). Errors as [`Self::evaluate`].
    pub(crate) fn long_range_derivatives(
        &mut self,
        sources: &Sources<'_>,
    ) -> Result<(&mut [[f64; DERIVATIVES]], Matrix3<f64>), PotentialError> {
        let (source_order, count) = self.prepare(sources, sources.len())?;
        let virial = self.long_range(sources, source_order, count);
        Ok((&mut self.derivatives, virial))
    }

    /// [`SiteTerms::prepare`], and the coefficients scaled to the mesh;
    /// returns the sources' order and the number of derivatives needed.
    fn prepare(
        &mut self,
        sources: &Sources<'_>,
        responses: usize,
    ) -> Result<(usize, usize), PotentialError> {
        let (source_order, count) = self.terms.prepare(
            sources,
            responses,
            (&mut self.wrapped, &mut self.coefficients),
            &mut self.derivatives,
        )?;
        // Charges' forces need the field only.
        let count = if self.gradient || source_order > 0 {
            count
        } else {
            UP_TO[1]
        };
        let tables = Tables::get();
        let scale = self.scale();
        for (scaled, c) in self.scaled.iter_mut().zip(&self.coefficients) {
            *scaled = std::array::from_fn(|e| {
                let x = tables.exponents[e];
                c[e] * (0..3).map(|a| scale[a].powi(x[a] as i32)).product::<f64>()
            });
        }
        Ok((source_order, count))
    }

    /// `K_a / L_a`.
    fn scale(&self) -> Vector3<f64> {
        Vector3::from_fn(|a, _| self.parameters.grid[a] as f64 / self.box_lengths[a])
    }

    /// Adds the reciprocal, self, background and surface derivatives;
    /// returns their virial (zero without [`Self::with_virial`]).
    fn long_range(
        &mut self,
        sources: &Sources<'_>,
        source_order: usize,
        count: usize,
    ) -> Matrix3<f64> {
        let derivative_order = Tables::get().order(count - 1);
        let scale = self.scale();
        let mut virial = self.reciprocal(sources, (source_order, derivative_order, count), &scale);
        virial += self.terms.add(
            sources,
            (&self.wrapped, &self.coefficients),
            (source_order, count),
            &mut self.derivatives,
        );
        if self.virial {
            virial
        } else {
            Matrix3::zeros()
        }
    }

    /// Spread, convolve with the influence function, gather; returns the
    /// reciprocal-space virial when asked (module doc): `1/2 sum_m w_m G(m)
    /// |S(m)|^2 (I - 2 (1/k^2 + 1/(4 alpha^2)) k k^T)` (Essmann et al. 1995,
    /// eq 2.8, `w_m` counting the half spectrum's mirrored modes) plus the
    /// multipoles' `sum_i (-mu_i E_i^T + 2 Theta_i W_i)` of the reciprocal
    /// fields (Sagui, Pedersen & Darden 2004: the strain turns `mu.k` into
    /// `((1 - eps) mu).k`).
    fn reciprocal(
        &mut self,
        sources: &Sources<'_>,
        (source_order, derivative_order, count): (usize, usize, usize),
        scale: &Vector3<f64>,
    ) -> Matrix3<f64> {
        self.weights
            .compute(&self.wrapped, &self.box_lengths, derivative_order);
        self.weights
            .spread(&self.scaled, source_order, &mut self.mesh);
        let [nx, ny, nz] = self.parameters.grid;
        let (mesh, influence) = (&self.mesh, &self.influence);
        let with_virial = self.virial;
        let lines = Mutex::new(&mut self.line_virials[..]);
        let wave = |a: usize, m: usize| {
            let n = self.parameters.grid[a];
            let signed = if m <= n / 2 {
                m as f64
            } else {
                m as f64 - n as f64
            };
            2.0 * PI * signed / self.box_lengths[a]
        };
        let inverse_4alpha2 = 0.25 / self.parameters.alpha.powi(2);
        let phi = self.fft.convolve_into(
            &mut self.convolution,
            (1, 1),
            |l, line| line.copy_from_slice(&mesh[l * nz..(l + 1) * nz]),
            |m, s, f| {
                let g = &influence[m * nx..(m + 1) * nx];
                for ((f, s), g) in f.iter_mut().zip(s).zip(g) {
                    *f = s * g;
                }
                if !with_virial {
                    return;
                }
                let (kz, ky) = (m / ny, m % ny);
                let mirrored = if kz == 0 || 2 * kz == nz { 1.0 } else { 2.0 };
                let mut sum = [0.0; 6];
                for (kx, (s, &g)) in s.iter().zip(g).enumerate() {
                    if g == 0.0 {
                        continue;
                    }
                    let k = Vector3::new(wave(0, kx), wave(1, ky), wave(2, kz));
                    let e = 0.5 * mirrored * g * s.norm_sqr();
                    let b = 2.0 * (1.0 / k.norm_squared() + inverse_4alpha2);
                    for (u, (a, c)) in UPPER.iter().enumerate() {
                        let delta = if a == c { 1.0 } else { 0.0 };
                        sum[u] += e * (delta - b * k[*a] * k[*c]);
                    }
                }
                lines.lock().unwrap_or_else(PoisonError::into_inner)[m] = sum;
            },
        );
        for d in self.reciprocal.iter_mut() {
            // -0 + x is x, bit for bit: the sums below are those of a gather into `derivatives`.
            *d = [-0.0; DERIVATIVES];
        }
        self.weights.gather(phi, scale, count, &mut self.reciprocal);
        for (d, r) in self.derivatives.iter_mut().zip(&self.reciprocal) {
            for (d, r) in d.iter_mut().zip(r).take(count) {
                *d += r;
            }
        }
        if !with_virial {
            return Matrix3::zeros();
        }
        self.reciprocal_virial(sources)
    }

    /// The reciprocal-space virial of [`Self::reciprocal`] from its
    /// per-line sums of the modes and the sites' reciprocal fields.
    fn reciprocal_virial(&self, sources: &Sources<'_>) -> Matrix3<f64> {
        let mut virial = Matrix3::zeros();
        for line in &self.line_virials {
            for (u, &(a, c)) in UPPER.iter().enumerate() {
                virial[(a, c)] += line[u];
            }
        }
        for a in 0..3 {
            for c in 0..a {
                virial[(a, c)] = virial[(c, a)];
            }
        }
        virial + multipole_virial(sources, &self.reciprocal)
    }
}

/// The upper triangle `(a, c)`, `a <= c`, of a symmetric 3x3 matrix.
const UPPER: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
