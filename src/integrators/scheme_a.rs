//! Scheme A of the note: the standard coupled pair of Gear predictor-correctors
//! for the first-order equations 10 (`Q' = 1/2 Q*(0, w_b)`) and 11 (Euler's
//! equations `I w_b' = n_b - w_b x (I w_b)`, which reduce to eq 11 for a
//! spherical top).
//!
//! Properties: stores per rotor 5 values of `Q` (`Q` and 4 scaled
//! derivatives) and 5 of `w_b`, plus the principal moments; corrector
//! `251/720, 1, 11/12, 1/3, 1/24` for both; one torque evaluation per step;
//! neither time reversible nor symplectic. Eq 15a holds by construction (`Q'`
//! comes from a pure `(0, w_b)`); the norm of `Q` drifts at the level of the
//! truncation error unless renormalised.
//!
//! Order: global error of order 5 in `h` with a consistent start-up. The note
//! calls the pair "4th order" after the highest stored derivative (Gear's
//! naming: 5 values, derivatives up to the 4th); the 5-value first-order
//! corrector is the 4-step Adams-Moulton formula (order 5) in Nordsieck form,
//! applied once to the order-4 Taylor prediction, which one correction raises
//! to order 5 (measured in `tests/gear_references.rs`).

use super::checkpoint::checkpoint_data;
use super::gear::{correct_pair, Nordsieck};
use super::rigid_body::TopKind;
use super::rotor_chunks::for_each_rotor_chunk;
use super::spec::IntegratorOptions;
use super::startup::{start, GearFrame, GearStart, StartChain, Startup, TopStep};
use super::torque::{evaluate_torques, torque_body};
use super::{GoOn, Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use crate::thermostat_hook::{ChainEquations, CoupledDegrees, Spin};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Options of [`GearA`] (the scene's `[integrator]` table with
/// `kind = "gear_a"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct GearAOptions {
    /// Rescale `Q` to unit norm after each step (default true).
    pub renormalise: bool,
    /// How the higher derivatives are set at t = 0 (default consistent).
    pub startup: Startup,
}

impl TopStep for GearA {
    fn frame(&self) -> &GearFrame {
        &self.frame
    }

    /// One step (a)-(f) of the note, monomorphised on the kind of top; the
    /// per-rotor work runs over chunks of rotors across the rayon pool.
    fn step_with<K: TopKind>(
        &mut self,
        potential: &dyn Potential,
        predicted: bool,
        next: &mut dyn FnMut() -> bool,
    ) -> bool {
        let h = self.frame.dt;
        let renormalise = self.options.renormalise;
        // (a), (b): predict.
        if !predicted {
            let rotors = (self.q.as_chunk(), self.omega_body.as_chunk());
            for_each_rotor_chunk(rotors, |(mut q, mut omega_body)| {
                q.predict();
                omega_body.predict();
            });
        }
        // (c): torque at the predicted Q; the chain, advanced with the
        // kinetic energy of the predicted w_b, gives the friction at t + h.
        evaluate_torques(potential, &self.q.r[0], &mut self.torque_space);
        let friction = self
            .thermostat
            .as_mut()
            .map(|t| t.step(&self.omega_body, h));
        let rotors = (
            self.q.as_chunk(),
            self.omega_body.as_chunk(),
            &self.torque_space[..],
            &self.frame.moments[..],
            &self.spins[..],
        );
        let predict_next = next();
        for_each_rotor_chunk(
            rotors,
            |(mut q, mut omega_body, torque_space, moments, spins)| {
                for i in 0..moments.len() {
                    let q_i = q.r[0][i];
                    // (d): correct w_b with Euler's equations at the predicted values.
                    let n_b = torque_body(&q_i, &torque_space[i]);
                    let w_dot = K::omega_dot_body(&moments[i], &omega_body.r[0][i], &n_b);
                    let w_dot = match friction {
                        Some(f) => {
                            let w = omega_body.r[0][i];
                            let coupled = match &spins[i] {
                                Some(s) => w - s.axis * s.axis.dot(&w),
                                None => w,
                            };
                            w_dot - coupled * f
                        }
                        None => w_dot,
                    };
                    // (e), (f): 1/2 Q*(0, w_b) with the corrected w_b and predicted Q.
                    let q_dot = |w: &Vector3<f64>| q_i.q_dot_from_omega_body(w);
                    correct_pair(&mut q, &mut omega_body, i, w_dot, q_dot, h);
                }
                if renormalise {
                    for q in q.r[0].iter_mut() {
                        *q = *q * (1.0 / q.norm());
                    }
                }
                // The next step's (a), (b).
                if predict_next {
                    q.predict();
                    omega_body.predict();
                }
            },
        );
        predict_next
    }
}

impl Default for GearAOptions {
    fn default() -> Self {
        GearAOptions {
            renormalise: true,
            startup: Startup::Consistent,
        }
    }
}

impl IntegratorOptions for GearAOptions {
    const NAME: &'static str = "gear_a";

    /// Scheme A alone ([`GearA::with_chain`] adds a thermostat chain).
    fn build(&self) -> Box<dyn Integrator> {
        Box::new(GearA::new(*self))
    }
}

/// Scheme A: coupled 5-value Gear correctors for eqs 10 and 11 (module doc).
#[derive(Clone, Debug)]
pub struct GearA {
    options: GearAOptions,
    frame: GearFrame,
    q: Nordsieck<Quat, 5>,
    omega_body: Nordsieck<Vector3<f64>, 5>,
    torque_space: Vec<Vector3<f64>>,
    /// The thermostat chain integrated with the rotors, if any.
    thermostat: Option<GearChain>,
    /// Per rotor, the spin the chain leaves out (all `None` without one).
    spins: Vec<Option<Spin>>,
}

/// A thermostat chain in scheme A: the friction `-p_1/Q_1 w_b` of a
/// [`ChainEquations`] in Euler's equations on the thermostatted components
/// (a conserved spin of [`CoupledDegrees`] left out), integrated by the
/// rotors' predictor-corrector with the chain's friction at the end of the
/// step; the chain's own equations advanced over the step by
/// [`ChainEquations::advance`] composed to sixth order
/// ([`ChainEquations::step_composed`]),
/// with the thermostatted kinetic energy of the predicted `w_b` polynomial.
/// (Integrated by the same Gear corrector, as they were until issue 37, the
/// chain's couplings `p_j p_{j+1}/Q_{j+1}` made the step unstable once
/// `dt p_{j+1}/Q_{j+1}` reached order one: a random start of the 1,000-rotor
/// dipole lattice, tau = 0.4, blew up at dt = 0.005 and 0.01, where plain
/// scheme A is stable. The start-up still integrates the chain with the
/// rotors, for the rotors' derivatives.)
#[derive(Clone, Debug)]
struct GearChain {
    /// The chain: its masses, positions and momenta.
    chain: Box<dyn ChainEquations>,
    /// The degrees of freedom it acts on, and the principal moments.
    coupled: CoupledDegrees,
    principal: Vec<Vector3<f64>>,
    /// Scratch: the body angular velocities at a time within the step.
    omega_scratch: Vec<Vector3<f64>>,
}

impl GearChain {
    /// Advances the chain over the step `h` ([`ChainEquations::step_composed`])
    /// with the thermostatted kinetic energy of the predicted `omega_body`
    /// (at `t + h`) along the step; returns the friction `p_1/Q_1` at the
    /// end of the step.
    fn step(&mut self, omega_body: &Nordsieck<Vector3<f64>, 5>, h: f64) -> f64 {
        let (coupled, principal, scratch) =
            (&self.coupled, &self.principal, &mut self.omega_scratch);
        let mut kinetic_at = |x: f64| {
            omega_body.values_at(x, scratch);
            coupled.kinetic_energy_of(principal, scratch)
        };
        self.chain.step_composed(&mut kinetic_at, h)
    }
}

impl GearA {
    /// A scheme-A integrator with the given options (set up before stepping).
    pub fn new(options: GearAOptions) -> Self {
        GearA {
            options,
            frame: GearFrame::default(),
            q: Nordsieck::zeros(0),
            omega_body: Nordsieck::zeros(0),
            torque_space: Vec::new(),
            thermostat: None,
            spins: Vec::new(),
        }
    }

    /// Scheme A with the thermostat chain `chain` (a Nose-Hoover chain;
    /// see `GearChain` in the source for how the extended equations are integrated).
    pub fn with_chain(options: GearAOptions, chain: Box<dyn ChainEquations>) -> Self {
        let mut gear = GearA::new(options);
        gear.thermostat = Some(GearChain {
            chain,
            coupled: CoupledDegrees::default(),
            principal: Vec::new(),
            omega_scratch: Vec::new(),
        });
        gear
    }
}

impl Default for GearA {
    fn default() -> Self {
        GearA::new(GearAOptions::default())
    }
}

impl Integrator for GearA {
    fn name(&self) -> &'static str {
        GearAOptions::NAME
    }

    fn setup(
        &mut self,
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        if let Some(t) = &mut self.thermostat {
            t.principal = inertia.iter().map(Inertia::principal).collect();
            t.omega_scratch = vec![Vector3::zeros(); inertia.len()];
            t.coupled = CoupledDegrees::new(&t.principal, potential);
            t.chain.reset(t.coupled.dof);
        }
        let chain = self.thermostat.as_ref().map(|t| StartChain {
            chain: t.chain.as_ref(),
            coupled: &t.coupled,
        });
        let GearStart { frame, derivatives } =
            start(self.options.startup, inertia, potential, initial, chain, dt)?;
        self.q = derivatives.q.truncated();
        self.omega_body = derivatives.omega_body.truncated();
        self.torque_space = vec![Vector3::zeros(); derivatives.q.len()];
        self.frame = frame;
        self.spins = match &self.thermostat {
            Some(t) => t.coupled.spins.clone(),
            None => vec![None; initial.len()],
        };
        Ok(())
    }

    fn step(&mut self, potential: &dyn Potential) {
        self.step_by_top(potential);
    }

    fn steps(&mut self, potential: &dyn Potential, count: u64, go_on: GoOn<'_>) -> u64 {
        self.steps_by_top(potential, count, go_on)
    }

    fn dt(&self) -> f64 {
        self.frame.dt
    }

    fn orientations(&self) -> &[Quat] {
        &self.q.r[0]
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        out.copy_from_slice(&self.omega_body.r[0]);
    }

    /// Layout: `[dt, Q..., w_b...]` (Nordsieck vectors), then the chain's
    /// checkpoint (its positions and momenta) when there is one.
    fn checkpoint(&self) -> Vec<f64> {
        let mut out = vec![self.frame.dt];
        self.q.write_flat(&mut out);
        self.omega_body.write_flat(&mut out);
        if let Some(t) = &self.thermostat {
            t.chain.write_checkpoint(&mut out);
        }
        out
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        let chain_len = self
            .thermostat
            .as_ref()
            .map_or(0, |t| t.chain.checkpoint_len());
        let len = self.q.flat_len() + self.omega_body.flat_len() + chain_len;
        let data = checkpoint_data(state, len)?;
        let rest = self.q.read_flat(data);
        let rest = self.omega_body.read_flat(rest);
        if let Some(t) = &mut self.thermostat {
            t.chain.read_checkpoint(rest)?;
        }
        Ok(())
    }

    /// The chain's energy (0 without one).
    fn thermostat_energy(&self) -> f64 {
        self.thermostat.as_ref().map_or(0.0, |t| t.chain.energy())
    }
}
