//! Cost per step of the runner against the bare integrator loop, on the
//! 1000-rotor simple-cubic dipole lattice (scheme B) and on 1000 free
//! asymmetric tops (DLM, where the runner's own overhead is most visible):
//! every observable every step, energies every 100 steps, nothing recorded,
//! and the bare `integrator.step(potential)` loop. Each iteration runs
//! `STEPS` steps from the same set-up integrator (setup excluded).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use quatrot::integrators::{Dlm, GearB, Integrator};
use quatrot::potential::{Boundary, ExternalFields, Free, MultipolePotential, Potential};
use quatrot::rotor::Inertia;
use quatrot::run::{run, Observer, RunOptions, Scheduled, SeriesObserver};
use quatrot::scene::{load, validate, Overrides, Quantity, Scene, Series};
use std::hint::black_box;

/// Steps per measured iteration.
const STEPS: u64 = 200;

fn options(scene: &Scene) -> RunOptions {
    RunOptions {
        dt: scene.dt,
        start_step: 0,
        end_step: STEPS,
        check_every: scene.record.check_every,
        energy_error_threshold: None,
        reference: None,
    }
}

fn every_quantity(every: u64, quantities: Vec<Quantity>) -> Series {
    Series {
        name: "bench".to_string(),
        every,
        quantities,
    }
}

fn bench_system<I: Integrator + Clone, P: Potential>(
    c: &mut Criterion,
    group_name: &str,
    scene: &Scene,
    mut integrator: I,
    potential: &P,
) {
    let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
    integrator
        .setup(&inertia, potential, &scene.initial, scene.dt)
        .expect("setup");
    let mut all: Vec<Quantity> = vec![
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
        Quantity::EnergyError,
        Quantity::Temperature,
        Quantity::NormError,
        Quantity::QDotQ,
    ];
    if integrator.name() == "gear_b" {
        all.push(Quantity::QDotN);
    }
    let energies = vec![
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
    ];
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("bench.csv");
    let mut group = c.benchmark_group(group_name);
    group.sample_size(10);
    group.bench_function("bare_loop", |b| {
        b.iter_batched(
            || integrator.clone(),
            |mut i| {
                for _ in 0..STEPS {
                    i.step(potential);
                }
                black_box(i.orientations()[0])
            },
            BatchSize::LargeInput,
        )
    });
    let cases: [(&str, Option<Series>); 3] = [
        ("nothing_recorded", None),
        ("energies_every_100", Some(every_quantity(100, energies))),
        ("everything_every_step", Some(every_quantity(1, all))),
    ];
    for (name, series) in cases {
        group.bench_function(name, |b| {
            b.iter_batched(
                || integrator.clone(),
                |mut i| {
                    let mut observer = series
                        .as_ref()
                        .map(|s| SeriesObserver::new(s, Some(&csv), false).expect("csv"));
                    let mut scheduled: Vec<Scheduled<'_>> = observer
                        .iter_mut()
                        .zip(&series)
                        .map(|(o, s)| Scheduled {
                            every: s.every,
                            observer: o as &mut dyn Observer,
                        })
                        .collect();
                    run(
                        &mut i,
                        potential,
                        &inertia,
                        &mut scheduled,
                        None,
                        &options(scene),
                    )
                    .expect("runs")
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn runner(c: &mut Criterion) {
    let (_, lattice) = load("dipole_lattice_sc", &Overrides::default()).expect("built-in");
    let periodic = Boundary::Periodic {
        box_lengths: lattice.box_lengths.expect("periodic"),
        cutoff: 3.1,
    };
    let potential = MultipolePotential::new(&lattice.rotors, periodic, ExternalFields::NONE)
        .expect("potential");
    bench_system(
        c,
        "runner_dipole_lattice_gear_b",
        &lattice,
        GearB::default(),
        &potential,
    );

    let (mut raw, _) = load("multipole_tops_bcc", &Overrides::default()).expect("built-in");
    raw.interactions = None;
    if let quatrot::scene::raw::RawRotors::Lattice(l) = &mut raw.rotors {
        l.cells = 8; // 1024 rotors
        l.default.dipole = None;
        l.default.quadrupole = None;
    }
    let free_tops = validate(&raw).expect("valid");
    bench_system(c, "runner_free_tops_dlm", &free_tops, Dlm::default(), &Free);
}

criterion_group!(benches, runner);
criterion_main!(benches);
