//! The measurements behind the mesh Ewald sum's cost model
//! (`mesh_ewald::estimate`'s `MeshCosts` of each kind of site and
//! `MESH_POINT_SECONDS`): evaluation times of forced parameters
//! fitted by least squares to
//!
//! `t = t_pair * N n (2 pi / 3) r_c^3 + t_mesh * M log2 M + t_spline * N p^3 + t_site * N`
//!
//! (the model's real-space pairs, `M` mesh points, `p` the spline order;
//! `t_site` the per-site work no parameter changes, which the choice does
//! not weigh), for each kind of site: 12,000 random charges at the charge
//! bench's density (one third -0.8476, two thirds 0.4238; 100.2 per unit
//! volume, as `benches/pme_charges.rs`'s water, forces without the field
//! gradient), 4,096 random unit dipoles at density 0.8 (forces and
//! torques) and as many linear unit quadrupoles (the general kernel). Each kind's cases vary one of `r_c`, the mesh and the order at
//! a time around a base case; each time is the median process CPU time of
//! repeated evaluations on one thread. Prints every case, the fitted
//! seconds and the model's (`Carried::costs`), and writes them to `<QUATROT_BENCH_RAW or target/bench/raw>/pme_costs.json`.
//! A measurement, not a test: state the machine and its load with the
//! numbers. `QUATROT_BENCH_QUICK=1` takes a tenth of the sites.
//!
//! `cargo run --release --example pme_costs`

#[path = "../benches/shared/harness.rs"]
mod harness;
#[path = "shared/least_squares.rs"]
mod least_squares;

use nalgebra::{Matrix3, Vector3};
use quatrot::potential::multipole::mesh_ewald::{
    Carried, MeshEwald, MeshParameters, SiteResponse, Sources,
};
use quatrot::potential::Surface;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::time::Instant;

/// Evaluations per case (the median is fitted).
const REPEATS: usize = 5;

/// What the sites of a kind carry.
#[derive(Clone, Copy, PartialEq)]
enum Carries {
    Charges,
    Dipoles,
    Quadrupoles,
}

/// One kind of site: its name, site count, density, and the base case's
/// cutoff, mesh points per axis and the cutoffs and meshes tried around it.
struct Kind {
    name: &'static str,
    sites: usize,
    density: f64,
    carries: Carries,
    cutoffs: [f64; 5],
    meshes: [usize; 5],
}

const KINDS: [Kind; 3] = [
    Kind {
        name: "charges",
        sites: 12_000,
        density: 100.2,
        carries: Carries::Charges,
        cutoffs: [0.35, 0.45, 0.6, 0.8, 1.0],
        meshes: [40, 64, 100, 144, 200],
    },
    Kind {
        name: "dipoles",
        sites: 4_096,
        density: 0.8,
        carries: Carries::Dipoles,
        cutoffs: [1.5, 2.0, 2.5, 3.0, 3.6],
        meshes: [16, 24, 48, 96, 160],
    },
    Kind {
        name: "quadrupoles",
        sites: 4_096,
        density: 0.8,
        carries: Carries::Quadrupoles,
        cutoffs: [1.5, 2.0, 2.5, 3.0, 3.6],
        meshes: [16, 24, 32, 40, 48],
    },
];

/// The spline order of the cases that vary the cutoff or the mesh.
const BASE_ORDER: usize = 6;

