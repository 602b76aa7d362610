//! The free-rotation sweeps of DLM and NO_SQUISH against the algorithms
//! written again from their papers, in rotation matrices and body angular
//! momenta (no quaternion, nothing of quatrot but the potential's torques):
//! Dullweber, Leimkuhler and McLachlan (J. Chem. Phys. 107, 5840 (1997))
//! rotate about body axes 1, 2, 3, 2, 1; Miller et al. (J. Chem. Phys. 116,
//! 8649 (2002)) about 3, 2, 1, 2, 3, in `substeps` sweeps per step. Both
//! kick the body angular momentum with the body torque for half a step
//! before and after.
//!
//! The trajectories agree to round-off, and the same restatement with the
//! sweep reversed misses them by the splitting's own `O(dt^3)` per step:
//! the order of the sweep is pinned, not only the order of the method.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use quatrot::integrators::{
    Dlm, DlmOptions, Integrator, NoSquish, NoSquishOptions, RotorState, SphericalTops,
};
use quatrot::potential::Potential;
use quatrot::rotor::Inertia;
use quatrot::Quat;

/// Round-off of `STEPS` steps of products of O(1) rotation matrices (each
/// entry rounding at ~1e-16 per product, some tens of products per step,
/// errors growing about linearly): measured 1e-14 to 3e-14.
const ROUND_OFF: f64 = 1e-12;
/// The reversed sweep changes each step by `O((|w| dt)^3 / substeps^2)`,
/// about 1e-6 / substeps^2 here: far above round-off (measured after `STEPS`
/// steps: 3.7e-5 with one sweep per step, 3.7e-7 with ten).
const REVERSED_SWEEP_MIN: f64 = 1e-9;
/// Steps of `DT` compared (t = 2 with |w| ~ 1).
const STEPS: usize = 200;
const DT: f64 = 0.01;

/// Body-to-space matrix `R` of a quaternion, through nalgebra (independent of
/// quatrot's eq 7).
fn rotation(q: &Quat) -> Matrix3<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]))
        .to_rotation_matrix()
        .into_inner()
}

/// Body-fixed dipoles in a uniform field: torque `mu_s x E` with
/// `mu_s = R mu_b`, energy `-mu_s.E`.
struct DipolesInField {
    dipoles_body: Vec<Vector3<f64>>,
    field: Vector3<f64>,
}

impl DipolesInField {
    /// Space-fixed torques for body-to-space matrices `r`.
    fn torques(&self, r: &[Matrix3<f64>]) -> Vec<Vector3<f64>> {
        r.iter()
            .zip(&self.dipoles_body)
            .map(|(r, mu)| (r * mu).cross(&self.field))
            .collect()
    }
}

impl Potential for DipolesInField {
    fn energy(&self, q: &[Quat]) -> f64 {
        q.iter()
            .zip(&self.dipoles_body)
            .map(|(q, mu)| -(rotation(q) * mu).dot(&self.field))
            .sum()
    }
    /// `dV/dq_k = -mu_b.(dA/dq_k E)` (eq 14 with `V = -mu_b.A E`).
    fn accumulate_gradient(&self, q: &[Quat], gradient: &mut [Quat]) {
        for ((g, q), mu) in gradient.iter_mut().zip(q).zip(&self.dipoles_body) {
            for (g_k, d_k) in g.0.iter_mut().zip(q.space_to_body_matrix_derivatives()) {
                *g_k -= mu.dot(&(d_k * self.field));
            }
        }
    }
    fn accumulate_torques(&self, q: &[Quat], torques: &mut [Vector3<f64>]) {
        let r: Vec<Matrix3<f64>> = q.iter().map(rotation).collect();
        for (t, n) in torques.iter_mut().zip(self.torques(&r)) {
            *t += n;
        }
    }
}

/// An asymmetric top, a symmetric one and a spherical one (which the sweep
/// treats like any other top under `SphericalTops::Split`, as LAMMPS does),
/// with tilted dipoles in a field.
fn system() -> (Vec<Vector3<f64>>, DipolesInField, Vec<RotorState>) {
    let moments = vec![
        Vector3::new(1.0, 2.0, 3.5),
        Vector3::new(0.6, 1.4, 1.4),
        Vector3::repeat(0.8),
    ];
    let potential = DipolesInField {
        dipoles_body: vec![
            Vector3::new(0.3, 0.2, 1.0),
            Vector3::new(-0.5, 0.8, 0.1),
            Vector3::new(0.0, 0.4, -0.9),
        ],
        field: Vector3::new(0.2, -0.4, 1.5),
    };
    let state = |q: [f64; 4], w: [f64; 3]| RotorState {
        orientation: Quat(q).try_normalize().expect("non-zero"),
        omega_body: Vector3::from(w),
    };
    let initial = vec![
        state([0.9, 0.1, -0.3, 0.2], [0.4, -1.1, 0.8]),
        state([0.2, 0.7, 0.5, -0.4], [-0.9, 0.3, 0.6]),
        state([0.5, -0.5, 0.1, 0.7], [0.2, 0.5, -1.3]),
    ];
    (moments, potential, initial)
}

/// The active rotation by `angle` about coordinate axis `axis` (0, 1, 2).
fn axis_rotation(axis: usize, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    let (i, j) = [(1, 2), (2, 0), (0, 1)][axis];
    let mut r = Matrix3::identity();
    r[(i, i)] = c;
    r[(j, j)] = c;
    r[(j, i)] = s;
    r[(i, j)] = -s;
    r
}

