//! Langevin dynamics on the body angular momenta, per principal axis, and
//! on the centres' momenta of bodies that move (scene `kind = "langevin"`).
//!
//! The equations (reduced units, `k_B = 1`): Euler's equations with a
//! friction and a random torque on each principal axis `k`,
//!
//! ```text
//! dL_k = (n_k + (L_b x w_b)_k) dt - gamma L_k dt + sqrt(2 gamma I_k T) dW_k
//! ```
//!
//! (`L_b = I w_b`, `n_b` the body torque of eq 6), whose stationary density
//! is `exp(-(K + V)/T)` over orientations (uniform measure on rotations) and
//! body angular momenta: the friction and the noise balance on each axis
//! (fluctuation-dissipation), and the Hamiltonian part preserves the density.
//!
//! Integration: BAOAB (Leimkuhler and Matthews, Appl. Math. Res. Express
//! 2013, 34), with the splitting's own pieces: half kick (B), the splitting's
//! free rotation over `dt/2` (A), the exact Ornstein-Uhlenbeck step over `dt`
//! (O), free rotation over `dt/2` (A), torques, half kick (B). The O step
//! solves `dL_k = -gamma L_k dt + sqrt(2 gamma I_k T) dW_k` exactly at fixed
//! `Q`: `w_k <- c w_k + sqrt((1 - c^2) T / I_k) xi_k`, `c = exp(-gamma dt)`,
//! `xi_k` standard normal, so it leaves the Maxwell density `exp(-K/T)`
//! exactly invariant whatever `dt`; axes with zero moment carry nothing and
//! draw nothing. A moving centre of mass `m` gets the same step on each
//! velocity component, `v_k <- c v_k + sqrt((1 - c^2) T / m) xi_k`: the
//! friction and the noise act on every centre independently, so the total
//! momentum is not kept and `T_trans` counts `3N` degrees of freedom. The
//! noise is drawn rotor by rotor, axis by axis, then centre by centre,
//! component by component, from [`super::noise::Noise`] (reproducible from
//! the seed; a checkpoint stores the position).
//!
//! Heat: the O step's change of the kinetic energy is summed over the run;
//! `K + V - heat` is conserved up to the splitting error (its drift is
//! measured like the NVE drift). Properties: the distribution of the
//! orientations has a bias of order `dt^2` (that of the splitting); for a
//! free spherical top with the exact free flow the body angular velocity is
//! sampled exactly (the A and B steps do not change it). Under torques the
//! momenta a step ends on (after the last B, where `T_rot` is read) are
//! not: on axis `k` their temperature is `T - (dt^2/4) <n_k^2> / I_k +
//! O(dt^4)` (the last A and B steps move the O step's Maxwell momenta by
//! `dt/2 n_k`; `<n_k^2>` the canonical mean square body torque), exactly
//! `T (1 - (w0 dt/2)^2)` for a harmonic libration of frequency `w0`, whose
//! orientations stay exact: a full-step reading 1.2 % low for SPC/E water
//! at 2 fs (issue 41, benchmarks/RESULTS.md), not a bias of the sampled
//! configurations.

use super::noise::HeatNoise;
use crate::checks::{non_negative, positive, InputError};
use crate::thermostat_hook::{CoupledDegrees, SplitDynamics, Thermostat};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Options of [`Langevin`] (the scene's `[thermostat]` table with
/// `kind = "langevin"`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LangevinOptions {
    /// The temperature `T` (energy units, `k_B = 1`), finite and `>= 0`.
    pub temperature: f64,
    /// The friction `gamma` (1/time), finite and `> 0`: each body angular
    /// velocity component (and each centre velocity component of bodies
    /// that move) forgets itself as `exp(-gamma t)`.
    pub friction: f64,
    /// The seed of the noise; a scene without one takes the seed of its
    /// random initial state, or draws one (recorded in the run summary).
    #[serde(
        default,
        deserialize_with = "crate::checks::deserialize_seed",
        skip_serializing_if = "Option::is_none"
    )]
    pub seed: Option<u64>,
}

impl LangevinOptions {
    /// Checks the temperature and the friction (paths `temperature`,
    /// `friction`).
    pub fn check(&self) -> Result<(), InputError> {
        let _ = non_negative(self.temperature).map_err(|e| e.at("temperature"))?;
        let _ = positive(self.friction).map_err(|e| e.at("friction"))?;
        Ok(())
    }
}

