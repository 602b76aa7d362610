//! Issue 40's charge benchmark (`cargo bench --bench pme_charges`, part of
//! `make bench`; `python -m validation.bench.charges` adds OpenMM's CPU PME
//! side by side and writes the results): quatrot's smooth PME of a
//! water-like configuration of 3 x 4,000 point charges, one thread.
//!
//! The configuration (nm, e, reduced units `4 pi eps0 = 1`): rigid
//! molecules of SPC/E geometry and charges (O-H 0.1 nm, H-O-H 109.47
//! degrees, -0.8476 e and 2 x 0.4238 e) centred on 16^3 simple-cubic cells
//! of which 4,000 are kept at random, each centre displaced by up to a tenth
//! of the spacing per axis, random orientations; the box holds liquid
//! water's 33.4 molecules per nm^3. Every pair of sites interacts (no
//! exclusions), as in OpenMM's `NonbondedForce` without exceptions.
//!
//! For each requested accuracy: the parameters `mesh_ewald::for_multipoles`
//! chooses (what a scene of charged bodies runs with; at 1e-4 also at
//! forced splittings, to check the cost model's choice), the set-up, the
//! median and best of repeated evaluations (energy, potentials, fields and
//! forces of every site, as OpenMM's: no field gradient; repeats fill ~`SECONDS_PER_CASE`), in wall and in
//! process CPU time, and the RMS
//! force error against the sum at accuracy 1e-9. Writes the configuration,
//! the reference forces and the cases to `<QUATROT_BENCH_RAW or
//! target/bench/raw>/pme_charges.json`; `QUATROT_BENCH_QUICK=1` takes 3 x
//! 500 sites.

#[path = "shared/harness.rs"]
mod harness;

use nalgebra::Vector3;
use quatrot::potential::multipole::mesh_ewald::{
    for_multipoles, Carried, MeshEwald, SiteResponse, Sources,
};
use quatrot::potential::Surface;
use quatrot::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use serde_json::{json, Value};
use std::time::Instant;

/// Wall time spent on each timed case (its repeats, at least `MIN_REPEATS`).
const SECONDS_PER_CASE: f64 = 3.0;
const MIN_REPEATS: usize = 3;
/// Liquid water's molecules per nm^3.
const WATER_DENSITY: f64 = 33.4;
/// SPC/E charges of O, H, H (e).
const CHARGES: [f64; 3] = [-0.8476, 0.4238, 0.4238];
/// The accuracy of the reference sum: its measured error is about a
/// twentieth of the request, 500 times below the finest case compared.
const CONVERGED: f64 = 1e-9;