/// One rotor of the restatement: body-to-space matrix and body angular momentum.
#[derive(Clone, Copy)]
struct Restated {
    r: Matrix3<f64>,
    l_body: Vector3<f64>,
}

/// The splitting step as the papers write it, for the sweep `axes` (outer,
/// middle, inner): half kick `L_b += dt/2 R^T n_s`; `substeps` sweeps, each
/// rotation about body axis `k` by `t L_k / I_k` turning the body
/// (`R <- R E`) with the space angular momentum fixed (`L_b <- E^T L_b`),
/// for `t` = half, half, whole, half, half the sweep's time; half kick with
/// the torques at the new orientations.
fn restated_run(
    moments: &[Vector3<f64>],
    potential: &DipolesInField,
    initial: &[RotorState],
    axes: [usize; 3],
    substeps: usize,
) -> Vec<Restated> {
    let mut rotors: Vec<Restated> = initial
        .iter()
        .zip(moments)
        .map(|(s, i)| Restated {
            r: rotation(&s.orientation),
            l_body: s.omega_body.component_mul(i),
        })
        .collect();
    let kick = |rotors: &mut [Restated]| {
        let r: Vec<Matrix3<f64>> = rotors.iter().map(|x| x.r).collect();
        for (x, n) in rotors.iter_mut().zip(potential.torques(&r)) {
            x.l_body += x.r.transpose() * n * (0.5 * DT);
        }
    };
    let sub = DT / substeps as f64;
    let [outer, middle, inner] = axes;
    let sweep = [
        (outer, 0.5),
        (middle, 0.5),
        (inner, 1.0),
        (middle, 0.5),
        (outer, 0.5),
    ];
    for _ in 0..STEPS {
        kick(&mut rotors);
        for (x, i) in rotors.iter_mut().zip(moments) {
            for _ in 0..substeps {
                for (k, fraction) in sweep {
                    let e = axis_rotation(k, fraction * sub * x.l_body[k] / i[k]);
                    x.r *= e;
                    x.l_body = e.transpose() * x.l_body;
                }
            }
        }
        kick(&mut rotors);
    }
    rotors
}

/// Largest difference of the body-to-space matrices and of the body angular
/// momenta between `integrator` after `STEPS` steps and a restatement.
fn distance<I: Integrator>(integrator: &I, moments: &[Vector3<f64>], restated: &[Restated]) -> f64 {
    let mut omega = vec![Vector3::zeros(); moments.len()];
    integrator.omega_body(&mut omega);
    integrator
        .orientations()
        .iter()
        .zip(&omega)
        .zip(moments)
        .zip(restated)
        .map(|(((q, w), i), x)| {
            let dr = (rotation(q) - x.r).amax();
            let dl = (w.component_mul(i) - x.l_body).amax();
            dr.max(dl)
        })
        .fold(0.0, f64::max)
}

/// Runs `integrator` and compares it with the restatement for `axes`, and
/// with the restatement for the reversed sweep.
fn check<I: Integrator>(name: &str, mut integrator: I, axes: [usize; 3], substeps: usize) {
    let (moments, potential, initial) = system();
    let inertia: Vec<Inertia> = moments.iter().map(|m| Inertia::Principal(*m)).collect();
    integrator
        .setup(&inertia, &potential, &initial, DT)
        .expect("valid setup");
    for _ in 0..STEPS {
        integrator.step(&potential);
    }
    let same = restated_run(&moments, &potential, &initial, axes, substeps);
    let reversed = restated_run(
        &moments,
        &potential,
        &initial,
        [axes[2], axes[1], axes[0]],
        substeps,
    );
    let (d_same, d_reversed) = (
        distance(&integrator, &moments, &same),
        distance(&integrator, &moments, &reversed),
    );
    eprintln!("{name}: vs restatement {d_same:.2e}, vs reversed sweep {d_reversed:.2e}");
    assert!(
        d_same < ROUND_OFF,
        "{name}: {d_same:e} from its restatement"
    );
    assert!(
        d_reversed > REVERSED_SWEEP_MIN,
        "{name}: the reversed sweep is only {d_reversed:e} away"
    );
}

/// DLM sweeps body axes 1, 2, 3, 2, 1, as its paper and LAMMPS
/// `fix nve/sphere update dipole/dlm`.
#[test]
fn dlm_sweeps_axes_1_2_3_2_1() {
    check(
        "dlm",
        Dlm::new(DlmOptions {
            spherical_tops: SphericalTops::Split,
        }),
        [0, 1, 2],
        1,
    );
}

/// NO_SQUISH sweeps body axes 3, 2, 1, 2, 3, as its paper, LAMMPS
/// `fix rigid/nve` and HOOMD-blue (one sweep) and DL_POLY (ten).
#[test]
fn no_squish_sweeps_axes_3_2_1_2_3() {
    for substeps in [
        NoSquishOptions::SUBSTEPS_LAMMPS,
        NoSquishOptions::SUBSTEPS_DL_POLY,
    ] {
        check(
            &format!("no_squish/{substeps}"),
            NoSquish::new(NoSquishOptions {
                substeps,
                spherical_tops: SphericalTops::Split,
            }),
            [2, 1, 0],
            substeps.get() as usize,
        );
    }
}
