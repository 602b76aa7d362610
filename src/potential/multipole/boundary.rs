//! Open or periodic boundaries: which site pairs interact and through which offset.

use super::PotentialError;
use nalgebra::Vector3;

/// How site pairs are enumerated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// An isolated cluster: every pair interacts, no cutoff.
    Open,
    /// An orthorhombic periodic box: minimum-image offsets, and only pairs with
    /// `|r_ij| <= cutoff` interact (a plain spherical cutoff: no Ewald sum, no
    /// shift, no tail correction). `box_lengths` (> 0, length unit of the
    /// scene) are the edges along x, y, z; `0 < cutoff <= min(box_lengths)/2`
    /// so that each pair has at most one image inside the cutoff.
    Periodic {
        box_lengths: Vector3<f64>,
        cutoff: f64,
    },
}

impl Boundary {
    /// Checks the box and the cutoff.
    pub(crate) fn validate(&self) -> Result<(), PotentialError> {
        let Boundary::Periodic {
            box_lengths,
            cutoff,
        } = *self
        else {
            return Ok(());
        };
        if !box_lengths.iter().all(|l| l.is_finite() && *l > 0.0) {
            return Err(PotentialError::new(
                "box_lengths",
                format!(
                    "must be finite and > 0, got [{}, {}, {}]",
                    box_lengths.x, box_lengths.y, box_lengths.z
                ),
            ));
        }
        if !(cutoff.is_finite() && cutoff > 0.0) {
            return Err(PotentialError::new(
                "cutoff",
                format!("must be finite and > 0, got {cutoff}"),
            ));
        }
        let half = 0.5 * box_lengths.min();
        if cutoff > half {
            return Err(PotentialError::new(
                "cutoff",
                format!("must be <= half the smallest box length L/2 = {half}, got {cutoff}"),
            ));
        }
        Ok(())
    }

    /// The offset `r_j - r_i` that interacts (the minimum image when periodic),
    /// or `None` when the pair lies beyond the cutoff.
    pub(crate) fn interacting_offset(
        &self,
        site_i: &Vector3<f64>,
        site_j: &Vector3<f64>,
    ) -> Option<Vector3<f64>> {
        let offset = site_j - site_i;
        match *self {
            Boundary::Open => Some(offset),
            Boundary::Periodic {
                box_lengths,
                cutoff,
            } => {
                let image = offset.zip_map(&box_lengths, |d, l| d - l * (d / l).round());
                (image.norm_squared() <= cutoff * cutoff).then_some(image)
            }
        }
    }
}
