//! The smooth PME sum of one box: plans, influence function and buffers
//! built once, positions taken at each evaluation.

use super::cartesian::{radial_derivatives, Tables, DERIVATIVES, SOURCES, UP_TO};
use super::influence::influence;
use super::parameters::MeshParameters;
use super::real_space::CellList;
use super::sites::{SiteResponse, Sources};
use super::spread::SiteWeights;
use crate::potential::multipole::fft3::{ConvolveBuffers, RealFft3};
use crate::potential::multipole::{PotentialError, Surface};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Bytes of the buffers of a `grid` mesh, all held: the mesh, the influence
/// function, and the two complex half spectra and the real result of
/// [`RealFft3::convolve_into`].
pub(crate) fn mesh_bytes(grid: [usize; 3]) -> f64 {
    let points: f64 = grid.iter().map(|&k| k as f64).product();
    16.0 * points + RealFft3::spectrum_len_of(grid) as f64 * (8.0 + 2.0 * 16.0)
}

/// A smooth particle-mesh Ewald sum for a fixed number of sites in a fixed
/// orthorhombic box (see the module doc for the terms).
#[derive(Clone, Debug)]
pub struct MeshEwald {
    parameters: MeshParameters,
    surface: Surface,
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
    /// `d^N` at the origin of the smooth part `erf(alpha r) / r` (the self term).
    smooth_at_origin: [f64; 56],
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
                * (SiteWeights::bytes_per_site() + 24.0 + 8.0 * (2 * SOURCES + DERIVATIVES) as f64)
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
        let alpha = parameters.alpha;
        // B_l(0) of erf(alpha r) / r: (2 alpha / sqrt(pi)) (2 alpha^2)^l / (2l + 1).
        let smooth: [f64; 6] = std::array::from_fn(|l| {
            2.0 * alpha / PI.sqrt() * (2.0 * alpha * alpha).powi(l as i32) / (2 * l + 1) as f64
        });
        let mut levels = [[0.0; 56]; 6];
        radial_derivatives(&Vector3::zeros(), &smooth, 56, &mut levels);
        let smooth_at_origin = levels[0];
        Ok(MeshEwald {
            parameters,
            surface,
            box_lengths,
            influence,
            mesh: vec![0.0; points as usize],
            convolution: ConvolveBuffers::held(&fft, (1, 1)),
            fft,
            weights: SiteWeights::new(sites, grid, parameters.order),
            cells: CellList::new(sites, &box_lengths, parameters.real_cutoff),
            wrapped: vec![Vector3::zeros(); sites],
            coefficients: vec![[0.0; SOURCES]; sites],
            scaled: vec![[0.0; SOURCES]; sites],
            derivatives: vec![[0.0; DERIVATIVES]; sites],
            smooth_at_origin,
        })
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
        let n = self.sites();
        let lengths = [
            Some(sources.len()),
            sources.charges.map(<[f64]>::len),
            sources.dipoles.map(<[Vector3<f64>]>::len),
            sources.quadrupoles.map(|t| t.len()),
            Some(response.potential.len()),
        ];
        if lengths.iter().flatten().any(|&len| len != n) {
            return Err(PotentialError::new(
                "positions",
                format!(
                    "the sum was built for {n} sites, got (positions, charges, dipoles, \
                     quadrupoles, response) lengths {lengths:?}"
                ),
            ));
        }
        let box_lengths = self.box_lengths;
        for (i, r) in sources.positions.iter().enumerate() {
            if !r.iter().all(|x| x.is_finite()) {
                return Err(PotentialError::new(
                    format!("positions[{i}]"),
                    format!("must be finite, got {r:?}"),
                ));
            }
            self.wrapped[i] =
                Vector3::from_fn(|a, _| r[a] - box_lengths[a] * (r[a] / box_lengths[a]).floor());
        }
        let tables = Tables::get();
        let scale = Vector3::from_fn(|a, _| self.parameters.grid[a] as f64 / box_lengths[a]);
        for i in 0..n {
            let c = sources.coefficients(i);
            self.coefficients[i] = c;
            self.scaled[i] = std::array::from_fn(|e| {
                let x = tables.exponents[e];
                c[e] * (0..3).map(|a| scale[a].powi(x[a] as i32)).product::<f64>()
            });
        }
        let source_order = sources.order();
        let derivative_order = (source_order + 1).max(2);
        let count = UP_TO[derivative_order];
        for d in self.derivatives.iter_mut() {
            *d = [0.0; DERIVATIVES];
        }
        let alpha = self.parameters.alpha;
        self.cells.add_derivatives(
            &self.wrapped,
            &box_lengths,
            alpha,
            self.parameters.real_cutoff,
            &self.coefficients,
            source_order,
            count,
            &mut self.derivatives,
        );
        self.reciprocal(source_order, derivative_order, count, &scale);
        self.add_self_background_surface(sources, source_order, count);
        response.fill(sources, &self.derivatives);
        Ok(())
    }

    /// Spread, convolve with the influence function, gather.
    fn reciprocal(
        &mut self,
        source_order: usize,
        derivative_order: usize,
        count: usize,
        scale: &Vector3<f64>,
    ) {
        self.weights
            .compute(&self.wrapped, &self.box_lengths, derivative_order);
        self.weights
            .spread(&self.scaled, source_order, &mut self.mesh);
        let [nx, _, nz] = self.parameters.grid;
        let (mesh, influence) = (&self.mesh, &self.influence);
        let phi = self.fft.convolve_into(
            &mut self.convolution,
            (1, 1),
            |l, line| line.copy_from_slice(&mesh[l * nz..(l + 1) * nz]),
            |m, s, f| {
                for ((f, s), g) in f.iter_mut().zip(s).zip(&influence[m * nx..(m + 1) * nx]) {
                    *f = s * g;
                }
            },
        );
        self.weights
            .gather(phi, scale, count, &mut self.derivatives);
    }

    /// Removes each site's own smooth potential, adds the neutralising
    /// background of a net charge `Q` (`phi = -pi Q / (V alpha^2)`) and, in
    /// vacuum, the surface term of the wrapped sites' dipole `M`
    /// (`phi(r) = 4 pi M.r / (3 V)`).
    fn add_self_background_surface(
        &mut self,
        sources: &Sources<'_>,
        source_order: usize,
        count: usize,
    ) {
        let tables = Tables::get();
        let volume = self.box_lengths.product();
        let alpha = self.parameters.alpha;
        let net = sources.charges.map_or(0.0, |q| q.iter().sum::<f64>());
        let background = -PI * net / (volume * alpha * alpha);
        let surface = match self.surface {
            Surface::Conducting => Vector3::zeros(),
            Surface::Vacuum => sources.total_dipole(&self.wrapped) * (4.0 * PI / (3.0 * volume)),
        };
        let sources_count = UP_TO[source_order];
        for (i, d) in self.derivatives.iter_mut().enumerate() {
            let c = &self.coefficients[i];
            for (a, value) in d.iter_mut().enumerate().take(count) {
                let own: f64 = (0..sources_count)
                    .map(|e| tables.parity[e] * c[e] * self.smooth_at_origin[tables.sum[a][e]])
                    .sum();
                *value -= own;
            }
            d[0] += background + surface.dot(&self.wrapped[i]);
            for a in 0..3 {
                d[1 + a] += surface[a];
            }
        }
    }
}
