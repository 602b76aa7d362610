//! Helpers shared by the integration tests: seeded random inputs, the
//! double-cover-aware distance, the ASE/scipy fixture of
//! `fixtures/conventions.json` (written by `validation/fixtures/gen_conventions.py`),
//! scenes read and run as the command line does, and the small two-rotor
//! scene of the run, restart and thermostat tests.
#![allow(dead_code)] // each test crate uses a different subset

use nalgebra::{Matrix3, Vector3};
use quatrot::run::Outputs;
use quatrot::scene::raw::RawScene;
use quatrot::scene::{parse_toml, validate, Overrides, Scene};
use quatrot::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::Deserialize;
use std::path::Path;

/// A reproducible generator for test inputs.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A quaternion with independent standard-normal components (not unit).
pub fn random_quat(rng: &mut ChaCha8Rng) -> Quat {
    Quat(std::array::from_fn(|_| rng.sample(StandardNormal)))
}

/// An isotropically distributed unit quaternion.
pub fn random_unit_quat(rng: &mut ChaCha8Rng) -> Quat {
    let q = random_quat(rng);
    q * (1.0 / q.norm())
}

/// A vector with standard-normal components.
pub fn random_vector(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.sample(StandardNormal))
}

/// A uniform sample in `[lo, hi)`.
pub fn uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo..hi)
}

/// Euler angles `(phi, theta, psi)` uniform over the y-convention ranges.
pub fn random_euler(rng: &mut ChaCha8Rng) -> (f64, f64, f64) {
    let pi = std::f64::consts::PI;
    (
        rng.random_range(-pi..pi),
        rng.random_range(0.0..pi),
        rng.random_range(-pi..pi),
    )
}

/// Largest component difference of two quaternions.
pub fn max_diff(a: &Quat, b: &Quat) -> f64 {
    (*a - *b).0.iter().fold(0.0, |m, x| f64::max(m, x.abs()))
}

/// Distance between the rotations of two unit quaternions, blind to the sign
/// (double cover): `min(|a - b|, |a + b|)` componentwise.
pub fn rotation_diff(a: &Quat, b: &Quat) -> f64 {
    max_diff(a, b).min(max_diff(a, &-*b))
}

/// Largest entry of `|a - b|`.
pub fn mat_diff(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    (a - b).amax()
}

/// Difference of two angles modulo `2 pi`, in `[0, pi]`.
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let d = (a - b).rem_euclid(tau);
    d.min(tau - d)
}

/// `fixtures/conventions.json` (see its `fields` entry for each meaning).
#[derive(Deserialize)]
pub struct ConventionsFixture {
    pub seed: u64,
    pub versions: std::collections::BTreeMap<String, String>,
    pub template: Template,
    pub quaternions: Vec<QuaternionRecord>,
    pub euler: Vec<EulerRecord>,
}

/// The rigid NH3 template of ASE, and the fixed point of the ASE rotations.
#[derive(Deserialize)]
pub struct Template {
    pub positions: Vec<[f64; 3]>,
    pub center: [f64; 3],
}

/// One random unit quaternion with what scipy and ASE make of it.
#[derive(Deserialize)]
pub struct QuaternionRecord {
    pub q: [f64; 4],
    pub v: [f64; 3],
    #[serde(rename = "scipy_R")]
    pub scipy_r: [[f64; 3]; 3],
    #[serde(rename = "scipy_A")]
    pub scipy_a: [[f64; 3]; 3],
    #[serde(rename = "ase_R")]
    pub ase_r: [[f64; 3]; 3],
    #[serde(rename = "scipy_R_v")]
    pub scipy_r_v: [f64; 3],
    #[serde(rename = "scipy_A_v")]
    pub scipy_a_v: [f64; 3],
    pub ase_rotate_v: [f64; 3],
    pub scipy_rotvec: [f64; 3],
    pub atoms_rotate: Vec<[f64; 3]>,
    pub product_next_scipy: [f64; 4],
    pub product_next_ase: [f64; 4],
}

