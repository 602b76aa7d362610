//! The kick-based baselines (NO_SQUISH, DLM, Richardson) as one integrator,
//! [`Kicked`], over a [`Splitting`]: per rotor the unit orientation, a
//! momentum variable, and the space-fixed torque at the orientation, reused
//! by the next step's first half kick. One step is a half kick, the
//! splitting's orientation update, the torques at the new orientations and a
//! second half kick. Each baseline only chooses its momentum variable, its
//! kick and its orientation update; everything else (set-up, the step, the
//! angular velocities, checkpoints) is written here once.
//!
//! The per-rotor passes run over chunks of rotors split across the rayon
//! pool (`rotor_chunks`); each rotor's update reads only its own state, so
//! results do not depend on the number of threads.
//!
//! A [`Thermostat`] of [`crate::thermostat_hook`] arranges the step: [`Nve`]
//! is the plain step above; a thermostat adds its operators around it or
//! between two half rotations, each as its own type, so the step stays
//! monomorphised. It sees the step through [`KickStep`], this module's
//! [`SplitDynamics`].

use super::checkpoint::{check_length, read_values, write_values, Components};
use super::rotor_chunks::for_each_rotor_chunk;
use super::setup_checks::{validate_setup, Moments, ValidSetup};
use super::spec::IntegratorOptions;
use super::torque::evaluate_torques;
use super::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use crate::thermostat_hook::{CoupledDegrees, Nve, SplitDynamics, Thermostat, ThermostatState};
use nalgebra::Vector3;
use std::array::{from_mut as one, from_ref as one_ref};
use std::fmt::Debug;

/// What distinguishes one kick-based baseline: its momentum variable, its
/// kick and its orientation update. Implemented by the baseline's options,
/// so that `Kicked<NoSquishOptions>` is NO_SQUISH with those options.
pub trait Splitting: IntegratorOptions + Clone + Debug + Send + Sync + 'static {
    /// The momentum variable (`L_b`, `L_s` or the conjugate `P`).
    type Momentum: Components + Copy + Debug + Send + Sync;

    /// The momentum of a rotor at unit orientation `q` with body angular
    /// momentum `angular_momentum_body` (`L_b = I w_b`).
    fn momentum(q: &Quat, angular_momentum_body: &Vector3<f64>) -> Self::Momentum;

    /// A half kick of duration `half` with the space-fixed torque at `q`.
    fn kick(momentum: &mut Self::Momentum, q: &Quat, torque_space: &Vector3<f64>, half: f64);

    /// The orientation updates of `K` rotors over a whole step `dt`
    /// (principal moments `moments`, zero moments allowed): each rotor's
    /// the same bits as alone (`K = 1`).
    fn rotate<const K: usize>(
        &self,
        q: &mut [Quat; K],
        momentum: &mut [Self::Momentum; K],
        moments: &[Vector3<f64>; K],
        dt: f64,
    );

    /// The body angular velocity of a rotor.
    fn omega_body(momentum: &Self::Momentum, q: &Quat, moments: &Vector3<f64>) -> Vector3<f64>;

    /// The body angular momentum `L_b` of a rotor at unit orientation `q`
    /// (the inverse of [`Splitting::momentum`]).
    fn angular_momentum_body(momentum: &Self::Momentum, q: &Quat) -> Vector3<f64>;
}

/// How many rotors [`Splitting::rotate`] takes together (their chains of
/// dependent operations overlap; four filled the CPU's window on
/// o-terphenyl's bodies).
pub const ROTATED_TOGETHER: usize = 4;

/// [`Splitting::rotate`] over `duration` of the rotors at `q`, `momentum`
/// (principal moments `moments`), [`ROTATED_TOGETHER`] at a time and the
/// last few one by one.
pub fn rotate_all<S: Splitting>(
    splitting: &S,
    q: &mut [Quat],
    momentum: &mut [S::Momentum],
    moments: &[Vector3<f64>],
    duration: f64,
) {
    let mut groups = (
        q.chunks_exact_mut(ROTATED_TOGETHER),
        momentum.chunks_exact_mut(ROTATED_TOGETHER),
        moments.chunks_exact(ROTATED_TOGETHER),
    );
    let whole = (&mut groups.0).zip(&mut groups.1).zip(&mut groups.2);
    for ((q, p), i) in whole {
        let (Ok(q), Ok(p), Ok(i)) = (q.try_into(), p.try_into(), i.try_into()) else {
            unreachable!("chunks of {ROTATED_TOGETHER}")
        };
        splitting.rotate::<ROTATED_TOGETHER>(q, p, i, duration);
    }
    let (qs, ps, is) = groups;
    let rest = qs
        .into_remainder()
        .iter_mut()
        .zip(ps.into_remainder())
        .zip(is.remainder());
    for ((q, p), i) in rest {
        splitting.rotate(one(q), one(p), one_ref(i), duration);
    }
}

