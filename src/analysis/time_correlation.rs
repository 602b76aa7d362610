//! Time-correlation functions of a trajectory, averaged over all time
//! origins and all rotors: the orientational `C1(t) = <u(0).u(t)>` and
//! `C2(t) = <P2(u(0).u(t))>` of body axes, and vector autocorrelations such
//! as the angular-velocity `<w(0).w(t)>`.
//!
//! Each lag `k` (time `k dt`) averages over the `T - k` origins of a
//! trajectory of `T` frames and over the rotors, computed by FFT (the
//! private `autocorrelation` module: zero-padded, power spectra summed). `C2` uses
//! `(u(0).u(t))^2 = sum_{a,b} u_a u_b (0) u_a u_b (t)`: the autocorrelations
//! of the six products `u_a u_b` (the three off-diagonal ones twice), so
//! `C2 = (3 <(u(0).u(t))^2> - 1) / 2` comes from the same FFT sums.

use super::autocorrelation::{Plan, PowerSum};
use super::error::AnalysisError;
use super::frames::Frames;
use crate::checks::{finite_and_positive, num};
use crate::observables::order::checked_unit_axis;
use crate::quaternion::Quat;
use nalgebra::{Unit, Vector3};
use rayon::prelude::*;

/// `C1` and `C2` of one body axis at lags `0..=max_lag`.
#[derive(Clone, Debug, PartialEq)]
pub struct OrientationalCorrelation {
    /// `C1(k dt) = <u(0).u(k dt)>` (1 at lag 0).
    pub c1: Vec<f64>,
    /// `C2(k dt) = <P2(u(0).u(k dt))>`, `P2(x) = (3x^2 - 1)/2` (1 at lag 0).
    pub c2: Vec<f64>,
}

/// The times `k dt` of lags `0..lags` of frames `dt` apart (finite, > 0,
/// and small enough that the last time is finite).
pub fn lag_times(dt: f64, lags: usize) -> Result<Vec<f64>, AnalysisError> {
    let dt = finite_and_positive("dt", dt)?;
    let last = lags.saturating_sub(1) as f64 * dt;
    if !last.is_finite() {
        return Err(AnalysisError::new(
            "dt",
            format!(
                "the time of lag {} overflows float64, got {}",
                lags - 1,
                num(dt)
            ),
        ));
    }
    Ok((0..lags).map(|k| k as f64 * dt).collect())
}

/// `values` (correlations of the input `what`) if all finite, else the
/// error that the input's magnitudes overflow.
pub(super) fn finite_correlation(values: Vec<f64>, what: &str) -> Result<Vec<f64>, AnalysisError> {
    if values.iter().all(|x| x.is_finite()) {
        Ok(values)
    } else {
        Err(AnalysisError::new(
            what,
            "the correlation is not finite: the values' products overflow float64",
        ))
    }
}

/// The largest lag: `max_lag` if given (must be below the frame count),
/// else the last frame.
pub(super) fn largest_lag(frames: usize, max_lag: Option<usize>) -> Result<usize, AnalysisError> {
    match max_lag {
        None => Ok(frames - 1),
        Some(k) if k < frames => Ok(k),
        Some(k) => Err(AnalysisError::new(
            "max_lag",
            format!("must be below the number of frames {frames}, got {k}"),
        )),
    }
}

/// The pairs `(a, b)`, `a <= b`, of the symmetric products `u_a u_b` and the
/// weight of each in `(u.v)^2 = sum_{a,b} u_a u_b v_a v_b`.
const PRODUCTS: [(usize, usize, f64); 6] = [
    (0, 0, 1.0),
    (1, 1, 1.0),
    (2, 2, 1.0),
    (0, 1, 2.0),
    (0, 2, 2.0),
    (1, 2, 2.0),
];