/// One y-convention Euler triple with what scipy and ASE make of it.
#[derive(Deserialize)]
pub struct EulerRecord {
    pub angles_y: [f64; 3],
    pub kind: String,
    pub scipy_q: [f64; 4],
    #[serde(rename = "scipy_R")]
    pub scipy_r: [[f64; 3]; 3],
    #[serde(rename = "scipy_A")]
    pub scipy_a: [[f64; 3]; 3],
    pub ase_q: [f64; 4],
    pub ase_euler_zyz: [f64; 3],
    #[serde(rename = "scipy_euler_ZYZ")]
    pub scipy_euler_zyz: [f64; 3],
    pub ase_euler_rotate_deg: [f64; 3],
    pub atoms_euler_rotate: Vec<[f64; 3]>,
}

/// Reads `fixtures/conventions.json` from the crate root.
pub fn conventions_fixture() -> ConventionsFixture {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/conventions.json");
    let text = std::fs::read_to_string(path).expect("fixtures/conventions.json (make fixtures)");
    serde_json::from_str(&text).expect("fixtures/conventions.json parses")
}

/// A row-major 3x3 array as a matrix.
pub fn mat(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// A 3-array as a vector.
pub fn vec3(v: &[f64; 3]) -> Vector3<f64> {
    Vector3::from(*v)
}

/// The scene of TOML `text` with `overrides` applied (as the command line's
/// `--steps`, `--dt`, `--integrator`), and its raw form.
pub fn scene_with(text: &str, overrides: &Overrides) -> (RawScene, Scene) {
    let mut raw = parse_toml(text).expect("valid");
    overrides.apply(&mut raw).expect("overrides");
    let scene = validate(&raw).expect("valid");
    (raw, scene)
}

/// The built-in scene `name`'s TOML without its `[thermostat]` table: the
/// scene at constant energy, which every integrator runs (the o-terphenyl
/// built-in holds a Bussi thermostat, which richardson and the Gear schemes
/// refuse for bodies). The rest of the text is kept as it is.
pub fn builtin_at_constant_energy(name: &str) -> String {
    let text = quatrot::scene::builtin(name).expect("a built-in").toml;
    match text.find("\n[thermostat]\n") {
        Some(at) => {
            let rest = &text[at + 1..];
            let end = rest[1..].find("\n[").map_or(rest.len(), |k| k + 2);
            format!("{}{}", &text[..at + 1], &rest[end..])
        }
        None => text.to_string(),
    }
}

/// Overrides of the run length only.
pub fn steps(steps: i64) -> Overrides {
    Overrides {
        steps: Some(steps),
        ..Overrides::default()
    }
}

/// Outputs written to `dir` (`None`: no files), the series and trajectory
/// kept in memory when `keep`; no stop control.
pub fn outputs(dir: Option<&Path>, keep: bool) -> Outputs {
    Outputs {
        dir: dir.map(Path::to_path_buf),
        keep,
        control: None,
        threads: None,
    }
}

/// Outputs kept in memory only (no files).
pub fn in_memory() -> Outputs {
    outputs(None, true)
}

/// The small scene of the run, restart and thermostat tests: two interacting
/// asymmetric tops (inertia 0.1, 0.2, 0.3) carrying unit dipoles along body
/// z, 1.5 apart with no boundary, random orientations and angular velocities
/// at T = 1 from seed 7, run by `integrator` (a kind, its default options) for
/// `steps` steps of `dt`. `tables` (TOML tables such as `[thermostat]` or
/// `[record]`) follow `[run]`.
pub fn two_rotors(integrator: &str, dt: f64, steps: i64, tables: &str) -> String {
    format!(
        r#"version = 1
[rotors]
kind = "sites"
sites = [{{ position = [0.0, 0.0, 0.0] }}, {{ position = [1.5, 0.0, 0.0] }}]
default = {{ inertia = [0.1, 0.2, 0.3], dipole = [0.0, 0.0, 1.0] }}
[interactions]
boundary = {{ kind = "open" }}
[initial]
kind = "random"
seed = 7
temperature = 1.0
[integrator]
kind = "{integrator}"
[run]
dt = {dt:?}
steps = {steps}
{tables}"#
    )
}

/// The `[record]` of the restart tests: a checkpoint every 20 steps, the
/// series `e` of `quantities` every 4 steps and a trajectory frame every 10.
pub fn restart_record(quantities: &[&str]) -> String {
    let quantities: Vec<String> = quantities.iter().map(|q| format!("{q:?}")).collect();
    format!(
        "[record]\ncheckpoint_every = 20\n[[record.series]]\nname = \"e\"\nevery = 4\nquantities = [{}]\n[record.trajectory]\nevery = 10\n",
        quantities.join(", ")
    )
}
