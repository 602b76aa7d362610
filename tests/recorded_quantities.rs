//! Every quantity a scene can record, for every integrator, against its
//! definition (docs/scenes.md) evaluated here from the state the same run
//! recorded in its trajectory (orientations and body angular velocities at
//! every step), with the potential built here from the scene's numbers.

use nalgebra::{Matrix3, Vector3};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::run::{execute, RunResult};
use quatrot::scene::{load_text, Overrides};
use quatrot::Quat;

mod common;

/// Recorded and recomputed values are the same sums in another order:
/// round-off relative to the largest term (energies of O(1) with terms of
/// O(1); measured below 1e-15).
const ROUND_OFF: f64 = 1e-13;
/// The order parameters recorded (nalgebra's iterative eigensolver) and
/// recomputed (the trigonometric closed form): eigenvalues of O(1) agree to
/// a few 1e-16 (measured).
const ORDER_ROUND_OFF: f64 = 1e-12;
/// The director recorded and recomputed (the closed form's eigenvector by a
/// cross product): its error is the eigenvalues' round-off over their gap,
/// O(0.1) here.
const DIRECTOR_ROUND_OFF: f64 = 1e-11;
/// `| |Q| - 1 |` recorded and recomputed: the same four squares, square root
/// and subtraction, a few ulps apart at most.
const NORM_ROUND_OFF: f64 = 4.0 * f64::EPSILON;

const QUADRUPOLE: [[f64; 3]; 3] = [[0.3, 0.1, 0.0], [0.1, -0.5, 0.0], [0.0, 0.0, 0.2]];
const SITES: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.4, 0.2, 0.0], [0.3, 1.5, -0.4]];
const MOMENTS: [[f64; 3]; 3] = [[0.8, 1.1, 1.5], [0.9, 0.9, 0.9], [0.8, 1.1, 1.5]];
const DIPOLE: [f64; 3] = [0.1, -0.2, 0.9];
const FIELD: [f64; 3] = [0.1, -0.3, 0.5];
const STEPS: usize = 25;

/// The scene: three rotors with dipoles and quadrupoles (an asymmetric top,
/// a spherical top, an asymmetric top) in a field, open boundary.
fn scene_text(integrator: &str, quantities: &[&str]) -> String {
    let quantities: Vec<String> = quantities.iter().map(|q| format!("\"{q}\"")).collect();
    format!(
        r#"
version = 1
[rotors]
kind = "sites"
default = {{ inertia = {m0:?}, dipole = {DIPOLE:?}, quadrupole = {QUADRUPOLE:?} }}
sites = [
  {{ position = {s0:?} }},
  {{ position = {s1:?}, inertia = {i1:?} }},
  {{ position = {s2:?} }},
]
[interactions]
boundary = {{ kind = "open" }}
[fields]
uniform = {FIELD:?}
[initial]
kind = "random"
seed = 11
temperature = 1.0
[integrator]
{integrator}
[run]
dt = 0.01
steps = {STEPS}
[[record.series]]
every = 1
quantities = [{quantities}]
[record.trajectory]
every = 1
"#,
        m0 = MOMENTS[0],
        i1 = MOMENTS[1][0],
        s0 = SITES[0],
        s1 = SITES[1],
        s2 = SITES[2],
        quantities = quantities.join(", "),
    )
}

/// The scene's potential, built from its numbers.
fn potential() -> MultipolePotential {
    let rotors: Vec<Rotor> = SITES
        .iter()
        .zip(MOMENTS)
        .map(|(s, m)| Rotor {
            site: Vector3::from(*s),
            inertia: Inertia::Principal(Vector3::from(m)),
            dipole_body: Some(Vector3::from(DIPOLE)),
            quadrupole_body: Some(Matrix3::from_fn(|i, j| QUADRUPOLE[i][j])),
        })
        .collect();
    let external = ExternalFields {
        field: Some(Vector3::from(FIELD)),
        field_gradient: None,
    };
    MultipolePotential::new(&rotors, Boundary::Open, external).expect("valid rotors")
}

/// Runs the scene with the `[integrator]` table `integrator`, recording
/// `quantities` every step.
fn run(integrator: &str, quantities: &[&str]) -> RunResult {
    let (_, scene) = load_text(&scene_text(integrator, quantities), &Overrides::default())
        .unwrap_or_else(|e| panic!("{integrator}: {e}"));
    execute(
        &scene,
        serde_json::Value::Null,
        &common::in_memory(),
        None,
        None,
    )
    .expect("runs")
}

