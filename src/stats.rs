//! The statistics of runs, each defined once: means, the least-squares line
//! (slope, residual, standard error of the slope), block averages, and the
//! drift and fluctuation of the total energy.

/// The arithmetic mean (NaN for no values).
pub fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// The least-squares line `y = mean_y + slope (x - mean_x)` through points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    /// The slope (0 when all `x` are equal).
    pub slope: f64,
    /// The number of points.
    pub points: usize,
    /// `sum (x - mean_x)^2`.
    pub sxx: f64,
    /// The residual sum of squares.
    pub residual: f64,
}

impl LineFit {
    /// The root-mean-square residual, `sqrt(residual / points)`.
    pub fn rms_residual(&self) -> f64 {
        (self.residual / self.points as f64).sqrt()
    }

    /// The standard error of the slope, `sqrt(residual / (points - 2) / sxx)`.
    pub fn slope_standard_error(&self) -> f64 {
        (self.residual / (self.points as f64 - 2.0) / self.sxx).sqrt()
    }
}

/// The least-squares line through `(x[i], y[i])`.
pub fn line_fit(x: &[f64], y: &[f64]) -> LineFit {
    let (mx, my) = (mean(x), mean(y));
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let residual = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    LineFit {
        slope,
        points: x.len(),
        sxx,
        residual,
    }
}

/// The means of `blocks` consecutive blocks of equal length (a remainder
/// shorter than a block is left out), so that correlated fluctuations
/// average out.
pub fn block_means(values: &[f64], blocks: usize) -> Vec<f64> {
    let len = values.len() / blocks;
    values.chunks_exact(len).take(blocks).map(mean).collect()
}

/// Drift and fluctuation of the total energy over a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyDrift {
    /// Least-squares slope of the total energy against time, divided by the
    /// scale: relative drift per unit time.
    pub relative_per_time: f64,
    /// RMS deviation of the total energy from that line, divided by the scale.
    pub relative_fluctuation: f64,
}

/// The drift of `total` against `times`, relative to the mean of `kinetic`,
/// or to `fallback_scale` when that mean is not positive (rotors at rest).
pub fn energy_drift(
    times: &[f64],
    total: &[f64],
    kinetic: &[f64],
    fallback_scale: f64,
) -> EnergyDrift {
    let mean_kinetic = mean(kinetic);
    let scale = if mean_kinetic > 0.0 {
        mean_kinetic
    } else {
        fallback_scale
    };
    let fit = line_fit(times, total);
    EnergyDrift {
        relative_per_time: fit.slope / scale,
        relative_fluctuation: fit.rms_residual() / scale,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line is fitted exactly, with zero residual; the standard error
    /// follows the textbook formula on a known set.
    #[test]
    fn line_fit_recovers_a_line_and_its_standard_error() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let fit = line_fit(&x, &[1.0, 3.0, 5.0, 7.0]);
        assert_eq!((fit.slope, fit.residual), (2.0, 0.0));
        // By hand: mean_x = mean_y = 1.5, sxy = 4, sxx = 5, slope 0.8,
        // residuals (-0.3, 0.9, -0.9, 0.3), residual sum of squares 1.8.
        let fit = line_fit(&x, &[0.0, 2.0, 1.0, 3.0]);
        assert!((fit.slope - 0.8).abs() < 1e-15);
        assert!((fit.residual - 1.8).abs() < 1e-14);
        assert!((fit.slope_standard_error() - (1.8_f64 / 2.0 / 5.0).sqrt()).abs() < 1e-15);
        assert_eq!(line_fit(&[1.0, 1.0], &[0.0, 5.0]).slope, 0.0);
    }

    /// Blocks of equal length, the remainder left out.
    #[test]
    fn block_means_average_consecutive_blocks() {
        assert_eq!(block_means(&[1.0, 3.0, 5.0, 7.0, 100.0], 2), vec![2.0, 6.0]);
    }

    /// The drift is relative to the mean kinetic energy, or to the fallback
    /// for rotors at rest.
    #[test]
    fn energy_drift_is_relative_to_the_kinetic_energy() {
        let t = [0.0, 1.0, 2.0];
        let d = energy_drift(&t, &[1.0, 1.5, 2.0], &[2.0, 2.0, 2.0], 7.0);
        assert_eq!((d.relative_per_time, d.relative_fluctuation), (0.25, 0.0));
        let d = energy_drift(&t, &[1.0, 1.5, 2.0], &[0.0; 3], 5.0);
        assert_eq!(d.relative_per_time, 0.1);
    }
}
