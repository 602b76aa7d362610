//! Nose-Hoover chains on the rotational degrees of freedom (Martyna, Klein
//! and Tuckerman, J. Chem. Phys. 97, 2635 (1992); scene
//! `kind = "nose_hoover"`).
//!
//! The extended equations, for `N_f` rotational degrees of freedom (one per
//! positive principal moment, less the conserved spins of
//! [`CoupledDegrees`], whose momenta are left out of `K` and of the
//! friction), kinetic energy `K`, and a chain of `M`
//! thermostats with positions `eta_j`, momenta `p_j` and masses
//! `Q_1 = N_f T tau^2`, `Q_j = T tau^2` (`j >= 2`):
//!
//! ```text
//! dL_b/dt = (Euler's equations) - (p_1/Q_1) L_b
//! deta_j/dt = p_j / Q_j
//! dp_1/dt = (2 K - N_f T) - p_1 p_2 / Q_2
//! dp_j/dt = (p_{j-1}^2 / Q_{j-1} - T) - p_j p_{j+1} / Q_{j+1}   (the last without its second term)
//! ```
//!
//! They conserve the extended energy
//! `H' = K + V + sum_j p_j^2 / (2 Q_j) + N_f T eta_1 + T sum_{j >= 2} eta_j`,
//! and sample `exp(-(K + V)/T)` when the motion is ergodic (not for a system
//! whose only coupling is the thermostat, such as free rotors).
//!
//! Integration in a kick-based step: the chain's flow over `dt` in the
//! middle of the splitting's step (half kick, rotation over `dt/2`, the
//! chain, rotation over `dt/2`, torques, half kick: where Langevin's O step
//! and Bussi's rescaling act, which keeps the orientations of a harmonic
//! libration exact at any `dt`, [`crate::thermostats::Bussi`]'s module doc;
//! at the full step they would be hot by `1 / (1 - (w0 dt / 2)^2)`), by the
//! symmetric Trotter factorisation of Martyna, Tuckerman,
//! Tobias and Klein (Mol. Phys. 87, 1117 (1996)) with one sweep (no
//! Suzuki-Yoshida weights): the momenta from the end of the chain to the
//! first over `h/2` (each `p_j` between two factors `exp(-h/4 p_{j+1}/Q_{j+1})`),
//! the positions and the scaling of every angular momentum by
//! `exp(-h p_1/Q_1)` over `h`, the momenta back over `h/2`. The step is time
//! reversible; `H'` is conserved up to the splitting error (measured like the
//! NVE drift). Scheme A integrates the rotors' friction with its
//! predictor-corrector and the chain by [`ChainEquations::advance`] (the same
//! factorisation without the scaling, composed to sixth order), with the
//! rotors' kinetic energy along the step.

use crate::checks::{positive, InputError};
use crate::thermostat_hook::{
    BadCheckpoint, ChainEquations, CoupledDegrees, SplitDynamics, Thermostat, ThermostatState,
};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::num::NonZeroU32;

/// The longest chain accepted (chains of more than a few thermostats are
/// never needed; the bound keeps a mistyped length from allocating).
pub const MAX_CHAIN: u32 = 100;

/// Options of [`NoseHoover`] and of scheme A's chain (the scene's
/// `[thermostat]` table with `kind = "nose_hoover"`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NoseHooverOptions {
    /// The temperature `T` (energy units, `k_B = 1`), finite and `> 0` (the
    /// chain masses are proportional to it).
    pub temperature: f64,
    /// The period `tau` of the thermostat's oscillation (time units), finite
    /// and `> 0`; the masses are `Q_1 = N_f T tau^2`, `Q_j = T tau^2`.
    pub tau: f64,
    /// The number of thermostats in the chain, `1..=100` (default 3).
    #[serde(
        default = "NoseHooverOptions::default_chain",
        deserialize_with = "crate::checks::deserialize_at_least_one"
    )]
    pub chain: NonZeroU32,
}

impl NoseHooverOptions {
    /// Three thermostats, as LAMMPS's `fix nvt` and HOOMD-blue's default.
    pub const DEFAULT_CHAIN: NonZeroU32 = match NonZeroU32::new(3) {
        Some(n) => n,
        None => NonZeroU32::MIN,
    };

