//! The measurements behind the moving bodies' choice between the direct
//! Ewald sum and PME (`bodies::direct_costs`): single-thread evaluation times of bodies'
//! sums, each path forced, fitted for the direct sum by least squares to
//!
//! `t = t_pair P + t_wave N W + t_site N`
//!
//! (`P = N n (2 pi / 3) r_c^3` the model's real-space pairs, `W = V k_c^3 /
//! (12 pi^2)` its wave vectors, both from the parameters the sum chose),
//! and for PME compared with the mesh model's seconds
//! (`mesh_ewald::mesh_cost`, the real-space pairs of dipoles and
//! quadrupoles at the direct sum's pair cost, as the bodies' sum has it). Bodies: one site
//! each, no Lennard-Jones (the electrostatics alone), on a jittered cubic
//! grid at density 0.75 with random orientations, 64 to 2,744 of them at
//! accuracies 1e-4 to 1e-6; three kinds: alternating charges +-1, unit
//! dipoles, and dipoles with a point quadrupole. Each time is the median
//! process CPU time of repeated evaluations (the neighbour list built
//! before). Prints every case and the fits, and writes them to
//! `<QUATROT_BENCH_RAW or target/bench/raw>/body_ewald_costs.json`. A
//! measurement, not a test: state the machine and its load with the
//! numbers. `QUATROT_BENCH_QUICK=1` takes the smallest sizes only.
//!
//! `cargo run --release --example body_ewald_costs`

#[path = "../benches/shared/harness.rs"]
mod harness;
#[path = "shared/least_squares.rs"]
mod least_squares;

use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    direct_costs, Body, BodySystem, BodyType, BodyTypeSpec, ElectrostaticsOptions, Evaluation,
    EwaldOptions, InteractionOptions, Site, Space,
};
use quatrot::potential::multipole::mesh_ewald::{mesh_cost, Carried, ForcedMesh, MeshCosts};
use quatrot::potential::multipole::{SumMethod, Surface};
use quatrot::quaternion::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::time::Instant;

/// Evaluations per case (the median is taken).
const REPEATS: usize = 5;
/// Bodies per unit volume.
const DENSITY: f64 = 0.75;
/// Bodies per case (cubes).
const SIZES: [usize; 5] = [64, 216, 512, 1000, 2744];
/// Requested accuracies.
const ACCURACIES: [f64; 3] = [1e-4, 1e-5, 1e-6];

/// The site types of a kind: charges alternate between two types.
fn kind_types(kind: &str) -> Vec<BodyType> {
    let site = |charge: Option<f64>, quadrupole: bool| Site {
        charge: charge.unwrap_or(0.0),
        dipole: (charge.is_none()).then(|| Vector3::new(0.0, 0.0, 1.0)),
        quadrupole: quadrupole.then(|| Matrix3::new(0.5, 0.2, 0.0, 0.2, -0.2, 0.1, 0.0, 0.1, -0.3)),
        ..Site::default()
    };
    let sites = match kind {
        "charges" => vec![site(Some(1.0), false), site(Some(-1.0), false)],
        "dipoles" => vec![site(None, false)],
        _ => vec![site(None, true)],
    };
    sites
        .into_iter()
        .map(|s| {
            BodyType::new(&BodyTypeSpec {
                sites: vec![s],
                mass: Some(1.0),
                inertia: Some(Matrix3::identity() * 0.1),
            })
            .expect("a valid body type")
        })
        .collect()
}

/// What the sites of a kind carry.
fn carried(kind: &str) -> Carried {
    Carried {
        charges: kind == "charges",
        dipoles: kind != "charges",
        quadrupoles: kind == "quadrupoles",
    }
}

/// `n` bodies of `types` types on a jittered cubic grid of spacing `spacing`.
fn grid_bodies(n: usize, spacing: f64, types: usize) -> Vec<Body> {
    let mut rng = ChaCha20Rng::seed_from_u64(11);
    let side = (n as f64).cbrt().round() as usize;
    (0..n)
        .map(|i| {
            let grid = Vector3::new(i % side, (i / side) % side, i / (side * side));
            let jitter = Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2));
            let q = Quat::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            Body {
                kind: i % types,
                position: (grid.map(|x| x as f64 + 0.5) + jitter) * spacing,
                image: [0; 3],
                velocity: Vector3::zeros(),
                orientation: q.try_normalize().expect("a nonzero quaternion"),
                angular_momentum_body: Vector3::zeros(),
            }
        })
        .collect()
}

