//! The time-correlation functions against closed forms for free tops in
//! thermal equilibrium (reduced units, k_B = 1): uniformly random
//! orientations, Maxwell angular velocities `w_a ~ N(0, T/I_a)`, and the
//! exact free motion written here in closed form.
//!
//! Statistics: the rotors are split into groups; each group's correlation
//! function is an independent estimate, so at every lag the mean over groups
//! and its standard error give a t statistic against the closed form. A
//! test fails when the largest |t| over all lags and functions exceeds
//! `T_MAX`; the same statistic against the closed form with `T/I` doubled
//! must exceed it (the test would see a factor-of-two error).

mod common;

use common::{random_unit_quat, rng};
use nalgebra::Vector3;
use quatrot::analysis::{orientational_correlations, vector_autocorrelation, Frames};
use quatrot::Quat;
use rand::RngExt;
use rand_distr::StandardNormal;

/// 40 groups: t with 39 degrees of freedom exceeds 6 with two-sided
/// probability ~5e-7 (scipy 1.17.1 `2 t.sf(6, 39)`), so the ~400 lags and
/// functions tested here fail together with probability < 3e-4.
const GROUPS: usize = 40;
const T_MAX: f64 = 6.0;

/// Mean over groups and its standard error, per lag.
fn mean_and_error(groups: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let g = groups.len() as f64;
    let lags = groups[0].len();
    (0..lags)
        .map(|k| {
            let mean = groups.iter().map(|c| c[k]).sum::<f64>() / g;
            let var = groups.iter().map(|c| (c[k] - mean).powi(2)).sum::<f64>() / (g - 1.0);
            (mean, (var / g).sqrt())
        })
        .unzip()
}

/// The largest |t| of the estimates against `exact(lag)` over lags >= 1
/// (lag 0 is exact in every group).
fn largest_t(groups: &[Vec<f64>], exact: impl Fn(usize) -> f64) -> f64 {
    let (mean, error) = mean_and_error(groups);
    (1..mean.len())
        .map(|k| ((mean[k] - exact(k)) / error[k]).abs())
        .fold(0.0, f64::max)
}

/// `E[cos(|w| t)]` for `w ~ N(0, s^2 I_3)`: `(1 - s^2 t^2) exp(-s^2 t^2 / 2)`
/// (`d/dt [t E(sin(|w|t)/(|w|t))]`, and `E[sin(|w|t)/(|w|t)] = exp(-s^2 t^2/2)`
/// is the Fourier transform of the 3-d Gaussian at wave vector t).
fn mean_cos(s2: f64, t: f64) -> f64 {
    (1.0 - s2 * t * t) * (-0.5 * s2 * t * t).exp()
}

/// Free spherical top: C1(t) = 1/3 + 2/3 E[cos(|w|t)] and
/// C2(t) = 1/5 + 2/5 E[cos(|w|t)] + 2/5 E[cos(2|w|t)], s^2 = T/I.
/// A rotation by angle a about a random axis gives <P_l(u.Ru)> over axes =
/// chi_l(a)/(2l+1) = (1 + 2 sum_{m=1..l} cos(m a))/(2l+1) (the addition
/// theorem and the character of the rotation group); the rotor turns by
/// |w| t about the fixed axis w.
fn spherical_c1(s2: f64, t: f64) -> f64 {
    1.0 / 3.0 + 2.0 / 3.0 * mean_cos(s2, t)
}

fn spherical_c2(s2: f64, t: f64) -> f64 {
    0.2 + 0.4 * mean_cos(s2, t) + 0.4 * mean_cos(s2, 2.0 * t)
}

/// The closed forms above hold at t = 0 and for t -> inf (C1 -> 1/3,
/// C2 -> 1/5, the isotropic averages of cos^2 and P2 of a random rotation
/// about a random axis), and C1 has the short-time expansion
/// 1 - s^2 t^2 (each of two perpendicular components of w turns u).
#[test]
fn spherical_closed_forms_limits() {
    for s2 in [0.5, 2.0] {
        assert!((spherical_c1(s2, 0.0) - 1.0).abs() < 1e-15);
        assert!((spherical_c2(s2, 0.0) - 1.0).abs() < 1e-15);
        assert!((spherical_c1(s2, 50.0) - 1.0 / 3.0).abs() < 1e-12);
        assert!((spherical_c2(s2, 50.0) - 0.2).abs() < 1e-12);
        let t = 1e-4;
        assert!((spherical_c1(s2, t) - (1.0 - s2 * t * t)).abs() < 1e-14);
        // C2 = 1 - 3 s^2 t^2 at short times (l(l+1)/2 s^2 t^2 with l = 2).
        assert!((spherical_c2(s2, t) - (1.0 - 3.0 * s2 * t * t)).abs() < 1e-14);
    }
}

