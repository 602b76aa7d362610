//! The parameters of a mesh Ewald sum.

use super::bspline::ORDERS;
use crate::potential::multipole::PotentialError;
use nalgebra::Vector3;

/// The splitting, the real-space cutoff and the mesh of a smooth PME sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshParameters {
    /// The splitting parameter `alpha` (inverse length, > 0).
    pub alpha: f64,
    /// The real-space cutoff `r_c` (length, at most half the shortest box side).
    pub real_cutoff: f64,
    /// Mesh points along x, y, z (each at least the spline order).
    pub grid: [usize; 3],
    /// The cardinal B-spline order `p`, 4 to 8 (interpolation error `~ h^p`).
    pub order: usize,
}

impl MeshParameters {
    /// Refuses parameters the sum cannot use in `box_lengths`, naming the field.
    pub fn check(&self, box_lengths: &Vector3<f64>) -> Result<(), PotentialError> {
        if !(self.alpha.is_finite() && self.alpha > 0.0) {
            return Err(PotentialError::new(
                "alpha",
                format!("must be finite and > 0, got {}", self.alpha),
            ));
        }
        if !ORDERS.contains(&self.order) {
            return Err(PotentialError::new(
                "order",
                format!(
                    "must be from {} to {}, got {}",
                    ORDERS.start(),
                    ORDERS.end(),
                    self.order
                ),
            ));
        }
        for (a, &points) in self.grid.iter().enumerate() {
            if points < self.order {
                return Err(PotentialError::new(
                    format!("grid[{a}]"),
                    format!(
                        "must be at least the spline order {}, got {points}",
                        self.order
                    ),
                ));
            }
        }
        check_cutoff(self.real_cutoff, box_lengths)?;
        Ok(())
    }
}

/// Refuses a real-space cutoff the box does not fit (minimum image: at most
/// half the shortest side), path `real_cutoff`.
pub(crate) fn check_cutoff(
    real_cutoff: f64,
    box_lengths: &Vector3<f64>,
) -> Result<(), PotentialError> {
    let half = 0.5 * box_lengths.min();
    if !(real_cutoff > 0.0 && real_cutoff <= half) {
        return Err(PotentialError::new(
            "real_cutoff",
            format!(
                "must be > 0 and at most half the shortest box side ({half:.6}), got {real_cutoff}"
            ),
        ));
    }
    Ok(())
}
