//! Autocorrelations of real series by FFT, summed over many series.
//!
//! For a series `x(0), ..., x(T-1)` the time-origin average at lag `k` is
//! `c(k) = 1/(T-k) sum_{t=0}^{T-1-k} x(t) x(t+k)`. Zero-padded to a length
//! `L >= 2T-1`, the circular autocorrelation of the padded series is the
//! linear one (Wiener-Khinchin: `sum_t x(t) x(t+k) = IFFT(|FFT x|^2)(k)`),
//! and because the inverse transform is linear the power spectra of many
//! series (rotors, vector components) are summed first and transformed back
//! once. Cost `O(L log L)` per series instead of `O(T^2)`.

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::sync::Arc;

/// The transforms for series of one length, shared by all threads.
pub(crate) struct Plan {
    frames: usize,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
}

impl Plan {
    /// Transforms for series of `frames` samples (>= 1), padded to the
    /// power of two at or above `2 frames` (fast, and `>= 2T - 1`).
    pub(crate) fn new(frames: usize) -> Plan {
        let padded = (2 * frames).next_power_of_two();
        let mut planner = RealFftPlanner::<f64>::new();
        Plan {
            frames,
            forward: planner.plan_fft_forward(padded),
            inverse: planner.plan_fft_inverse(padded),
        }
    }

    /// An empty sum of power spectra.
    pub(crate) fn power_sum(&self) -> PowerSum<'_> {
        PowerSum {
            plan: self,
            input: self.forward.make_input_vec(),
            spectrum: self.forward.make_output_vec(),
            scratch: self.forward.make_scratch_vec(),
            power: vec![0.0; self.forward.make_output_vec().len()],
        }
    }
}

/// A weighted sum of the power spectra `|FFT x|^2` of zero-padded series.
pub(crate) struct PowerSum<'p> {
    plan: &'p Plan,
    input: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    power: Vec<f64>,
}

impl PowerSum<'_> {
    /// Adds `weight |FFT x|^2` of the series `x` (exactly `frames` values).
    pub(crate) fn add(&mut self, weight: f64, series: impl Iterator<Item = f64>) {
        self.input.fill(0.0);
        let mut count = 0;
        for (slot, x) in self.input.iter_mut().zip(series) {
            *slot = x;
            count += 1;
        }
        debug_assert_eq!(count, self.plan.frames);
        self.plan
            .forward
            .process_with_scratch(&mut self.input, &mut self.spectrum, &mut self.scratch)
            .expect("buffers made by the plan have its lengths");
        for (p, z) in self.power.iter_mut().zip(&self.spectrum) {
            *p += weight * z.norm_sqr();
        }
    }

    /// The sum of two sums (for a parallel reduction).
    pub(crate) fn merge(mut self, other: PowerSum<'_>) -> Self {
        for (p, q) in self.power.iter_mut().zip(&other.power) {
            *p += q;
        }
        self
    }

    /// `sum_series weight * 1/(T-k) sum_t x(t) x(t+k)` for lags `k = 0..=max_lag`
    /// (`max_lag < frames`).
    pub(crate) fn correlation(self, max_lag: usize) -> Vec<f64> {
        let plan = self.plan;
        let padded = plan.inverse.len();
        let mut spectrum: Vec<Complex<f64>> =
            self.power.iter().map(|&p| Complex::new(p, 0.0)).collect();
        let mut lags = plan.inverse.make_output_vec();
        let mut scratch = plan.inverse.make_scratch_vec();
        plan.inverse
            .process_with_scratch(&mut spectrum, &mut lags, &mut scratch)
            .expect("a real power spectrum of the plan's length");
        // realfft's inverse is unnormalised: it returns `padded` times the sum.
        (0..=max_lag)
            .map(|k| lags[k] / (padded as f64 * (plan.frames - k) as f64))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct double sum over time origins, for comparison.
    fn direct(series: &[f64], lag: usize) -> f64 {
        let t = series.len();
        (0..t - lag)
            .map(|i| series[i] * series[i + lag])
            .sum::<f64>()
            / (t - lag) as f64
    }

    /// The FFT sum equals the direct origin average at every lag, for
    /// lengths on and off a power of two, and weights add linearly.
    #[test]
    fn matches_the_direct_origin_average() {
        for frames in [1, 2, 7, 64, 100] {
            let a: Vec<f64> = (0..frames).map(|i| (0.37 * i as f64).sin() + 0.2).collect();
            let b: Vec<f64> = (0..frames).map(|i| (1.3 * i as f64).cos()).collect();
            let plan = Plan::new(frames);
            let mut sum = plan.power_sum();
            sum.add(1.0, a.iter().copied());
            let mut other = plan.power_sum();
            other.add(2.0, b.iter().copied());
            let c = sum.merge(other).correlation(frames - 1);
            for (k, ck) in c.iter().enumerate() {
                let expected = direct(&a, k) + 2.0 * direct(&b, k);
                assert!(
                    (ck - expected).abs() < 1e-12 * (1.0 + expected.abs()),
                    "frames {frames}, lag {k}: {ck} vs {expected}"
                );
            }
        }
    }
}