/// A kick-based baseline: half kick, [`Splitting::rotate`], torques, half
/// kick, with the operators of the thermostat `T` (none by default). Stores
/// per rotor `Q` (4), the momentum variable and the space-fixed torque at
/// `Q` (3, reused by the next step's first kick), plus the principal moments
/// (3), and the thermostat's state. One potential evaluation per step.
#[derive(Clone, Debug, Default)]
pub struct Kicked<S: Splitting, T: Thermostat = Nve> {
    splitting: S,
    thermostat: T,
    state: KickState<S::Momentum>,
}

impl<S: Splitting> Kicked<S> {
    /// The baseline with these options (set up before stepping).
    pub fn new(options: S) -> Self {
        Kicked::with_thermostat(options, Nve)
    }
}

impl<S: Splitting, T: Thermostat> Kicked<S, T> {
    /// The baseline with these options and the thermostat `thermostat`.
    pub fn with_thermostat(options: S, thermostat: T) -> Self {
        Kicked {
            splitting: options,
            thermostat,
            state: KickState::default(),
        }
    }
}

impl<S: Splitting, T: Thermostat> Integrator for Kicked<S, T> {
    fn name(&self) -> &'static str {
        S::NAME
    }

    fn setup(
        &mut self,
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
    ) -> Result<(), IntegratorError> {
        self.state = KickState::new(inertia, potential, initial, dt, S::momentum)?;
        let degrees = CoupledDegrees::new(&self.state.inertia, potential);
        self.thermostat.setup(&self.state.inertia, &degrees, dt);
        Ok(())
    }

    fn step(&mut self, potential: &dyn Potential) {
        let mut step = KickStep {
            splitting: &self.splitting,
            state: &mut self.state,
            potential,
        };
        self.thermostat.step(&mut step);
    }

    fn dt(&self) -> f64 {
        self.state.dt
    }

    fn orientations(&self) -> &[Quat] {
        &self.state.orientation
    }

    fn omega_body(&self, out: &mut [Vector3<f64>]) {
        self.state.omega_body(out, S::omega_body);
    }

    /// Layout: every `Q` (4 values each), then every momentum (4 for `P`,
    /// 3 for `L`), then every space-fixed torque (3 each), then the
    /// thermostat's state (none without one).
    fn checkpoint(&self) -> Vec<f64> {
        let mut out = self.state.checkpoint();
        self.thermostat.state().write_checkpoint(&mut out);
        out
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        let rotors = self.state.checkpoint_len().min(state.len());
        let (rotors, thermostat) = state.split_at(rotors);
        let expected = self.thermostat.state().checkpoint_len();
        if thermostat.len() != expected {
            return Err(IntegratorError::BadCheckpoint(format!(
                "expected {expected} thermostat values after the rotors' {}, got {}",
                rotors.len(),
                thermostat.len()
            )));
        }
        self.state.restore(rotors)?;
        Ok(self.thermostat.state_mut().read_checkpoint(thermostat)?)
    }

    fn thermostat_energy(&self) -> f64 {
        self.thermostat.state().energy()
    }
}

/// The per-rotor arrays of a kick-based baseline, sized once at setup.
#[derive(Clone, Debug)]
struct KickState<M> {
    /// The time step.
    dt: f64,
    /// Principal moments `(I1, I2, I3)` per rotor (zero moments allowed).
    inertia: Vec<Vector3<f64>>,
    /// Unit orientations.
    orientation: Vec<Quat>,
    /// The momentum variable (`L_b`, `L_s` or the conjugate `P`).
    momentum: Vec<M>,
    /// Space-fixed torques at `orientation`.
    torque_space: Vec<Vector3<f64>>,
}

impl<M> Default for KickState<M> {
    /// Empty, before setup.
    fn default() -> Self {
        KickState {
            dt: 0.0,
            inertia: Vec::new(),
            orientation: Vec::new(),
            momentum: Vec::new(),
            torque_space: Vec::new(),
        }
    }
}