/// The median process CPU seconds of an evaluation with `parameters`.
fn time(kind: &Kind, sources: &Sources, edge: f64, parameters: MeshParameters) -> f64 {
    let n = sources.len();
    let mesh = MeshEwald::new(n, Vector3::repeat(edge), parameters, Surface::Conducting)
        .expect("forced parameters");
    let mut mesh = if kind.carries == Carries::Charges {
        mesh.without_field_gradient()
    } else {
        mesh
    };
    let mut response = SiteResponse::zeros(n);
    mesh.evaluate(sources, &mut response).expect("evaluation");
    let mut times: Vec<f64> = (0..REPEATS)
        .map(|_| {
            let cpu = harness::cpu_seconds();
            mesh.evaluate(sources, &mut response).expect("evaluation");
            harness::cpu_seconds() - cpu
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[REPEATS / 2]
}

/// The cases and fit of one kind.
fn measure(kind: &Kind, quick: bool) -> Value {
    let n = if quick { kind.sites / 10 } else { kind.sites };
    let edge = (n as f64 / kind.density).cbrt();
    let mut rng = ChaCha20Rng::seed_from_u64(7);
    let positions: Vec<Vector3<f64>> = (0..n)
        .map(|_| Vector3::from_fn(|_, _| rng.random_range(0.0..edge)))
        .collect();
    let charges: Vec<f64> = (0..n)
        .map(|i| if i % 3 == 0 { -0.8476 } else { 0.4238 })
        .collect();
    let dipoles: Vec<Vector3<f64>> = (0..n)
        .map(|_| Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize())
        .collect();
    // Linear quadrupoles (3 u u^T - 1) / 2 along the dipoles' directions.
    let quadrupoles: Vec<Matrix3<f64>> = dipoles
        .iter()
        .map(|u| 1.5 * u * u.transpose() - 0.5 * Matrix3::identity())
        .collect();
    let sources = Sources {
        positions: &positions,
        charges: (kind.carries == Carries::Charges).then_some(&charges[..]),
        dipoles: (kind.carries == Carries::Dipoles).then_some(&dipoles[..]),
        quadrupoles: (kind.carries == Carries::Quadrupoles).then_some(&quadrupoles[..]),
    };
    let scale = if quick { 10f64.cbrt().recip() } else { 1.0 };
    let meshes = kind.meshes.map(|k| ((k as f64 * scale) as usize).max(8));
    let cutoffs = kind.cutoffs.map(|rc| rc.min(0.5 * edge));
    let (rc0, k0) = (cutoffs[1], meshes[1]);
    let mut cases: Vec<(f64, usize, usize)> = Vec::new();
    cases.extend(cutoffs.iter().map(|&rc| (rc, k0, BASE_ORDER)));
    cases.extend(meshes.iter().map(|&k| (rc0, k, BASE_ORDER)));
    cases.extend((4..=8).map(|p| (rc0, k0, p)));
    let mut rows = Vec::new();
    let mut design = Vec::new();
    let mut seconds = Vec::new();
    for &(rc, k, p) in &cases {
        let parameters = MeshParameters {
            alpha: 3.0 / rc,
            real_cutoff: rc,
            grid: [k; 3],
            order: p,
        };
        let t = time(kind, &sources, edge, parameters);
        let pairs = n as f64 * kind.density * (2.0 * PI / 3.0) * rc.powi(3);
        let points = (k as f64).powi(3);
        let row = [
            pairs,
            points * points.log2(),
            n as f64 * (p as f64).powi(3),
            n as f64,
        ];
        println!(
            "{} r_c {rc:.3} mesh {k}^3 order {p}: {:.2} ms CPU",
            kind.name,
            t * 1e3
        );
        rows.push(json!({"real_cutoff": rc, "mesh": k, "order": p, "cpu_seconds": t}));
        design.extend(row);
        seconds.push(t);
    }
    let (fit, residual) = least_squares::fit(&design, 4, &seconds);
    let names = ["pair", "mesh_point_log2", "spline_point", "site"];
    let costs = Carried {
        charges: kind.carries == Carries::Charges,
        dipoles: kind.carries == Carries::Dipoles,
        quadrupoles: kind.carries == Carries::Quadrupoles,
    }
    .costs();
    let model = [costs.pair, f64::NAN, costs.spline_point, costs.site];
    for ((name, s), m) in names.iter().zip(fit.iter()).zip(model) {
        println!(
            "{} {name}: {:.4} ns (the model's {:.4} ns)",
            kind.name,
            s * 1e9,
            m * 1e9
        );
    }
    println!("{} relative residual of the fit: {residual:.3}", kind.name);
    json!({
        "kind": kind.name,
        "sites": n,
        "density": kind.density,
        "cases": rows,
        "seconds": names.iter().zip(fit.iter()).map(|(k, v)| (k.to_string(), json!(v))).collect::<serde_json::Map<_, _>>(),
        "relative_residual": residual,
    })
}

fn main() {
    let quick = harness::quick();
    let started = Instant::now();
    let out = harness::one_thread(|| {
        let kinds: Vec<Value> = KINDS.iter().map(|k| measure(k, quick)).collect();
        json!({"quick": quick, "kinds": kinds})
    });
    harness::write("pme_costs.json", out, started);
}