/// Sites, charges and the cubic box edge of `molecules` water-like
/// molecules on `cells^3` cells (module doc).
fn water(cells: usize, molecules: usize, seed: u64) -> (Vec<Vector3<f64>>, Vec<f64>, f64) {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let edge = (molecules as f64 / WATER_DENSITY).cbrt();
    let spacing = edge / cells as f64;
    let mut chosen: Vec<usize> = (0..cells.pow(3)).collect();
    while chosen.len() > molecules {
        let k = rng.random_range(0..chosen.len());
        chosen.swap_remove(k);
    }
    chosen.sort_unstable();
    let half = 109.47f64.to_radians() / 2.0;
    let body = [
        Vector3::zeros(),
        Vector3::new(0.1 * half.sin(), 0.0, 0.1 * half.cos()),
        Vector3::new(-0.1 * half.sin(), 0.0, 0.1 * half.cos()),
    ];
    let mut sites = Vec::with_capacity(3 * molecules);
    for k in chosen {
        let cell = Vector3::new(k % cells, (k / cells) % cells, k / (cells * cells));
        let centre =
            Vector3::from_fn(|a, _| (cell[a] as f64 + 0.5 + rng.random_range(-0.1..0.1)) * spacing);
        let v: [f64; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let q = Quat(v.map(|x| x / norm));
        sites.extend(body.iter().map(|b| centre + q.body_to_space(b)));
    }
    let charges = CHARGES.repeat(molecules);
    (sites, charges, edge)
}

/// The sum at `accuracy` (at splitting `alpha` when given, else the cost
/// model's choice) for the configuration: the mesh and its parameters.
fn mesh(accuracy: f64, alpha: Option<f64>, sites: usize, edge: f64) -> (MeshEwald, Value) {
    let carried = Carried {
        charges: true,
        ..Carried::default()
    };
    let box_lengths = Vector3::repeat(edge);
    let (p, estimate) =
        for_multipoles(accuracy, carried, sites, &box_lengths, None, alpha).expect("parameters");
    let mesh = MeshEwald::new(sites, box_lengths, p, Surface::Conducting)
        .expect("mesh")
        .without_field_gradient();
    let parameters = json!({
        "alpha": p.alpha, "real_cutoff": p.real_cutoff, "grid": p.grid, "order": p.order,
        "estimate_real": estimate.real, "estimate_mesh": estimate.mesh,
    });
    (mesh, parameters)
}

fn rms(v: &[Vector3<f64>]) -> f64 {
    (v.iter().map(|x| x.norm_squared()).sum::<f64>() / v.len() as f64).sqrt()
}

fn main() {
    let quick = harness::quick();
    let (cells, molecules) = if quick { (8, 500) } else { (16, 4000) };
    let started = Instant::now();
    let out = harness::one_thread(|| {
        let (sites, charges, edge) = water(cells, molecules, 40);
        let n = sites.len();
        let sources = Sources {
            positions: &sites,
            charges: Some(&charges),
            dipoles: None,
            quadrupoles: None,
        };
        let (mut reference_sum, reference_parameters) = mesh(CONVERGED, None, n, edge);
        let mut reference = SiteResponse::zeros(n);
        reference_sum
            .evaluate(&sources, &mut reference)
            .expect("reference");
        eprintln!("reference {reference_parameters}");
        let scale = rms(&reference.force);
        let accuracies: &[f64] = if quick {
            &[1e-4]
        } else {
            &[3e-3, 1e-3, 5e-4, 2e-4, 1e-4, 1e-5, 1e-6]
        };
        // The cost model's choice, then (at 1e-4) forced splittings: a
        // longer cutoff and a coarser mesh than it takes.
        let forced: &[f64] = if quick { &[] } else { &[3.0, 5.0] };
        let runs = accuracies
            .iter()
            .map(|&a| (a, None))
            .chain(forced.iter().map(|&alpha| (1e-4, Some(alpha))));
        let mut cases = Vec::new();
        for (accuracy, alpha) in runs {
            let start = Instant::now();
            let (mut sum, parameters) = mesh(accuracy, alpha, n, edge);
            let setup = start.elapsed().as_secs_f64();
            let mut response = SiteResponse::zeros(n);
            let (mut times, mut cpu_times) = (Vec::new(), Vec::new());
            let budget = Instant::now();
            while times.len() < MIN_REPEATS
                || (budget.elapsed().as_secs_f64() < SECONDS_PER_CASE && times.len() < 2000)
            {
                let (t, cpu) = (Instant::now(), harness::cpu_seconds());
                sum.evaluate(&sources, &mut response).expect("evaluation");
                times.push(t.elapsed().as_secs_f64());
                cpu_times.push(harness::cpu_seconds() - cpu);
            }
            times.sort_by(f64::total_cmp);
            cpu_times.sort_by(f64::total_cmp);
            let errors: Vec<Vector3<f64>> = response
                .force
                .iter()
                .zip(&reference.force)
                .map(|(a, b)| a - b)
                .collect();
            let case = json!({
                "accuracy": accuracy,
                "forced_alpha": alpha,
                "parameters": parameters,
                "setup_seconds": setup,
                "median_seconds": times[times.len() / 2],
                "best_seconds": times[0],
                "median_cpu_seconds": cpu_times[cpu_times.len() / 2],
                "best_cpu_seconds": cpu_times[0],
                "repeats": times.len(),
                "rms_force_error": rms(&errors),
                "relative_force_error": rms(&errors) / scale,
                "energy_error": (response.energy - reference.energy).abs(),
            });
            eprintln!("{case}");
            cases.push(case);
        }
        let flat =
            |v: &[Vector3<f64>]| -> Vec<[f64; 3]> { v.iter().map(|x| (*x).into()).collect() };
        json!({
            "quick": quick,
            "quatrot": env!("CARGO_PKG_VERSION"),
            "molecules": molecules,
            "box_edge": edge,
            "sites": flat(&sites),
            "charges": charges,
            "reference": {
                "accuracy": CONVERGED,
                "parameters": reference_parameters,
                "energy": reference.energy,
                "forces": flat(&reference.force),
            },
            "cases": cases,
        })
    });
    harness::write("pme_charges.json", out, started);
}