impl<M: Components + Copy + Send + Sync> KickState<M> {
    /// Validates the setup arguments, normalises the orientations, sets each
    /// momentum from the unit orientation and the body angular momentum
    /// `L_b = I w_b`, and evaluates the torques.
    fn new(
        inertia: &[Inertia],
        potential: &dyn Potential,
        initial: &[RotorState],
        dt: f64,
        momentum: impl Fn(&Quat, &Vector3<f64>) -> M,
    ) -> Result<Self, IntegratorError> {
        let ValidSetup { moments, initial } =
            validate_setup(inertia, initial, dt, Moments::MayBeZero)?;
        let orientation: Vec<Quat> = initial.iter().map(|s| s.orientation).collect();
        let momentum = orientation
            .iter()
            .zip(&initial)
            .zip(&moments)
            .map(|((q, s), i)| momentum(q, &s.omega_body.component_mul(i)))
            .collect();
        let mut state = KickState {
            dt,
            inertia: moments,
            orientation,
            momentum,
            torque_space: vec![Vector3::zeros(); initial.len()],
        };
        state.evaluate_torques(potential);
        Ok(state)
    }

    /// Half kick: `kick(momentum, Q, n_s, dt/2)` for every rotor.
    fn half_kick(&mut self, kick: impl Fn(&mut M, &Quat, &Vector3<f64>, f64) + Sync) {
        let half = 0.5 * self.dt;
        let rotors = (
            &mut self.momentum[..],
            &self.orientation[..],
            &self.torque_space[..],
        );
        for_each_rotor_chunk(rotors, |(ps, qs, ns)| {
            for ((p, q), n) in ps.iter_mut().zip(qs).zip(ns) {
                kick(p, q, n, half);
            }
        });
    }

    /// `update(Qs, momenta, moments)` for every chunk of rotors (the
    /// orientation update).
    fn update(&mut self, update: impl Fn(&mut [Quat], &mut [M], &[Vector3<f64>]) + Sync) {
        let rotors = (
            &mut self.orientation[..],
            &mut self.momentum[..],
            &self.inertia[..],
        );
        for_each_rotor_chunk(rotors, |(qs, ps, is)| update(qs, ps, is));
    }

    /// [`Self::half_kick`] then [`Self::update`] in one parallel pass: each
    /// chunk of rotors is kicked, then updated, as two loops (one loop doing
    /// both grew each rotor's chain of dependent operations and made a
    /// NO_SQUISH step 10 % longer).
    fn half_kick_then_update(
        &mut self,
        kick: impl Fn(&mut M, &Quat, &Vector3<f64>, f64) + Sync,
        update: impl Fn(&mut [Quat], &mut [M], &[Vector3<f64>]) + Sync,
    ) {
        let half = 0.5 * self.dt;
        let rotors = (
            &mut self.orientation[..],
            &mut self.momentum[..],
            &self.torque_space[..],
            &self.inertia[..],
        );
        for_each_rotor_chunk(rotors, |(qs, ps, ns, is)| {
            for ((p, q), n) in ps.iter_mut().zip(qs.iter()).zip(ns) {
                kick(p, q, n, half);
            }
            update(qs, ps, is);
        });
    }

    /// The torques at the current orientations.
    fn evaluate_torques(&mut self, potential: &dyn Potential) {
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
    }

    /// Writes `f(momentum, Q, moments)` for every rotor (the body angular
    /// velocity).
    fn omega_body(
        &self,
        out: &mut [Vector3<f64>],
        f: impl Fn(&M, &Quat, &Vector3<f64>) -> Vector3<f64>,
    ) {
        for (((w, p), q), i) in out
            .iter_mut()
            .zip(&self.momentum)
            .zip(&self.orientation)
            .zip(&self.inertia)
        {
            *w = f(p, q, i);
        }
    }

    /// The length of [`KickState::checkpoint`]'s output.
    fn checkpoint_len(&self) -> usize {
        self.orientation.len() * (Quat::LEN + M::LEN + 3)
    }

    /// Layout: all `Q` (4 each), then all momenta (`P`: 4 each, `L`: 3 each),
    /// then all space-fixed torques (3 each).
    fn checkpoint(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.checkpoint_len());
        write_values(&self.orientation, &mut out);
        write_values(&self.momentum, &mut out);
        write_values(&self.torque_space, &mut out);
        out
    }

    /// Reads back [`KickState::checkpoint`]'s output after checking that it
    /// holds exactly that many finite values.
    fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        check_length(state, self.orientation.len(), Quat::LEN + M::LEN + 3)?;
        let rest = read_values(state, &mut self.orientation);
        let rest = read_values(rest, &mut self.momentum);
        let _ = read_values(rest, &mut self.torque_space);
        Ok(())
    }
}

/// One step of a kick-based baseline as a thermostat sees it: the
/// splitting's pieces over the rotors' state in `potential`.
pub struct KickStep<'a, S: Splitting> {
    splitting: &'a S,
    state: &'a mut KickState<S::Momentum>,
    potential: &'a dyn Potential,
}

