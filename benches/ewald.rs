//! The periodic sums' cost (`cargo bench --bench ewald`, part of `make bench`;
//! `python -m validation.bench.ewald` adds LAMMPS side by side and writes the
//! results): one energy + eq 14 gradient evaluation, one thread, of
//!
//! * the built-in 1000-dipole simple-cubic lattice (10^3, spacing 1, |mu| = 1):
//!   the truncated pair sum at cutoff 3.1 (today's kernel), the FFT lattice
//!   sum of the same truncated tensor, the FFT lattice Ewald sum at
//!   accuracies 1e-6 and 1e-12, the direct Ewald sum at 1e-6 and 1e-12;
//! * the FFT lattice Ewald sum (1e-12) from 10^3 to 100^3 rotors (and its
//!   one-off set-up);
//! * the direct Ewald sum (1e-6 and 1e-12, `method = "direct"`) of irregular sites (uniform random
//!   at unit density, seed 14) from 125 to 4000 rotors;
//! * issue 40's mesh Ewald (PME) against the direct Ewald sum at accuracy
//!   1e-5 on a dipolar fluid-like configuration (a simple-cubic lattice of
//!   unit spacing, each site displaced uniformly within +-0.25 per axis, so
//!   no two closer than 0.5: irregular, as a liquid, without overlaps) from
//!   1,000 to 1,000,000 dipoles (PME) and to 8,000 (direct: its crossover);
//!   and at about 10,000 dipoles (22^3 such sites less 648 at random, box
//!   22) at accuracies 1e-4 to 1e-6 for the side-by-side with LAMMPS
//!   `pppm/dipole`, which `validation.bench.ewald` measures on a
//!   configuration of the same kind; the crossover of the two sums at
//!   1e-4 and 1e-6 (512 to 4,096 dipoles), and of linear quadrupoles on
//!   the same sites at 1e-4 to 1e-6 (125 to 2,197), and the automatic
//!   choice's estimates of both (`method = "auto"`'s cost models) at 1e-4
//!   to 1e-6, for the crossover they give and their calibration.
//!
//! Each time is the median and the best of repeated single evaluations
//! (repeats fill ~`SECONDS_PER_CASE`), in wall and in process CPU time (on
//! a shared machine the wall time follows the other jobs). Writes `<QUATROT_BENCH_RAW or
//! target/bench/raw>/ewald.json`; `QUATROT_BENCH_QUICK=1` shrinks the sizes.

#[path = "shared/harness.rs"]
mod harness;

use nalgebra::{Matrix3, Vector3};
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::{
    Accuracy, Boundary, ExternalFields, MultipolePotential, PeriodicSum, Potential, SumMethod,
    Surface,
};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;
use serde_json::{json, Value};
use std::hint::black_box;
use std::time::Instant;

/// Wall time spent on each timed case (its repeats).
const SECONDS_PER_CASE: f64 = 1.5;

fn dipoles(sites: &[Vector3<f64>]) -> Vec<Rotor> {
    sites
        .iter()
        .map(|s| Rotor {
            site: *s,
            inertia: Inertia::Spherical(0.1),
            dipole_body: Some(Vector3::z()),
            quadrupole_body: None,
        })
        .collect()
}

/// What the irregular configurations' sites carry.
#[derive(Clone, Copy, PartialEq)]
enum Carries {
    /// A unit dipole along body z.
    Dipoles,
    /// A linear unit quadrupole along body z (diag(-1/2, -1/2, 1)).
    Quadrupoles,
}

impl Carries {
    fn rotors(self, sites: &[Vector3<f64>]) -> Vec<Rotor> {
        let mut rotors = dipoles(sites);
        if self == Carries::Quadrupoles {
            for r in &mut rotors {
                r.dipole_body = None;
                r.quadrupole_body = Some(Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0)));
            }
        }
        rotors
    }

    fn name(self) -> &'static str {
        match self {
            Carries::Dipoles => "dipoles",
            Carries::Quadrupoles => "quadrupoles",
        }
    }
}

fn orientations(n: usize, seed: u64) -> Vec<Quat> {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let v: [f64; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            Quat(v.map(|x| x / norm))
        })
        .collect()
}

/// The fluid-like dipolar configuration: `cells^3` jittered simple-cubic
/// sites of unit spacing, of which `keep` (all when `None`) are kept at
/// random; returns the sites and the cubic box edge.
fn jittered(cells: usize, keep: Option<usize>, seed: u64) -> (Vec<Vector3<f64>>, f64) {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut sites: Vec<Vector3<f64>> = (0..cells.pow(3))
        .map(|k| {
            let cell = Vector3::new(k % cells, (k / cells) % cells, k / (cells * cells));
            Vector3::from_fn(|a, _| cell[a] as f64 + 0.5 + rng.random_range(-0.25..0.25))
        })
        .collect();
    if let Some(keep) = keep {
        while sites.len() > keep {
            let k = rng.random_range(0..sites.len());
            sites.swap_remove(k);
        }
    }
    (sites, cells as f64)
}

