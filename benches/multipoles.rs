//! One energy+gradient evaluation (and one torque evaluation) of the periodic
//! simple-cubic lattice of 10^3 rotors (spacing 1, |mu| = 1, cutoff 3.1:
//! 61,000 pairs), on 1 and 2 threads; then the same lattice with a field, with
//! quadrupoles, and with both multipoles, to show that absent terms cost nothing.
//! Throughput is in pairs, so criterion's time per element is the time per pair.
//! On a shared machine criterion's means carry other processes' load; the
//! bench also prints the best of `BEST_OF` single evaluations (the minimum is
//! the estimator least affected by that load), in ns per pair and rotor
//! evaluations per second.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::{Matrix3, Vector3};
use quatrot::lattice::{Lattice, LatticeKind};
use quatrot::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use quatrot::rotor::{Inertia, Rotor};
use quatrot::Quat;
use std::hint::black_box;
use std::time::Duration;

fn lattice_potential(
    dipole: bool,
    quadrupole: bool,
    external: ExternalFields,
) -> (MultipolePotential, Vec<Quat>) {
    let lattice = Lattice::cubic(LatticeKind::SimpleCubic, 10, 1.0).expect("valid lattice");
    let theta = Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0));
    let rotors: Vec<Rotor> = lattice
        .sites
        .iter()
        .map(|s| Rotor {
            site: *s,
            inertia: Inertia::Spherical(1.0),
            dipole_body: dipole.then(Vector3::z),
            quadrupole_body: quadrupole.then_some(theta),
        })
        .collect();
    let boundary = Boundary::periodic_cutoff(lattice.box_lengths, 3.1);
    let potential = MultipolePotential::new(&rotors, boundary, external).expect("valid potential");
    // Deterministic, varied orientations (golden-angle spiral of rotation axes).
    let orientations = (0..rotors.len())
        .map(|i| {
            let t = i as f64;
            let axis = Vector3::new(
                (2.4 * t).cos(),
                (2.4 * t).sin(),
                1.0 - 2.0 * (t + 0.5) / 1000.0,
            );
            Quat::exp(&(axis.normalize() * (0.3 + 2.5 * ((t * 0.618).fract()))))
        })
        .collect();
    (potential, orientations)
}

/// Single evaluations timed for the printed minimum.
const BEST_OF: usize = 300;

/// Prints the best of `BEST_OF` single calls of `evaluate` on `threads` threads.
fn print_best(
    name: &str,
    threads: usize,
    pairs: usize,
    rotors: usize,
    mut evaluate: impl FnMut() + Send,
) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let best = pool.install(|| {
        (0..BEST_OF)
            .map(|_| {
                let start = std::time::Instant::now();
                evaluate();
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    });
    println!(
        "best of {BEST_OF}: {name}, {threads} thread(s): {:.1} us, {:.2} ns/pair, {:.2e} rotor evaluations/s",
        best * 1e6,
        best * 1e9 / pairs as f64,
        rotors as f64 / best
    );
}

fn bench(c: &mut Criterion) {
    let field = ExternalFields {
        field: Some(Vector3::new(0.1, 0.2, 0.3)),
        field_gradient: None,
    };
    let both_fields = ExternalFields {
        field: field.field,
        field_gradient: Some(Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, -0.3))),
    };
    let systems = [
        (
            "dipoles",
            lattice_potential(true, false, ExternalFields::NONE),
            [1, 2].as_slice(),
        ),
        ("dipoles+field", lattice_potential(true, false, field), &[1]),
        (
            "quadrupoles",
            lattice_potential(false, true, ExternalFields::NONE),
            &[1, 2],
        ),
        (
            "dipoles+quadrupoles+fields",
            lattice_potential(true, true, both_fields),
            &[1],
        ),
    ];
    let mut group = c.benchmark_group("multipoles sc 10^3 cutoff 3.1");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    for (name, (potential, q), threads) in &systems {
        group.throughput(Throughput::Elements(potential.pair_count() as u64));
        let mut gradient = vec![Quat::ZERO; q.len()];
        let mut torques = vec![Vector3::zeros(); q.len()];
        for &t in *threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .expect("thread pool");
            group.bench_function(
                BenchmarkId::new(format!("{name} energy+gradient"), format!("{t} thread")),
                |b| {
                    pool.install(|| {
                        b.iter(|| {
                            black_box(potential.energy_and_gradient(black_box(q), &mut gradient))
                        })
                    })
                },
            );
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("thread pool");
        group.bench_function(
            BenchmarkId::new(format!("{name} torques"), "1 thread"),
            |b| {
                pool.install(|| b.iter(|| potential.accumulate_torques(black_box(q), &mut torques)))
            },
        );
    }
    group.finish();
    for (name, (potential, q), threads) in &systems {
        let mut gradient = vec![Quat::ZERO; q.len()];
        let mut torques = vec![Vector3::zeros(); q.len()];
        for &t in *threads {
            print_best(
                &format!("{name} energy+gradient"),
                t,
                potential.pair_count(),
                q.len(),
                || {
                    black_box(potential.energy_and_gradient(black_box(q), &mut gradient));
                },
            );
        }
        print_best(
            &format!("{name} torques"),
            1,
            potential.pair_count(),
            q.len(),
            || potential.accumulate_torques(black_box(q), &mut torques),
        );
    }
}

/// An open cluster of `n` dipoles scattered in a cube (every pair
/// interacts; the pair geometry is computed row by row, `O(N)` memory).
fn open_cluster(n: usize) -> (MultipolePotential, Vec<Quat>) {
    let rotors: Vec<Rotor> = (0..n)
        .map(|k| {
            let t = k as f64;
            Rotor {
                site: Vector3::new(
                    (t * 0.618_034).fract() * 30.0,
                    (t * 0.414_214).fract() * 30.0,
                    (t * 0.732_051).fract() * 30.0 + t * 1e-3,
                ),
                inertia: Inertia::Spherical(1.0),
                dipole_body: Some(Vector3::z()),
                quadrupole_body: None,
            }
        })
        .collect();
    let potential = MultipolePotential::new(&rotors, Boundary::Open, ExternalFields::NONE)
        .expect("valid cluster");
    (potential, vec![Quat::IDENTITY; n])
}

/// The open-boundary sum per evaluation (one per step of every integrator).
fn bench_open(c: &mut Criterion) {
    let mut group = c.benchmark_group("multipoles open cluster");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for n in [1000, 4000] {
        let (potential, q) = open_cluster(n);
        let mut gradient = vec![Quat::ZERO; n];
        group.throughput(Throughput::Elements(potential.pair_count() as u64));
        group.bench_function(BenchmarkId::new("dipoles energy+gradient", n), |b| {
            b.iter(|| black_box(potential.energy_and_gradient(black_box(&q), &mut gradient)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench, bench_open);
criterion_main!(benches);
