//! Stochastic velocity rescaling of the rotational kinetic energy (Bussi,
//! Donadio and Parrinello, J. Chem. Phys. 126, 014101 (2007); scene
//! `kind = "bussi"`).
//!
//! The total kinetic energy `K` of the `N_f` rotational degrees of freedom
//! (one per positive principal moment, less the conserved spins of
//! [`CoupledDegrees`], which are left alone) follows
//!
//! ```text
//! dK = (K_bar - K) dt / tau + 2 sqrt(K K_bar / N_f) dW / sqrt(tau),   K_bar = N_f T / 2,
//! ```
//!
//! whose stationary density is the canonical `K^(N_f/2 - 1) exp(-K/T)`;
//! every (thermostatted) angular momentum is scaled by the same factor `alpha`, so the
//! direction of the momenta is left to the dynamics. The step applies the
//! exact solution of this equation over `h = dt/2` before and after the
//! splitting's step (half kick, rotation over `dt`, torques, half kick),
//! with `c = exp(-h/tau)`, `R` standard normal and `S` a chi-square number of
//! `N_f - 1` degrees of freedom (`rand_distr::Gamma`, exact):
//!
//! ```text
//! alpha = sign(a) sqrt(K'/K),   a = sqrt(c) + R sqrt((1 - c) K_bar / (N_f K)),
//! K' = K a^2 + (1 - c) K_bar S / N_f
//! ```
//!
//! (Bussi et al.'s eq A7 with the sign of their appendix, which makes the
//! operator the exact flow of the equation above). Rotors at rest (`K = 0`)
//! have no direction to scale and are left at rest.
//!
//! Heat: the changes `K' - K` are summed over the run; `K + V - heat` is
//! conserved up to the splitting error. The numbers come from [`super::noise::Noise`]
//! (reproducible from the seed; a checkpoint stores the position).

use super::noise::HeatNoise;
use crate::checks::{non_negative, positive, InputError};
use crate::potential::Potential;
use crate::thermostat_hook::{CoupledDegrees, SplitDynamics, Thermostat};
use nalgebra::Vector3;
use rand_distr::Gamma;
use serde::{Deserialize, Serialize};

/// Options of [`Bussi`] (the scene's `[thermostat]` table with
/// `kind = "bussi"`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BussiOptions {
    /// The temperature `T` (energy units, `k_B = 1`), finite and `>= 0`.
    pub temperature: f64,
    /// The relaxation time `tau` of the kinetic energy (time units), finite
    /// and `> 0`.
    pub tau: f64,
    /// The seed of the noise; a scene without one takes the seed of its
    /// random initial state, or draws one (recorded in the run summary).
    #[serde(
        default,
        deserialize_with = "crate::checks::deserialize_seed",
        skip_serializing_if = "Option::is_none"
    )]
    pub seed: Option<u64>,
}

impl BussiOptions {
    /// Checks the temperature and `tau` (paths `temperature`, `tau`).
    pub fn check(&self) -> Result<(), InputError> {
        let _ = non_negative(self.temperature).map_err(|e| e.at("temperature"))?;
        let _ = positive(self.tau).map_err(|e| e.at("tau"))?;
        Ok(())
    }
}

/// The Bussi thermostat in a kick-based step (module doc).
#[derive(Clone, Debug)]
pub struct Bussi {
    options: BussiOptions,
    /// The noise, and the kinetic energy the rescalings have put into the
    /// rotors.
    record: HeatNoise,
    /// The degrees of freedom it acts on (`N_f` and the spins left out).
    coupled: CoupledDegrees,
    /// `c = exp(-dt / (2 tau))`.
    decay: f64,
    /// Chi-square of `N_f - 1` degrees of freedom (none for `N_f = 1`).
    chi_square: Option<Gamma<f64>>,
}

impl Bussi {
    /// The thermostat with checked `options` ([`BussiOptions::check`]),
    /// drawing its noise from `seed`.
    pub fn new(options: BussiOptions, seed: u64) -> Self {
        Bussi {
            options,
            record: HeatNoise::new(seed),
            coupled: CoupledDegrees::default(),
            decay: 1.0,
            chi_square: None,
        }
    }

    /// The exact rescaling over `dt/2` (module doc).
    fn rescale(&mut self, dynamics: &mut impl SplitDynamics) {
        let kinetic = self.coupled.kinetic_energy(dynamics);
        if kinetic <= 0.0 {
            return;
        }
        let n = self.coupled.dof as f64;
        let target = 0.5 * n * self.options.temperature;
        let c = self.decay;
        let noise = &mut self.record.noise;
        let r = noise.normal();
        let s = match &self.chi_square {
            Some(chi_square) => noise.sample(chi_square),
            None => 0.0,
        };
        let a = c.sqrt() + r * ((1.0 - c) * target / (n * kinetic)).sqrt();
        let rescaled = kinetic * a * a + (1.0 - c) * target * s / n;
        self.coupled
            .scale(dynamics, (rescaled / kinetic).sqrt().copysign(a));
        self.record.heat += rescaled - kinetic;
    }
}

impl Thermostat for Bussi {
    type State = HeatNoise;

    fn setup(&mut self, moments: &[Vector3<f64>], potential: &dyn Potential, dt: f64) {
        self.coupled = CoupledDegrees::new(moments, potential);
        let dof = self.coupled.dof;
        self.decay = (-0.5 * dt / self.options.tau).exp();
        // Shape (N_f - 1)/2 > 0 and scale 2 are valid: `new` cannot fail.
        self.chi_square = (dof > 1)
            .then(|| Gamma::new(0.5 * (dof - 1) as f64, 2.0).ok())
            .flatten();
        self.record.reset();
    }

    /// Rescaling over `dt/2`, the splitting's step, rescaling over `dt/2`.
    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D, potential: &dyn Potential) {
        self.rescale(dynamics);
        dynamics.kick_flow_kick(potential);
        self.rescale(dynamics);
    }

    fn state(&self) -> &HeatNoise {
        &self.record
    }

    fn state_mut(&mut self) -> &mut HeatNoise {
        &mut self.record
    }
}
