//! One evaluation of the Stockmayer fluid (issue 39's moving bodies: LJ and
//! point dipoles cut at 2.5, skin 0.3, rho* = 0.8, simple-cubic start, random
//! orientations) at 1,000, 8,000 and 64,000 bodies, one thread: the
//! interactions of a step (LJ and dipole pair loops over the Verlet list,
//! the site-to-body sums), the list fresh so none is rebuilt. Throughput is
//! in bodies, so criterion's time per element is the time per body.
//! `python -m validation.bench.bodies` times whole runs against LAMMPS.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::{Matrix3, Vector3};
use quatrot::bodies::{
    lattice_start, BodySystem, BodyType, BodyTypeSpec, ElectrostaticTruncation,
    ElectrostaticsOptions, Evaluation, InteractionOptions, Lattice, LatticeStart, LennardJones,
    LennardJonesOptions, Mixing, Site, Truncation,
};
use std::hint::black_box;
use std::time::Duration;

/// The built-in Stockmayer fluid's body, interactions and density at `n`
/// bodies (a cube of simple-cubic cells).
fn stockmayer_fluid(n: usize) -> BodySystem {
    let sphere = BodyType::new(&BodyTypeSpec {
        sites: vec![Site {
            lennard_jones: Some(LennardJones {
                epsilon: 1.0,
                sigma: 1.0,
            }),
            dipole: Some(Vector3::new(0.0, 0.0, 1.0)),
            ..Site::default()
        }],
        mass: Some(1.0),
        inertia: Some(Matrix3::identity() * 0.025),
    })
    .expect("a valid sphere");
    let start = LatticeStart {
        lattice: Lattice::SimpleCubic,
        density: 0.8,
        orientation: None,
        temperature: 1.35,
        seed: 1,
    };
    let types = vec![sphere];
    let (space, bodies) = lattice_start(&types, &vec![0; n], &start).expect("a lattice");
    let options = InteractionOptions {
        lennard_jones: Some(LennardJonesOptions {
            cutoff: 2.5,
            truncation: Truncation::Shifted,
            mixing: Mixing::LorentzBerthelot,
        }),
        electrostatics: Some(ElectrostaticsOptions::Cutoff(
            2.5,
            ElectrostaticTruncation::Plain,
        )),
        skin: 0.3,
    };
    BodySystem::new(types, bodies, space, &options).expect("a valid system")
}

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let mut group = c.benchmark_group("stockmayer fluid evaluation, 1 thread");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for n in [1_000, 8_000, 64_000] {
        let mut system = stockmayer_fluid(n);
        let mut evaluation = Evaluation::default();
        pool.install(|| system.evaluate(&mut evaluation));
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::new("LJ + dipole cutoff 2.5", n), |b| {
            b.iter(|| pool.install(|| system.evaluate(black_box(&mut evaluation))))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
