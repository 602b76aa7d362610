//! The start-up of the body Gear schemes: the scaled derivatives at t = 0 of
//! every centre, centre velocity, orientation and body angular velocity,
//! as the rotors' start-up ([`crate::integrators::startup`]) computes them:
//! the orders the equations give directly (`r' = v`, `v' = F/m`, eq 10,
//! Euler's equations, eq 12), and with [`Startup::Consistent`] the higher
//! ones from the same RK4 integration to `+-4h` and polynomial fit, here of
//! the whole body system (65 force-and-torque evaluations once per run),
//! with scheme A's Nose-Hoover chains integrated with the bodies when it
//! carries them ([`GearChains`]). The system is left as it was given. Also the schemes' shared pieces:
//! their moments, and the evaluation at predicted values.

use super::gear_chains::{ChainStates, GearChains};
use crate::bodies::evaluate::{Evaluation, Scope};
use crate::bodies::system::{Body, BodySystem};
use crate::checks::{finite_and_positive, InputError};
use crate::integrators::gear::Nordsieck;
use crate::integrators::rigid_body::{q_ddot, General, PrincipalMoments, TopKind};
use crate::integrators::startup::{axpy, fit_into, samples, Rk4State, Startup};
use crate::integrators::torque::torque_body;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// Displacements of the centres from their start, velocities, orientations
/// and body angular velocities of all bodies, and the chains' variables
/// (empty without chains), or their rates of change.
/// (Displacements, not centres: their rounding is then that of the motion,
/// not of the box coordinates, ~1e-15, which the fit would put into every
/// `r_k`, and scheme B's velocity `r_1 / h` would carry as a momentum
/// error.)
#[derive(Clone)]
struct State {
    displacement: Vec<Vector3<f64>>,
    velocity: Vec<Vector3<f64>>,
    q: Vec<Quat>,
    omega_body: Vec<Vector3<f64>>,
    chains: ChainStates,
}

impl Rk4State for State {
    fn advanced(&self, rate: &State, s: f64) -> State {
        State {
            displacement: axpy(&self.displacement, &rate.displacement, s),
            velocity: axpy(&self.velocity, &rate.velocity, s),
            q: axpy(&self.q, &rate.q, s),
            omega_body: axpy(&self.omega_body, &rate.omega_body, s),
            chains: (
                self.chains.0.advanced(&rate.chains.0, s),
                self.chains.1.advanced(&rate.chains.1, s),
            ),
        }
    }
}

/// The scaled derivatives `h^k/k! x^(k)(0)`, orders 0..=5.
pub(super) struct BodyDerivatives {
    pub position: Nordsieck<Vector3<f64>, 6>,
    pub velocity: Nordsieck<Vector3<f64>, 6>,
    pub q: Nordsieck<Quat, 6>,
    pub omega_body: Nordsieck<Vector3<f64>, 6>,
}

/// What the start-up integrates: the bodies' moments, their centres at
/// t = 0 and the chains if any.
struct Equations<'a> {
    moments: &'a [PrincipalMoments],
    start: &'a [Vector3<f64>],
    chains: Option<&'a GearChains>,
}

impl Equations<'_> {
    /// The rates `(v, F/m, Q', w_b')` at `y` (the system evaluated at the
    /// centres `start + y.displacement` and the normalised orientations),
    /// less the chains' frictions, and the chains' rates.
    fn rate(&self, system: &mut BodySystem, evaluation: &mut Evaluation, y: &State) -> State {
        let mut positions = axpy(self.start, &y.displacement, 1.0);
        evaluate_at(system, &mut positions, &y.q, evaluation, Scope::Full);
        let mass = |i: usize| system.types[system.bodies[i].kind].mass;
        let n = y.q.len();
        let mut rate = State {
            displacement: y.velocity.clone(),
            velocity: (0..n).map(|i| evaluation.force[i] / mass(i)).collect(),
            q: (0..n)
                .map(|i| y.q[i].q_dot_from_omega_body(&y.omega_body[i]))
                .collect(),
            omega_body: (0..n)
                .map(|i| {
                    let n_b = torque_body(&y.q[i], &evaluation.torque[i]);
                    General::omega_dot_body(&self.moments[i], &y.omega_body[i], &n_b)
                })
                .collect(),
            chains: ChainStates::default(),
        };
        if let Some(chains) = self.chains {
            let (rates, frictions) = chains.rates(&y.chains, &y.omega_body, &y.velocity);
            for i in 0..n {
                rate.velocity[i] -= frictions.on_translation(&y.velocity[i]);
                rate.omega_body[i] -= chains.on_rotation(&frictions, i, &y.omega_body[i]);
            }
            rate.chains = rates;
        }
        rate
    }
}