/// The Langevin thermostat in a kick-based step (module doc).
#[derive(Clone, Debug)]
pub struct Langevin {
    options: LangevinOptions,
    /// The noise, and the kinetic energy the O steps have put into the
    /// rotors.
    record: HeatNoise,
    /// `c = exp(-gamma dt)`.
    decay: f64,
    /// Per rotor and axis `sqrt((1 - c^2) T / I_k)`, 0 for a zero moment.
    spread: Vec<Vector3<f64>>,
    /// Per moving centre `sqrt((1 - c^2) T / m)`.
    velocity_spread: Vec<f64>,
    /// The standard normal numbers of one O step, one per rotor and axis
    /// of nonzero moment, then three per moving centre, in stream order
    /// (sized at setup).
    draws: Vec<f64>,
}

impl Langevin {
    /// The thermostat with checked `options` ([`LangevinOptions::check`]),
    /// drawing its noise from `seed`.
    pub fn new(options: LangevinOptions, seed: u64) -> Self {
        Langevin {
            options,
            record: HeatNoise::new(seed),
            decay: 1.0,
            spread: Vec::new(),
            velocity_spread: Vec::new(),
            draws: Vec::new(),
        }
    }

    /// The exact Ornstein-Uhlenbeck step over `dt` on every rotor, then
    /// every moving centre, in order, with the numbers in `self.draws`.
    fn ornstein_uhlenbeck(&mut self, dynamics: &mut impl SplitDynamics) {
        let (c, spread, velocity_spread) = (self.decay, &self.spread, &self.velocity_spread);
        let mut draws = self.draws.iter();
        let mut heat = 0.0;
        dynamics.update_omega_body(|rotor, w, moments| {
            for k in 0..3 {
                if moments[k] > 0.0 {
                    let before = w[k];
                    let xi = *draws.next().expect("one draw per axis of nonzero moment");
                    w[k] = c * before + spread[rotor][k] * xi;
                    heat += 0.5 * moments[k] * (w[k] * w[k] - before * before);
                }
            }
        });
        dynamics.update_velocities(|body, v, mass| {
            for k in 0..3 {
                let before = v[k];
                let xi = *draws.next().expect("three draws per centre");
                v[k] = c * before + velocity_spread[body] * xi;
                heat += 0.5 * mass * (v[k] * v[k] - before * before);
            }
        });
        self.record.heat += heat;
    }
}

impl Thermostat for Langevin {
    type State = HeatNoise;

    fn setup(&mut self, moments: &[Vector3<f64>], degrees: &CoupledDegrees, dt: f64) {
        let LangevinOptions {
            temperature,
            friction,
            ..
        } = self.options;
        self.decay = (-friction * dt).exp();
        let variance = -(-2.0 * friction * dt).exp_m1() * temperature;
        self.spread = moments
            .iter()
            .map(|m| m.map(|i| if i > 0.0 { (variance / i).sqrt() } else { 0.0 }))
            .collect();
        self.velocity_spread = degrees
            .masses
            .iter()
            .map(|m| (variance / m).sqrt())
            .collect();
        let axes = moments.iter().flat_map(|m| m.iter()).filter(|&&i| i > 0.0);
        self.draws = vec![0.0; axes.count() + 3 * degrees.masses.len()];
        self.record.reset();
    }

    /// B, A(dt/2), O(dt), A(dt/2), forces and torques, B.
    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D) {
        let half = 0.5 * dynamics.dt();
        // The O step's numbers do not depend on the state: drawn in stream
        // order on one thread while the others kick and flow.
        let (noise, draws) = (&mut self.record.noise, &mut self.draws);
        let ((), ()) = rayon::join(
            || dynamics.half_kick_then_flow(half),
            || draws.iter_mut().for_each(|xi| *xi = noise.normal()),
        );
        self.ornstein_uhlenbeck(dynamics);
        dynamics.free_flow(half);
        dynamics.evaluate();
        dynamics.half_kick();
    }

    fn state(&self) -> &HeatNoise {
        &self.record
    }

    fn state_mut(&mut self) -> &mut HeatNoise {
        &mut self.record
    }
}