/// `C1` and `C2` for each body axis in `axes_body` (body-frame vectors,
/// normalised here; nonzero) of the rotors in `orientations` (normalised
/// per frame, so Gear schemes' drifting `|Q|` does not enter), at lags
/// `0..=max_lag` (default: every lag). Time is `lag * dt` for frames `dt`
/// apart; the function needs only the frames.
pub fn orientational_correlations(
    orientations: &Frames<'_, Quat>,
    axes_body: &[Vector3<f64>],
    max_lag: Option<usize>,
) -> Result<Vec<OrientationalCorrelation>, AnalysisError> {
    let max_lag = largest_lag(orientations.frames(), max_lag)?;
    if axes_body.is_empty() {
        return Err(AnalysisError::new("axes_body", "needs at least one axis"));
    }
    let axes = axes_body
        .iter()
        .enumerate()
        .map(|(a, v)| checked_unit_axis(&format!("axes_body[{a}]"), v).map(Unit::into_inner))
        .collect::<Result<Vec<_>, _>>()?;
    check_memory(orientations.frames(), axes.len(), max_lag)?;
    let plan = Plan::new(orientations.frames());
    let weight = 1.0 / orientations.rotors() as f64;
    let empty = || -> Vec<(PowerSum<'_>, PowerSum<'_>)> {
        axes.iter()
            .map(|_| (plan.power_sum(), plan.power_sum()))
            .collect()
    };
    let sums = (0..orientations.rotors())
        .into_par_iter()
        .fold(empty, |mut sums, rotor| {
            let rotations: Vec<_> = orientations
                .rotor(rotor)
                .map(|q| q.try_normalize().unwrap_or(q).body_to_space_matrix())
                .collect();
            for (axis, (first, second)) in axes.iter().zip(sums.iter_mut()) {
                let u: Vec<Vector3<f64>> = rotations.iter().map(|r| r * axis).collect();
                for c in 0..3 {
                    first.add(weight, u.iter().map(|u| u[c]));
                }
                for (a, b, w) in PRODUCTS {
                    second.add(weight * w, u.iter().map(|u| u[a] * u[b]));
                }
            }
            sums
        })
        .reduce(empty, |left, right| {
            left.into_iter()
                .zip(right)
                .map(|((l1, l2), (r1, r2))| (l1.merge(r1), l2.merge(r2)))
                .collect()
        });
    Ok(sums
        .into_iter()
        .map(|(first, second)| OrientationalCorrelation {
            c1: first.correlation(max_lag),
            c2: second
                .correlation(max_lag)
                .into_iter()
                .map(|x2| 1.5 * x2 - 0.5)
                .collect(),
        })
        .collect())
}

/// Refuses, before anything is allocated, correlations whose buffers pass
/// the memory limit: per thread, two FFT power sums (input, spectrum and
/// power, about `3 x 8` bytes per padded sample) for each axis, and the
/// `C1` and `C2` of each axis (found by the analysis fuzz: 10^5 axes of
/// 10^5 frames aborted the process on a failed allocation).
fn check_memory(frames: usize, axes: usize, max_lag: usize) -> Result<(), AnalysisError> {
    let padded = (2.0 * frames as f64).log2().ceil().exp2();
    let threads = rayon::current_num_threads() as f64;
    let per_axis = threads * 2.0 * 3.0 * 8.0 * padded + 2.0 * 8.0 * (max_lag as f64 + 1.0);
    crate::memory::check("axes_body, orientations", axes as f64 * per_axis)
}

