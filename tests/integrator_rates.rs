//! What every integrator reports besides the orientations, against the
//! orientations' own time derivative: `Q'` (`Integrator::q_dot`, behind the
//! recorded `q_dot_q`) and the body angular velocity (behind every kinetic
//! energy), on the interacting multipole cluster, for all five schemes.

mod gear_common;

use gear_common::cluster::cube;
use gear_common::run;
use nalgebra::{Quaternion, Vector3};
use quatrot::integrators::{Dlm, GearA, GearB, Integrator, NoSquish, Richardson};
use quatrot::Quat;

/// Time step of the finite differences.
const DT: f64 = 1e-3;
/// Largest body angular velocity of the cluster's run (|w| <= 0.8 at t = 0).
const OMEGA_MAX: f64 = 2.0;
/// The central difference of a scheme's own orientations differs from its
/// `Q'` by the difference's truncation, `dt^2/6 |Q'''|`, and by the scheme's
/// `O(dt^2)` departure from its own smooth interpolant (the second-order
/// baselines): both below `(|w|max dt)^2` (measured up to 2e-7).
const DERIVATIVE_TOLERANCE: f64 = (OMEGA_MAX * DT) * (OMEGA_MAX * DT);

/// What an integrator reports after a step: orientations, `Q'` and `w_b`.
struct Frame {
    orientations: Vec<Quat>,
    q_dot: Vec<Quat>,
    omega_body: Vec<Vector3<f64>>,
}

fn to_nalgebra(q: &Quat) -> Quaternion<f64> {
    Quaternion::new(q[0], q[1], q[2], q[3])
}

/// Runs `integrator` on the mixed cluster and compares, at every step with
/// a neighbour on each side, its `q_dot` and `omega_body` with the central
/// difference of its orientations (`w_b = 2 vec(Q~*Q')/|Q|^2`, eq 10
/// inverted, in nalgebra's quaternion algebra). Returns the largest
/// differences.
fn rate_errors<I: Integrator>(mut integrator: I) -> (f64, f64) {
    let (cluster, inertia, initial) = cube(true);
    let n = initial.len();
    let mut frames: Vec<Frame> = Vec::new();
    run(
        &mut integrator,
        &inertia,
        &cluster,
        &initial,
        DT,
        20,
        |_, i| {
            let mut q_dot = vec![Quat::ZERO; n];
            let mut omega = vec![Vector3::zeros(); n];
            i.q_dot(&mut q_dot);
            i.omega_body(&mut omega);
            frames.push(Frame {
                orientations: i.orientations().to_vec(),
                q_dot,
                omega_body: omega,
            });
        },
    );
    let (mut q_dot_error, mut omega_error) = (0.0_f64, 0.0_f64);
    for k in 1..frames.len() - 1 {
        let Frame {
            orientations: q,
            q_dot,
            omega_body: omega,
        } = &frames[k];
        for r in 0..n {
            let fd = (frames[k + 1].orientations[r] - frames[k - 1].orientations[r]) * (0.5 / DT);
            q_dot_error =
                q_dot_error.max((q_dot[r] - fd).0.iter().fold(0.0, |m, x| m.max(x.abs())));
            let q_n = to_nalgebra(&q[r]);
            let w = (q_n.conjugate() * to_nalgebra(&fd)).imag() * (2.0 / q_n.norm_squared());
            omega_error = omega_error.max((w - omega[r]).amax());
        }
    }
    (q_dot_error, omega_error)
}

/// `Q'` and `w_b` of every integrator are the time derivative of its
/// orientations (the default `Integrator::q_dot`, eq 10 from `w_b`, serves
/// all but scheme B, which stores `Q'`).
#[test]
fn q_dot_and_omega_body_are_the_rate_of_the_orientations() {
    let results = [
        ("gear_a", rate_errors(GearA::default())),
        ("gear_b", rate_errors(GearB::default())),
        // One free-rotation sweep (LAMMPS) and the exact spherical flow.
        ("no_squish", rate_errors(NoSquish::default())),
        ("dlm", rate_errors(Dlm::default())),
        ("richardson", rate_errors(Richardson::default())),
    ];
    for (name, (q_dot, omega)) in results {
        eprintln!("{name}: Q' off by {q_dot:.2e}, w_b off by {omega:.2e}");
        assert!(
            q_dot < DERIVATIVE_TOLERANCE && omega < DERIVATIVE_TOLERANCE,
            "{name}: Q' off by {q_dot:e}, w_b off by {omega:e}"
        );
    }
}
