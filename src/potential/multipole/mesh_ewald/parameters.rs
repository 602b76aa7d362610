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

/// The parameters of a mesh Ewald sum a user forces (a scene's `order`,
/// `grid`, `real_cutoff` and `alpha`, the Python keywords of the same
/// names); what is not forced is chosen from the accuracy given what is
/// (`super::estimate`'s choice, which also refuses forced values that do
/// not reach the accuracy and a cutoff the box does not fit).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForcedMesh {
    /// The spline order, 4 to 8.
    pub order: Option<usize>,
    /// Mesh points along x, y, z (each at least the order).
    pub grid: Option<[usize; 3]>,
    /// The real-space cutoff (length, > 0).
    pub real_cutoff: Option<f64>,
    /// The splitting parameter (inverse length, > 0).
    pub alpha: Option<f64>,
}

impl ForcedMesh {
    /// The forced values as a user gives them (`grid`: one count for every
    /// axis, or three), checked on their own, naming the field: an order
    /// outside 4 to 8, a grid of other than one or three counts or with an
    /// axis below the order (4 when none is forced), a grid over the memory
    /// limit (estimated before anything is allocated), an `alpha` or
    /// `real_cutoff` not finite and > 0.
    pub fn new(
        order: Option<i64>,
        grid: Option<&[i64]>,
        real_cutoff: Option<f64>,
        alpha: Option<f64>,
    ) -> Result<ForcedMesh, PotentialError> {
        let order = order
            .map(|p| match usize::try_from(p) {
                Ok(p) if ORDERS.contains(&p) => Ok(p),
                _ => Err(PotentialError::new(
                    "order",
                    format!(
                        "must be from {} to {}, got {p}",
                        ORDERS.start(),
                        ORDERS.end()
                    ),
                )),
            })
            .transpose()?;
        let least = order.unwrap_or(*ORDERS.start());
        let grid = grid.map(|counts| forced_grid(counts, least)).transpose()?;
        for (name, value) in [("real_cutoff", real_cutoff), ("alpha", alpha)] {
            if let Some(v) = value {
                if !(v.is_finite() && v > 0.0) {
                    return Err(PotentialError::new(
                        name,
                        format!("must be finite and > 0, got {}", crate::checks::num(v)),
                    ));
                }
            }
        }
        Ok(ForcedMesh {
            order,
            grid,
            real_cutoff,
            alpha,
        })
    }

    /// The name of the first value forced (`None` when nothing is).
    pub fn first_forced(&self) -> Option<&'static str> {
        [
            ("order", self.order.is_some()),
            ("grid", self.grid.is_some()),
            ("real_cutoff", self.real_cutoff.is_some()),
            ("alpha", self.alpha.is_some()),
        ]
        .into_iter()
        .find_map(|(name, forced)| forced.then_some(name))
    }
}

/// The grid of `counts` (one for every axis, or three), each at least
/// `least`, within the memory limit; path `grid`.
fn forced_grid(counts: &[i64], least: usize) -> Result<[usize; 3], PotentialError> {
    let grid: [i64; 3] = match *counts {
        [k] => [k; 3],
        [x, y, z] => [x, y, z],
        _ => {
            return Err(PotentialError::new(
                "grid",
                format!(
                    "must be one count of mesh points (every axis) or three, got {}",
                    counts.len()
                ),
            ))
        }
    };
    let mut points = [0; 3];
    for (a, (&k, p)) in grid.iter().zip(&mut points).enumerate() {
        *p = match usize::try_from(k) {
            Ok(k) if k >= least => k,
            _ => {
                return Err(PotentialError::new(
                    format!("grid[{a}]"),
                    format!("must be at least the spline order {least}, got {k}"),
                ))
            }
        };
    }
    crate::memory::check("grid", super::mesh::mesh_bytes(points))
        .map_err(|e| PotentialError::new("grid", format!("{points:?}: {}", e.message)))?;
    Ok(points)
}