/// Thermal free spherical tops, Q(t) = Q0 exp(w_b t) (constant body angular
/// velocity): C1 and C2 of the three body axes and of an oblique one match
/// the closed forms; with T/I doubled they do not.
#[test]
fn free_spherical_top_c1_c2() {
    let (rotors_per_group, frames, dt) = (50, 60, 0.05);
    let (temperature, moment): (f64, f64) = (1.3, 0.8);
    let s2 = temperature / moment;
    let axes = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, -2.0, 0.5),
    ];
    let mut rng = rng(2026);
    let mut c1 = vec![Vec::new(); axes.len()];
    let mut c2 = vec![Vec::new(); axes.len()];
    for _ in 0..GROUPS {
        let starts: Vec<(Quat, Vector3<f64>)> = (0..rotors_per_group)
            .map(|_| {
                let q0 = random_unit_quat(&mut rng);
                let w = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal) * s2.sqrt());
                (q0, w)
            })
            .collect();
        let q: Vec<Quat> = (0..frames)
            .flat_map(|f| {
                let t = f as f64 * dt;
                starts.iter().map(move |(q0, w)| *q0 * Quat::exp(&(w * t)))
            })
            .collect();
        let trajectory = Frames::new(&q, rotors_per_group, "orientations").unwrap();
        for (a, c) in orientational_correlations(&trajectory, &axes, None)
            .unwrap()
            .into_iter()
            .enumerate()
        {
            c1[a].push(c.c1);
            c2[a].push(c.c2);
        }
    }
    let time = |k: usize| k as f64 * dt;
    for a in 0..axes.len() {
        let t1 = largest_t(&c1[a], |k| spherical_c1(s2, time(k)));
        let t2 = largest_t(&c2[a], |k| spherical_c2(s2, time(k)));
        assert!(t1 < T_MAX && t2 < T_MAX, "axis {a}: |t| {t1}, {t2}");
        let wrong1 = largest_t(&c1[a], |k| spherical_c1(2.0 * s2, time(k)));
        let wrong2 = largest_t(&c2[a], |k| spherical_c2(2.0 * s2, time(k)));
        assert!(
            wrong1 > T_MAX && wrong2 > T_MAX,
            "axis {a}: |t| {wrong1}, {wrong2}"
        );
    }
}

/// Free symmetric top (I1 = I2): Euler's equations turn the perpendicular
/// body angular velocity at Omega = w3 (I1 - I3)/I1 about body axis 3 and
/// keep w3, so <w_b(0).w_b(t)> = E[w3^2] + E[|w_perp|^2 cos(Omega t)]
/// = T/I3 + (2T/I1) exp(-((I1-I3)/I1)^2 T t^2 / (2 I3)) (w3 ~ N(0, T/I3)
/// independent of w_perp). With T doubled it fails.
#[test]
fn free_symmetric_top_angular_velocity_autocorrelation() {
    let (rotors_per_group, frames, dt) = (50, 80, 0.1);
    let (temperature, i1, i3) = (0.9, 1.0, 2.5);
    let rate = (i1 - i3) / i1;
    let exact = |t: f64, temperature: f64| {
        temperature / i3
            + 2.0 * temperature / i1 * (-(rate * rate) * temperature * t * t / (2.0 * i3)).exp()
    };
    let mut rng = rng(7);
    let mut groups = Vec::new();
    for _ in 0..GROUPS {
        let starts: Vec<Vector3<f64>> = (0..rotors_per_group)
            .map(|_| {
                let g = |rng: &mut _, i: f64| {
                    rand::RngExt::sample::<f64, _>(rng, StandardNormal) * (temperature / i).sqrt()
                };
                Vector3::new(g(&mut rng, i1), g(&mut rng, i1), g(&mut rng, i3))
            })
            .collect();
        let w: Vec<Vector3<f64>> = (0..frames)
            .flat_map(|f| {
                let t = f as f64 * dt;
                starts.iter().map(move |w0| {
                    let (s, c) = (rate * w0.z * t).sin_cos();
                    Vector3::new(w0.x * c + w0.y * s, -w0.x * s + w0.y * c, w0.z)
                })
            })
            .collect();
        let series = Frames::new(&w, rotors_per_group, "omega_body").unwrap();
        groups.push(vector_autocorrelation(&series, None).unwrap());
    }
    let t = largest_t(&groups, |k| exact(k as f64 * dt, temperature));
    assert!(t < T_MAX, "|t| {t}");
    let wrong = largest_t(&groups, |k| exact(k as f64 * dt, 2.0 * temperature));
    assert!(wrong > T_MAX, "|t| {wrong}");
}