    fn default_chain() -> NonZeroU32 {
        Self::DEFAULT_CHAIN
    }

    /// Checks the temperature, `tau` and the chain length (paths
    /// `temperature`, `tau`, `chain`).
    pub fn check(&self) -> Result<(), InputError> {
        let _ = positive(self.temperature).map_err(|e| e.at("temperature"))?;
        let _ = positive(self.tau).map_err(|e| e.at("tau"))?;
        if self.chain.get() > MAX_CHAIN {
            return Err(InputError::new(
                "chain",
                format!("must be <= {MAX_CHAIN}, got {}", self.chain),
            ));
        }
        Ok(())
    }
}

/// The chain's variables and masses (module doc), for `N_f` degrees of
/// freedom.
#[derive(Clone, Debug, PartialEq)]
pub struct NoseHooverChain {
    options: NoseHooverOptions,
    dof: f64,
    /// `Q_j`.
    masses: Vec<f64>,
    /// `eta_j`.
    pub positions: Vec<f64>,
    /// `p_j`.
    pub momenta: Vec<f64>,
}

impl NoseHooverChain {
    /// The chain at rest (`eta = p = 0`) for `dof` degrees of freedom.
    pub fn new(options: &NoseHooverOptions, dof: usize) -> Self {
        let m = options.chain.get() as usize;
        let unit = options.temperature * options.tau * options.tau;
        let mut masses = vec![unit; m];
        masses[0] *= dof as f64;
        NoseHooverChain {
            options: *options,
            dof: dof as f64,
            masses,
            positions: vec![0.0; m],
            momenta: vec![0.0; m],
        }
    }

    /// The force on `p_j` from below it in the chain, for the chain momenta
    /// `momenta`: `2 K - N_f T` for the first, `p_{j-1}^2 / Q_{j-1} - T` for
    /// the others.
    fn force(&self, momenta: &[f64], j: usize, kinetic: f64) -> f64 {
        if j == 0 {
            2.0 * kinetic - self.dof * self.options.temperature
        } else {
            momenta[j - 1] * momenta[j - 1] / self.masses[j - 1] - self.options.temperature
        }
    }

    /// `p_j` over `h/2` in the Trotter sandwich of its upper neighbour.
    fn kick_momentum(&mut self, j: usize, kinetic: f64, h: f64) {
        let force = self.force(&self.momenta, j, kinetic);
        if j + 1 < self.len() {
            let damping = (-0.25 * h * self.momenta[j + 1] / self.masses[j + 1]).exp();
            self.momenta[j] = (self.momenta[j] * damping + 0.5 * h * force) * damping;
        } else {
            self.momenta[j] += 0.5 * h * force;
        }
    }

    /// The momenta from the end of the chain to the first over `h/2`, with
    /// the rotors' kinetic energy `kinetic`.
    fn kick_down(&mut self, kinetic: f64, h: f64) {
        for j in (0..self.len()).rev() {
            self.kick_momentum(j, kinetic, h);
        }
    }

    /// The momenta from the first to the end of the chain over `h/2`.
    fn kick_up(&mut self, kinetic: f64, h: f64) {
        for j in 0..self.len() {
            self.kick_momentum(j, kinetic, h);
        }
    }

    /// The positions over `h`.
    fn drift(&mut self, h: f64) {
        for ((eta, p), q) in self
            .positions
            .iter_mut()
            .zip(&self.momenta)
            .zip(&self.masses)
        {
            *eta += h * p / q;
        }
    }

    /// The chain's flow over `h` (module doc) with the rotors' kinetic
    /// energy `kinetic`; returns the factor by which every angular momentum
    /// must be scaled.
    pub fn flow(&mut self, kinetic: f64, h: f64) -> f64 {
        self.kick_down(kinetic, h);
        self.drift(h);
        let scale = (-h * self.friction(&self.momenta)).exp();
        self.kick_up(kinetic * scale * scale, h);
        scale
    }
}

