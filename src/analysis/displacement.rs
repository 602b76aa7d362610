//! Translational motion of moving bodies: the mean-squared displacement of
//! their centres, averaged over all time origins and bodies, and the
//! self-diffusion coefficient from its linear regime (Einstein relation).
//!
//! Centres are unwrapped first, `r = x + n L` (the wrapped position `x`,
//! the image counts `n` a run records and the box lengths `L`), so a body
//! that crosses the box keeps moving. With `d(t) = r(t) - r(0)` per body,
//! `MSD(k) = 1/(T-k) sum_t |d(t+k) - d(t)|^2
//!         = 1/(T-k) sum_t (|d(t)|^2 + |d(t+k)|^2) - 2 <d(t).d(t+k)>`:
//! the first sum from prefix sums, the second by FFT (the private
//! `autocorrelation` module), `O(T log T)` per body instead of `O(T^2)`.

use super::autocorrelation::{Plan, PowerSum};
use super::error::AnalysisError;
use super::frames::Frames;
use super::radial::check_box;
use super::time_correlation::{finite_correlation, largest_lag};
use crate::checks::num;
use crate::stats::line_fit;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Unwrapped centres `x + n L` of wrapped `positions` with image counts
/// `images` (the same shape) in a periodic box of `box_lengths` (finite,
/// > 0).
pub fn unwrapped_positions(
    positions: &Frames<'_, Vector3<f64>>,
    images: &Frames<'_, Vector3<f64>>,
    box_lengths: &Vector3<f64>,
) -> Result<Vec<Vector3<f64>>, AnalysisError> {
    check_box(box_lengths)?;
    if (images.frames(), images.rotors()) != (positions.frames(), positions.rotors()) {
        return Err(AnalysisError::new(
            images.what(),
            format!(
                "{} frames of {} bodies, but {} has {} frames of {}",
                images.frames(),
                images.rotors(),
                positions.what(),
                positions.frames(),
                positions.rotors()
            ),
        ));
    }
    let unwrapped: Vec<Vector3<f64>> = (0..positions.frames())
        .flat_map(|f| {
            positions
                .frame(f)
                .iter()
                .zip(images.frame(f))
                .map(|(x, n)| x + n.component_mul(box_lengths))
        })
        .collect();
    if let Some(k) = unwrapped
        .iter()
        .position(|r| !r.iter().all(|c| c.is_finite()))
    {
        return Err(AnalysisError::new(
            format!(
                "{}[{}, {}]",
                images.what(),
                k / positions.rotors(),
                k % positions.rotors()
            ),
            "the unwrapped position overflows float64",
        ));
    }
    Ok(unwrapped)
}

/// `MSD(k dt) = <|r(t + k dt) - r(t)|^2>` at lags `0..=max_lag` (default:
/// every lag) of unwrapped centres, over all time origins and bodies.
pub fn mean_squared_displacement(
    centres: &Frames<'_, Vector3<f64>>,
    max_lag: Option<usize>,
) -> Result<Vec<f64>, AnalysisError> {
    let max_lag = largest_lag(centres.frames(), max_lag)?;
    let frames = centres.frames();
    crate::memory::check(
        centres.what(),
        rayon::current_num_threads() as f64
            * 3.0
            * 8.0
            * (2.0 * frames as f64).log2().ceil().exp2()
            + 16.0 * frames as f64,
    )?;
    let plan = Plan::new(frames);
    let weight = 1.0 / centres.rotors() as f64;
    // Per body: the FFT sum of d(t).d(t+k) and the origin sums of |d|^2.
    let empty = || (plan.power_sum(), vec![0.0; max_lag + 1]);
    let (products, squares) = (0..centres.rotors())
        .into_par_iter()
        .fold(empty, |(mut products, mut squares), body| {
            let start = centres.rotor(body).next().unwrap_or_default();
            let d: Vec<Vector3<f64>> = centres.rotor(body).map(|r| r - start).collect();
            for c in 0..3 {
                products.add(weight, d.iter().map(|v| v[c]));
            }
            // prefix[t] = sum_{s < t} |d(s)|^2
            let mut prefix = vec![0.0; frames + 1];
            for (t, v) in d.iter().enumerate() {
                prefix[t + 1] = prefix[t] + v.norm_squared();
            }
            for (k, s) in squares.iter_mut().enumerate() {
                let early = prefix[frames - k];
                let late = prefix[frames] - prefix[k];
                *s += weight * (early + late) / (frames - k) as f64;
            }
            (products, squares)
        })
        .reduce(empty, |(p, mut s), (q, r)| {
            s.iter_mut().zip(&r).for_each(|(a, b)| *a += b);
            (p.merge(q), s)
        });
    let msd = squares
        .iter()
        .zip(PowerSum::correlation(products, max_lag))
        // Round-off can leave a zero displacement a hair below 0.
        .map(|(s, c)| (s - 2.0 * c).max(0.0))
        .collect();
    finite_correlation(msd, centres.what())
}

/// The self-diffusion coefficient from the linear regime of an MSD.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelfDiffusion {
    /// `D = slope / 6` (Einstein relation in three dimensions).
    pub coefficient: f64,
    /// The least-squares slope of `MSD(t)` over the window.
    pub slope: f64,
    /// Its intercept at `t = 0`.
    pub intercept: f64,
    /// The number of lags in the window.
    pub points: usize,
}

/// `D = lim MSD(t) / 6t`, fitted as the slope of a straight line through
/// the points `(time, msd)` with `window.0 <= time <= window.1` (at least
/// two), so the ballistic start and the noisy long lags are left out.
pub fn self_diffusion(
    time: &[f64],
    msd: &[f64],
    window: (f64, f64),
) -> Result<SelfDiffusion, AnalysisError> {
    if time.len() != msd.len() {
        return Err(AnalysisError::new(
            "msd",
            format!("{} values for {} times", msd.len(), time.len()),
        ));
    }
    let (start, end) = window;
    if !(start.is_finite() && end.is_finite() && start < end) {
        return Err(AnalysisError::new(
            "fit_window",
            format!(
                "must be finite with start < end, got ({}, {})",
                num(start),
                num(end)
            ),
        ));
    }
    let (t, m): (Vec<f64>, Vec<f64>) = time
        .iter()
        .zip(msd)
        .filter(|(t, _)| (start..=end).contains(*t))
        .map(|(t, m)| (*t, *m))
        .unzip();
    if t.len() < 2 {
        return Err(AnalysisError::new(
            "fit_window",
            format!(
                "holds {} lag times, needs at least 2, got ({}, {})",
                t.len(),
                num(start),
                num(end)
            ),
        ));
    }
    let fit = line_fit(&t, &m);
    let intercept = crate::stats::mean(&m) - fit.slope * crate::stats::mean(&t);
    Ok(SelfDiffusion {
        coefficient: fit.slope / 6.0,
        slope: fit.slope,
        intercept,
        points: t.len(),
    })
}