/// The scaled derivatives at t = 0 for steps of `dt` (module doc) of the
/// bodies of `system` (principal moments `moments`, all > 0), with
/// `chains` (at their state at t = 0) if given.
fn body_derivatives(
    system: &mut BodySystem,
    moments: &[PrincipalMoments],
    chains: Option<&GearChains>,
    startup: Startup,
    dt: f64,
) -> BodyDerivatives {
    let given: Vec<Body> = system.bodies.clone();
    let start: Vec<Vector3<f64>> = given.iter().map(|b| b.position).collect();
    let y0 = State {
        displacement: vec![Vector3::zeros(); given.len()],
        velocity: given.iter().map(|b| b.velocity).collect(),
        q: given.iter().map(|b| b.orientation).collect(),
        omega_body: given
            .iter()
            .zip(moments)
            .map(|(b, m)| b.angular_momentum_body.component_mul(&m.inverse))
            .collect(),
        chains: chains.map(GearChains::states).unwrap_or_default(),
    };
    let equations = Equations {
        moments,
        start: &start,
        chains,
    };
    let mut evaluation = Evaluation::default();
    let rate0 = equations.rate(system, &mut evaluation, &y0);
    let n = given.len();
    let mut out = BodyDerivatives {
        position: Nordsieck::zeros(n),
        velocity: Nordsieck::zeros(n),
        q: Nordsieck::zeros(n),
        omega_body: Nordsieck::zeros(n),
    };
    if startup == Startup::Consistent {
        let samples = samples(&y0, dt, |y| equations.rate(system, &mut evaluation, y));
        fit_into(&samples, |s| &s.displacement, 3, &mut out.position);
        fit_into(&samples, |s| &s.velocity, 2, &mut out.velocity);
        fit_into(&samples, |s| &s.q, 3, &mut out.q);
        fit_into(&samples, |s| &s.omega_body, 2, &mut out.omega_body);
    }
    // The orders given directly by the equations of motion, exactly.
    let half_dt2 = 0.5 * dt * dt;
    for (i, centre) in start.iter().enumerate() {
        let (q, q_dot) = (y0.q[i], rate0.q[i]);
        out.position.r[0][i] = *centre;
        out.position.r[1][i] = y0.velocity[i] * dt;
        out.position.r[2][i] = rate0.velocity[i] * half_dt2;
        out.velocity.r[0][i] = y0.velocity[i];
        out.velocity.r[1][i] = rate0.velocity[i] * dt;
        out.q.r[0][i] = q;
        out.q.r[1][i] = q_dot * dt;
        out.q.r[2][i] = q_ddot(&q, &q_dot, &Quat::pure(&rate0.omega_body[i])) * half_dt2;
        out.omega_body.r[0][i] = y0.omega_body[i];
        out.omega_body.r[1][i] = rate0.omega_body[i] * dt;
    }
    system.bodies = given;
    out
}

/// What the setup of a Gear scheme computes: its checked time step, the
/// bodies' moments, the scaled derivatives at t = 0 and the evaluation of
/// the initial state.
pub(super) struct GearSetup {
    pub dt: f64,
    pub moments: Vec<PrincipalMoments>,
    pub start: BodyDerivatives,
    pub evaluation: Evaluation,
}

impl GearSetup {
    /// The setup on `system` for steps of `dt` (> 0) with the start-up
    /// `startup` and `chains` if given; errors name `dt` or a linear body's
    /// type.
    pub fn new(
        system: &mut BodySystem,
        dt: f64,
        startup: Startup,
        chains: Option<&GearChains>,
    ) -> Result<Self, InputError> {
        let dt = finite_and_positive("dt", dt)?;
        let moments = positive_moments(system)?;
        let start = body_derivatives(system, &moments, chains, startup, dt);
        let mut evaluation = Evaluation::default();
        system.evaluate(&mut evaluation);
        Ok(GearSetup {
            dt,
            moments,
            start,
            evaluation,
        })
    }
}

/// The principal moments of every body, all > 0 (the Gear schemes divide
/// by each); a linear body is refused naming its type's inertia.
fn positive_moments(system: &BodySystem) -> Result<Vec<PrincipalMoments>, InputError> {
    if let Some(t) = system.types.iter().position(|t| t.moments.min() <= 0.0) {
        return Err(InputError::new(
            format!("body_types[{t}].inertia"),
            format!(
                "the Gear schemes need three positive principal moments, got {:?}",
                system.types[t].moments.as_slice()
            ),
        ));
    }
    Ok(system
        .bodies
        .iter()
        .map(|b| PrincipalMoments::new(system.types[b.kind].moments))
        .collect())
}

/// Evaluates `system` at the centres `positions` and the orientations
/// `q / |q|` (a Gear scheme's predicted values) in `scope`; the centres come back
/// wrapped into a periodic box if the neighbour list was rebuilt.
pub(super) fn evaluate_at(
    system: &mut BodySystem,
    positions: &mut [Vector3<f64>],
    q: &[Quat],
    evaluation: &mut Evaluation,
    scope: Scope,
) {
    for ((body, r), q) in system.bodies.iter_mut().zip(&*positions).zip(q) {
        body.position = *r;
        body.orientation = *q * (1.0 / q.norm());
    }
    system.evaluate_in(evaluation, scope);
    for (r, body) in positions.iter_mut().zip(&system.bodies) {
        *r = body.position;
    }
}
