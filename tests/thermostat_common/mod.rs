//! Helpers of the thermostat tests: independent replicas of a small system
//! run with a thermostat, and the statistics that judge their samples
//! against exact distributions (Kolmogorov-Smirnov, z tests), with closed-form
//! CDFs checked against scipy in `statistics_match_scipy`.
#![allow(dead_code)] // each test crate uses a different subset

use nalgebra::Vector3;
use quatrot::integrators::{IntegratorSpec, RotorState};
use quatrot::potential::{Boundary, ExternalFields, Free, MultipolePotential, Potential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::scene::random_states;
use quatrot::thermostats::ThermostatSpec;
use rayon::prelude::*;

/// Significance level of every distribution test: with exact, independent
/// samples a correct implementation fails one test in 1e4 runs.
pub const ALPHA: f64 = 1e-4;

/// The p-value below which a deliberately wrong run (temperature or friction
/// wrong by a factor of two) must fall: so far below [`ALPHA`] that such a
/// run fails every time (its p-values are typically 1e-50 and smaller).
pub const WRONG_BY_TWO_P: f64 = 1e-12;

/// A small system: its rotors and external fields (`None`: no interactions).
#[derive(Clone, Debug)]
pub struct System {
    /// The rotors.
    pub rotors: Vec<Rotor>,
    /// Uniform field and gradient (the multipole potential also adds the
    /// pair terms of several rotors, open boundary).
    pub fields: ExternalFields,
}

impl System {
    /// Free rotors of inertia `inertia`, one per replica.
    pub fn free(inertia: Inertia) -> Self {
        System {
            rotors: vec![Rotor {
                site: Vector3::zeros(),
                inertia,
                dipole_body: None,
                quadrupole_body: None,
            }],
            fields: ExternalFields::NONE,
        }
    }

    /// One dipole `dipole_body` of inertia `inertia` in the uniform field `field`.
    pub fn dipole_in_field(
        inertia: Inertia,
        dipole_body: Vector3<f64>,
        field: Vector3<f64>,
    ) -> Self {
        System {
            rotors: vec![Rotor {
                site: Vector3::zeros(),
                inertia,
                dipole_body: Some(dipole_body),
                quadrupole_body: None,
            }],
            fields: ExternalFields {
                field: Some(field),
                field_gradient: None,
            },
        }
    }

    fn potential(&self) -> Option<MultipolePotential> {
        let interacting =
            self.rotors.len() > 1 && self.rotors.iter().any(|r| r.dipole_body.is_some());
        (self.fields != ExternalFields::NONE || interacting).then(|| {
            MultipolePotential::new(&self.rotors, Boundary::Open, self.fields)
                .expect("a valid test system")
        })
    }
}

/// Dipolar spherical tops (`I = 0.1`, a unit dipole along body z) on the
/// `cells`^3 sites of a simple-cubic lattice of spacing 1, in its periodic
/// box with the cutoff `cutoff`: their potential and inertia.
pub fn dipole_lattice(cells: usize, cutoff: f64) -> (MultipolePotential, Vec<Inertia>) {
    let lattice =
        quatrot::lattice::Lattice::cubic(quatrot::lattice::LatticeKind::SimpleCubic, cells, 1.0)
            .expect("a lattice");
    let rotors: Vec<Rotor> = lattice
        .sites
        .iter()
        .map(|s| Rotor {
            site: *s,
            inertia: Inertia::Spherical(0.1),
            dipole_body: Some(Vector3::z()),
            quadrupole_body: None,
        })
        .collect();
    let boundary = Boundary::periodic_cutoff(lattice.box_lengths, cutoff);
    let potential =
        MultipolePotential::new(&rotors, boundary, ExternalFields::NONE).expect("valid");
    let inertia = rotors.iter().map(|r| r.inertia).collect();
    (potential, inertia)
}

/// How the replicas are run.
#[derive(Clone, Copy, Debug)]
pub struct Replicas {
    /// The number of independent replicas.
    pub count: usize,
    /// The temperature of the Maxwell initial angular velocities (the
    /// orientations are uniform).
    pub initial_temperature: f64,
    /// The time step.
    pub dt: f64,
    /// Steps before the first sample.
    pub steps: usize,
    /// Steps between the first and the second sample (0: one sample).
    pub lag: usize,
}

/// The states of every rotor of a replica at the samples.
pub type Samples = Vec<Vec<RotorState>>;

/// Runs `replicas.count` independent copies of `system` with `integrator`
/// and `thermostat` (replica `r` draws its initial state and its noise from
/// seed `seed + r`), and returns, per replica, the states after `steps`
/// steps and, when `lag > 0`, after `lag` more.
pub fn run_replicas(
    system: &System,
    integrator: &IntegratorSpec,
    thermostat: &ThermostatSpec,
    replicas: Replicas,
    seed: u64,
) -> Vec<Samples> {
    let potential = system.potential();
    let potential: &dyn Potential = match &potential {
        Some(p) => p,
        None => &Free,
    };
    let inertia: Vec<Inertia> = system.rotors.iter().map(|r| r.inertia).collect();
    (0..replicas.count)
        .into_par_iter()
        .map(|r| {
            let seed = seed + r as u64;
            let initial = random_states(&inertia, replicas.initial_temperature, seed);
            let mut run = quatrot::dynamics::try_build(integrator, Some(&thermostat.seeded(seed)))
                .expect("a valid pair");
            run.setup(&inertia, potential, &initial, replicas.dt)
                .expect("valid set-up");
            let mut samples = Vec::new();
            for (k, steps) in [replicas.steps, replicas.lag].into_iter().enumerate() {
                if k > 0 && steps == 0 {
                    break;
                }
                for _ in 0..steps {
                    run.step(potential);
                }
                let mut omega = vec![Vector3::zeros(); inertia.len()];
                run.omega_body(&mut omega);
                samples.push(
                    run.orientations()
                        .iter()
                        .zip(&omega)
                        .map(|(q, w)| RotorState {
                            orientation: *q,
                            omega_body: *w,
                        })
                        .collect(),
                );
            }
            samples
        })
        .collect()
}

/// The Kolmogorov-Smirnov statistic `D` of `samples` against `cdf`.
pub fn ks_statistic(samples: &[f64], cdf: impl Fn(f64) -> f64) -> f64 {
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len() as f64;
    sorted
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let f = cdf(*x);
            ((i + 1) as f64 / n - f).max(f - i as f64 / n)
        })
        .fold(0.0, f64::max)
}

