//! Open or periodic boundaries: the box, the cutoff, and the limit on the
//! size of the periodic image sum.

use super::PotentialError;
use crate::checks::{each, positive};
use nalgebra::Vector3;

/// The most interacting pairs (periodic images included) a pair list may
/// hold: about 0.8 GB of pair indices, and it bounds the build time. The
/// largest lattice a scene allows (1e6 sites) with cutoff 3.1 at unit
/// density has about 6.1e7.
pub const MAX_PAIRS: usize = 100_000_000;

/// How site pairs are enumerated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// An isolated cluster: every pair interacts, no cutoff.
    Open,
    /// An orthorhombic periodic box of edges `box_lengths` (> 0, length unit
    /// of the scene, along x, y, z) and a spherical `cutoff` (> 0, any size):
    /// the lattice sum
    /// `V = sum_{i<j} sum_n v(r_j - r_i + n L) + 1/2 sum_i sum_{n != 0} v(n L)`,
    /// truncated at `|r| <= cutoff`, over every image `n L` (`n` integer,
    /// `L` the box) inside the cutoff, so a
    /// pair may interact through several images and a rotor with its own
    /// images (a plain spherical cutoff: no Ewald sum, no shift, no tail
    /// correction). The cutoff is limited only by the size of the sum: about
    /// `N^2 (4 pi / 3) cutoff^3 / (2 V)` pairs for `N` sites in a box of
    /// volume `V`, at most [`MAX_PAIRS`].
    Periodic {
        /// The edges of the box along x, y, z.
        box_lengths: Vector3<f64>,
        /// The spherical cutoff.
        cutoff: f64,
    },
}

impl Boundary {
    /// Checks the box (path `box_lengths[k]`) and the cutoff (path `cutoff`)
    /// for `sites` sites: finite and > 0, and the estimated size of the
    /// periodic image sum at most [`MAX_PAIRS`].
    pub fn validate(&self, sites: usize) -> Result<(), PotentialError> {
        let Boundary::Periodic {
            box_lengths,
            cutoff,
        } = *self
        else {
            return Ok(());
        };
        each(box_lengths.as_slice(), positive).map_err(|e| e.at("box_lengths"))?;
        let _ = positive(cutoff).map_err(|e| e.at("cutoff"))?;
        let sphere = 4.0 / 3.0 * std::f64::consts::PI * cutoff.powi(3);
        let estimate = (sites as f64).powi(2) * sphere / (2.0 * box_lengths.product());
        if estimate > MAX_PAIRS as f64 {
            return Err(too_many_pairs(
                cutoff,
                sites,
                &format!("about {estimate:.2e}"),
            ));
        }
        Ok(())
    }
}

/// The error for a periodic sum larger than [`MAX_PAIRS`]; `count` says how
/// many pairs (estimated or found).
pub(crate) fn too_many_pairs(cutoff: f64, sites: usize, count: &str) -> PotentialError {
    PotentialError::new(
        "cutoff",
        format!(
            "{cutoff} gives {count} interacting pairs (periodic images included) \
             for {sites} rotors, more than the limit {MAX_PAIRS}"
        ),
    )
}
