//! Nose-Hoover chains in scheme A for bodies, as the rotors' scheme A
//! carries one ([`crate::integrators::GearA::with_chain`]): the chains of
//! the kick-based integrators ([`NoseHooverChains`], the same masses and
//! degrees of freedom), one on the rotations and one on the centres, each
//! entering the equations of motion as a friction (Martyna, Klein and
//! Tuckerman, J. Chem. Phys. 97, 2635 (1992)):
//!
//! ```text
//! w_b' = (Euler's equations) - (p_1/Q_1) w_c      (w_c: w_b less its conserved spin)
//! v'   = F/m - (p'_1/Q'_1) (v - V)                (V: the centre-of-mass velocity)
//! ```
//!
//! The rotational chain counts and acts on the degrees of freedom of
//! [`CoupledDegrees`], the translational one on `3N - 3` (the velocities
//! relative to the centre of mass, so the total momentum is kept: `sum m
//! (v - V) = 0`). Their sum of energies is the thermostat's share of the
//! conserved energy. Scheme A corrects `w_b` and `v` with the frictions at
//! the end of the step, the chains advanced over the step by
//! [`ChainEquations::step_composed`] with the kinetic energies of the
//! predicted polynomials; the start-up integrates the chains with the
//! bodies.

use crate::bodies::system::BodySystem;
use crate::integrators::gear::Nordsieck;
use crate::integrators::startup::{axpy, Rk4State};
use crate::thermostat_hook::{ChainEquations, CoupledDegrees};
use crate::thermostats::{NoseHooverChain, NoseHooverChains, NoseHooverOptions};
use nalgebra::Vector3;

/// The chains of scheme A for bodies (module doc).
#[derive(Clone, Debug)]
pub(super) struct GearChains {
    /// The rotational chain, and the translational one (none for one body).
    pub chains: NoseHooverChains,
    coupled: CoupledDegrees,
    /// The principal moments of every body.
    principal: Vec<Vector3<f64>>,
    /// Scratch: values of the body angular velocities or of the centre
    /// velocities at a time within the step.
    scratch: Vec<Vector3<f64>>,
}

/// The frictions of the chains at one time: `p_1/Q_1` of each, and the
/// centre-of-mass velocity the translational one acts relative to.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frictions {
    rotation: f64,
    translation: f64,
    centre: Vector3<f64>,
}

/// The positions and momenta of a chain in the start-up integration (empty
/// without the chain), or their rates.
#[derive(Clone, Debug, Default)]
pub(super) struct ChainState {
    eta: Vec<f64>,
    p: Vec<f64>,
}

impl ChainState {
    fn of(chain: &NoseHooverChain) -> Self {
        ChainState {
            eta: chain.positions.clone(),
            p: chain.momenta.clone(),
        }
    }

    fn zeros_like(&self) -> Self {
        ChainState {
            eta: vec![0.0; self.eta.len()],
            p: vec![0.0; self.p.len()],
        }
    }
}

impl Rk4State for ChainState {
    fn advanced(&self, rate: &Self, s: f64) -> Self {
        ChainState {
            eta: axpy(&self.eta, &rate.eta, s),
            p: axpy(&self.p, &rate.p, s),
        }
    }
}

/// The chains' variables in the start-up integration: rotational, then
/// translational.
pub(super) type ChainStates = (ChainState, ChainState);

impl GearChains {
    /// The chains at rest with `options` for the bodies of `system`.
    pub fn new(options: &NoseHooverOptions, system: &BodySystem) -> Self {
        let coupled = system.coupled_degrees();
        let translational = coupled.translational_dof();
        let principal: Vec<Vector3<f64>> = system
            .bodies
            .iter()
            .map(|b| system.types[b.kind].moments)
            .collect();
        GearChains {
            chains: NoseHooverChains {
                rotational: NoseHooverChain::new(options, coupled.dof),
                translational: (translational > 0)
                    .then(|| NoseHooverChain::new(options, translational)),
            },
            scratch: vec![Vector3::zeros(); principal.len()],
            coupled,
            principal,
        }
    }

    /// Advances both chains over the step `h` with the kinetic energies of
    /// the predicted body angular velocities `omega_body` and centre
    /// velocities `velocity` along it; the frictions at the end of the
    /// step, relative to the predicted centre-of-mass velocity.
    pub fn step(
        &mut self,
        omega_body: &Nordsieck<Vector3<f64>, 5>,
        velocity: &Nordsieck<Vector3<f64>, 5>,
        h: f64,
    ) -> Frictions {
        let (coupled, principal, scratch) = (&self.coupled, &self.principal, &mut self.scratch);
        let rotation = self.chains.rotational.step_composed(
            &mut |x| {
                omega_body.values_at(x, scratch);
                coupled.kinetic_energy_of(principal, scratch)
            },
            h,
        );
        let translation = self.chains.translational.as_mut().map_or(0.0, |chain| {
            chain.step_composed(
                &mut |x| {
                    velocity.values_at(x, scratch);
                    coupled.translational_kinetic_energy_of(scratch)
                },
                h,
            )
        });
        Frictions {
            rotation,
            translation,
            centre: self.coupled.centre_of_mass_velocity_of(&velocity.r[0]),
        }
    }

    /// The chains' variables now (the start of the start-up integration).
    pub fn states(&self) -> ChainStates {
        let translational = self.chains.translational.as_ref();
        (
            ChainState::of(&self.chains.rotational),
            translational.map(ChainState::of).unwrap_or_default(),
        )
    }

    /// The rates of the chains' variables `y` at the body angular
    /// velocities `omega_body` and centre velocities `velocity`, and the
    /// frictions there (the start-up's right-hand side).
    pub fn rates(
        &self,
        y: &ChainStates,
        omega_body: &[Vector3<f64>],
        velocity: &[Vector3<f64>],
    ) -> (ChainStates, Frictions) {
        let (mut rotational, mut translational) = (y.0.zeros_like(), y.1.zeros_like());
        let chain = &self.chains.rotational;
        let kinetic = self.coupled.kinetic_energy_of(&self.principal, omega_body);
        chain.rates(&y.0.p, kinetic, &mut rotational.eta, &mut rotational.p);
        let mut translation = 0.0;
        if let Some(chain) = &self.chains.translational {
            let kinetic = self.coupled.translational_kinetic_energy_of(velocity);
            chain.rates(
                &y.1.p,
                kinetic,
                &mut translational.eta,
                &mut translational.p,
            );
            translation = chain.friction(&y.1.p);
        }
        let frictions = Frictions {
            rotation: chain.friction(&y.0.p),
            translation,
            centre: self.coupled.centre_of_mass_velocity_of(velocity),
        };
        ((rotational, translational), frictions)
    }

    /// The rotational friction on body `i` at the body angular velocity `w`:
    /// `(p_1/Q_1) w_c`.
    pub fn on_rotation(&self, frictions: &Frictions, i: usize, w: &Vector3<f64>) -> Vector3<f64> {
        self.coupled.coupled(i, w) * frictions.rotation
    }
}

impl Frictions {
    /// The translational friction on a centre of velocity `v`:
    /// `(p'_1/Q'_1) (v - V)`.
    pub fn on_translation(&self, v: &Vector3<f64>) -> Vector3<f64> {
        (v - self.centre) * self.translation
    }
}
