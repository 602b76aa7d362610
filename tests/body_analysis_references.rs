//! The analysis of moving bodies against closed forms (reduced units,
//! k_B = 1): the ballistic mean-squared displacement of free particles,
//! `<|v t|^2> = 3 T t^2 / m` for Maxwell velocities (each component
//! `N(0, T/m)`); the radial distribution function of an ideal gas (uniform
//! random points), 1 at every r; that of a perfect fcc lattice, its first
//! shell of 12 neighbours at `a / sqrt 2` and its second of 6 at `a`; the
//! FFT mean-squared displacement against the direct double sum, through
//! unwrapping by image counts; the Einstein coefficient of random walkers.

mod common;

use common::{rng, uniform};
use nalgebra::Vector3;
use quatrot::analysis::{
    mean_squared_displacement, radial_distribution, self_diffusion, unwrapped_positions, Frames,
};
use rand::RngExt;
use rand_distr::StandardNormal;

/// Free particles with Maxwell velocities at `T / m = 1.7` moving in a
/// straight line: the MSD at every lag is `3 T t^2 / m` within its
/// statistical error. Each lag's estimate is a mean over bodies of
/// `|v|^2 t^2` (origins add nothing: each body's displacement is exactly
/// `v t`), whose relative standard error is `sqrt(2/3) / sqrt(N)` (`|v|^2`
/// is `T/m` times a chi-square with 3 degrees of freedom, variance 6).
#[test]
fn free_particles_have_the_ballistic_msd() {
    let mut rng = rng(39);
    let (bodies, frames, dt, t_over_m) = (4000, 30, 0.05, 1.7_f64);
    let velocity: Vec<Vector3<f64>> = (0..bodies)
        .map(|_| Vector3::from_fn(|_, _| t_over_m.sqrt() * rng.sample::<f64, _>(StandardNormal)))
        .collect();
    let start: Vec<Vector3<f64>> = (0..bodies)
        .map(|_| Vector3::from_fn(|_, _| uniform(&mut rng, -5.0, 5.0)))
        .collect();
    let r: Vec<Vector3<f64>> = (0..frames)
        .flat_map(|t| {
            let time = t as f64 * dt;
            start.iter().zip(&velocity).map(move |(x, v)| x + v * time)
        })
        .collect();
    let msd =
        mean_squared_displacement(&Frames::new(&r, bodies, "positions").unwrap(), None).unwrap();
    assert_eq!(msd.len(), frames);
    assert!(msd[0].abs() < 1e-12);
    let relative_error = (2.0_f64 / 3.0).sqrt() / (bodies as f64).sqrt();
    for (k, m) in msd.iter().enumerate().skip(1) {
        let exact = 3.0 * t_over_m * (k as f64 * dt).powi(2);
        let z = (m / exact - 1.0) / relative_error;
        // The same sample at every lag: one z, at most 5 (two-sided 6e-7).
        assert!(z.abs() < 5.0, "lag {k}: msd {m}, exact {exact}, z {z}");
    }
    // A parabola c t^2: a fit over t in [1, 1.4] has slope 2 t_mid * 3 T/m.
    let time: Vec<f64> = (0..frames).map(|k| k as f64 * dt).collect();
    let fit = self_diffusion(&time, &msd, (0.99, 1.41)).unwrap();
    assert_eq!(fit.points, 9);
    let mean_slope = msd[28] / (28.0 * dt).powi(2) * 2.0 * 1.2;
    assert!((fit.slope / mean_slope - 1.0).abs() < 1e-9, "{fit:?}");
    assert!((fit.coefficient - fit.slope / 6.0).abs() < 1e-15);
}