/// One PME or direct-Ewald case on the jittered configuration of dipoles.
fn irregular_case(cells: usize, keep: Option<usize>, accuracy: f64, method: SumMethod) -> Value {
    carrying_case(Carries::Dipoles, (cells, keep), accuracy, method)
}

/// One PME or direct-Ewald case on the jittered configuration of sites
/// carrying `carries`.
fn carrying_case(
    carries: Carries,
    (cells, keep): (usize, Option<usize>),
    accuracy: f64,
    method: SumMethod,
) -> Value {
    let (sites, edge) = jittered(cells, keep, 40);
    let rotors = carries.rotors(&sites);
    let q = orientations(rotors.len(), 41);
    let mut case = time_case(&rotors, ewald(Vector3::repeat(edge), accuracy), method, &q);
    case["accuracy"] = json!(accuracy);
    case["carries"] = json!(carries.name());
    case["method"] = json!(if method == SumMethod::Pme {
        "pme"
    } else {
        "direct"
    });
    eprintln!("{case}");
    case
}

/// What `method = "auto"` estimates for the jittered configuration of
/// `cells^3` sites carrying `carries` at `accuracy` (its cost models in
/// seconds, the path it takes), for the crossover the models give.
fn auto_choice(carries: Carries, cells: usize, accuracy: f64) -> Value {
    let (sites, edge) = jittered(cells, None, 40);
    let p = MultipolePotential::with_method(
        &carries.rotors(&sites),
        ewald(Vector3::repeat(edge), accuracy),
        ExternalFields::NONE,
        SumMethod::Auto,
    )
    .expect("valid potential");
    let choice = p.auto_choice().expect("irregular sites: a choice");
    json!({
        "rotors": sites.len(),
        "accuracy": accuracy,
        "carries": carries.name(),
        "path": p.sum_path().as_str(),
        "direct_seconds": choice.direct_seconds,
        "pme_seconds": choice.pme_seconds,
    })
}

fn ewald(box_lengths: Vector3<f64>, accuracy: f64) -> Boundary {
    Boundary::Periodic {
        box_lengths,
        sum: PeriodicSum::Ewald {
            accuracy: Accuracy::new(accuracy).expect("in (0, 1)"),
            surface: Surface::Conducting,
        },
    }
}

/// Set-up seconds, then (median, best) seconds of one energy + gradient evaluation.
fn time_case(rotors: &[Rotor], boundary: Boundary, method: SumMethod, q: &[Quat]) -> Value {
    let start = Instant::now();
    let p = MultipolePotential::with_method(rotors, boundary, ExternalFields::NONE, method)
        .expect("valid potential");
    let setup = start.elapsed().as_secs_f64();
    let mut gradient = vec![Quat::ZERO; q.len()];
    let (mut times, mut cpu_times) = (Vec::new(), Vec::new());
    let budget = Instant::now();
    while times.len() < 5
        || (budget.elapsed().as_secs_f64() < SECONDS_PER_CASE && times.len() < 2000)
    {
        gradient.fill(Quat::ZERO);
        let (t, cpu) = (Instant::now(), harness::cpu_seconds());
        black_box(p.energy_and_gradient(black_box(q), &mut gradient));
        times.push(t.elapsed().as_secs_f64());
        cpu_times.push(harness::cpu_seconds() - cpu);
    }
    times.sort_by(f64::total_cmp);
    cpu_times.sort_by(f64::total_cmp);
    let parameters = match (p.ewald_parameters(), p.mesh_parameters()) {
        (Some(e), _) => Some(
            json!({"alpha": e.alpha, "real_cutoff": e.real_cutoff, "reciprocal_cutoff": e.reciprocal_cutoff}),
        ),
        (None, Some((m, estimate))) => Some(json!({
            "alpha": m.alpha, "real_cutoff": m.real_cutoff, "grid": m.grid, "order": m.order,
            "estimate_real": estimate.real, "estimate_mesh": estimate.mesh,
        })),
        (None, None) => None,
    };
    json!({
        "rotors": rotors.len(),
        "path": p.sum_path().as_str(),
        "setup_seconds": setup,
        "median_seconds": times[times.len() / 2],
        "best_seconds": times[0],
        "median_cpu_seconds": cpu_times[cpu_times.len() / 2],
        "best_cpu_seconds": cpu_times[0],
        "repeats": times.len(),
        "real_space_pairs": p.pair_count(),
        "parameters": parameters,
    })
}