impl<S: Splitting> SplitDynamics for KickStep<'_, S> {
    fn dt(&self) -> f64 {
        self.state.dt
    }

    fn half_kick(&mut self) {
        self.state.half_kick(S::kick);
    }

    fn free_flow(&mut self, duration: f64) {
        let splitting = self.splitting;
        self.state
            .update(|qs, ps, is| rotate_all(splitting, qs, ps, is, duration));
    }

    fn half_kick_then_flow(&mut self, duration: f64) {
        let splitting = self.splitting;
        self.state.half_kick_then_update(S::kick, |qs, ps, is| {
            rotate_all(splitting, qs, ps, is, duration)
        });
    }

    fn evaluate(&mut self) {
        self.state.evaluate_torques(self.potential);
    }

    /// Summed in rotor order on one thread, so the sum does not depend on
    /// the thread count.
    fn kinetic_energy(&self) -> f64 {
        let state = &self.state;
        state
            .momentum
            .iter()
            .zip(&state.orientation)
            .zip(&state.inertia)
            .map(|((p, q), i)| {
                let w = S::omega_body(p, q, i);
                0.5 * w.dot(&i.component_mul(&w))
            })
            .sum()
    }

    fn for_each_omega_body(&self, mut f: impl FnMut(usize, &Vector3<f64>, &Vector3<f64>)) {
        let state = &self.state;
        for (rotor, ((p, q), i)) in state
            .momentum
            .iter()
            .zip(&state.orientation)
            .zip(&state.inertia)
            .enumerate()
        {
            f(rotor, &S::omega_body(p, q, i), i);
        }
    }

    /// Every angular momentum, in either frame, and the conjugate `P` alike.
    fn scale_momenta(&mut self, factor: f64) {
        for p in &mut self.state.momentum {
            for c in p.components_mut() {
                *c *= factor;
            }
        }
    }

    fn update_omega_body(&mut self, mut f: impl FnMut(usize, &mut Vector3<f64>, &Vector3<f64>)) {
        let state = &mut *self.state;
        for (rotor, ((p, q), i)) in state
            .momentum
            .iter_mut()
            .zip(&state.orientation)
            .zip(&state.inertia)
            .enumerate()
        {
            let mut w = S::omega_body(p, q, i);
            f(rotor, &mut w, i);
            *p = S::momentum(q, &w.component_mul(i));
        }
    }

    /// Rotors on fixed sites: no centres.
    fn for_each_velocity(&self, _: impl FnMut(usize, &Vector3<f64>, f64)) {}

    /// Rotors on fixed sites: no centres.
    fn update_velocities(&mut self, _: impl FnMut(usize, &mut Vector3<f64>, f64)) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{DlmOptions, NoSquishOptions};

    /// [`rotate_all`] of seven rotors (a group and three left over) leaves
    /// each with the bits of its rotation alone, for NO_SQUISH and DLM.
    #[test]
    fn rotating_all_rotates_each_as_alone() {
        fn check<S: Splitting>(splitting: S) {
            let moments: Vec<Vector3<f64>> = (0..7)
                .map(|k| Vector3::new(1.0 + 0.1 * k as f64, 2.0, 3.5 - 0.2 * k as f64))
                .collect();
            let q: Vec<Quat> = (0..7)
                .map(|k| {
                    let k = k as f64;
                    Quat::new(0.4 + k, -0.3, 0.8 - k, 0.1 * k)
                        .try_normalize()
                        .unwrap()
                })
                .collect();
            let momentum: Vec<S::Momentum> = (0..7)
                .map(|k| S::momentum(&q[k], &Vector3::new(0.7, -1.3 + k as f64, 0.4)))
                .collect();
            let (mut q_all, mut p_all) = (q.clone(), momentum.clone());
            rotate_all(&splitting, &mut q_all, &mut p_all, &moments, 0.37);
            for k in 0..7 {
                let (mut q1, mut p1) = ([q[k]], [momentum[k]]);
                splitting.rotate(&mut q1, &mut p1, &[moments[k]], 0.37);
                assert_ne!(q1[0], q[k], "rotor {k} turned");
                assert_eq!(
                    q_all[k].0.map(f64::to_bits),
                    q1[0].0.map(f64::to_bits),
                    "rotor {k}"
                );
                let bits = |p: &S::Momentum| format!("{p:?}");
                assert_eq!(bits(&p_all[k]), bits(&p1[0]), "rotor {k}");
            }
        }
        check(NoSquishOptions::default());
        check(DlmOptions::default());
    }
}