/// The chain's energy and its checkpoint (positions, then momenta).
impl ThermostatState for NoseHooverChain {
    /// The chain's energy `sum_j p_j^2 / (2 Q_j) + N_f T eta_1 + T sum_{j>=2} eta_j`.
    fn energy(&self) -> f64 {
        let kinetic: f64 = self
            .momenta
            .iter()
            .zip(&self.masses)
            .map(|(p, q)| 0.5 * p * p / q)
            .sum();
        let potential: f64 = self.positions[1..].iter().sum::<f64>() * self.options.temperature;
        kinetic + self.dof * self.options.temperature * self.positions[0] + potential
    }

    /// The length of [`ThermostatState::write_checkpoint`]'s output.
    fn checkpoint_len(&self) -> usize {
        2 * self.len()
    }

    /// Appends the positions, then the momenta.
    fn write_checkpoint(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&self.positions);
        out.extend_from_slice(&self.momenta);
    }

    /// Reads back [`ThermostatState::write_checkpoint`]'s output (exactly
    /// that many finite values).
    fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), BadCheckpoint> {
        if data.len() != self.checkpoint_len() || data.iter().any(|x| !x.is_finite()) {
            return Err(BadCheckpoint(format!(
                "expected {} finite chain values, got {}",
                self.checkpoint_len(),
                data.len()
            )));
        }
        let (positions, momenta) = data.split_at(self.len());
        self.positions.copy_from_slice(positions);
        self.momenta.copy_from_slice(momenta);
        Ok(())
    }
}

/// The chain's equations, integrated by scheme A with the rotors'.
impl ChainEquations for NoseHooverChain {
    fn reset(&mut self, dof: usize) {
        *self = NoseHooverChain::new(&self.options, dof);
    }

    fn len(&self) -> usize {
        self.masses.len()
    }

    fn positions(&self) -> &[f64] {
        &self.positions
    }

    fn momenta(&self) -> &[f64] {
        &self.momenta
    }

    /// `p_1 / Q_1`.
    fn friction(&self, momenta: &[f64]) -> f64 {
        momenta[0] / self.masses[0]
    }

    /// The chain's own equations over `h` by the factorisation of the
    /// module doc without the scaling of the rotors (which the caller's
    /// friction term does): momenta down the chain over `h/2` with
    /// `kinetic_start`, positions over `h`, momenta up over `h/2` with
    /// `kinetic_end`.
    fn advance(&mut self, kinetic_start: f64, kinetic_end: f64, h: f64) {
        self.kick_down(kinetic_start, h);
        self.drift(h);
        self.kick_up(kinetic_end, h);
    }

    /// The chain's equations (module doc).
    fn rates(
        &self,
        momenta: &[f64],
        kinetic: f64,
        positions_dot: &mut [f64],
        momenta_dot: &mut [f64],
    ) {
        let m = self.len();
        for j in 0..m {
            positions_dot[j] = momenta[j] / self.masses[j];
            let upper = if j + 1 < m {
                momenta[j] * momenta[j + 1] / self.masses[j + 1]
            } else {
                0.0
            };
            momenta_dot[j] = self.force(momenta, j, kinetic) - upper;
        }
    }

    fn boxed_clone(&self) -> Box<dyn ChainEquations> {
        Box::new(self.clone())
    }
}

/// The chains of a kick-based step: the rotational one, and the
/// translational one of bodies that move. Its energy is their sum; its
/// checkpoint the rotational chain's, then the translational chain's.
#[derive(Clone, Debug, PartialEq)]
pub struct NoseHooverChains {
    /// On the rotational degrees of freedom.
    pub rotational: NoseHooverChain,
    /// On the centres' (`None` for rotors on fixed sites).
    pub translational: Option<NoseHooverChain>,
}

impl ThermostatState for NoseHooverChains {
    fn energy(&self) -> f64 {
        let rotational = self.rotational.energy();
        match &self.translational {
            Some(chain) => rotational + chain.energy(),
            None => rotational,
        }
    }

    fn checkpoint_len(&self) -> usize {
        let translational = self.translational.as_ref();
        self.rotational.checkpoint_len() + translational.map_or(0, |c| c.checkpoint_len())
    }

    fn write_checkpoint(&self, out: &mut Vec<f64>) {
        self.rotational.write_checkpoint(out);
        if let Some(chain) = &self.translational {
            chain.write_checkpoint(out);
        }
    }