/// The definitions, evaluated from the recorded state of one step.
struct State {
    orientations: Vec<Quat>,
    omega_body: Vec<Vector3<f64>>,
}

impl State {
    /// `K = sum_i 1/2 sum_a I_ia w_ia^2`.
    fn kinetic(&self) -> f64 {
        self.omega_body
            .iter()
            .zip(MOMENTS)
            .map(|(w, m)| (0..3).map(|a| 0.5 * m[a] * w[a] * w[a]).sum::<f64>())
            .sum()
    }

    /// `max_i | |Q_i| - 1 |`.
    fn norm_error(&self) -> f64 {
        self.orientations
            .iter()
            .map(|q| (q.0.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs())
            .fold(0.0, f64::max)
    }
}

/// `R(Q/|Q|)`, body to space, written out from the note's `A(Q)` (eq 7)
/// transposed.
fn body_to_space(q: &Quat) -> Matrix3<f64> {
    let n = q.0.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [a, b, c, d] = q.0.map(|x| x / n);
    Matrix3::new(
        a * a + b * b - c * c - d * d,
        2.0 * (b * c - a * d),
        2.0 * (b * d + a * c),
        2.0 * (b * c + a * d),
        a * a - b * b + c * c - d * d,
        2.0 * (c * d - a * b),
        2.0 * (b * d - a * c),
        2.0 * (c * d + a * b),
        a * a - b * b - c * c + d * d,
    )
}

/// The eigenvalues of a symmetric 3x3 matrix in decreasing order, by the
/// trigonometric closed form (Smith, Commun. ACM 4, 168 (1961)).
fn eigenvalues(m: &Matrix3<f64>) -> [f64; 3] {
    let mean = m.trace() / 3.0;
    let off = m.m12 * m.m12 + m.m13 * m.m13 + m.m23 * m.m23;
    let p =
        (((m.m11 - mean).powi(2) + (m.m22 - mean).powi(2) + (m.m33 - mean).powi(2) + 2.0 * off)
            / 6.0)
            .sqrt();
    let r = ((m - Matrix3::identity() * mean) / p).determinant() / 2.0;
    let phi = r.clamp(-1.0, 1.0).acos() / 3.0;
    let largest = mean + 2.0 * p * phi.cos();
    let smallest = mean + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [largest, 3.0 * mean - largest - smallest, smallest]
}

/// The unit eigenvector of `m` for its simple eigenvalue `lambda`: the
/// longest cross product of two rows of `m - lambda I`.
fn eigenvector(m: &Matrix3<f64>, lambda: f64) -> Vector3<f64> {
    let a = m - Matrix3::identity() * lambda;
    let rows = [
        a.row(0).transpose(),
        a.row(1).transpose(),
        a.row(2).transpose(),
    ];
    let v = [(0, 1), (0, 2), (1, 2)]
        .map(|(i, j)| rows[i].cross(&rows[j]))
        .into_iter()
        .max_by(|x, y| x.norm().total_cmp(&y.norm()))
        .expect("three products");
    v.normalize()
}

/// `[P1, P2, director]` of unit axes `u` (docs/scenes.md): the largest
/// eigenvalue of `<3/2 u u - 1/2 I>`, its eigenvector signed along `<u>`.
fn order(u: &[Vector3<f64>]) -> [f64; 5] {
    let n = u.len() as f64;
    let q = u
        .iter()
        .map(|u| u * u.transpose() * 1.5)
        .sum::<Matrix3<f64>>()
        / n
        - Matrix3::identity() * 0.5;
    let p2 = eigenvalues(&q)[0];
    let mean = u.iter().sum::<Vector3<f64>>() / n;
    let mut d = eigenvector(&q, p2);
    if d.dot(&mean) < 0.0 {
        d = -d;
    }
    [mean.dot(&d), p2, d.x, d.y, d.z]
}

/// The axis of the body quadrupole (docs/scenes.md): the eigenvector of the
/// eigenvalue largest in magnitude, its first nonzero component positive.
fn quadrupole_axis() -> Vector3<f64> {
    let theta = Matrix3::from_fn(|i, j| QUADRUPOLE[i][j]);
    let lambda = eigenvalues(&theta)
        .into_iter()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .expect("three eigenvalues");
    let e = eigenvector(&theta, lambda);
    let first = e.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    e * first.signum()
}

/// Checks every recorded column of `result` against the definitions.
fn check(integrator: &str, result: &RunResult, quantities: &[&str]) {
    let frames = result.trajectory.as_ref().expect("trajectory kept");
    let table = &result.series[0];
    let n = SITES.len();
    assert_eq!(frames.steps.len(), STEPS + 1, "{integrator}: frames");
    assert_eq!(table.values.len(), (STEPS + 1) * table.columns.len());
    let potential = potential();
    let state = |k: usize| State {
        orientations: frames.orientations[4 * n * k..4 * n * (k + 1)]
            .chunks(4)
            .map(|c| Quat::new(c[0], c[1], c[2], c[3]))
            .collect(),
        omega_body: frames.omega_body[3 * n * k..3 * n * (k + 1)]
            .chunks(3)
            .map(Vector3::from_column_slice)
            .collect(),
    };
    let start = state(0);
    let (kinetic0, total0) = (
        start.kinetic(),
        start.kinetic() + potential.energy(&start.orientations),
    );
    let listed: Vec<String> = quantities
        .iter()
        .flat_map(|q| match *q {
            "M" => vec!["M_x".to_string(), "M_y".to_string(), "M_z".to_string()],
            "P2_dipole" | "P2_quadrupole" => {
                let m = &q[3..];
                std::iter::once(q.to_string())
                    .chain(["x", "y", "z"].map(|c| format!("director_{m}_{c}")))
                    .collect()
            }
            other => vec![other.to_string()],
        })
        .collect();
    assert_eq!(table.columns[2..], listed, "{integrator}: columns");
    for (k, row) in table.values.chunks(table.columns.len()).enumerate() {
        assert_eq!(
            row[0], frames.steps[k] as f64,
            "{integrator}: step of row {k}"
        );
        let s = state(k);
        let (kinetic, v) = (s.kinetic(), potential.energy(&s.orientations));
        let rotations: Vec<Matrix3<f64>> = s.orientations.iter().map(body_to_space).collect();
        let dipole = Vector3::from(DIPOLE);
        let m: Vector3<f64> = rotations.iter().map(|r| r * dipole).sum();
        let dipole_order = order(
            &rotations
                .iter()
                .map(|r| r * dipole.normalize())
                .collect::<Vec<_>>(),
        );
        let axis = quadrupole_axis();
        let quadrupole_order = order(&rotations.iter().map(|r| r * axis).collect::<Vec<_>>());
        for (name, recorded) in table.columns[2..].iter().zip(&row[2..]) {
            let (expected, scale) = match name.as_str() {
                "kinetic_energy" => (kinetic, kinetic.max(1.0)),
                "potential_energy" => (v, v.abs().max(1.0)),
                "total_energy" => (kinetic + v, (kinetic + v.abs()).max(1.0)),
                "energy_error" => ((kinetic + v - total0) / kinetic0, 1.0),
                "temperature" => (2.0 * kinetic / (3.0 * n as f64), kinetic.max(1.0)),
                "norm_error" => (s.norm_error(), NORM_ROUND_OFF / ROUND_OFF),
                // Q.Q' (eq 15a) and Q.N (eq 15b) vanish on the motion; all
                // five schemes keep them at round-off (scheme B by its
                // projections, the others by eq 10).
                "q_dot_q" | "q_dot_n" => (0.0, 1.0),
                "M_x" => (m.x, 1.0),
                "M_y" => (m.y, 1.0),
                "M_z" => (m.z, 1.0),
                "M2" => (m.norm_squared(), 1.0),
                "P1_dipole" => (dipole_order[0], ORDER_ROUND_OFF / ROUND_OFF),
                "P2_dipole" => (dipole_order[1], ORDER_ROUND_OFF / ROUND_OFF),
                "director_dipole_x" => (dipole_order[2], DIRECTOR_ROUND_OFF / ROUND_OFF),
                "director_dipole_y" => (dipole_order[3], DIRECTOR_ROUND_OFF / ROUND_OFF),
                "director_dipole_z" => (dipole_order[4], DIRECTOR_ROUND_OFF / ROUND_OFF),
                "P2_quadrupole" => (quadrupole_order[1], ORDER_ROUND_OFF / ROUND_OFF),
                "director_quadrupole_x" => (quadrupole_order[2], DIRECTOR_ROUND_OFF / ROUND_OFF),
                "director_quadrupole_y" => (quadrupole_order[3], DIRECTOR_ROUND_OFF / ROUND_OFF),
                "director_quadrupole_z" => (quadrupole_order[4], DIRECTOR_ROUND_OFF / ROUND_OFF),
                other => panic!("no definition for {other}"),
            };
            assert!(
                (recorded - expected).abs() <= ROUND_OFF * scale,
                "{integrator}, step {k}, {name}: recorded {recorded:e}, definition {expected:e}"
            );
        }
    }
}

/// Every recordable quantity, for every integrator (`q_dot_n` for scheme B,
/// the one that stores the quaternion force; scheme A also without
/// renormalisation, so that `norm_error` is not zero).
#[test]
fn recorded_quantities_follow_their_definitions_for_every_integrator() {
    const QUANTITIES: [&str; 12] = [
        "kinetic_energy",
        "potential_energy",
        "total_energy",
        "energy_error",
        "temperature",
        "norm_error",
        "q_dot_q",
        "M",
        "M2",
        "P1_dipole",
        "P2_dipole",
        "P2_quadrupole",
    ];
    for integrator in [
        "kind = \"gear_a\"",
        "kind = \"gear_a\"\nrenormalise = false",
        "kind = \"gear_b\"",
        "kind = \"no_squish\"",
        "kind = \"dlm\"",
        "kind = \"richardson\"",
    ] {
        let mut quantities = QUANTITIES.to_vec();
        if integrator.contains("gear_b") {
            quantities.push("q_dot_n");
        }
        let result = run(integrator, &quantities);
        check(integrator, &result, &quantities);
    }
}

/// The potential energy recorded is the potential's value, not the total
/// minus the kinetic energy: with `K = 1e20 >> |V| = O(1)` the difference
/// of the two would keep none of V's digits (issue 37: a lattice at
/// `initial.temperature = 1e20` recorded exactly 0). Every integrator, and
/// every thermostat each can carry (at `T = 1e30`, as the issue's Langevin
/// case); steps of 1e-12 keep `w dt` small at these speeds.
#[test]
fn the_recorded_potential_energy_is_the_potential_even_when_k_dwarfs_it() {
    let thermostats = [
        (
            "",
            &["gear_a", "gear_b", "no_squish", "dlm", "richardson"][..],
        ),
        (
            "kind = \"langevin\"\ntemperature = 1e30\nfriction = 1.0\nseed = 3",
            &["no_squish", "dlm"],
        ),
        (
            "kind = \"bussi\"\ntemperature = 1e30\ntau = 0.1\nseed = 3",
            &["no_squish", "dlm"],
        ),
        (
            "kind = \"nose_hoover\"\ntemperature = 1e30\ntau = 0.1",
            &["no_squish", "dlm", "gear_a"],
        ),
    ];
    let quantities = ["kinetic_energy", "potential_energy"];
    let potential = potential();
    for (thermostat, integrators) in thermostats {
        for integrator in integrators {
            let mut text = scene_text(&format!("kind = \"{integrator}\""), &quantities)
                .replace("temperature = 1.0", "temperature = 1e20")
                .replace("dt = 0.01", "dt = 1e-12");
            if !thermostat.is_empty() {
                text += &format!("[thermostat]\n{thermostat}\n");
            }
            let (_, scene) = load_text(&text, &Overrides::default())
                .unwrap_or_else(|e| panic!("{integrator} {thermostat}: {e}"));
            let result = execute(
                &scene,
                serde_json::Value::Null,
                &common::in_memory(),
                None,
                None,
            )
            .expect("runs");
            let frames = result.trajectory.as_ref().expect("trajectory kept");
            let table = &result.series[0];
            let n = SITES.len();
            for (k, row) in table.values.chunks(table.columns.len()).enumerate() {
                let orientations: Vec<Quat> = frames.orientations[4 * n * k..4 * n * (k + 1)]
                    .chunks(4)
                    .map(|c| Quat::new(c[0], c[1], c[2], c[3]))
                    .collect();
                let v = potential.energy(&orientations);
                assert!(row[2] > 1e19, "{integrator} {thermostat}: K = {}", row[2]);
                assert!(
                    (row[3] - v).abs() <= ROUND_OFF * v.abs().max(1.0),
                    "{integrator} {thermostat}, step {k}: recorded V = {:e}, V = {v:e}",
                    row[3]
                );
            }
        }
    }
}
