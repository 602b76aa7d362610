//! Helpers shared by the Gear scheme tests: running an integrator, the
//! orientation error, and the least-squares order fit.
#![allow(dead_code)]

use nalgebra::Vector3;
use quatrot::integrators::{Integrator, RotorState};
use quatrot::potential::Potential;
use quatrot::rotor::Inertia;
use quatrot::stats::line_fit;
use quatrot::Quat;

pub mod cluster;
pub mod fixtures;

/// Sets up `integrator` and runs it for `steps` steps of `dt`, calling
/// `observe(step, integrator)` after setup (step 0) and after each step.
pub fn run<I: Integrator, P: Potential>(
    integrator: &mut I,
    inertia: &[Inertia],
    potential: &P,
    initial: &[RotorState],
    dt: f64,
    steps: usize,
    mut observe: impl FnMut(usize, &I),
) {
    integrator
        .setup(inertia, potential, initial, dt)
        .expect("valid test setup");
    observe(0, integrator);
    for step in 1..=steps {
        integrator.step(potential);
        observe(step, integrator);
    }
}

/// The orientations after running to `t_end` with steps of `t_end / steps`.
pub fn final_orientations<I: Integrator, P: Potential>(
    integrator: &mut I,
    inertia: &[Inertia],
    potential: &P,
    initial: &[RotorState],
    t_end: f64,
    steps: usize,
) -> Vec<Quat> {
    run(
        integrator,
        inertia,
        potential,
        initial,
        t_end / steps as f64,
        steps,
        |_, _| {},
    );
    integrator.orientations().to_vec()
}

/// The largest rotation angle between corresponding orientations (radians).
pub fn max_angle(a: &[Quat], b: &[Quat]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let (p, q) = (
                p.try_normalize().unwrap_or(*p),
                q.try_normalize().unwrap_or(*q),
            );
            p.angle_to(&q)
        })
        .fold(0.0, f64::max)
}

/// The slope of `ln error` against `ln dt` by least squares.
pub fn fitted_order(dts: &[f64], errors: &[f64]) -> f64 {
    let x: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    line_fit(&x, &y).slope
}

/// A spherical top: `Q(t) = Q0 * exp(w_b t)` with constant `w_b`.
pub fn free_spherical_exact(initial: &RotorState, t: f64) -> Quat {
    initial.orientation * Quat::exp(&(initial.omega_body * t))
}

/// A symmetric top `I1 = I2 != I3` (axis 3): the body rotates about the
/// space-fixed angular momentum `L` at rate `|L|/I1` and about its own axis 3
/// at rate `-Omega`, `Omega = (I3 - I1)/I1 w3`:
/// `Q(t) = exp(L_hat |L| t/I1) * Q0 * exp(-Omega t e3)`.
pub fn free_symmetric_exact(i1: f64, i3: f64, initial: &RotorState, t: f64) -> Quat {
    let w = initial.omega_body;
    let l_body = Vector3::new(i1 * w.x, i1 * w.y, i3 * w.z);
    let l_space = initial.orientation.body_to_space(&l_body);
    let precession = Quat::exp(&(l_space * (t / i1)));
    let omega = (i3 - i1) / i1 * w.z;
    precession * initial.orientation * Quat::exp(&Vector3::new(0.0, 0.0, -omega * t))
}
