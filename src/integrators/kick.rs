//! The state and the pieces of a step shared by the kick-based baselines
//! (NO_SQUISH, DLM, Richardson): per rotor the unit orientation, a momentum
//! variable, and the space-fixed torque at the orientation, reused by the
//! next step's first half kick. Each baseline only chooses its momentum
//! variable, its kick and its orientation update.
//!
//! The per-rotor passes run over chunks of rotors split across the rayon
//! pool (`rotor_chunks`); each rotor's update reads only its own state, so
//! results do not depend on the number of threads.

use super::checkpoint::{check_length, read_values, write_values, Components};
use super::rotor_chunks::for_each_rotor_chunk;
use super::setup::{validate_setup, Moments, ValidSetup};
use super::torque::evaluate_torques;
use super::{IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// The per-rotor arrays of a kick-based baseline, sized once at setup.
#[derive(Clone, Debug)]
pub struct KickState<M> {
    /// The time step.
    pub dt: f64,
    /// Principal moments `(I1, I2, I3)` per rotor (zero moments allowed).
    pub inertia: Vec<Vector3<f64>>,
    /// Unit orientations.
    pub orientation: Vec<Quat>,
    /// The momentum variable (`L_b`, `L_s` or the conjugate `P`).
    pub momentum: Vec<M>,
    /// Space-fixed torques at `orientation`.
    pub torque_space: Vec<Vector3<f64>>,
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
    pub fn new<P: Potential>(
        inertia: &[Inertia],
        potential: &P,
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
    pub fn half_kick(&mut self, kick: impl Fn(&mut M, &Quat, &Vector3<f64>, f64) + Sync) {
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

    /// `update(Q, momentum, moments)` for every rotor (the orientation
    /// update). A pass of its own: fused into the kick's pass, each rotor's
    /// chain of dependent operations grew and a NO_SQUISH step took 10 % longer.
    pub fn update(&mut self, update: impl Fn(&mut Quat, &mut M, &Vector3<f64>) + Sync) {
        let rotors = (
            &mut self.orientation[..],
            &mut self.momentum[..],
            &self.inertia[..],
        );
        for_each_rotor_chunk(rotors, |(qs, ps, is)| {
            for ((q, p), i) in qs.iter_mut().zip(ps).zip(is) {
                update(q, p, i);
            }
        });
    }

    /// The torques at the current orientations.
    pub fn evaluate_torques<P: Potential>(&mut self, potential: &P) {
        evaluate_torques(potential, &self.orientation, &mut self.torque_space);
    }

    /// Writes `f(momentum, Q, moments)` for every rotor (the body angular
    /// velocity).
    pub fn omega_body(
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

    /// Layout: all `Q` (4 each), then all momenta (`P`: 4 each, `L`: 3 each),
    /// then all space-fixed torques (3 each).
    pub fn checkpoint(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.orientation.len() * (Quat::LEN + M::LEN + 3));
        write_values(&self.orientation, &mut out);
        write_values(&self.momentum, &mut out);
        write_values(&self.torque_space, &mut out);
        out
    }

    /// Reads back [`KickState::checkpoint`]'s output after checking that it
    /// holds exactly that many finite values.
    pub fn restore(&mut self, state: &[f64]) -> Result<(), IntegratorError> {
        check_length(state, self.orientation.len(), Quat::LEN + M::LEN + 3)?;
        let rest = read_values(state, &mut self.orientation);
        let rest = read_values(rest, &mut self.momentum);
        read_values(rest, &mut self.torque_space);
        Ok(())
    }
}