/// Random walkers (Gaussian steps of variance `s^2` per component every
/// `dt`) diffuse with `D = s^2 / (2 dt)`: the fit of the MSD over a stated
/// window, lags 10 to 50 of 200 frames, gives it. The estimate averages
/// 2000 independent walkers: its relative standard error is about
/// `sqrt(2/3) / sqrt(2000) * 1.2` (the MSD at the window's lags, correlated
/// over the window, ~2 %); 5 % is over two of those, and a D off by the
/// factor 3 of a one-dimensional Einstein relation would fail.
#[test]
fn random_walkers_have_the_einstein_diffusion_coefficient() {
    let mut rng = rng(3);
    let (bodies, frames, dt, s) = (2000, 200, 0.1, 0.3_f64);
    let mut r = vec![Vector3::zeros(); bodies * frames];
    for t in 1..frames {
        for i in 0..bodies {
            let step = Vector3::from_fn(|_, _| s * rng.sample::<f64, _>(StandardNormal));
            r[t * bodies + i] = r[(t - 1) * bodies + i] + step;
        }
    }
    let msd = mean_squared_displacement(&Frames::new(&r, bodies, "positions").unwrap(), Some(60))
        .unwrap();
    let time: Vec<f64> = (0..msd.len()).map(|k| k as f64 * dt).collect();
    let fit = self_diffusion(&time, &msd, (0.95, 5.05)).unwrap();
    assert_eq!(fit.points, 41);
    let exact = s * s / (2.0 * dt);
    assert!(
        (fit.coefficient / exact - 1.0).abs() < 0.05,
        "{fit:?} vs {exact}"
    );
    // A straight line through the origin: the intercept is small beside the
    // MSD at the window's end (its noise is ~2 % of the MSD there).
    assert!(fit.intercept.abs() < 0.1 * msd[50], "{fit:?}");
}

/// The FFT estimate is the direct double sum over origins and bodies of
/// `|r(t+k) - r(t)|^2`, for centres that wrap through a box of unequal
/// sides and are unwrapped from their image counts.
#[test]
fn msd_of_wrapped_centres_is_the_direct_sum() {
    let mut rng = rng(7);
    let (bodies, frames) = (5, 23);
    let box_lengths = Vector3::new(3.0, 4.0, 5.0);
    let mut r = vec![Vector3::zeros(); bodies * frames];
    for i in 0..bodies {
        for t in 0..frames {
            let step = Vector3::from_fn(|_, _| uniform(&mut rng, -1.5, 1.5));
            r[t * bodies + i] = if t == 0 {
                step
            } else {
                r[(t - 1) * bodies + i] + step
            };
        }
    }
    let wrap = |x: f64, l: f64| (x - l * (x / l).floor(), (x / l).floor());
    let (wrapped, images): (Vec<Vector3<f64>>, Vec<Vector3<f64>>) = r
        .iter()
        .map(|x| {
            let parts: Vec<(f64, f64)> = (0..3).map(|c| wrap(x[c], box_lengths[c])).collect();
            (
                Vector3::new(parts[0].0, parts[1].0, parts[2].0),
                Vector3::new(parts[0].1, parts[1].1, parts[2].1),
            )
        })
        .unzip();
    assert!(
        images.iter().any(|n| n.abs().max() >= 2.0),
        "the walk must cross the box"
    );
    let unwrapped = unwrapped_positions(
        &Frames::new(&wrapped, bodies, "positions").unwrap(),
        &Frames::new(&images, bodies, "images").unwrap(),
        &box_lengths,
    )
    .unwrap();
    let msd = mean_squared_displacement(
        &Frames::new(&unwrapped, bodies, "positions").unwrap(),
        Some(20),
    )
    .unwrap();
    assert_eq!(msd.len(), 21);
    for (k, m) in msd.iter().enumerate() {
        let mut direct = 0.0;
        for i in 0..bodies {
            for t in 0..frames - k {
                direct += (r[(t + k) * bodies + i] - r[t * bodies + i]).norm_squared();
            }
        }
        direct /= (bodies * (frames - k)) as f64;
        assert!(
            (m - direct).abs() < 1e-11 * direct.max(1.0),
            "lag {k}: {m} vs {direct}"
        );
    }
}