    fn read_checkpoint(&mut self, data: &[f64]) -> Result<(), BadCheckpoint> {
        if data.len() != self.checkpoint_len() {
            return Err(BadCheckpoint(format!(
                "expected {} chain values, got {}",
                self.checkpoint_len(),
                data.len()
            )));
        }
        let (rotational, translational) = data.split_at(self.rotational.checkpoint_len());
        let mut read = self.clone();
        read.rotational.read_checkpoint(rotational)?;
        if let Some(chain) = &mut read.translational {
            chain.read_checkpoint(translational)?;
        }
        *self = read;
        Ok(())
    }
}

/// The Nose-Hoover chains in a kick-based step (module doc).
#[derive(Clone, Debug)]
pub struct NoseHoover {
    chains: NoseHooverChains,
    coupled: CoupledDegrees,
}

impl NoseHoover {
    /// The thermostat with checked `options` ([`NoseHooverOptions::check`]).
    pub fn new(options: NoseHooverOptions) -> Self {
        NoseHoover {
            chains: NoseHooverChains {
                rotational: NoseHooverChain::new(&options, 0),
                translational: None,
            },
            coupled: CoupledDegrees::default(),
        }
    }

    /// The chains over `dt`, and the angular momenta and the centres'
    /// velocities scaled.
    fn flow(&mut self, dynamics: &mut impl SplitDynamics) {
        let h = dynamics.dt();
        let kinetic = self.coupled.kinetic_energy(dynamics);
        let scale = self.chains.rotational.flow(kinetic, h);
        self.coupled.scale(dynamics, scale);
        if let Some(chain) = &mut self.chains.translational {
            let kinetic = self.coupled.translational_kinetic_energy(dynamics);
            let scale = chain.flow(kinetic, h);
            self.coupled.scale_translation(dynamics, scale);
        }
    }
}

impl Thermostat for NoseHoover {
    type State = NoseHooverChains;

    fn setup(&mut self, _: &[Vector3<f64>], degrees: &CoupledDegrees, _dt: f64) {
        self.coupled = degrees.clone();
        let options = self.chains.rotational.options;
        self.chains.rotational.reset(degrees.dof);
        let translational = degrees.translational_dof();
        self.chains.translational =
            (translational > 0).then(|| NoseHooverChain::new(&options, translational));
    }

