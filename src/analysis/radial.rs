//! The radial distribution function of body centres in a periodic
//! orthorhombic box, averaged over frames.
//!
//! Pairs are counted at their minimum-image distance `r < r_max <= L_min/2`
//! in `bins` shells of width `dr = r_max / bins`, and each shell's count is
//! divided by what an ideal gas of the same `N` bodies gives:
//! `g(r) = 2 h(r) / (F N (N - 1)/V * 4/3 pi (r_out^3 - r_in^3))` for `F`
//! frames, so uniform random points give `g = 1` exactly on average (`N - 1`
//! partners, not `N`). The coordination number `n(r)`, the mean count of
//! neighbours closer than a shell's outer radius, is the running sum
//! `2 h / (F N)`.

use super::error::AnalysisError;
use super::frames::Frames;
use crate::checks::{finite_and_positive, num};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::f64::consts::PI;

/// `g(r)` and `n(r)` over `bins` shells.
#[derive(Clone, Debug, PartialEq)]
pub struct RadialDistribution {
    /// The shells' edges, `bins + 1` values from 0 to `r_max`.
    pub edges: Vec<f64>,
    /// The shells' mid radii.
    pub r: Vec<f64>,
    /// `g` of each shell.
    pub g: Vec<f64>,
    /// The mean number of neighbours closer than each shell's outer edge.
    pub coordination: Vec<f64>,
}

/// Refuses a periodic box with a side that is not finite and > 0.
pub(super) fn check_box(box_lengths: &Vector3<f64>) -> Result<(), AnalysisError> {
    ["x", "y", "z"]
        .iter()
        .zip(box_lengths.iter())
        .try_for_each(|(axis, &l)| finite_and_positive(&format!("box_lengths.{axis}"), l).map(drop))
}

/// The radial distribution function of `centres` (wrapped or not: the
/// minimum image is taken) in the periodic box `box_lengths`, out to
/// `r_max` (default and largest: half the shortest side) in `bins` shells.
pub fn radial_distribution(
    centres: &Frames<'_, Vector3<f64>>,
    box_lengths: &Vector3<f64>,
    r_max: Option<f64>,
    bins: usize,
) -> Result<RadialDistribution, AnalysisError> {
    check_box(box_lengths)?;
    let r_max = largest_radius(box_lengths, r_max)?;
    if bins == 0 {
        return Err(AnalysisError::new("bins", "must be at least 1, got 0"));
    }
    let n = centres.rotors();
    if n < 2 {
        return Err(AnalysisError::new(
            centres.what(),
            "needs at least two bodies for pairs, got 1",
        ));
    }
    crate::memory::check(
        "bins",
        (rayon::current_num_threads() as f64 + 4.0) * 8.0 * bins as f64,
    )?;
    let width = r_max / bins as f64;
    let counts = pair_counts(centres, box_lengths, r_max, bins);
    let frames = centres.frames() as f64;
    let volume = box_lengths.product();
    let pair_density = frames * n as f64 * (n - 1) as f64 / volume;
    let edges: Vec<f64> = (0..=bins).map(|b| b as f64 * width).collect();
    let g: Vec<f64> = counts
        .iter()
        .zip(edges.windows(2))
        .map(|(&h, e)| {
            2.0 * h as f64 / (pair_density * 4.0 / 3.0 * PI * (e[1].powi(3) - e[0].powi(3)))
        })
        .collect();
    if let Some(b) = g.iter().position(|x| !x.is_finite()) {
        return Err(AnalysisError::new(
            "box_lengths",
            format!(
                "g(r) of shell {b} is not finite: the box volume {} or the shell volumes (width {}) under- or overflow float64",
                num(volume),
                num(width)
            ),
        ));
    }
    let coordination = counts
        .iter()
        .scan(0u64, |sum, &h| {
            *sum += h;
            Some(2.0 * *sum as f64 / (frames * n as f64))
        })
        .collect();
    let r = edges.windows(2).map(|e| 0.5 * (e[0] + e[1])).collect();
    Ok(RadialDistribution {
        edges,
        r,
        g,
        coordination,
    })
}

/// Pairs of each frame's centres at minimum-image distance `r < r_max`,
/// counted in `bins` shells of equal width.
fn pair_counts(
    centres: &Frames<'_, Vector3<f64>>,
    box_lengths: &Vector3<f64>,
    r_max: f64,
    bins: usize,
) -> Vec<u64> {
    let n = centres.rotors();
    let width = r_max / bins as f64;
    (0..centres.frames() * n)
        .into_par_iter()
        .fold(
            || vec![0u64; bins],
            |mut counts, k| {
                let (frame, i) = (centres.frame(k / n), k % n);
                for other in &frame[i + 1..] {
                    let mut d = other - frame[i];
                    for c in 0..3 {
                        d[c] -= box_lengths[c] * (d[c] / box_lengths[c]).round();
                    }
                    let r = d.norm();
                    if r < r_max {
                        // r < r_max: the bin is below `bins` but for round-off.
                        counts[((r / width) as usize).min(bins - 1)] += 1;
                    }
                }
                counts
            },
        )
        .reduce(
            || vec![0u64; bins],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        )
}

/// `r_max` if finite, > 0 and at most half the shortest side, which is the
/// default.
fn largest_radius(box_lengths: &Vector3<f64>, r_max: Option<f64>) -> Result<f64, AnalysisError> {
    let half = 0.5 * box_lengths.min();
    let Some(r) = r_max else {
        return Ok(half);
    };
    let r = finite_and_positive("r_max", r)?;
    if r > half {
        return Err(AnalysisError::new(
            "r_max",
            format!(
                "must be at most half the shortest box side {}, got {}",
                num(half),
                num(r)
            ),
        ));
    }
    Ok(r)
}
