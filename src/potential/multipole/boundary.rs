//! Open or periodic boundaries: the box, how the periodic sum is taken
//! ([`PeriodicSum`]), and the limits on the size of the sums.

use super::{Accuracy, PeriodicSum, PotentialError, SumOptions, Surface};
use crate::checks::{each, positive};
use nalgebra::Vector3;

/// The most interacting pairs (periodic images included) a pair list may
/// hold: about 0.8 GB of pair indices, and it bounds the build time. The
/// largest lattice a scene allows (1e6 sites) with cutoff 3.1 at unit
/// density has about 6.1e7.
pub const MAX_PAIRS: usize = 100_000_000;

/// Bytes a pair of the truncated periodic sum may cost while the pair list
/// is built, at most: its partner and geometry index (8), a geometry of its
/// own when its offset is shared by no other pair (96, and about 56 in the
/// map of offsets), and the two directed entries of the quad kernel's build
/// (64). Sizes are checked against the memory limit with it.
pub const BYTES_PER_PAIR: f64 = 224.0;

/// How site pairs are enumerated and summed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// An isolated cluster: every pair interacts, no cutoff.
    Open,
    /// An orthorhombic periodic box of edges `box_lengths` (> 0, length unit
    /// of the scene, along x, y, z), summed as `sum` says.
    Periodic {
        /// The edges of the box along x, y, z.
        box_lengths: Vector3<f64>,
        /// How the images are summed.
        sum: PeriodicSum,
    },
}

impl Boundary {
    /// A periodic box summed with a spherical cutoff.
    pub fn periodic_cutoff(box_lengths: Vector3<f64>, cutoff: f64) -> Boundary {
        Boundary::Periodic {
            box_lengths,
            sum: PeriodicSum::Cutoff { cutoff },
        }
    }

    /// A periodic box summed by Ewald at the default accuracy, conducting surface.
    pub fn periodic_ewald(box_lengths: Vector3<f64>) -> Boundary {
        Boundary::Periodic {
            box_lengths,
            sum: PeriodicSum::Ewald {
                accuracy: Accuracy::DEFAULT,
                surface: Surface::default(),
            },
        }
    }

    /// The periodic box `box_lengths` summed as `options` say: the one
    /// reading of the sum's options, by the scene and the Python keywords
    /// alike. Refused, in this order, for keys of the other sum
    /// (`SumOptions::truncation`), a bad box (path `box_lengths`) and an
    /// accuracy outside (0, 1) ([`Accuracy::new`]); the cutoff and the size
    /// of the sum are checked by [`Self::validate`].
    pub fn periodic(
        box_lengths: Vector3<f64>,
        options: &SumOptions,
    ) -> Result<Boundary, PotentialError> {
        let truncation = options.truncation()?;
        check_box(&box_lengths)?;
        Ok(Boundary::Periodic {
            box_lengths,
            sum: PeriodicSum::new(truncation, options)?,
        })
    }

    /// Checks the box (path `box_lengths[k]`: finite and > 0) and the cutoff
    /// (path `cutoff`: finite and > 0) for `sites` sites (the estimated size
    /// of a truncated periodic sum at most [`MAX_PAIRS`]; the Ewald sums
    /// check their own sizes when they are built, their accuracy is checked
    /// when it is made).
    pub fn validate(&self, sites: usize) -> Result<(), PotentialError> {
        let Boundary::Periodic { box_lengths, sum } = *self else {
            return Ok(());
        };
        check_box(&box_lengths)?;
        if let PeriodicSum::Cutoff { cutoff } = sum {
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
            pair_memory(cutoff, sites, estimate)?;
        }
        Ok(())
    }
}

/// Checks the edges of a periodic box (path `box_lengths[k]`: finite and
/// > 0) and its volume, which the sums divide by (a normal number).
fn check_box(box_lengths: &Vector3<f64>) -> Result<(), PotentialError> {
    each(box_lengths.as_slice(), positive).map_err(|e| e.at("box_lengths"))?;
    let volume = box_lengths.product();
    if !volume.is_normal() {
        return Err(PotentialError::new(
            "box_lengths",
            format!(
                "must give a volume between {:e} and {:e}, got {}",
                f64::MIN_POSITIVE,
                f64::MAX,
                crate::checks::num(volume)
            ),
        ));
    }
    Ok(())
}

/// Refuses a truncated periodic sum of `pairs` pairs (estimated or found)
/// whose pair list would exceed the memory limit.
pub(crate) fn pair_memory(cutoff: f64, sites: usize, pairs: f64) -> Result<(), PotentialError> {
    crate::memory::check("cutoff", pairs * BYTES_PER_PAIR).map_err(|e| {
        PotentialError::new(
            "cutoff",
            format!(
                "{cutoff} gives about {pairs:.2e} interacting pairs (periodic images included) for {sites} rotors: {}",
                e.message
            ),
        )
    })
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