/// `<v(0).v(k dt)>` at lags `0..=max_lag` (default: every lag) of per-rotor
/// vectors, averaged over time origins and rotors, in whatever frame the
/// vectors are given (for angular velocities: body components from a run's
/// `omega_body`, or space components). Not normalised: lag 0 is `<|v|^2>`.
pub fn vector_autocorrelation(
    vectors: &Frames<'_, Vector3<f64>>,
    max_lag: Option<usize>,
) -> Result<Vec<f64>, AnalysisError> {
    let max_lag = largest_lag(vectors.frames(), max_lag)?;
    let plan = Plan::new(vectors.frames());
    let weight = 1.0 / vectors.rotors() as f64;
    let sum = (0..vectors.rotors())
        .into_par_iter()
        .fold(
            || plan.power_sum(),
            |mut sum, rotor| {
                for c in 0..3 {
                    sum.add(weight, vectors.rotor(rotor).map(|v| v[c]));
                }
                sum
            },
        )
        .reduce(|| plan.power_sum(), PowerSum::merge);
    finite_correlation(sum.correlation(max_lag), vectors.what())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lag `k` is at time `k dt`; a time step that is not finite and
    /// positive is refused by name.
    #[test]
    fn lag_times_are_multiples_of_a_positive_dt() {
        assert_eq!(lag_times(0.5, 3).unwrap(), vec![0.0, 0.5, 1.0]);
        assert_eq!(
            lag_times(0.0, 3).unwrap_err().to_string(),
            "dt: must be finite and > 0, got 0"
        );
        assert_eq!(
            lag_times(f64::NAN, 3).unwrap_err().to_string(),
            "dt: must be finite and > 0, got NaN"
        );
    }

    /// Rotors turning at constant rates about fixed space axes: the direct
    /// double sum over origins of `u(0).u(t)` and `P2` of it, for two axes.
    #[test]
    fn match_the_direct_average_over_origins_and_rotors() {
        let frames = 40;
        let rotors = 3;
        let spin = [
            Vector3::new(0.3, -0.1, 0.2),
            Vector3::new(0.0, 0.5, 0.1),
            Vector3::new(-0.2, 0.2, 0.7),
        ];
        let start = [
            Quat::new(0.9, 0.1, -0.3, 0.2),
            Quat::new(0.2, 0.8, 0.1, -0.5),
            Quat::IDENTITY,
        ];
        let q: Vec<Quat> = (0..frames)
            .flat_map(|t| {
                (0..rotors).map(move |i| {
                    // Not normalised on purpose: the analysis normalises.
                    Quat::exp(&(spin[i] * t as f64)) * start[i] * 1.7
                })
            })
            .collect();
        let trajectory = Frames::new(&q, rotors, "orientations").unwrap();
        let axes = [Vector3::new(0.0, 0.0, 2.0), Vector3::new(1.0, 1.0, 0.0)];
        let result = orientational_correlations(&trajectory, &axes, Some(25)).unwrap();
        for (axis, c) in axes.iter().zip(&result) {
            let axis = Unit::new_normalize(*axis).into_inner();
            let u = |t: usize, i: usize| {
                q[t * rotors + i]
                    .try_normalize()
                    .unwrap()
                    .body_to_space(&axis)
            };
            for lag in 0..=25 {
                let (mut c1, mut c2) = (0.0, 0.0);
                for i in 0..rotors {
                    for t in 0..frames - lag {
                        let x = u(t, i).dot(&u(t + lag, i));
                        c1 += x;
                        c2 += 1.5 * x * x - 0.5;
                    }
                }
                let origins = (rotors * (frames - lag)) as f64;
                assert!((c.c1[lag] - c1 / origins).abs() < 1e-13, "lag {lag}");
                assert!((c.c2[lag] - c2 / origins).abs() < 1e-13, "lag {lag}");
            }
        }
    }

    /// The vector autocorrelation is the direct origin and rotor average.
    #[test]
    fn vector_autocorrelation_is_the_direct_average() {
        let frames = 17;
        let v: Vec<Vector3<f64>> = (0..frames * 2)
            .map(|k| Vector3::new((k as f64).sin(), (0.3 * k as f64).cos(), 0.1 * k as f64))
            .collect();
        let c = vector_autocorrelation(&Frames::new(&v, 2, "omega").unwrap(), None).unwrap();
        assert_eq!(c.len(), frames);
        for (lag, value) in c.iter().enumerate() {
            let mut direct = 0.0;
            for i in 0..2 {
                for t in 0..frames - lag {
                    direct += v[t * 2 + i].dot(&v[(t + lag) * 2 + i]);
                }
            }
            direct /= (2 * (frames - lag)) as f64;
            assert!((value - direct).abs() < 1e-12 * direct.abs().max(1.0));
        }
    }

    /// A lag beyond the trajectory and a zero axis are refused by name.
    #[test]
    fn bad_lag_and_axis_are_refused() {
        let q = [Quat::IDENTITY; 4];
        let f = Frames::new(&q, 1, "orientations").unwrap();
        let err = orientational_correlations(&f, &[Vector3::z()], Some(4)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "max_lag: must be below the number of frames 4, got 4"
        );
        let err = orientational_correlations(&f, &[Vector3::zeros()], None).unwrap_err();
        assert_eq!(err.path, "axes_body[0]");
    }
}