    /// Half kick, flow over `dt/2`, the chains over `dt`, flow over `dt/2`,
    /// torques, half kick.
    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D) {
        dynamics.kick_flow_around(|d| self.flow(d));
    }

    fn state(&self) -> &NoseHooverChains {
        &self.chains
    }

    fn state_mut(&mut self) -> &mut NoseHooverChains {
        &mut self.chains
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table without `chain` has three thermostats; 1 to [`MAX_CHAIN`]
    /// are accepted, one more is refused naming the bound.
    #[test]
    fn chain_defaults_to_three_and_is_bounded() {
        let options: NoseHooverOptions =
            toml::from_str("temperature = 1.0\ntau = 0.5").expect("valid table");
        assert_eq!(options.chain.get(), 3);
        let with = |chain: u32| NoseHooverOptions {
            chain: NonZeroU32::new(chain).expect("non-zero"),
            ..options
        };
        assert!(with(1).check().is_ok());
        assert!(with(MAX_CHAIN).check().is_ok());
        let error = with(MAX_CHAIN + 1).check().expect_err("too long");
        assert_eq!(error.to_string(), "chain: must be <= 100, got 101");
    }

    /// A chain's checkpoint restores its positions and momenta (hence its
    /// energy) exactly; a checkpoint of another length, or with a value
    /// that is not finite, is refused and leaves the chain as it was.
    #[test]
    fn chain_checkpoint_round_trips_and_refuses_bad_data() {
        let options = NoseHooverOptions {
            temperature: 0.7,
            tau: 0.2,
            chain: NonZeroU32::new(3).expect("non-zero"),
        };
        let mut chain = NoseHooverChain::new(&options, 12);
        chain.positions.copy_from_slice(&[0.3, -0.1, 0.05]);
        chain.momenta.copy_from_slice(&[0.2, -0.4, 0.6]);
        let mut saved = Vec::new();
        chain.write_checkpoint(&mut saved);
        assert_eq!(saved.len(), chain.checkpoint_len());
        let mut restored = NoseHooverChain::new(&options, 12);
        restored.read_checkpoint(&saved).expect("valid");
        assert_eq!(restored, chain);
        assert_eq!(restored.energy().to_bits(), chain.energy().to_bits());
        let fresh = NoseHooverChain::new(&options, 12);
        let mut bad_values = saved.clone();
        bad_values[4] = f64::NAN;
        for bad in [&saved[..5], &bad_values[..]] {
            let mut target = fresh.clone();
            assert!(target.read_checkpoint(bad).is_err(), "{bad:?}");
            assert_eq!(target, fresh);
        }
    }

    /// The chains of bodies that move (rotational, then translational)
    /// restore both exactly, their energy is the sum of the two chains'; a
    /// checkpoint of one chain only is refused and leaves them as they
    /// were.
    #[test]
    fn translational_chain_checkpoints_after_the_rotational_one() {
        let options = NoseHooverOptions {
            temperature: 0.7,
            tau: 0.2,
            chain: NonZeroU32::new(2).expect("non-zero"),
        };
        let chain = |dof: usize, values: [f64; 4]| {
            let mut c = NoseHooverChain::new(&options, dof);
            c.positions.copy_from_slice(&values[..2]);
            c.momenta.copy_from_slice(&values[2..]);
            c
        };
        let chains = NoseHooverChains {
            rotational: chain(12, [0.3, -0.1, 0.2, -0.4]),
            translational: Some(chain(9, [0.5, 0.2, -0.3, 0.1])),
        };
        let sum = chains.rotational.energy() + chain(9, [0.5, 0.2, -0.3, 0.1]).energy();
        assert_eq!(chains.energy().to_bits(), sum.to_bits());
        let mut saved = Vec::new();
        chains.write_checkpoint(&mut saved);
        assert_eq!(saved.len(), 8);
        assert_eq!(&saved[4..], &[0.5, 0.2, -0.3, 0.1]);
        let fresh = NoseHooverChains {
            rotational: NoseHooverChain::new(&options, 12),
            translational: Some(NoseHooverChain::new(&options, 9)),
        };
        let mut restored = fresh.clone();
        restored.read_checkpoint(&saved).expect("valid");
        assert_eq!(restored, chains);
        let mut target = fresh.clone();
        assert!(target.read_checkpoint(&saved[..4]).is_err());
        assert_eq!(target, fresh);
    }

    /// The chain's half step alone (with a kinetic energy that only the
    /// scaling changes) conserves `K + chain energy` to second order and
    /// is reversed exactly by the step with `-h` (time reversibility).
    #[test]
    fn chain_flow_conserves_its_energy_and_reverses() {
        let options = NoseHooverOptions {
            temperature: 1.5,
            tau: 0.3,
            chain: NonZeroU32::new(4).expect("non-zero"),
        };
        let mut chain = NoseHooverChain::new(&options, 30);
        chain.momenta.copy_from_slice(&[0.4, -0.2, 0.1, 0.05]);
        let initial = chain.clone();
        let start_kinetic = 40.0;
        let energy = |c: &NoseHooverChain, k: f64| c.energy() + k;
        let mut errors = Vec::new();
        for h in [0.02, 0.01] {
            let (mut c, mut kinetic) = (initial.clone(), start_kinetic);
            let e0 = energy(&c, kinetic);
            for _ in 0..(0.4 / h) as usize {
                let s = c.flow(kinetic, h);
                kinetic *= s * s;
            }
            errors.push((energy(&c, kinetic) - e0).abs());
            for _ in 0..(0.4 / h) as usize {
                let s = c.flow(kinetic, -h);
                kinetic *= s * s;
            }
            assert!((kinetic - start_kinetic).abs() < 1e-11, "{kinetic}");
            for (a, b) in c.momenta.iter().zip(&initial.momenta) {
                assert!((a - b).abs() < 1e-12);
            }
        }
        let order = (errors[0] / errors[1]).log2();
        assert!(
            (order - 2.0).abs() < 0.2,
            "order {order}, errors {errors:?}"
        );
    }
}
