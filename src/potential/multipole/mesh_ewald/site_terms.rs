//! The terms every Ewald sum of sites has besides its real and reciprocal
//! parts (self, background, surface), and the multipoles' share of a
//! reciprocal-space virial: shared by the mesh and the wave-vector sums.

use super::cartesian::{radial_derivatives, Tables, DERIVATIVES, SOURCES, UP_TO};
use super::sites::Sources;
use crate::potential::multipole::{PotentialError, Surface};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// The multipoles' share of a reciprocal-space virial, from each site's
/// reciprocal potential derivatives `reciprocal`: `sum_i (-mu_i E_i^T + 2
/// Theta_i W_i)` (Sagui, Pedersen & Darden 2004: the strain turns `mu.k`
/// into `((1 - eps) mu).k`).
pub(crate) fn multipole_virial(
    sources: &Sources<'_>,
    reciprocal: &[[f64; DERIVATIVES]],
) -> Matrix3<f64> {
    let tables = Tables::get();
    let mut virial = Matrix3::zeros();
    for (i, r) in reciprocal.iter().enumerate() {
        if let Some(mu) = sources.dipoles.map(|m| m[i]) {
            virial += mu * Vector3::new(r[1], r[2], r[3]).transpose();
        }
        if let Some(theta) = sources.quadrupoles.map(|t| t[i]) {
            let w = Matrix3::from_fn(|a, b| r[tables.sum[1 + a][1 + b]] / 3.0);
            virial += theta * w * 2.0;
        }
    }
    virial
}

/// The terms every Ewald sum of sites has besides its real and reciprocal
/// parts (self, background, surface: module doc of [`super`]), for a
/// splitting and a box.
#[derive(Clone, Debug)]
pub(crate) struct SiteTerms {
    alpha: f64,
    surface: Surface,
    box_lengths: Vector3<f64>,
    /// `d^N` at the origin of the smooth part `erf(alpha r) / r` (the self term).
    smooth_at_origin: [f64; 56],
    /// Whether the surface term takes the positions as given (whole
    /// molecules) rather than wrapped (`with_whole_molecules` of the sums).
    pub(crate) whole_molecules: bool,
}

impl SiteTerms {
    /// The terms of splitting `alpha` in `box_lengths` with `surface`.
    pub fn new(alpha: f64, surface: Surface, box_lengths: Vector3<f64>) -> Self {
        // B_l(0) of erf(alpha r) / r: (2 alpha / sqrt(pi)) (2 alpha^2)^l / (2l + 1).
        let smooth: [f64; 6] = std::array::from_fn(|l| {
            2.0 * alpha / PI.sqrt() * (2.0 * alpha * alpha).powi(l as i32) / (2 * l + 1) as f64
        });
        let mut levels = [[0.0; 56]; 6];
        radial_derivatives(&Vector3::zeros(), &smooth, 56, &mut levels);
        SiteTerms {
            alpha,
            surface,
            box_lengths,
            smooth_at_origin: levels[0],
            whole_molecules: false,
        }
    }

    /// Checks the lengths (path `positions`) and the positions (finite,
    /// `positions[i]`), wraps the sites into the box, sets their
    /// coefficients and zeroes the derivatives (all sized for the sites);
    /// returns the sources' order and the number of derivatives needed.
    pub fn prepare(
        &self,
        sources: &Sources<'_>,
        responses: usize,
        (wrapped, coefficients): (&mut [Vector3<f64>], &mut [[f64; SOURCES]]),
        derivatives: &mut [[f64; DERIVATIVES]],
    ) -> Result<(usize, usize), PotentialError> {
        let n = wrapped.len();
        let lengths = [
            Some(sources.len()),
            sources.charges.map(<[f64]>::len),
            sources.dipoles.map(<[Vector3<f64>]>::len),
            sources.quadrupoles.map(|t| t.len()),
            Some(responses),
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
            wrapped[i] =
                Vector3::from_fn(|a, _| r[a] - box_lengths[a] * (r[a] / box_lengths[a]).floor());
        }
        for (i, c) in coefficients.iter_mut().enumerate() {
            *c = sources.coefficients(i);
        }
        let source_order = sources.order();
        for d in derivatives.iter_mut() {
            *d = [0.0; DERIVATIVES];
        }
        Ok((source_order, UP_TO[(source_order + 1).max(2)]))
    }

    /// Removes each site's own smooth potential, adds the neutralising
    /// background of a net charge `Q` (`phi = -pi Q / (V alpha^2)`) and, in
    /// vacuum, the surface term of the sites' dipole `M` (wrapped, or as
    /// given for whole molecules)
    /// (`phi(r) = 4 pi M.r / (3 V)`); returns their virial: `E_bg I` (the
    /// background's `1/V`), `E_s I - 4 pi / (3 V) P M^T` in vacuum (`P =
    /// sum_i q_i r_i` the charges' part of `M`, scaled by the strain), none
    /// of the self term (independent of the positions).
    pub fn add(
        &self,
        sources: &Sources<'_>,
        (wrapped, coefficients): (&[Vector3<f64>], &[[f64; SOURCES]]),
        (source_order, count): (usize, usize),
        derivatives: &mut [[f64; DERIVATIVES]],
    ) -> Matrix3<f64> {
        let tables = Tables::get();
        let volume = self.box_lengths.product();
        let alpha = self.alpha;
        let net = sources.charges.map_or(0.0, |q| q.iter().sum::<f64>());
        let background = -PI * net / (volume * alpha * alpha);
        let positions = if self.whole_molecules {
            sources.positions
        } else {
            wrapped
        };
        let total_dipole = sources.total_dipole(positions);
        let surface = match self.surface {
            Surface::Conducting => Vector3::zeros(),
            Surface::Vacuum => total_dipole * (4.0 * PI / (3.0 * volume)),
        };
        let sources_count = UP_TO[source_order];
        for (i, d) in derivatives.iter_mut().enumerate() {
            let c = &coefficients[i];
            for (a, value) in d.iter_mut().enumerate().take(count) {
                let own: f64 = (0..sources_count)
                    .map(|e| tables.parity[e] * c[e] * self.smooth_at_origin[tables.sum[a][e]])
                    .sum();
                *value -= own;
            }
            d[0] += background + surface.dot(&positions[i]);
            for a in 0..3 {
                d[1 + a] += surface[a];
            }
        }
        let mut virial = Matrix3::identity() * (0.5 * net * background);
        if self.surface == Surface::Vacuum {
            let charges_dipole =
                total_dipole - sources.dipoles.map_or(Vector3::zeros(), |m| m.iter().sum());
            virial += Matrix3::identity() * (0.5 * surface.dot(&total_dipole))
                - charges_dipole * surface.transpose();
        }
        virial
    }
}