/// Uniform random points (an ideal gas) in a box of unequal sides: g = 1
/// in every shell within its statistical error. A shell's pair count is
/// close to Poisson (pairs of independent points; the count of one frame
/// has variance within 1 % of its mean here), so each shell's z is
/// `(g - 1) sqrt(expected count)`; all 60 must be below 4.5 (two-sided
/// 7e-6 each, 4e-4 for all), and a g off by the missing `N - 1` (a 0.2 %
/// bias at N = 500) would not show, but one off by 1 % would in the
/// outer shells (expected counts ~ 2e5 there: z ~ 4.5 at 1 %).
#[test]
fn ideal_gas_has_g_of_one() {
    let mut rng = rng(11);
    let (n, frames, bins) = (500, 40, 60);
    let box_lengths = Vector3::new(9.0, 10.0, 11.0);
    let points: Vec<Vector3<f64>> = (0..n * frames)
        .map(|_| Vector3::from_fn(|c, _| uniform(&mut rng, 0.0, box_lengths[c])))
        .collect();
    let rdf = radial_distribution(
        &Frames::new(&points, n, "positions").unwrap(),
        &box_lengths,
        None,
        bins,
    )
    .unwrap();
    assert_eq!((rdf.g.len(), rdf.edges.len()), (bins, bins + 1));
    assert!((rdf.edges[bins] - 4.5).abs() < 1e-12);
    let volume = box_lengths.product();
    for (b, g) in rdf.g.iter().enumerate() {
        let shell =
            4.0 / 3.0 * std::f64::consts::PI * (rdf.edges[b + 1].powi(3) - rdf.edges[b].powi(3));
        let expected_pairs = frames as f64 * (n * (n - 1)) as f64 / 2.0 * shell / volume;
        let z = (g - 1.0) * expected_pairs.sqrt();
        assert!(z.abs() < 4.5, "shell {b} at r = {}: g {g}, z {z}", rdf.r[b]);
    }
    // n(r) at the last edge: (N - 1) 4/3 pi r^3 / V neighbours on average.
    let sphere = (n - 1) as f64 * 4.0 / 3.0 * std::f64::consts::PI * 4.5_f64.powi(3) / volume;
    assert!((rdf.coordination[bins - 1] / sphere - 1.0).abs() < 0.01);
}

/// A perfect fcc lattice (4 x 4 x 4 cells of side a = 1.5, 256 sites):
/// nothing closer than `a / sqrt 2`, 12 neighbours in the shell holding it
/// and 6 more at `a`, in every frame (the lattice shifted rigidly between
/// frames).
#[test]
fn fcc_lattice_has_twelve_nearest_neighbours() {
    let (a, cells) = (1.5, 4);
    let basis = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(0.5, 0.5, 0.0),
        Vector3::new(0.5, 0.0, 0.5),
        Vector3::new(0.0, 0.5, 0.5),
    ];
    let mut sites = Vec::new();
    for i in 0..cells {
        for j in 0..cells {
            for k in 0..cells {
                for b in &basis {
                    sites.push((Vector3::new(i as f64, j as f64, k as f64) + b) * a);
                }
            }
        }
    }
    let shifts = [Vector3::zeros(), Vector3::new(0.31, -0.7, 2.2)];
    let frames: Vec<Vector3<f64>> = shifts
        .iter()
        .flat_map(|s| sites.iter().map(move |x| x + s))
        .collect();
    let side = a * cells as f64;
    let bins = 293;
    let rdf = radial_distribution(
        &Frames::new(&frames, sites.len(), "positions").unwrap(),
        &Vector3::new(side, side, side),
        Some(2.0),
        bins,
    )
    .unwrap();
    let nearest = a / 2.0_f64.sqrt();
    let shell = |r: f64| rdf.edges.iter().position(|&e| e > r).unwrap() - 1;
    let first = shell(nearest);
    let peak = rdf
        .g
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(y.1))
        .unwrap()
        .0;
    assert_eq!(peak, first, "the first peak is the nearest-neighbour shell");
    assert!(rdf.g[..first].iter().all(|&g| g == 0.0));
    assert!(first > 0 && rdf.coordination[first - 1] == 0.0);
    assert_eq!(rdf.coordination[first], 12.0);
    assert_eq!(rdf.coordination[shell(a) - 1], 12.0);
    assert_eq!(rdf.coordination[shell(a)], 18.0);
}

/// Bad input is refused by name: r_max beyond half the shortest side, a
/// single body, no shells, a fit window without two lags.
#[test]
fn bad_input_is_named() {
    let x = [Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)];
    let f = Frames::new(&x, 2, "positions").unwrap();
    let cube = Vector3::new(4.0, 4.0, 3.0);
    assert_eq!(
        radial_distribution(&f, &cube, Some(2.0), 10)
            .unwrap_err()
            .to_string(),
        "r_max: must be at most half the shortest box side 1.5, got 2"
    );
    assert_eq!(
        radial_distribution(&f, &cube, None, 0).unwrap_err().path,
        "bins"
    );
    assert_eq!(
        radial_distribution(&f, &Vector3::new(4.0, 0.0, 4.0), None, 3)
            .unwrap_err()
            .path,
        "box_lengths.y"
    );
    let one = Frames::new(&x, 1, "positions").unwrap();
    assert_eq!(
        radial_distribution(&one, &cube, None, 3).unwrap_err().path,
        "positions"
    );
    assert_eq!(
        self_diffusion(&[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0], (0.5, 1.5))
            .unwrap_err()
            .to_string(),
        "fit_window: holds 1 lag times, needs at least 2, got (0.5, 1.5)"
    );
}