/// The asymptotic Kolmogorov tail `Q(l) = 2 sum_k (-1)^(k-1) exp(-2 k^2 l^2)`
/// (scipy's `kstwobign.sf`).
pub fn kolmogorov_tail(l: f64) -> f64 {
    if l < 0.2 {
        return 1.0;
    }
    let sum: f64 = (1..=100)
        .map(|k| {
            let k = k as f64;
            let sign = if k as u64 % 2 == 1 { 1.0 } else { -1.0 };
            sign * (-2.0 * k * k * l * l).exp()
        })
        .sum();
    (2.0 * sum).clamp(0.0, 1.0)
}

/// The p-value of a KS statistic `d` of `n` samples, with Stephens'
/// finite-`n` correction `l = (sqrt(n) + 0.12 + 0.11/sqrt(n)) d`.
pub fn ks_p_value(d: f64, n: usize) -> f64 {
    let s = (n as f64).sqrt();
    kolmogorov_tail((s + 0.12 + 0.11 / s) * d)
}

/// The KS p-value of `samples` against `cdf`.
pub fn ks_test(samples: &[f64], cdf: impl Fn(f64) -> f64) -> f64 {
    ks_p_value(ks_statistic(samples, cdf), samples.len())
}

/// The standard normal CDF.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// The two-sided p-value of a standard normal statistic `z`.
pub fn two_sided_p(z: f64) -> f64 {
    libm::erfc(z.abs() / std::f64::consts::SQRT_2)
}

/// The CDF of the Gamma distribution of shape 3/2 and scale 1 (the kinetic
/// energy of one rotor over `T`): `erf(sqrt x) - 2 sqrt(x/pi) exp(-x)`.
pub fn gamma_three_halves_cdf(x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    libm::erf(x.sqrt()) - 2.0 * (x / std::f64::consts::PI).sqrt() * (-x).exp()
}

/// The CDF of `cos(theta)` for a dipole in a uniform field at `x = mu E / T`:
/// `p(c) ~ exp(x c)` on `[-1, 1]`, so `F(c) = (exp(x c) - exp(-x)) / (exp(x) - exp(-x))`.
pub fn dipole_cos_cdf(c: f64, x: f64) -> f64 {
    let c = c.clamp(-1.0, 1.0);
    // exp(x (c - 1)) - exp(-2x), over 1 - exp(-2x): stable for large x.
    ((x * (c - 1.0)).exp() - (-2.0 * x).exp()) / -(-2.0 * x).exp_m1()
}

/// `<cos theta> = coth x - 1/x` (Langevin's function).
pub fn langevin_function(x: f64) -> f64 {
    1.0 / x.tanh() - 1.0 / x
}

/// The slope of the least-squares line through `(x, y)` and its
/// heteroscedasticity-robust standard error (White's HC0).
pub fn slope_with_error(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let meat: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| {
            let e = b - intercept - slope * a;
            (a - mx) * (a - mx) * e * e
        })
        .sum();
    (slope, meat.sqrt() / sxx)
}

/// The body angular velocity components over `sqrt(T / I_a)` (standard
/// normal in the canonical ensemble), axes with zero moment left out.
pub fn scaled_omega(states: &[RotorState], inertia: &[Inertia], temperature: f64) -> Vec<f64> {
    states
        .iter()
        .zip(inertia)
        .flat_map(|(s, i)| {
            let m = i.principal();
            (0..3)
                .filter(move |&a| m[a] > 0.0)
                .map(move |a| s.omega_body[a] / (temperature / m[a]).sqrt())
        })
        .collect()
}

/// Each rotor's kinetic energy over `T` (Gamma of shape 3/2 for a top in
/// the canonical ensemble).
pub fn scaled_kinetic(states: &[RotorState], inertia: &[Inertia], temperature: f64) -> Vec<f64> {
    states
        .iter()
        .zip(inertia)
        .map(|(s, i)| quatrot::observables::kinetic_energy(i, &s.omega_body) / temperature)
        .collect()
}

/// `cos(theta)` between the space-fixed direction of body vector `body` and
/// the unit vector `axis`, per state.
pub fn cosines(states: &[RotorState], body: &Vector3<f64>, axis: &Vector3<f64>) -> Vec<f64> {
    let body = body.normalize();
    states
        .iter()
        .map(|s| s.orientation.body_to_space(&body).dot(axis))
        .collect()
}
