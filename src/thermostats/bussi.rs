//! Stochastic velocity rescaling of the rotational kinetic energy (Bussi,
//! Donadio and Parrinello, J. Chem. Phys. 126, 014101 (2007); scene
//! `kind = "bussi"`).
//!
//! The total kinetic energy `K` of the `N_f` rotational degrees of freedom
//! (one per positive principal moment, less the conserved spins of
//! [`super::CoupledDegrees`], which are left alone) follows
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
//! conserved up to the splitting error. The numbers come from [`Noise`]
//! (reproducible from the seed; a checkpoint stores the position).

use super::coupled::CoupledDegrees;
use super::noise::{finite_heat, required_seed, Noise};
use crate::checks::{non_negative, positive, InputError};
use crate::integrators::{IntegratorError, KickState, KickThermostat, Splitting};
use crate::potential::Potential;
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
    #[serde(default, skip_serializing_if = "Option::is_none")]
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
    seed: u64,
    noise: Noise,
    /// The degrees of freedom it acts on (`N_f` and the spins left out).
    coupled: CoupledDegrees,
    /// `c = exp(-dt / (2 tau))`.
    decay: f64,
    /// Chi-square of `N_f - 1` degrees of freedom (none for `N_f = 1`).
    chi_square: Option<Gamma<f64>>,
    /// Kinetic energy the rescalings have put into the rotors.
    heat: f64,
}

impl Bussi {
    /// The thermostat with checked `options` and a seed.
    pub fn new(options: BussiOptions) -> Result<Self, InputError> {
        options.check()?;
        let seed = required_seed(options.seed)?;
        Ok(Bussi {
            options,
            seed,
            noise: Noise::new(seed),
            coupled: CoupledDegrees::default(),
            decay: 1.0,
            chi_square: None,
            heat: 0.0,
        })
    }

    /// The exact rescaling over `dt/2` (module doc).
    fn rescale<S: Splitting>(&mut self, state: &mut KickState<S::Momentum>) {
        let kinetic = self.coupled.kinetic_energy::<S>(state);
        if kinetic <= 0.0 {
            return;
        }
        let n = self.coupled.dof as f64;
        let target = 0.5 * n * self.options.temperature;
        let c = self.decay;
        let r = self.noise.normal();
        let s = match &self.chi_square {
            Some(chi_square) => self.noise.sample(chi_square),
            None => 0.0,
        };
        let a = c.sqrt() + r * ((1.0 - c) * target / (n * kinetic)).sqrt();
        let rescaled = kinetic * a * a + (1.0 - c) * target * s / n;
        self.coupled
            .scale::<S>(state, (rescaled / kinetic).sqrt().copysign(a));
        self.heat += rescaled - kinetic;
    }
}

impl KickThermostat for Bussi {
    fn setup(&mut self, moments: &[Vector3<f64>], potential: &dyn Potential, dt: f64) {
        self.coupled = CoupledDegrees::new(moments, potential);
        let dof = self.coupled.dof;
        self.decay = (-0.5 * dt / self.options.tau).exp();
        // Shape (N_f - 1)/2 > 0 and scale 2 are valid: `new` cannot fail.
        self.chi_square = (dof > 1)
            .then(|| Gamma::new(0.5 * (dof - 1) as f64, 2.0).ok())
            .flatten();
        self.heat = 0.0;
        self.noise = Noise::new(self.seed);
    }

    /// Rescaling over `dt/2`, the splitting's step, rescaling over `dt/2`.
    fn step<S: Splitting>(
        &mut self,
        splitting: &S,
        state: &mut KickState<S::Momentum>,
        potential: &dyn Potential,
    ) {
        self.rescale::<S>(state);
        state.kick_rotate_kick(splitting, potential);
        self.rescale::<S>(state);
    }

    /// Minus the heat put into the rotors.
    fn energy(&self) -> f64 {
        -self.heat
    }

    fn checkpoint_len(&self) -> usize {
        1 + Noise::CHECKPOINT_LEN
    }

    /// The heat, then the noise position.
    fn write_checkpoint(&self, out: &mut Vec<f64>) {
        out.push(self.heat);
        self.noise.write_checkpoint(out);
    }

    fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), IntegratorError> {
        let (heat, noise) = data.split_at(1);
        self.heat = finite_heat(heat[0])?;
        self.noise.read_checkpoint(noise)
    }
}