fn main() {
    let quick = harness::quick();
    let started = Instant::now();
    let out = harness::one_thread(|| {
        let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 10, 1.0).expect("lattice");
        let rotors = dipoles(&lattice.sites);
        let q = orientations(rotors.len(), 1);
        let l = lattice.box_lengths;
        let cutoff = Boundary::periodic_cutoff(l, 3.1);
        let mut lattice_cases = Vec::new();
        for (name, boundary, method) in [
            (
                "truncated, cutoff 3.1, pair kernel",
                cutoff,
                SumMethod::Auto,
            ),
            ("truncated, cutoff 3.1, FFT", cutoff, SumMethod::LatticeFft),
            ("Ewald 1e-6, FFT", ewald(l, 1e-6), SumMethod::Auto),
            ("Ewald 1e-12, FFT", ewald(l, 1e-12), SumMethod::Auto),
            ("Ewald 1e-6, direct", ewald(l, 1e-6), SumMethod::Direct),
            ("Ewald 1e-12, direct", ewald(l, 1e-12), SumMethod::Direct),
        ] {
            let mut case = time_case(&rotors, boundary, method, &q);
            case["case"] = json!(name);
            eprintln!("{case}");
            lattice_cases.push(case);
        }
        let cells: &[usize] = if quick { &[10, 22] } else { &[10, 22, 46, 100] };
        let scaling: Vec<Value> = cells
            .iter()
            .map(|&c| {
                let lattice = Lattice::cubic(LatticeKind::SimpleCubic, c, 1.0).expect("lattice");
                let rotors = dipoles(&lattice.sites);
                let q = orientations(rotors.len(), 2);
                let case = time_case(
                    &rotors,
                    ewald(lattice.box_lengths, 1e-12),
                    SumMethod::Auto,
                    &q,
                );
                eprintln!("{case}");
                case
            })
            .collect();
        let sizes: &[usize] = if quick {
            &[125, 250]
        } else {
            &[125, 250, 500, 1000, 2000, 4000]
        };
        let mut direct = Vec::new();
        for &accuracy in &[1e-6, 1e-12] {
            for &n in sizes {
                let edge = (n as f64).cbrt();
                let mut rng = ChaCha20Rng::seed_from_u64(14);
                let sites: Vec<Vector3<f64>> = (0..n)
                    .map(|_| Vector3::from_fn(|_, _| rng.random_range(0.0..edge)))
                    .collect();
                let rotors = dipoles(&sites);
                let q = orientations(n, 3);
                let mut case = time_case(
                    &rotors,
                    ewald(Vector3::repeat(edge), accuracy),
                    SumMethod::Direct,
                    &q,
                );
                case["accuracy"] = json!(accuracy);
                eprintln!("{case}");
                direct.push(case);
            }
        }
        let cells: &[usize] = if quick {
            &[10, 20]
        } else {
            &[10, 20, 40, 80, 100]
        };
        let mut mesh_scaling: Vec<Value> = cells
            .iter()
            .map(|&c| irregular_case(c, None, 1e-5, SumMethod::Pme))
            .collect();
        let direct_cells: &[usize] = if quick {
            &[10]
        } else {
            &[5, 8, 10, 13, 16, 20]
        };
        mesh_scaling.extend(
            direct_cells
                .iter()
                .map(|&c| irregular_case(c, None, 1e-5, SumMethod::Direct)),
        );
        if !quick {
            mesh_scaling.extend(
                [5, 8, 13, 16]
                    .iter()
                    .map(|&c| irregular_case(c, None, 1e-5, SumMethod::Pme)),
            );
        }
        let crossover_cells: &[usize] = if quick { &[8, 10] } else { &[8, 10, 13, 16] };
        let mut crossover = Vec::new();
        for &accuracy in &[1e-4, 1e-6] {
            for &c in crossover_cells {
                crossover.push(irregular_case(c, None, accuracy, SumMethod::Direct));
                crossover.push(irregular_case(c, None, accuracy, SumMethod::Pme));
            }
        }
        let quadrupole_cells: &[usize] = if quick { &[5, 8] } else { &[5, 8, 10, 13, 16] };
        for &accuracy in &[1e-4, 1e-5, 1e-6] {
            for &c in quadrupole_cells {
                for method in [SumMethod::Direct, SumMethod::Pme] {
                    crossover.push(carrying_case(
                        Carries::Quadrupoles,
                        (c, None),
                        accuracy,
                        method,
                    ));
                }
            }
        }
        let mut auto_choices = Vec::new();
        for &accuracy in &[1e-4, 1e-5, 1e-6] {
            for &c in direct_cells {
                auto_choices.push(auto_choice(Carries::Dipoles, c, accuracy));
            }
            for &c in quadrupole_cells {
                auto_choices.push(auto_choice(Carries::Quadrupoles, c, accuracy));
            }
        }
        let ten_thousand: Vec<Value> = [1e-4, 1e-5, 1e-6]
            .iter()
            .map(|&a| irregular_case(22, Some(10_000), a, SumMethod::Pme))
            .collect();
        json!({
            "mesh_scaling": mesh_scaling,
            "mesh_10000": ten_thousand,
            "crossover": crossover,
            "auto_choices": auto_choices,
            "quick": quick,
            "quatrot": env!("CARGO_PKG_VERSION"),
            "lattice": lattice_cases,
            "fft_scaling": scaling,
            "direct_scaling": direct,
        })
    });
    harness::write("ewald.json", out, started);
}