/// One case: the median CPU seconds of an evaluation and its model's counts.
fn case(kind: &str, n: usize, accuracy: f64, method: SumMethod) -> Value {
    let types = kind_types(kind);
    let spacing = DENSITY.recip().cbrt();
    let edge = spacing * (n as f64).cbrt().round();
    let interactions = InteractionOptions {
        lennard_jones: None,
        electrostatics: Some(ElectrostaticsOptions::Ewald(EwaldOptions {
            accuracy,
            method,
            surface: Surface::Conducting,
            forced: ForcedMesh::default(),
        })),
        skin: 0.3,
    };
    let box_lengths = Vector3::repeat(edge);
    let mut system = BodySystem::new(
        types.clone(),
        grid_bodies(n, spacing, types.len()),
        Space::Periodic(box_lengths),
        &interactions,
    )
    .expect("a valid system");
    let mut out = Evaluation::default();
    system.evaluate(&mut out);
    let mut times: Vec<f64> = (0..REPEATS)
        .map(|_| {
            let cpu = harness::cpu_seconds();
            system.evaluate(&mut out);
            harness::cpu_seconds() - cpu
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let seconds = times[REPEATS / 2];
    let sum = system.electrostatic_sum().expect("an Ewald sum");
    let volume = box_lengths.product();
    let (n_f, density) = (n as f64, n as f64 / volume);
    let mut row = json!({"kind": kind, "bodies": n, "accuracy": accuracy, "cpu_seconds": seconds});
    if let Some(p) = sum.ewald_parameters() {
        let pairs = n_f * density * (2.0 * PI / 3.0) * p.real_cutoff.powi(3);
        let waves = volume * p.reciprocal_cutoff.powi(3) / (12.0 * PI * PI);
        row["method"] = json!("direct");
        row["real_cutoff"] = json!(p.real_cutoff);
        row["pairs"] = json!(pairs);
        row["site_waves"] = json!(n_f * waves);
    } else {
        let (p, _) = sum.mesh_parameters().expect("a mesh");
        let carried = carried(kind);
        let costs = if kind == "charges" {
            carried.costs()
        } else {
            MeshCosts {
                pair: direct_costs(carried).0,
                ..carried.costs()
            }
        };
        row["method"] = json!("pme");
        row["real_cutoff"] = json!(p.real_cutoff);
        row["mesh"] = json!(p.grid[0]);
        row["order"] = json!(p.order);
        row["model_seconds"] = json!(mesh_cost(&p, n, &box_lengths, costs));
    }
    println!("{row}");
    row
}

/// The least-squares fit of the direct cases of `kind` (module doc).
fn fit_direct(kind: &str, rows: &[Value]) -> Value {
    let direct: Vec<&Value> = rows
        .iter()
        .filter(|r| r["kind"] == kind && r["method"] == "direct")
        .collect();
    let design: Vec<f64> = direct
        .iter()
        .flat_map(|r| {
            [
                r["pairs"].as_f64().unwrap(),
                r["site_waves"].as_f64().unwrap(),
                r["bodies"].as_f64().unwrap(),
            ]
        })
        .collect();
    let seconds: Vec<f64> = direct
        .iter()
        .map(|r| r["cpu_seconds"].as_f64().unwrap())
        .collect();
    let (fit, residual) = least_squares::fit(&design, 3, &seconds);
    let (pair, wave) = direct_costs(carried(kind));
    println!(
        "{kind} direct: {:.1} ns per pair (the model's {:.1}), {:.2} ns per site wave ({:.2}), \
         {:.0} ns per site; residual {residual:.3}",
        fit[0] * 1e9,
        pair * 1e9,
        fit[1] * 1e9,
        wave * 1e9,
        fit[2] * 1e9,
    );
    json!({"kind": kind, "pair_seconds": fit[0], "wave_seconds": fit[1], "site_seconds": fit[2],
           "relative_residual": residual})
}

fn main() {
    let quick = harness::quick();
    let started = Instant::now();
    let sizes = if quick { &SIZES[..2] } else { &SIZES[..] };
    let out = harness::one_thread(|| {
        let kinds = ["charges", "dipoles", "quadrupoles"];
        let mut rows = Vec::new();
        for kind in kinds {
            for &n in sizes {
                for &accuracy in &ACCURACIES {
                    for method in [SumMethod::Direct, SumMethod::Pme] {
                        rows.push(case(kind, n, accuracy, method));
                    }
                }
            }
        }
        let fits: Vec<Value> = kinds.iter().map(|k| fit_direct(k, &rows)).collect();
        json!({"quick": quick, "cases": rows, "direct_fits": fits})
    });
    harness::write("body_ewald_costs.json", out, started);
}
