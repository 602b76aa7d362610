//! Stochastic velocity rescaling of the rotational kinetic energy, and of
//! the translational one of bodies that move (Bussi, Donadio and
//! Parrinello, J. Chem. Phys. 126, 014101 (2007); scene `kind = "bussi"`).
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
//! direction of the momenta is left to the dynamics. Rotors at rest (`K = 0`)
//! have no direction to scale and are left at rest. The rescaling over `dt`
//! acts in the middle of the splitting's step (half kick, rotation over
//! `dt/2`, rescaling, rotation over `dt/2`, torques, half kick), where
//! Langevin's O step acts, with `c = exp(-dt/tau)`, `R` standard normal and
//! `S` a chi-square number of `N_f - 1` degrees of freedom
//! (`rand_distr::Gamma`, exact):
//!
//! ```text
//! alpha = sign(a) sqrt(K'/K),   a = sqrt(c) + R sqrt((1 - c) K_bar / (N_f K)),
//! K' = K a^2 + (1 - c) K_bar S / N_f
//! ```
//!
//! (Bussi et al.'s eq A7 with the sign of their appendix).
//!
//! Why in the middle: at the full step, where the step's kicks end, the
//! splitting keeps velocity Verlet's invariant `w0^2 q^2 + p^2 / (1 - a)`
//! of a harmonic libration (`a = (w0 dt / 2)^2`), so a thermostat bringing
//! the momenta there to `T` leaves the orientations hot, `<w0^2 q^2> = T /
//! (1 - a)` (1.2 % for rigid water's librations at 2 fs). Between two actions
//! in the middle the map is position Verlet, whose invariant is `w0^2 q^2 /
//! (1 - a) + p^2`: the momenta there at `T` put the orientations at the full
//! step at `T` exactly, as Langevin's B A O A B does, and the full-step
//! momenta low by `(1 - a)` (the kinetic temperature read there: ERRATA.md,
//! traps). Tests: `tests/thermostat_distributions.rs`.
//!
//! Bodies that move: one rescaling per kind, the rotational one above and
//! the same on the translational kinetic energy relative to the centre of
//! mass with `N_f = 3N - 3` ([`CoupledDegrees::scale_translation`]: the
//! total momentum is kept), each drawing its own numbers. One per kind
//! rather than one over both, so that each kind is brought to `T` by the
//! thermostat itself, not only through the exchange of energy between
//! translation and rotation, which is slow for nearly spherical bodies
//! (none at all for a Lennard-Jones sphere): LAMMPS's `fix rigid/nvt`
//! (Kamberaj, Low and Neal 2005) thermostats the two kinds apart for the
//! same reason.
//!
//! Heat: the changes `K' - K` are summed over the run; `K + V - heat` is
//! conserved up to the splitting error. The numbers come from [`super::noise::Noise`]
//! (reproducible from the seed; a checkpoint stores the position).

use super::noise::{HeatNoise, Noise};
use crate::checks::{non_negative, positive, InputError};
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
    /// `c = exp(-dt / tau)`.
    decay: f64,
    /// The rotational kinetic energy's rescaling.
    rotation: Rescaling,
    /// The translational kinetic energy's rescaling (no degrees of
    /// freedom for rotors on fixed sites).
    translation: Rescaling,
}

/// The exact rescaling of one kind's kinetic energy (module doc).
#[derive(Clone, Debug, Default)]
struct Rescaling {
    /// `N_f`.
    dof: usize,
    /// Chi-square of `N_f - 1` degrees of freedom (none for `N_f = 1`).
    chi_square: Option<Gamma<f64>>,
}

impl Rescaling {
    fn new(dof: usize) -> Self {
        // Shape (N_f - 1)/2 > 0 and scale 2 are valid: `new` cannot fail.
        let chi_square = (dof > 1)
            .then(|| Gamma::new(0.5 * (dof - 1) as f64, 2.0).ok())
            .flatten();
        Rescaling { dof, chi_square }
    }

    /// The factor `alpha` for the kinetic energy `kinetic` at temperature
    /// `temperature` over a step of decay `c`, and the rescaled kinetic
    /// energy, drawing from `noise`; `None` (nothing drawn) at rest.
    fn factor(
        &self,
        kinetic: f64,
        temperature: f64,
        c: f64,
        noise: &mut Noise,
    ) -> Option<(f64, f64)> {
        if kinetic <= 0.0 {
            return None;
        }
        let n = self.dof as f64;
        let target = 0.5 * n * temperature;
        let r = noise.normal();
        let s = match &self.chi_square {
            Some(chi_square) => noise.sample(chi_square),
            None => 0.0,
        };
        let a = c.sqrt() + r * ((1.0 - c) * target / (n * kinetic)).sqrt();
        let rescaled = kinetic * a * a + (1.0 - c) * target * s / n;
        Some(((rescaled / kinetic).sqrt().copysign(a), rescaled))
    }
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
            rotation: Rescaling::default(),
            translation: Rescaling::default(),
        }
    }

    /// The exact rescalings over `dt` (module doc): rotation, then
    /// translation.
    fn rescale(&mut self, dynamics: &mut impl SplitDynamics) {
        let (temperature, c) = (self.options.temperature, self.decay);
        let kinetic = self.coupled.kinetic_energy(dynamics);
        let noise = &mut self.record.noise;
        if let Some((alpha, rescaled)) = self.rotation.factor(kinetic, temperature, c, noise) {
            self.coupled.scale(dynamics, alpha);
            self.record.heat += rescaled - kinetic;
        }
        if self.translation.dof == 0 {
            return;
        }
        let kinetic = self.coupled.translational_kinetic_energy(dynamics);
        let noise = &mut self.record.noise;
        if let Some((alpha, rescaled)) = self.translation.factor(kinetic, temperature, c, noise) {
            self.coupled.scale_translation(dynamics, alpha);
            self.record.heat += rescaled - kinetic;
        }
    }
}

impl Thermostat for Bussi {
    type State = HeatNoise;

    fn setup(&mut self, _: &[Vector3<f64>], degrees: &CoupledDegrees, dt: f64) {
        self.coupled = degrees.clone();
        self.decay = (-dt / self.options.tau).exp();
        self.rotation = Rescaling::new(degrees.dof);
        self.translation = Rescaling::new(degrees.translational_dof());
        self.record.reset();
    }

    /// Half kick, flow over `dt/2`, rescaling over `dt`, flow over `dt/2`,
    /// torques, half kick.
    fn step<D: SplitDynamics>(&mut self, dynamics: &mut D) {
        dynamics.kick_flow_around(|d| self.rescale(d));
    }

    fn state(&self) -> &HeatNoise {
        &self.record
    }

    fn state_mut(&mut self) -> &mut HeatNoise {
        &mut self.record
    }
}
